#include "cubeao/gl/timer.h"

#include <chrono>
#include <string>

namespace cubeao::gl {

GpuClock trustedClock(std::string_view renderer) {
    // Mesa's CPU rasterisers run the work inside glFinish, after the query has ended.
    const bool software = renderer.find("llvmpipe") != std::string_view::npos ||
                          renderer.find("softpipe") != std::string_view::npos;
    return software ? GpuClock::WallClock : GpuClock::TimerQuery;
}

GpuClock trustedClock() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return trustedClock(renderer != nullptr ? std::string_view(renderer) : std::string_view());
}

TimerQuery::TimerQuery() : query_(Query::create(GL_TIME_ELAPSED)) {}

void TimerQuery::begin() { glBeginQuery(GL_TIME_ELAPSED, query_.id()); }

void TimerQuery::end() { glEndQuery(GL_TIME_ELAPSED); }

bool TimerQuery::ready() const {
    GLint available = GL_FALSE;
    glGetQueryObjectiv(query_.id(), GL_QUERY_RESULT_AVAILABLE, &available);
    return available == GL_TRUE;
}

double TimerQuery::elapsedMs() const {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_.id(), GL_QUERY_RESULT, &ns);
    return static_cast<double>(ns) * 1e-6;
}

GpuTime timeGpu(const std::function<void()>& work) {
    using Clock = std::chrono::steady_clock;
    TimerQuery query;
    glFinish();
    const Clock::time_point start = Clock::now();
    query.begin();
    work();
    query.end();
    glFinish();
    const Clock::time_point stop = Clock::now();
    GpuTime t;
    t.wallMs = std::chrono::duration<double, std::milli>(stop - start).count();
    t.queryMs = query.elapsedMs();
    t.trusted = trustedClock();
    return t;
}

}  // namespace cubeao::gl
