// Projecting baked probes onto a surface point (DESIGN.md §4 "Projection", thesis 003 ch. 5): the
// per-point math of the run-time pass on the CPU, what tests and tools use to read a cache at arbitrary
// points. The math itself is shaders/common/projection.h, compiled here as C++ and in the projection
// shader (shaders/runtime/project.comp) as GLSL; these functions feed it decoded probes.
//
// Per candidate probe: a depth test (does the probe see the point?), then a quality that is one
// physical number instead of the thesis' three heuristics: the world-space area one probe texel
// covers on the surface at the point. It grows with the distance squared (Q_a), shrinks off a cube
// face's centre where texels subtend less solid angle (Q_b) and grows as the surface turns away from
// the probe (Q_c). quality = confidence / area. The best two probes are blended with weights
// q1 − q3 and q2 − q3 (q3: the third best, 0 if none), so a probe's weight reaches zero exactly when
// it drops out of the top two: the result is continuous when the ranking changes (no popping,
// unlike the thesis' hard switch, fig. 5.12).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/cube.h"

namespace cubeao {

struct ProjectSettings {
    float depthTolerance = 0.0f;  // relative bias of the depth test; 0 → depth::kDepthTolerance
    float depthSlope = 0.0f;      // slope-scaled bias; 0 → depth::kDepthSlope (src/cubeao/cache/depth_cube.h)
    float depthOffset = 0.0f;     // lift of the test's second half in coarse texels; 0 → depth::kDepthOffset
                                  // (off; depth::kThinWallLift: no leak through thin walls)
    float minFacing = 0.0f;       // smallest cos θ between normal and probe direction used; 0 → 0.05
};

// One probe as the projection reads it: decoded AO + confidence per texel (cube::texelIndex order,
// res × res faces) and a distance cube (depthRes × depthRes faces, distance from the probe, 0 = empty).
struct DecodedProbe {
    glm::vec3 position{0.0f};
    int res = 0;
    std::span<const float> ao, confidence;
    int depthRes = 0;
    std::span<const float> distance;
};

// World-space area of the probe texel that sees point x on a surface with unit normal n, or +inf when
// the surface faces away from the probe. Solid angle of a texel at face coordinates (u, v):
// (2/res)² / (1 + u² + v²)^{3/2}; area = solid angle · d² / |cos θ|.
double texelFootprint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int res, float minFacing);

// Whether the probe sees surface point x with normal n (turned to the camera): depth::visible() of
// src/cubeao/cache/depth_cube.h (both halves) with the settings' biases and lift, except
// that an empty texel in x's direction (the probe saw no surface that way) does not count as seeing
// x: its AO texels hold nothing for x either.
bool probeSees(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n, const ProjectSettings& settings);

// texelFootprint() of a probe that sees x (probeSees), +inf when it does not: the area that ranks
// probes, as quality = confidence / area in projectAo and as 1 / area in the candidate grid
// (probe_grid.h), so the grid chooses by what the pass will rank.
double visibleFootprint(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n,
                        const ProjectSettings& settings);
// Surface point x with normal n lifted off its surface by settings.depthOffset coarse texels of a
// depthRes cube, for the depth test's second half (shaders/common/depth_test.h depthLiftedPoint).
glm::vec3 depthLiftedPoint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int depthRes,
                           const ProjectSettings& settings);
// The two distance texels the depth test reads for x: cube::texelIndex(x − probe, depthRes) and
// cube::texelIndex(depthLiftedPoint(...) − probe, depthRes).
struct StoredDistances {
    float atPoint = 0.0f, atLifted = 0.0f;
};
// Those texels read through `distanceAt(texel index)` from a probe at `probe`: the lifted one only with
// a lift (settings.depthOffset > 0), as the shader reads it; one rule for every reader of the cube.
template <class DistanceAt>
StoredDistances storedDistances(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int depthRes,
                                const ProjectSettings& settings, DistanceAt&& distanceAt) {
    StoredDistances s{distanceAt(cube::texelIndex(x - probe, depthRes)), 0.0f};
    if (settings.depthOffset > 0.0f)
        s.atLifted = distanceAt(cube::texelIndex(depthLiftedPoint(probe, x, n, depthRes, settings) - probe, depthRes));
    return s;
}
// The same for a probe at `probe` (faces res², distance cube depthRes²) whose two distance texels for
// x are `stored`, for readers that hold the distance cube in another form (the run-time's stored
// bytes, probe_source.h).
double visibleFootprint(const glm::vec3& probe, StoredDistances stored, int res, int depthRes, const glm::vec3& x,
                        const glm::vec3& n, const ProjectSettings& settings);

struct Projected {
    float ao = 1.0f;
    bool covered = false;  // some candidate saw the point
    int used = 0;          // probes blended: 0, 1 or 2 (3 when three tie for first)
};

// AO at x (normal n) from the candidate probes: depth test, quality, soft best-two blend. All
// candidates share res and depthRes (one cache); std::invalid_argument otherwise.
Projected projectAo(std::span<const DecodedProbe> candidates, const glm::vec3& x, const glm::vec3& n,
                    const ProjectSettings& settings);

// Resolves the zero fields of settings.
ProjectSettings resolveProjectSettings(ProjectSettings s);

}  // namespace cubeao
