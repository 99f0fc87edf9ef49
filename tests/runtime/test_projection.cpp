// The projection's per-point math (src/cubeao/runtime/projection.h) on synthetic probes with known
// answers: texel footprint, depth test, the soft best-two blend, and continuity when probes swap rank.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "cubeao/core/cube.h"
#include "cubeao/runtime/projection.h"

namespace {

using namespace cubeao;

// A probe whose every texel has the same AO, confidence and distance.
struct SyntheticProbe {
    std::vector<float> ao, confidence, distance;
    DecodedProbe view;

    SyntheticProbe(glm::vec3 position, int res, float aoValue, float conf, int depthRes, float dist)
        : ao(std::size_t(6 * res * res), aoValue), confidence(ao.size(), conf),
          distance(std::size_t(6 * depthRes * depthRes), dist) {
        view = {position, res, ao, confidence, depthRes, distance};
    }
};

TEST(ProjectionFootprint, IsTheTexelsSolidAngleTimesDistanceSquaredOverCosine) {
    const int res = 64;
    const double texel = 2.0 / res;
    // Straight ahead of face −Z, surface facing the probe: (2/res)² d².
    EXPECT_NEAR(texelFootprint({0, 0, 0}, {0, 0, -3}, {0, 0, 1}, res, 0.05f), texel * texel * 9.0, 1e-12);
    // Tilted by 60°: twice the area.
    const glm::vec3 n60(0.0f, std::sin(glm::radians(60.0f)), std::cos(glm::radians(60.0f)));
    EXPECT_NEAR(texelFootprint({0, 0, 0}, {0, 0, -3}, n60, res, 0.05f), 2.0 * texel * texel * 9.0, 1e-6 * 2.0 * texel * texel * 9.0);  // float cos 60°
    // Towards a face corner (u = v = 1) a texel subtends 1/3^{3/2} of the centre's solid angle; at
    // the same distance and facing the area shrinks by the same factor.
    const glm::vec3 corner = glm::normalize(glm::vec3(1.0f, -1.0f, -1.0f)) * 3.0f;
    const double ratio = texelFootprint({0, 0, 0}, corner * 0.999f, -glm::normalize(corner), res, 0.05f) /
                         texelFootprint({0, 0, 0}, {0, 0, -2.997f}, {0, 0, 1}, res, 0.05f);
    EXPECT_NEAR(ratio, 1.0 / std::pow(3.0, 1.5), 1e-4);
    // Facing away: the probe sees the back of the surface; unusable.
    EXPECT_TRUE(std::isinf(texelFootprint({0, 0, 0}, {0, 0, -3}, {0, 0, -1}, res, 0.05f)));
    // Grazing (cos θ = 0.01): clamped by minFacing, not near infinite.
    const glm::vec3 grazing = glm::normalize(glm::vec3(0.0f, 1.0f, 0.01f));
    EXPECT_NEAR(texelFootprint({0, 0, 0}, {0, 0, -3}, grazing, res, 0.05f), texel * texel * 9.0 / 0.05, 1e-6);
}

TEST(ProjectionDepthTest, SeesUpToTheStoredDistanceWithSlack) {
    ProjectSettings s;
    s.depthTolerance = 0.01f;
    s.depthSlope = 1e-9f;  // no slope term: facing the probe squarely it would be 0 anyway
    s = resolveProjectSettings(s);
    const glm::vec3 facing(-1.0f, 0.0f, 0.0f);  // a wall facing the probe at the origin
    const SyntheticProbe probe({0, 0, 0}, 8, 0.5f, 1.0f, 4, 5.0f);
    EXPECT_TRUE(probeSees(probe.view, {4.0f, 1.0f, 0.0f}, facing, s));
    EXPECT_TRUE(probeSees(probe.view, {5.04f, 0.0f, 0.0f}, facing, s));
    EXPECT_FALSE(probeSees(probe.view, {5.06f, 0.0f, 0.0f}, facing, s));
    EXPECT_FALSE(probeSees(probe.view, {4.0f, 0.0f, 0.0f}, -facing, s)) << "its back faces the probe";
    const SyntheticProbe empty({0, 0, 0}, 8, 0.5f, 1.0f, 4, 0.0f);
    EXPECT_FALSE(probeSees(empty.view, {1.0f, 0.0f, 0.0f}, facing, s)) << "an empty texel saw no surface";
}

TEST(ProjectionBlend, BestTwoBlendByQualityAndUncoveredIsReported) {
    const ProjectSettings s = resolveProjectSettings({});
    const glm::vec3 x(0.0f, 0.0f, 0.0f), n(0.0f, 1.0f, 0.0f);
    // Two probes straight above at heights 1 and 2: areas in ratio 1 : 4, qualities 4 : 1, no third.
    const SyntheticProbe nearProbe({0, 1, 0}, 32, 0.2f, 1.0f, 16, 10.0f), farProbe({0, 2, 0}, 32, 0.8f, 1.0f, 16, 10.0f);
    const DecodedProbe both[] = {nearProbe.view, farProbe.view};
    const Projected p = projectAo(both, x, n, s);
    EXPECT_TRUE(p.covered);
    EXPECT_EQ(p.used, 2);
    EXPECT_NEAR(p.ao, (4.0f * 0.2f + 1.0f * 0.8f) / 5.0f, 1e-5f);
    // Confidence scales quality: a near probe that doubts its texels yields to the far one.
    const SyntheticProbe doubtful({0, 1, 0}, 32, 0.2f, 0.1f, 16, 10.0f);
    const DecodedProbe mixed[] = {doubtful.view, farProbe.view};
    EXPECT_NEAR(projectAo(mixed, x, n, s).ao, (0.4f * 0.2f + 1.0f * 0.8f) / 1.4f, 1e-5f);
    // The near probe's depth says something stands between it and x (distance 0.5 < 1): not used.
    const SyntheticProbe blocked({0, 1, 0}, 32, 0.2f, 1.0f, 16, 0.5f);
    const DecodedProbe hidden[] = {blocked.view, farProbe.view};
    const Projected h = projectAo(hidden, x, n, s);
    EXPECT_EQ(h.used, 1);
    EXPECT_NEAR(h.ao, 0.8f, 1e-6f);
    // Nobody sees x: uncovered, AO left open for the caller's fallback.
    const DecodedProbe none[] = {blocked.view};
    const Projected u = projectAo(none, x, n, s);
    EXPECT_FALSE(u.covered);
    EXPECT_EQ(u.ao, 1.0f);
}

// Walking along a floor under three probes whose AO differs, the ranking changes twice; the soft
// weights keep the projected AO continuous. The hard best-one choice of the thesis jumps by the full
// AO difference there, which this test would catch.
TEST(ProjectionBlend, ContinuousWhenProbesSwapRank) {
    const ProjectSettings s = resolveProjectSettings({});
    const SyntheticProbe a({-2, 1.5f, 0}, 64, 0.2f, 1.0f, 16, 100.0f), b({0, 1.5f, 0}, 64, 0.9f, 1.0f, 16, 100.0f),
        c({2, 1.5f, 0}, 64, 0.5f, 1.0f, 16, 100.0f);
    const DecodedProbe probes[] = {a.view, b.view, c.view};
    float previous = projectAo(probes, {-3.0f, 0.0f, 0.3f}, {0, 1, 0}, s).ao, largestStep = 0.0f;
    const int steps = 2000;
    for (int i = 1; i <= steps; ++i) {
        const glm::vec3 x(-3.0f + 6.0f * float(i) / float(steps), 0.0f, 0.3f);
        const float ao = projectAo(probes, x, {0, 1, 0}, s).ao;
        largestStep = std::max(largestStep, std::fabs(ao - previous));
        previous = ao;
    }
    // 3 mm steps; the AO values differ by up to 0.7, so a hard switch would jump by ≥ 0.3. Smooth
    // variation over metres changes by ~0.003 per step; texel-centre quantisation of the footprint
    // adds little. Bound: 0.01.
    EXPECT_LT(largestStep, 0.01f);
}

// The shared kernel (shaders/common/projection.h) reads every candidate at one res and depthRes, as
// the GPU pass reads one cache; probes of two caches are refused rather than read at the wrong texel.
TEST(ProjectionBlend, CandidatesMustShareOneResolution) {
    const ProjectSettings s = resolveProjectSettings({});
    const SyntheticProbe a({0, 1, 0}, 32, 0.2f, 1.0f, 16, 10.0f), b({0, 2, 0}, 16, 0.8f, 1.0f, 16, 10.0f),
        c({0, 2, 0}, 32, 0.8f, 1.0f, 8, 10.0f);
    const DecodedProbe resMismatch[] = {a.view, b.view}, depthMismatch[] = {a.view, c.view};
    EXPECT_THROW(projectAo(resMismatch, {0, 0, 0}, {0, 1, 0}, s), std::invalid_argument);
    EXPECT_THROW(projectAo(depthMismatch, {0, 0, 0}, {0, 1, 0}, s), std::invalid_argument);
    EXPECT_FALSE(projectAo({}, {0, 0, 0}, {0, 1, 0}, s).covered);
}

}  // namespace
