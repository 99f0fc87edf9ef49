#include "cubeao/placement/gpu_coverage.h"

#include <algorithm>
#include <array>
#include <deque>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#include "common/coverage.h"
#include "common/placement_layout.h"
#include "common/runtime_layout.h"
#include "cubeao/bake/bvh.h"
#include "cubeao/bake/gpu_bvh.h"
#include "cubeao/core/camera.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/placement/coverage.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/scene/scene.h"

namespace cubeao::placement {
namespace {

constexpr const char* kShader = "placement/coverage_count.comp";

// Location of a uniform the shader must use: a name that drifted from the shader fails loudly.
GLint uniformLocation(GLuint program, const char* name) {
    const GLint location = glGetUniformLocation(program, name);
    if (location < 0) throw Error(std::string(kShader) + ": no active uniform " + name);
    return location;
}

struct FenceDeleter {
    void operator()(GLsync sync) const { glDeleteSync(sync); }
};
using Fence = std::unique_ptr<std::remove_pointer_t<GLsync>, FenceDeleter>;

}  // namespace

struct GpuCoverageCount::Impl {
    // One frame in flight: the counters copied out of the pass, and the fence after the copy.
    struct Slot {
        gl::Buffer readBack;
        Fence fence;
        std::uint64_t ticket = 0;
    };

    Impl(const Scene& scene, float nearPlane)
        : gbuffer(scene.positions, scene.indices), bvh(buildBvh(scene)), nearPlane(nearPlane) {}

    // Reads a slot whose fence has signaled and frees it.
    Result take(Slot& slot) {
        kernel::CoverageCounters c{};
        glGetNamedBufferSubData(slot.readBack.id(), 0, sizeof c, &c);
        slot.fence.reset();
        return {slot.ticket, c.pixels, c.uncovered};
    }

    // Blocks until the oldest in-flight frame is done and returns its result.
    Result waitOldest() {
        Slot& slot = slots[inFlight.front()];
        for (;;) {
            // Flush on the first try so the fence reaches the GPU (submit flushes too; this is cheap).
            const GLenum status = glClientWaitSync(slot.fence.get(), GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000);
            if (status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED) break;
            if (status == GL_WAIT_FAILED) throw Error("GpuCoverageCount: glClientWaitSync failed");
        }
        inFlight.pop_front();
        return take(slot);
    }

    CameraGBuffer gbuffer;
    GpuBvh bvh;
    float nearPlane;
    gl::Program program;
    gl::Buffer probes, counters;
    std::size_t probeCapacity = 0;  // vec4s the probe buffer holds
    std::array<Slot, kSlots> slots;
    std::deque<std::size_t> inFlight;  // slot indices, oldest first
    std::deque<Result> finished;       // results submit() had to wait for, before any in flight
    std::uint64_t nextTicket = 0;
};

GpuCoverageCount::GpuCoverageCount(const Scene& scene, float nearPlane)
    : impl_(std::make_unique<Impl>(scene, nearPlane)) {
    Impl& m = *impl_;
    m.program = gl::compileComputeProgram(kShader);
    m.counters = gl::Buffer::create();
    glNamedBufferStorage(m.counters.id(), sizeof(kernel::CoverageCounters), nullptr, GL_DYNAMIC_STORAGE_BIT);
    for (Impl::Slot& slot : m.slots) {
        slot.readBack = gl::Buffer::create();
        // Read on the CPU once its fence has signaled: client storage is the hint for that.
        glNamedBufferStorage(slot.readBack.id(), sizeof(kernel::CoverageCounters), nullptr, GL_CLIENT_STORAGE_BIT);
    }
}

GpuCoverageCount::~GpuCoverageCount() = default;

std::uint64_t GpuCoverageCount::submit(const PinholeCamera& camera, std::span<const glm::vec3> probes,
                                       const CoverageCriterion& criterion, float surfaceEpsilon) {
    Impl& m = *impl_;
    if (m.inFlight.size() == kSlots) m.finished.push_back(m.waitOldest());  // every slot busy: the documented wait
    std::size_t free = 0;
    while (m.slots[free].fence) ++free;
    Impl::Slot& slot = m.slots[free];

    const CameraView view = CameraView::fromPinhole(camera, m.nearPlane);
    m.gbuffer.render(view);

    // Probes as vec4 (std430 pads a vec3 array to 16 bytes); at least one so the binding is never empty.
    std::vector<glm::vec4> table(std::max<std::size_t>(probes.size(), 1), glm::vec4(0.0f));
    for (std::size_t i = 0; i < probes.size(); ++i) table[i] = glm::vec4(probes[i], 1.0f);
    const auto bytes = GLsizeiptr(table.size() * sizeof(glm::vec4));
    if (table.size() > m.probeCapacity) {
        m.probes = gl::Buffer::create();
        m.probeCapacity = std::max(table.size(), 2 * m.probeCapacity);
        glNamedBufferStorage(m.probes.id(), GLsizeiptr(m.probeCapacity * sizeof(glm::vec4)), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    // GL orders this update after the frames already queued that read the buffer.
    glNamedBufferSubData(m.probes.id(), 0, bytes, table.data());
    const kernel::CoverageCounters zero{};
    glNamedBufferSubData(m.counters.id(), 0, sizeof zero, &zero);

    const GLuint p = m.program.id();
    const kernel::CoverageParams params = criterion.kernelParams();
    // kernel::CoverageParams member by member (a plain uniform struct has no buffer layout).
    glProgramUniform1f(p, uniformLocation(p, "params.maxArea"), params.maxArea);
    glProgramUniform1f(p, uniformLocation(p, "params.maxDistance"), params.maxDistance);
    glProgramUniform1f(p, uniformLocation(p, "params.minFacing"), params.minFacing);
    glProgramUniform1i(p, uniformLocation(p, "params.res"), params.res);
    glProgramUniform1ui(p, uniformLocation(p, "probeCount"), GLuint(probes.size()));
    glProgramUniform1f(p, uniformLocation(p, "surfaceEpsilon"), surfaceEpsilon);
    glProgramUniform2i(p, uniformLocation(p, "frameSize"), m.gbuffer.width(), m.gbuffer.height());
    glProgramUniform1f(p, uniformLocation(p, "tanHalfFovY"), view.tanHalfFovY);
    const glm::mat4 worldFromView = view.worldFromView();
    glProgramUniformMatrix4fv(p, uniformLocation(p, "worldFromView"), 1, GL_FALSE, glm::value_ptr(worldFromView));

    glUseProgram(p);
    glBindTextureUnit(kernel::kGBufferDepthUnit, m.gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, m.gbuffer.normalTexture());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCoverageProbeBuffer, m.probes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCoverageCounterBuffer, m.counters.id());
    m.bvh.bind();
    glDispatchCompute(kernel::pixelGroups(m.gbuffer.width()), kernel::pixelGroups(m.gbuffer.height()), 1);
    // The shader's atomics must land before the copy reads the counters.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glCopyNamedBufferSubData(m.counters.id(), slot.readBack.id(), 0, 0, sizeof(kernel::CoverageCounters));
    slot.fence.reset(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
    if (!slot.fence) throw Error("GpuCoverageCount: glFenceSync failed");
    glFlush();  // so the fence reaches the GPU and poll() can see it signal without flushing
    slot.ticket = m.nextTicket++;
    m.inFlight.push_back(free);
    return slot.ticket;
}

std::optional<GpuCoverageCount::Result> GpuCoverageCount::poll() {
    Impl& m = *impl_;
    if (!m.finished.empty()) {
        const Result r = m.finished.front();
        m.finished.pop_front();
        return r;
    }
    if (m.inFlight.empty()) return std::nullopt;
    Impl::Slot& slot = m.slots[m.inFlight.front()];
    const GLenum status = glClientWaitSync(slot.fence.get(), 0, 0);
    if (status == GL_WAIT_FAILED) throw Error("GpuCoverageCount: glClientWaitSync failed");
    if (status != GL_ALREADY_SIGNALED && status != GL_CONDITION_SATISFIED) return std::nullopt;
    m.inFlight.pop_front();
    return m.take(slot);
}

GpuCoverageCount::Result GpuCoverageCount::wait() {
    Impl& m = *impl_;
    if (!m.finished.empty()) {
        const Result r = m.finished.front();
        m.finished.pop_front();
        return r;
    }
    if (m.inFlight.empty()) throw Error("GpuCoverageCount::wait: nothing submitted is pending");
    return m.waitOldest();
}

std::size_t GpuCoverageCount::pending() const { return impl_->finished.size() + impl_->inFlight.size(); }

}  // namespace cubeao::placement
