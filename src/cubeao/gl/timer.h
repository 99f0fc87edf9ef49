// Timing GPU work. Two clocks, because neither is right everywhere:
// - GL_TIME_ELAPSED queries measure execution on a real GPU without stalling the pipeline, but on
//   Mesa llvmpipe they cover only handing the work over, not running it (../shared/gpu/README.md);
// - wall clock around glFinish() is right on llvmpipe (the "GPU" is this CPU), and on a real GPU it
//   adds the submit and glFinish round trip.
// timeGpu() takes both; trustedClock() says which one to report for the current renderer.
#pragma once

#include "cubeao/gl/handles.h"

#include <functional>
#include <string_view>

namespace cubeao::gl {

enum class GpuClock { TimerQuery, WallClock };

// Which clock measures execution on a renderer (GL_RENDERER text): wall clock for llvmpipe (and
// softpipe), timer queries elsewhere. Pure; unit-testable.
GpuClock trustedClock(std::string_view renderer);
// The same for the current context.
GpuClock trustedClock();

// One GL_TIME_ELAPSED query. Queries of this kind cannot nest: at most one is active at a time.
class TimerQuery {
public:
    TimerQuery();  // needs a current context
    void begin();
    void end();
    bool ready() const;        // the result is available without waiting
    double elapsedMs() const;  // waits for the result if needed

private:
    Query query_;
};

struct GpuTime {
    double queryMs = 0.0;  // GL_TIME_ELAPSED around the work
    double wallMs = 0.0;   // host clock from before submission until glFinish returned
    GpuClock trusted = GpuClock::TimerQuery;
    double ms() const { return trusted == GpuClock::WallClock ? wallMs : queryMs; }
};

// Runs work once, timed by both clocks. Earlier work is finished first so it is not counted; the
// call therefore stalls the pipeline: use it for benchmarks, not inside a frame.
GpuTime timeGpu(const std::function<void()>& work);

}  // namespace cubeao::gl
