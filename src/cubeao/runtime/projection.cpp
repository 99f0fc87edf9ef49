#include "cubeao/runtime/projection.h"

#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "common/projection.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/cube.h"

namespace cubeao {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

kernel::ProjectionParams kernelParams(const ProjectSettings& s, int res, int depthRes) {
    return {s.depthTolerance, s.depthSlope, s.minFacing, res, depthRes, s.depthOffset};
}

// The probes of projectAo as the shared loop (shaders/common/projection.h) reads them: candidate k is
// probes[k], texels come from the decoded arrays.
struct DecodedReader {
    std::span<const DecodedProbe> probes;

    std::uint32_t projectionCandidate(int k) const { return std::uint32_t(k); }
    // Decoded probes are all at hand: a probe's slot is its index.
    std::uint32_t projectionSlot(std::uint32_t probe) const { return probe; }
    int projectionLevel(std::uint32_t) const { return 0; }  // each at its own res (one cache: the same)
    float projectionQualityScale(std::uint32_t) const { return 1.0f; }
    glm::vec3 projectionProbePosition(std::uint32_t probe) const { return probes[probe].position; }
    float projectionDistance(std::uint32_t probe, std::uint32_t, int face, glm::vec2 sc) const {
        const DecodedProbe& p = probes[probe];
        const glm::ivec2 t = cube::texelOf(sc, p.depthRes);
        return p.distance[cube::texelIndex(face, t.x, t.y, p.depthRes)];
    }
    glm::vec2 projectionAoConfidence(std::uint32_t probe, std::uint32_t, int face, glm::vec2 sc) const {
        const DecodedProbe& p = probes[probe];
        const glm::ivec2 t = cube::texelOf(sc, p.res);
        const std::size_t i = cube::texelIndex(face, t.x, t.y, p.res);
        return {p.ao[i], p.confidence[i]};
    }
};

}  // namespace

ProjectSettings resolveProjectSettings(ProjectSettings s) {
    if (s.depthTolerance == 0.0f) s.depthTolerance = depth::kDepthTolerance;
    if (s.depthSlope == 0.0f) s.depthSlope = depth::kDepthSlope;
    if (s.depthOffset == 0.0f) s.depthOffset = depth::kDepthOffset;
    if (s.minFacing == 0.0f) s.minFacing = 0.05f;
    return s;
}

double texelFootprint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int res, float minFacing) {
    const glm::vec3 d = x - probe;
    const float distance = glm::length(d);
    if (!(distance > 0.0f)) return kInfinity;
    const float facing = -glm::dot(n, d) / distance;  // cos θ between the normal and the way to the probe
    if (!(facing > 0.0f)) return kInfinity;
    return double(kernel::probeTexelArea(cube::faceOf(d).sc, distance, facing, res, minFacing));
}

namespace {

bool probeSeesStored(const glm::vec3& probe, StoredDistances stored, int res, int depthRes, const glm::vec3& x,
                     const glm::vec3& n, const ProjectSettings& settings) {
    const glm::vec3 d = x - probe;
    const float distance = glm::length(d);
    const float liftedDistance =
        settings.depthOffset > 0.0f ? glm::length(depthLiftedPoint(probe, x, n, depthRes, settings) - probe) : 0.0f;
    return kernel::probeSeesPoint(stored.atPoint, distance, -glm::dot(n, d) / distance, stored.atLifted,
                                  liftedDistance, kernelParams(settings, res, depthRes));
}

StoredDistances storedFor(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n,
                          const ProjectSettings& settings) {
    return storedDistances(probe.position, x, n, probe.depthRes, settings,
                           [&](std::size_t texel) { return probe.distance[texel]; });
}

}  // namespace

glm::vec3 depthLiftedPoint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int depthRes,
                           const ProjectSettings& settings) {
    return kernel::depthLiftedPoint(x, n, glm::length(x - probe), settings.depthOffset, depthRes);
}

bool probeSees(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n, const ProjectSettings& settings) {
    return probeSeesStored(probe.position, storedFor(probe, x, n, settings), probe.res, probe.depthRes, x, n, settings);
}

double visibleFootprint(const glm::vec3& probe, StoredDistances stored, int res, int depthRes, const glm::vec3& x,
                        const glm::vec3& n, const ProjectSettings& settings) {
    if (!probeSeesStored(probe, stored, res, depthRes, x, n, settings)) return kInfinity;
    return texelFootprint(probe, x, n, res, settings.minFacing);
}

double visibleFootprint(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n,
                        const ProjectSettings& settings) {
    return visibleFootprint(probe.position, storedFor(probe, x, n, settings), probe.res, probe.depthRes, x, n, settings);
}

Projected projectAo(std::span<const DecodedProbe> candidates, const glm::vec3& x, const glm::vec3& n,
                    const ProjectSettings& settings) {
    if (candidates.empty()) return {};
    const int res = candidates.front().res, depthRes = candidates.front().depthRes;
    for (const DecodedProbe& p : candidates)
        if (p.res != res || p.depthRes != depthRes)
            throw std::invalid_argument("projectAo: candidates of different resolutions (" + std::to_string(p.res) +
                                        "/" + std::to_string(p.depthRes) + " vs " + std::to_string(res) + "/" +
                                        std::to_string(depthRes) + "): the projection reads one cache");
    const kernel::ProjectedAo r = kernel::projectCandidates(DecodedReader{candidates}, int(candidates.size()), x, n,
                                                            kernelParams(settings, res, depthRes));
    return {r.ao, r.used > 0, r.used};
}

}  // namespace cubeao
