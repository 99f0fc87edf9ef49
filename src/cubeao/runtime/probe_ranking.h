// Which probes a frame wants on the GPU, best first (DESIGN.md §4 "Run time that grows"): the order the
// residency loads them in and keeps them by. Pure (no GL): the pass asks it each frame with the
// camera, the candidate grid and the planner's slots and pixel feedback; tests ask it on the CPU
// (tests/runtime/test_probe_ranking.cpp).
//
// What the pixels asked for comes first (by how many sampled pixels asked), then by place: each cell
// of a box around the camera scores its candidates by the cell's distance from the eye (×2 out of view
// within two cells, ×4 farther) or, if less, 1.25× the distance from where the eye will be
// `lookaheadFrames` from now along its smoothed motion, times 1 + the probe's rank in the cell; the box
// grows until it lists as many probes as there are slots. With room for every probe: all of them,
// nearest first (the order they stream in); nothing once every live probe is resident.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/probe_grid.h"
#include "cubeao/runtime/probe_id.h"
#include "cubeao/runtime/residency_planner.h"

namespace cubeao {

class ProbeRanking {
public:
    explicit ProbeRanking(float lookaheadFrames = 8.0f) : lookahead_(lookaheadFrames) {}

    // This frame's wanted probes (live ones of `probes`, by `grid`'s cells, plus those the pixels asked
    // for), best first.
    // Each call is a frame: the eye's motion is smoothed over the calls.
    std::vector<ProbeId> wanted(const CameraView& view, const ProbeGrid& grid, const ProbeSet& probes,
                                const ResidencyPlanner& residency);

private:
    float lookahead_;
    glm::vec3 lastEye_{0.0f}, motion_{0.0f};
    bool haveEye_ = false;
    std::vector<float> score_;  // scratch, per probe id
};

}  // namespace cubeao
