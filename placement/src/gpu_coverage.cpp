#include "cubeao/placement/gpu_coverage.h"

#include <algorithm>
#include <deque>
#include <string>
#include <vector>

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
#include "cubeao/gl/sync.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/placement/coverage.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/scene/scene.h"

namespace cubeao::placement {
namespace {

constexpr const char* kShader = "placement/coverage_count.comp";

}  // namespace

struct GpuCoverageCount::Impl {
    using Ring = gl::ReadbackRing<kernel::CoverageCounters>;  // tagged with the ticket

    Impl(const Scene& scene, float nearPlane)
        : gbuffer(scene.positions, scene.indices), bvh(buildBvh(scene)), nearPlane(nearPlane) {}

    static Result result(const Ring::Slot& slot) {
        const kernel::CoverageCounters& c = slot.data.front();
        return {slot.tag, c.pixels, c.uncovered};
    }

    CameraGBuffer gbuffer;
    GpuBvh bvh;
    float nearPlane;
    gl::Program program;
    gl::Buffer probes, counters;
    gl::UniformBlock block;  // kernel::CoverageBlock
    gl::UniformBlock camera;  // kernel::CameraBlock, per frame
    std::size_t probeCapacity = 0;  // vec4s the probe buffer holds
    Ring ring;                      // the frames in flight
    std::deque<Result> finished;  // results submit() had to wait for, before any in flight
    std::uint64_t nextTicket = 0;
};

GpuCoverageCount::GpuCoverageCount(const Scene& scene, float nearPlane)
    : impl_(std::make_unique<Impl>(scene, nearPlane)) {
    Impl& m = *impl_;
    m.program = gl::compileComputeProgram(kShader);
    m.counters = gl::Buffer::create();
    glNamedBufferStorage(m.counters.id(), sizeof(kernel::CoverageCounters), nullptr, GL_DYNAMIC_STORAGE_BIT);
    m.ring = Impl::Ring(kSlots, 1);
    m.block = gl::UniformBlock::create(kernel::CoverageBlock{});
}

GpuCoverageCount::~GpuCoverageCount() = default;

std::uint64_t GpuCoverageCount::submit(const PinholeCamera& camera, std::span<const glm::vec3> probes,
                                       const CoverageCriterion& criterion, float surfaceEpsilon) {
    Impl& m = *impl_;
    if (m.ring.inFlight() == kSlots) m.finished.push_back(Impl::result(m.ring.wait()));  // the documented wait

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

    m.block.set(kernel::CoverageBlock{criterion.kernelParams(), std::uint32_t(probes.size()), surfaceEpsilon});
    glUseProgram(m.program.id());
    m.block.bind(kernel::kCoverageBlock);
    m.camera.upload(view.block(m.gbuffer.width(), m.gbuffer.height()), kernel::kCameraBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, m.gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, m.gbuffer.normalTexture());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCoverageProbeBuffer, m.probes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCoverageCounterBuffer, m.counters.id());
    m.bvh.bind();
    glDispatchCompute(kernel::pixelGroups(m.gbuffer.width()), kernel::pixelGroups(m.gbuffer.height()), 1);
    const std::uint64_t ticket = m.nextTicket++;
    m.ring.push(m.counters.id(), ticket);  // (the ring's barrier lets the atomics land before its copy)
    glFlush();  // the GPU starts on the frame now, not at the first poll
    return ticket;
}

std::optional<GpuCoverageCount::Result> GpuCoverageCount::poll() {
    Impl& m = *impl_;
    if (!m.finished.empty()) {
        const Result r = m.finished.front();
        m.finished.pop_front();
        return r;
    }
    const std::optional<Impl::Ring::Slot> slot = m.ring.poll();
    if (!slot) return std::nullopt;
    return Impl::result(*slot);
}

GpuCoverageCount::Result GpuCoverageCount::wait() {
    Impl& m = *impl_;
    if (!m.finished.empty()) {
        const Result r = m.finished.front();
        m.finished.pop_front();
        return r;
    }
    if (m.ring.inFlight() == 0) throw Error("GpuCoverageCount::wait: nothing submitted is pending");
    return Impl::result(m.ring.wait());
}

std::size_t GpuCoverageCount::pending() const { return impl_->finished.size() + impl_->ring.inFlight(); }

bool GpuCoverageCount::submitWouldWait() {
    return impl_->ring.inFlight() == kSlots && !impl_->ring.oldestFinished();
}

}  // namespace cubeao::placement
