// The GPU bake path (DESIGN.md §4 "Bake"): the scene rasterised into a cube G-buffer (a 6-layer
// RGBA32F array texture: normal facing the probe, distance), then one compute pass per estimator
// writing (ao, confidence) per texel, then the encoders (gpu_bc5.h, gpu_depth.h) that make what the
// cache stores, so only compressed bytes need to come back to the CPU. Twin: the CPU path in bake.h; tests/bake/test_bake_gl.cpp checks
// that the two agree.
//
// A GpuBaker needs a current GL 4.5 context for its whole life (it owns GL objects).
#pragma once

#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

enum class GBufferMode {
    Layered,  // one draw; a geometry shader routes each triangle to the faces it can touch
    SixPass,  // one draw per face
};

// What GpuBaker::bake copies back to the CPU.
enum class BakeReadback {
    Encoded,  // the cache's bytes only (BakedProbe::encoded): a production bake (DESIGN.md §4 "Storage")
    All,      // also the G-buffer, AO and confidence (for --verify, --dump and tests)
};

class GpuBaker {
public:
    // Uploads the mesh (and for traced/hybrid a BVH), compiles the programs. `settings` resolved.
    GpuBaker(const Scene& scene, const BakeSettings& settings);
    ~GpuBaker();
    GpuBaker(const GpuBaker&) = delete;
    GpuBaker& operator=(const GpuBaker&) = delete;

    void setGBufferMode(GBufferMode mode);
    void setReadback(BakeReadback readback);  // default: Encoded
    // Per-stage timings (BakedProbe::timings): each stage then runs alone between glFinish calls
    // (gl::timeGpu), a stall a production bake must not pay. Default off: the stage times stay 0.
    void setTimings(bool timings);

    // G-buffer, AO, BC5 and distance cube encoding and the BC5 AO error on the GPU, then the
    // read-back the readback mode asks for; timings per stage only with setTimings(true).
    BakedProbe bake(const glm::vec3& probe, std::uint32_t probeIndex);

    // The same bake cut into steps that never wait for the GPU, for a frame loop that interleaves bake
    // work with its frames in one context (the viewer's live placement): begin() starts a job, each
    // step() issues one stage — the G-buffer; the AO pass (hybrid: its three dispatches); the encoders,
    // the BC5 error dispatch and a fence — and every later step() polls the fence (gl::Fence::passed,
    // timeout 0) and only once it has signalled does the read-backs, which then cannot wait. step()
    // returns true when the result is ready; take() hands it over and ends the job. The result is
    // bit-identical to bake(probe, probeIndex) in the same readback mode (tests/placement/test_live_placement.cpp);
    // its per-stage timings stay 0 (timing a stage means waiting for it). One job at a time: begin()
    // throws cubeao::Error while one is in progress, take() unless one is ready. A step restores the GL
    // state a frame relies on (viewport, program, framebuffers, VAO, depth test and function, face
    // culling, clip control); buffer and texture binding points are left as the stage set them (every
    // pass here binds what it uses before it runs).
    void begin(const glm::vec3& probe, std::uint32_t probeIndex);
    bool step();
    BakedProbe take();
    bool busy() const;   // a job begun and not yet taken
    bool ready() const;  // the job's result is there for take()
    // All of the job's work is issued and its fence not yet seen signalled: the next step() only polls.
    bool waiting() const;

    // For tests: the horizon pass alone on a given G-buffer (uploaded), returning (ao, confidence)
    // per texel and, if asked, the G-buffer lookups made; the estimator must be hsplit or gtao.
    std::vector<glm::vec2> horizonOn(const CubeGBuffer& g, std::uint32_t probeIndex, std::uint64_t* fetches = nullptr);

    const BakeSettings& settings() const { return settings_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    BakeSettings settings_;
};

}  // namespace cubeao
