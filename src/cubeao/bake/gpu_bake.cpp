#include "cubeao/bake/gpu_bake.h"

#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "common/bake_layout.h"
#include "cubeao/bake/bvh.h"
#include "cubeao/core/cube.h"
#include "cubeao/bake/gpu_bc5.h"
#include "cubeao/bake/gpu_bvh.h"
#include "cubeao/bake/gpu_depth.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/gpu_mesh.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/gl/state.h"
#include "cubeao/gl/sync.h"
#include "cubeao/gl/timer.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/reference/embree_scene.h"

namespace cubeao {
namespace {

using kernel::bakeGroups;  // binding points, group sizes and buffer structs: common/bake_layout.h

bool needsHorizon(Estimator e) { return e != Estimator::Traced; }

}  // namespace

struct GpuBaker::Impl {
    float zNear = 0.0f, surfaceEpsilon = 0.0f;
    GBufferMode mode = GBufferMode::Layered;
    BakeReadback readback = BakeReadback::Encoded;
    bool timings = false;  // per-stage timeGpu (stalls between stages): bench and --timings only

    std::unique_ptr<gl::GpuMesh> mesh;  // positions, indices, per-triangle normals
    gl::Buffer aoBuffer, aoSource, texelList, fetchCount;
    gl::Texture gbuffer, depth;
    gl::Framebuffer framebuffer;
    gl::Program layered, sixPass, horizon, traced, tracedList, select, denoise, denoiseList;
    gl::UniformBlock block;  // kernel::BakeBlock: the G-buffer pass's, then the AO passes'
    std::unique_ptr<GpuBvh> bvh;
    std::unique_ptr<GpuBc5Encoder> bc5;
    std::unique_ptr<GpuDepthEncoder> depthCube;

    void renderGBuffer(const glm::vec3& probe, int res);
    // What the AO passes of one probe read: uploaded by aoPass (and horizonOn) before the passes below.
    kernel::BakeBlock probeBlock(const glm::vec3& probe, std::uint32_t probeKey, const BakeSettings& s) const;
    void horizonPass(const BakeSettings& s);
    void tracedPass(const BakeSettings& s);
    void hybridPass(const BakeSettings& s);
    // The edge-aware filter of the traced texels (all, or the hybrid's list), after their AO pass.
    void denoisePass(const BakeSettings& s, bool list);
    // Texels the last hybrid pass traced: read once the probe's work is done, not between passes.
    std::uint32_t hybridTraced() const {
        kernel::TexelListHeader header{};
        glGetNamedBufferSubData(texelList.id(), 0, sizeof header, &header);
        return header.count;
    }
    void readAll(BakedProbe& out, const glm::vec3& probe, int res) const;
    // The stages bake() and step() share: the AO pass of the estimator, the encoders, and the
    // read-backs once the work is done (wait unless a fence says it is).
    void aoPass(const glm::vec3& probe, std::uint32_t probeKey, const BakeSettings& s);
    void encode();
    void readEncoded(BakedProbe& out, const glm::vec3& probe, const BakeSettings& s) const;
    void readCounters(BakedProbe& out, const BakeSettings& s) const;

    // The stepped bake's job (GpuBaker::begin/step/take).
    enum class Stage { GBuffer, Ao, Encode, Waiting, Ready };
    struct Job {
        glm::vec3 probe{0.0f};
        std::uint32_t index = 0;
        Stage stage = Stage::GBuffer;
        gl::Fence fence;  // after the encoders and the error dispatch
        BakedProbe result;
    };
    std::optional<Job> job;
    std::uint64_t fetches() const {
        kernel::FetchCount count{0u, 0u};
        glGetNamedBufferSubData(fetchCount.id(), 0, sizeof count, &count);
        return kernel::joinWords(count.fetchesLow, count.fetchesHigh);
    }
};

GpuBaker::GpuBaker(const Scene& scene, const BakeSettings& settings) : impl_(std::make_unique<Impl>()), settings_(settings) {
    Impl& m = *impl_;
    const int res = settings.res;
    m.surfaceEpsilon = surfaceEpsilonFor(scene);
    // Anything nearer the probe than zNear is clipped: keep it far below a texel's footprint.
    m.zNear = std::max(1e-6f, 1e-6f * glm::length(scene.bounds.max - scene.bounds.min));

    m.mesh = std::make_unique<gl::GpuMesh>(scene.positions, scene.indices);

    // G-buffer: (normal, distance) as RGBA32F, reversed-Z float depth; six layers = six faces.
    m.gbuffer = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.gbuffer.id(), 1, GL_RGBA32F, res, res, cube::kFaces);
    m.depth = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.depth.id(), 1, GL_DEPTH_COMPONENT32F, res, res, cube::kFaces);
    m.framebuffer = gl::Framebuffer::create();

    const std::size_t texels = std::size_t(cube::kFaces) * std::size_t(res) * std::size_t(res);
    m.aoBuffer = gl::Buffer::create();
    glNamedBufferStorage(m.aoBuffer.id(), GLsizeiptr(texels * sizeof(glm::vec2)), nullptr, 0);

    m.layered = gl::buildProgram({gl::loadShaderStage(GL_VERTEX_SHADER, "bake/gbuffer.vert"),
                                  gl::loadShaderStage(GL_GEOMETRY_SHADER, "bake/gbuffer.geom"),
                                  gl::loadShaderStage(GL_FRAGMENT_SHADER, "bake/gbuffer.frag")},
                                 {{"LAYERED", "1"}});
    m.sixPass = gl::compileRenderProgram("bake/gbuffer.vert", "bake/gbuffer.frag");
    m.fetchCount = gl::Buffer::create();
    glNamedBufferStorage(m.fetchCount.id(), sizeof(kernel::FetchCount), nullptr, GL_DYNAMIC_STORAGE_BIT);
    if (needsHorizon(settings.estimator)) {
        const bool gtao = settings.estimator == Estimator::Gtao;
        m.horizon = gl::compileComputeProgram("bake/ao_horizon.comp", {{"ESTIMATOR", gtao ? "1" : "0"}});
    }
    if (tracesRays(settings.estimator)) {
        m.bvh = std::make_unique<GpuBvh>(buildBvh(scene));
        m.traced = gl::compileComputeProgram("bake/ao_traced.comp");
    }
    if (settings.denoise > 0) {
        m.aoSource = gl::Buffer::create();
        glNamedBufferStorage(m.aoSource.id(), GLsizeiptr(texels * sizeof(glm::vec2)), nullptr, 0);
        if (settings.estimator == Estimator::Hybrid)
            m.denoiseList = gl::compileComputeProgram("bake/ao_denoise.comp", {{"TEXEL_LIST", "1"}});
        else
            m.denoise = gl::compileComputeProgram("bake/ao_denoise.comp");
    }
    m.bc5 = std::make_unique<GpuBc5Encoder>(res);
    m.depthCube = std::make_unique<GpuDepthEncoder>(res, settings.depthRes, settings.depthFormat);
    if (settings.estimator == Estimator::Hybrid) {
        m.tracedList = gl::compileComputeProgram("bake/ao_traced.comp", {{"TEXEL_LIST", "1"}});
        m.select = gl::compileComputeProgram("bake/hybrid_select.comp");
        m.texelList = gl::Buffer::create();
        glNamedBufferStorage(m.texelList.id(), GLsizeiptr(sizeof(kernel::TexelListHeader) + texels * sizeof(std::uint32_t)), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }
}

GpuBaker::~GpuBaker() = default;

void GpuBaker::setGBufferMode(GBufferMode mode) { impl_->mode = mode; }
void GpuBaker::setReadback(BakeReadback readback) { impl_->readback = readback; }
void GpuBaker::setTimings(bool timings) { impl_->timings = timings; }


void GpuBaker::Impl::renderGBuffer(const glm::vec3& probe, int res) {
    const GLfloat clearNormal[4] = {0.0f, 0.0f, 0.0f, 0.0f}, clearDepth = 0.0f;  // distance 0 = empty
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);  // reversed-Z (cube.h clipFromWorld)
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);  // architecture is open and two-sided
    glViewport(0, 0, res, res);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    mesh->bind(kernel::kBakeTriangleNormalsBuffer);
    const auto draw = [&] { mesh->draw(); };
    kernel::BakeBlock b{};
    b.probe = probe;

    if (mode == GBufferMode::Layered) {
        glNamedFramebufferTexture(framebuffer.id(), GL_COLOR_ATTACHMENT0, gbuffer.id(), 0);
        glNamedFramebufferTexture(framebuffer.id(), GL_DEPTH_ATTACHMENT, depth.id(), 0);
        glClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, clearNormal);  // clears all layers
        glClearNamedFramebufferfv(framebuffer.id(), GL_DEPTH, 0, &clearDepth);
        for (int f = 0; f < cube::kFaces; ++f) b.clipFromWorld[f] = cube::clipFromWorld(f, probe, zNear);
        glUseProgram(layered.id());
        block.upload(b, kernel::kBakeBlock);
        draw();
    } else {
        glUseProgram(sixPass.id());
        for (int f = 0; f < cube::kFaces; ++f) {
            glNamedFramebufferTextureLayer(framebuffer.id(), GL_COLOR_ATTACHMENT0, gbuffer.id(), 0, f);
            glNamedFramebufferTextureLayer(framebuffer.id(), GL_DEPTH_ATTACHMENT, depth.id(), 0, f);
            glClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, clearNormal);
            glClearNamedFramebufferfv(framebuffer.id(), GL_DEPTH, 0, &clearDepth);
            b.clipFromWorld[0] = cube::clipFromWorld(f, probe, zNear);
            block.upload(b, kernel::kBakeBlock);  // in order: the last face's draw still reads its own
            draw();
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

kernel::BakeBlock GpuBaker::Impl::probeBlock(const glm::vec3& probe, std::uint32_t probeKey,
                                             const BakeSettings& s) const {
    kernel::BakeBlock b{};
    b.probe = probe;
    b.res = s.res;
    b.radius = s.ao.radius;
    b.falloff = falloffUniform(s.ao.falloff);
    b.probeKey = probeKey;
    b.directions = s.directions;
    b.steps = s.steps;
    b.spp = s.ao.spp;
    b.surfaceEpsilon = surfaceEpsilon;
    b.denoiseRadius = s.denoise;
    b.threshold = s.hybridThreshold;
    return b;
}

void GpuBaker::Impl::horizonPass(const BakeSettings& s) {
    const kernel::FetchCount zero{0u, 0u};
    glNamedBufferSubData(fetchCount.id(), 0, sizeof zero, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeFetchCountBuffer, fetchCount.id());
    glUseProgram(horizon.id());
    glBindTextureUnit(kernel::kBakeGBufferUnit, gbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeAoBuffer, aoBuffer.id());
    glDispatchCompute(bakeGroups(std::size_t(s.res), kernel::kBakeTileSize), bakeGroups(std::size_t(s.res), kernel::kBakeTileSize),
                      cube::kFaces);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void GpuBaker::Impl::tracedPass(const BakeSettings& s) {
    glUseProgram(traced.id());
    glBindTextureUnit(kernel::kBakeGBufferUnit, gbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeAoBuffer, aoBuffer.id());
    bvh->bind();
    glDispatchCompute(bakeGroups(std::size_t(cube::kFaces) * std::size_t(s.res) * std::size_t(s.res), kernel::kBakeListGroupSize),
                      1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    if (s.denoise > 0) denoisePass(s, false);
}

void GpuBaker::Impl::hybridPass(const BakeSettings& s) {
    horizonPass(s);
    const kernel::TexelListHeader header{0u, 1u, 1u, 0u};  // indirect dispatch (x, y, z) + count
    glNamedBufferSubData(texelList.id(), 0, sizeof header, &header);
    glUseProgram(select.id());
    glBindTextureUnit(kernel::kBakeGBufferUnit, gbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeAoBuffer, aoBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeTexelListBuffer, texelList.id());
    glDispatchCompute(bakeGroups(std::size_t(cube::kFaces) * std::size_t(s.res) * std::size_t(s.res), kernel::kBakeListGroupSize),
                      1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(tracedList.id());
    bvh->bind();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, texelList.id());
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    if (s.denoise > 0) denoisePass(s, true);
}

void GpuBaker::Impl::denoisePass(const BakeSettings& s, bool list) {
    const std::size_t texels = std::size_t(cube::kFaces) * std::size_t(s.res) * std::size_t(s.res);
    glCopyNamedBufferSubData(aoBuffer.id(), aoSource.id(), 0, 0, GLsizeiptr(texels * sizeof(glm::vec2)));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    const gl::Program& program = list ? denoiseList : denoise;
    glUseProgram(program.id());
    glBindTextureUnit(kernel::kBakeGBufferUnit, gbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeAoBuffer, aoBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeAoSourceBuffer, aoSource.id());
    if (list) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kBakeTexelListBuffer, texelList.id());
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, texelList.id());
        glDispatchComputeIndirect(0);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    } else {
        glDispatchCompute(bakeGroups(texels, kernel::kBakeListGroupSize), 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

// The uncompressed G-buffer, AO and confidence (BakeReadback::All).
void GpuBaker::Impl::readAll(BakedProbe& out, const glm::vec3& probe, int res) const {
    const std::size_t texels = std::size_t(cube::kFaces) * std::size_t(res) * std::size_t(res);
    out.gbuffer.res = res;
    out.gbuffer.probe = probe;
    out.gbuffer.texels.resize(texels);
    glGetTextureImage(gbuffer.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(texels * sizeof(glm::vec4)), out.gbuffer.texels.data());
    std::vector<glm::vec2> aoConfidence(texels);
    glGetNamedBufferSubData(aoBuffer.id(), 0, GLsizeiptr(texels * sizeof(glm::vec2)), aoConfidence.data());
    out.ao.resize(texels);
    out.confidence.resize(texels);
    for (std::size_t i = 0; i < texels; ++i) {
        out.ao[i] = aoConfidence[i].x;
        out.confidence[i] = aoConfidence[i].y;
    }
}

BakedProbe GpuBaker::bake(const glm::vec3& probe, std::uint32_t probeIndex) {
    Impl& m = *impl_;
    if (m.job) throw Error("GpuBaker::bake: a stepped bake is in progress (its buffers are in use)");
    const BakeSettings& s = settings_;
    const std::uint32_t probeKey = probeIndex ^ s.ao.seed;
    BakedProbe out;
    // Without timings the stages are queued back to back and the first read-back waits for them all;
    // with them each stage is timed alone (timeGpu finishes the work before and after it).
    const auto stage = [&](double& ms, const std::function<void()>& work) {
        if (m.timings)
            ms = gl::timeGpu(work).ms();
        else
            work();
    };
    stage(out.timings.gbufferMs, [&] { m.renderGBuffer(probe, s.res); });
    stage(out.timings.aoMs, [&] { m.aoPass(probe, probeKey, s); });
    stage(out.timings.encodeMs, [&] { m.encode(); });
    const auto clock = std::chrono::steady_clock::now;
    const auto msSince = [&](auto start) { return std::chrono::duration<double, std::milli>(clock() - start).count(); };
    const auto errorStart = clock();
    const GpuBc5Encoder::AoError error = m.bc5->aoError(m.aoBuffer.id(), m.gbuffer.id());
    out.encoded.aoSquaredError = error.squaredError;
    out.encoded.surfaceTexels = error.texels;
    if (m.timings) out.timings.errorMs = msSince(errorStart);  // else: mostly the wait for every stage

    const auto readbackStart = clock();
    m.readEncoded(out, probe, s);
    if (m.timings) out.timings.readbackMs = msSince(readbackStart);
    m.readCounters(out, s);
    return out;
}

void GpuBaker::Impl::aoPass(const glm::vec3& probe, std::uint32_t probeKey, const BakeSettings& s) {
    block.upload(probeBlock(probe, probeKey, s), kernel::kBakeBlock);  // every dispatch below reads it
    switch (s.estimator) {
        case Estimator::HorizonSplit:
        case Estimator::Gtao: horizonPass(s); break;
        case Estimator::Traced: tracedPass(s); break;
        case Estimator::Hybrid: hybridPass(s); break;
    }
}

void GpuBaker::Impl::encode() {
    bc5->encode(aoBuffer.id());
    depthCube->encode(gbuffer.id());
}

void GpuBaker::Impl::readEncoded(BakedProbe& out, const glm::vec3& probe, const BakeSettings& s) const {
    out.encoded.aoConfidence = bc5->read();
    EncodedDepth depth = depthCube->read();
    out.encoded.depth = std::move(depth.bytes);
    out.encoded.maxDistance = depth.maxDistance;
    if (readback == BakeReadback::All) readAll(out, probe, s.res);
    if (s.levels > 1) {  // the coarser levels are made on the CPU from the full-resolution data
        BakedProbe full;
        if (readback != BakeReadback::All) readAll(full, probe, s.res);
        const BakedProbe& from = readback == BakeReadback::All ? out : full;
        std::vector<glm::vec2> aoConfidence(from.ao.size());
        for (std::size_t t = 0; t < aoConfidence.size(); ++t) aoConfidence[t] = {from.ao[t], from.confidence[t]};
        appendLevels(out.encoded, aoConfidence, from.gbuffer, s);
    }
}

void GpuBaker::Impl::readCounters(BakedProbe& out, const BakeSettings& s) const {
    if (needsHorizon(s.estimator)) out.fetches = fetches();
    if (s.estimator == Estimator::Traced) out.tracedTexels = out.encoded.surfaceTexels;
    if (s.estimator == Estimator::Hybrid) out.tracedTexels = hybridTraced();
    out.rays = out.tracedTexels * std::uint64_t(s.ao.spp);
}


void GpuBaker::begin(const glm::vec3& probe, std::uint32_t probeIndex) {
    if (impl_->job) throw Error("GpuBaker::begin: a stepped bake is still in progress (take() it first)");
    impl_->job.emplace();
    impl_->job->probe = probe;
    impl_->job->index = probeIndex;
}

bool GpuBaker::busy() const { return impl_->job.has_value(); }
bool GpuBaker::ready() const { return impl_->job && impl_->job->stage == Impl::Stage::Ready; }
bool GpuBaker::waiting() const { return impl_->job && impl_->job->stage == Impl::Stage::Waiting; }

bool GpuBaker::step() {
    Impl& m = *impl_;
    if (!m.job) throw Error("GpuBaker::step: no stepped bake in progress (begin() one first)");
    Impl::Job& job = *m.job;
    const BakeSettings& s = settings_;
    using Stage = Impl::Stage;
    switch (job.stage) {
        case Stage::GBuffer: {
            const gl::SavedState saved;  // a stage runs inside the caller's frame
            m.renderGBuffer(job.probe, s.res);
            glFlush();  // start the work now, not at the frame's flush
            job.stage = Stage::Ao;
            return false;
        }
        case Stage::Ao: {
            const gl::SavedState saved;  // a stage runs inside the caller's frame
            m.aoPass(job.probe, job.index ^ s.ao.seed, s);
            glFlush();
            job.stage = Stage::Encode;
            return false;
        }
        case Stage::Encode: {
            const gl::SavedState saved;  // a stage runs inside the caller's frame
            m.encode();
            m.bc5->dispatchAoError(m.aoBuffer.id(), m.gbuffer.id());
            job.fence = gl::Fence::insert();
            glFlush();  // the GPU starts on the encoders now, not at the next step's poll
            job.stage = Stage::Waiting;
            return false;
        }
        case Stage::Waiting: {
            if (!job.fence.passed()) return false;
            // Everything issued before the fence is done: none of these reads waits.
            const GpuBc5Encoder::AoError error = m.bc5->readAoError();
            job.result.encoded.aoSquaredError = error.squaredError;
            job.result.encoded.surfaceTexels = error.texels;
            m.readEncoded(job.result, job.probe, s);
            m.readCounters(job.result, s);
            job.stage = Stage::Ready;
            return true;
        }
        case Stage::Ready: return true;
    }
    return false;
}

BakedProbe GpuBaker::take() {
    if (!ready()) throw Error("GpuBaker::take: no stepped bake is ready");
    BakedProbe out = std::move(impl_->job->result);
    impl_->job.reset();
    return out;
}

std::vector<glm::vec2> GpuBaker::horizonOn(const CubeGBuffer& g, std::uint32_t probeIndex, std::uint64_t* fetches) {
    Impl& m = *impl_;
    if (!m.horizon) throw Error("GpuBaker::horizonOn needs the hsplit or gtao estimator");
    if (g.res != settings_.res) throw Error("GpuBaker::horizonOn: G-buffer resolution differs from the settings'");
    glTextureSubImage3D(m.gbuffer.id(), 0, 0, 0, 0, g.res, g.res, cube::kFaces, GL_RGBA, GL_FLOAT, g.texels.data());
    m.block.upload(m.probeBlock(g.probe, probeIndex ^ settings_.ao.seed, settings_), kernel::kBakeBlock);
    m.horizonPass(settings_);
    std::vector<glm::vec2> out(g.texelCount());
    glGetNamedBufferSubData(m.aoBuffer.id(), 0, GLsizeiptr(out.size() * sizeof(glm::vec2)), out.data());
    if (fetches) *fetches = m.fetches();
    return out;
}

}  // namespace cubeao
