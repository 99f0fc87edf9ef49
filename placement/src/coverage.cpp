#include "cubeao/placement/coverage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "common/coverage.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/cube.h"
#include "cubeao/core/sampling.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/projection.h"
#include "cubeao/scene/scene.h"

namespace cubeao::placement {

kernel::CoverageParams CoverageCriterion::kernelParams() const {
    return {maxArea(), maxDistance(), minFacing, res};
}

float CoverageCriterion::footprint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n) const {
    return float(texelFootprint(probe, x, n, res, minFacing));
}

std::vector<float> imageShare(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                              std::span<const PinholeCamera> cameras, float nearPlane, float farPlane) {
    const float eps = embree.surfaceEpsilon();
    std::vector<float> share(samples.size(), 0.0f);
    if (cameras.empty()) return share;
    const float aspect = float(cameras.front().width) / float(cameras.front().height);
    // The image plane at distance 1 spans (2 tan(fov/2))² · aspect: the frame's solid angle, near enough
    // for a near-horizontal field of view.
    const float frameSolidAngle = 4.0f * cameras.front().tanHalfFovY * cameras.front().tanHalfFovY * aspect;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const SurfaceSample& s = samples[i];
            double sum = 0.0;
            for (const PinholeCamera& cam : cameras) {
                const glm::vec3 d = s.position - cam.eye;
                const float z = glm::dot(d, cam.forward), distance = glm::length(d);
                if (!(z > nearPlane) || distance > farPlane || !(glm::dot(s.normal, d) < 0.0f)) continue;
                const float h = z * cam.tanHalfFovY;
                if (std::abs(glm::dot(d, cam.up)) > h || std::abs(glm::dot(d, cam.right)) > h * aspect) continue;
                const glm::vec3 origin = s.position + s.normal * eps;
                const glm::vec3 toEye = cam.eye - origin;
                const float length = glm::length(toEye);
                if (embree.occluded(origin, toEye / length, 0.0f, length)) continue;
                // Solid angle on the image plane (z² / distance³ · cos): what the sample's pixels are.
                const float cosine = -glm::dot(s.normal, d) / distance;
                sum += double(s.area * cosine / (distance * distance)) * double(z / distance);
            }
            // A sample seen at all is relevant even where its share rounds to 0 (a grazing view).
            if (sum > 0.0) share[i] = std::max(float(sum / double(cameras.size()) / frameSolidAngle), 1e-30f);
        }
    });
    return share;
}

std::vector<float> imageShareFromCamera(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                        const CameraPath& path, std::size_t maxFrames) {
    std::vector<PinholeCamera> cameras;
    const std::size_t frames = path.frames.size();
    const std::size_t used = std::min(frames, std::max<std::size_t>(maxFrames, 1));
    for (std::size_t k = 0; k < used; ++k) cameras.emplace_back(path, k * frames / used, path.width, path.height);
    return imageShare(embree, samples, cameras, path.nearPlane, path.farPlane);
}

std::vector<std::uint8_t> relevantFromCamera(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                             const CameraPath& path, std::size_t maxFrames) {
    const std::vector<float> share = imageShareFromCamera(embree, samples, path, maxFrames);
    std::vector<std::uint8_t> relevant(share.size());
    for (std::size_t i = 0; i < share.size(); ++i) relevant[i] = share[i] > 0.0f ? 1 : 0;
    return relevant;
}

namespace {

// The distance the bake stores in coarse texel `key` (cube::texelIndex at depthRes) of a probe at
// `probe`: the nearest hit of its fine texels' centre rays (depth::Filter::Min), 0 when all miss.
float storedDistance(const EmbreeScene& embree, const glm::vec3& probe, std::size_t key, int res, int depthRes) {
    const auto face = int(key / (std::size_t(depthRes) * std::size_t(depthRes)));
    const auto rest = int(key % (std::size_t(depthRes) * std::size_t(depthRes)));
    const int I = rest % depthRes, J = rest / depthRes;
    float nearest = 0.0f;
    for (int j = J * res / depthRes; j < (J + 1) * res / depthRes; ++j)
        for (int i = I * res / depthRes; i < (I + 1) * res / depthRes; ++i) {
            const glm::vec3 d = glm::normalize(cube::texelDirection(face, i, j, res));
            const RayHit h = embree.intersect(probe, d, 0.0f, std::numeric_limits<float>::infinity());
            if (h.hit && (nearest == 0.0f || h.t < nearest)) nearest = h.t;
        }
    return nearest;
}

}  // namespace

std::vector<SampleView> visibleSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                       std::span<const std::uint8_t> relevant, const CoverageCriterion& criterion,
                                       const glm::vec3& probe) {
    std::vector<float> area(samples.size(), INFINITY);
    const float eps = embree.surfaceEpsilon();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!relevant[i]) continue;
            const SurfaceSample& s = samples[i];
            const float a = criterion.footprint(probe, s.position, s.normal);
            if (!(a < INFINITY)) continue;
            const glm::vec3 origin = s.position + s.normal * eps;
            const glm::vec3 toProbe = probe - origin;
            const float length = glm::length(toProbe);
            if (length > 0.0f && !embree.occluded(origin, toProbe / length, 0.0f, length)) area[i] = a;
        }
    });
    std::vector<SampleView> seen;
    for (std::size_t i = 0; i < area.size(); ++i)
        if (area[i] < INFINITY) seen.push_back({std::uint32_t(i), area[i]});
    return seen;
}

std::vector<SampleView> servedSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                      const CoverageCriterion& criterion, const glm::vec3& probe,
                                      std::span<const SampleView> seen, std::span<const float> occlusion) {
    const int depthRes = depth::depthResFor(criterion.res);
    auto tested = [&](std::size_t k) { return occlusion.empty() || occlusion[seen[k].sample] > 0.0f; };
    std::vector<std::size_t> texelOf(seen.size()), texels;
    for (std::size_t k = 0; k < seen.size(); ++k)
        if (tested(k)) texels.push_back(texelOf[k] = cube::texelIndex(samples[seen[k].sample].position - probe, depthRes));
    std::sort(texels.begin(), texels.end());
    texels.erase(std::unique(texels.begin(), texels.end()), texels.end());
    std::vector<float> stored(texels.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, texels.size(), 16), [&](const auto& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k)
            stored[k] = storedDistance(embree, probe, texels[k], criterion.res, depthRes);
    });
    std::vector<SampleView> served;
    for (std::size_t k = 0; k < seen.size(); ++k) {
        if (!tested(k)) {
            served.push_back(seen[k]);
            continue;
        }
        const SurfaceSample& s = samples[seen[k].sample];
        const glm::vec3 d = s.position - probe;
        const float distance = glm::length(d);
        const auto t = std::size_t(std::lower_bound(texels.begin(), texels.end(), texelOf[k]) - texels.begin());
        if (depth::visible(depth::DepthTest{}, stored[t], distance, -glm::dot(s.normal, d) / distance, depthRes))
            served.push_back(seen[k]);
    }
    return served;
}

bool probeMayCover(const CoverageCriterion& criterion, const glm::vec3& probe, const SurfaceSample& s) {
    return kernel::probeMayCoverPoint(probe, s.position, s.normal, criterion.kernelParams());
}

bool probeCovers(const EmbreeScene& embree, const CoverageCriterion& criterion, const glm::vec3& probe,
                 const SurfaceSample& s) {
    if (!probeMayCover(criterion, probe, s)) return false;
    const glm::vec3 origin = s.position + s.normal * embree.surfaceEpsilon();
    const glm::vec3 toProbe = probe - origin;
    const float length = glm::length(toProbe);
    return !embree.occluded(origin, toProbe / length, 0.0f, length);
}

std::vector<std::uint32_t> coveredSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                          std::span<const std::uint8_t> relevant, const CoverageCriterion& criterion,
                                          const glm::vec3& probe) {
    std::vector<std::uint8_t> hit(samples.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
            if (relevant[i] && probeCovers(embree, criterion, probe, samples[i])) hit[i] = 1;
    });
    std::vector<std::uint32_t> covered;
    for (std::size_t i = 0; i < hit.size(); ++i)
        if (hit[i]) covered.push_back(std::uint32_t(i));
    return covered;
}

CoverageCounts::CoverageCounts(std::span<const SurfaceSample> samples, std::span<const std::uint8_t> relevant)
    : samples_(samples), counts_(samples.size(), 0) {
    for (std::size_t i = 0; i < samples.size(); ++i)
        if (relevant[i]) relevantArea_ += samples[i].area;
}

void CoverageCounts::add(std::span<const std::uint32_t> covered) {
    for (const std::uint32_t i : covered) {
        const std::uint32_t c = counts_[i]++;
        if (c == 0) once_ += samples_[i].area;
        if (c == 1) twice_ += samples_[i].area;
    }
}

void CoverageCounts::remove(std::span<const std::uint32_t> covered) {
    for (const std::uint32_t i : covered) {
        const std::uint32_t c = --counts_[i];
        if (c == 0) once_ -= samples_[i].area;
        if (c == 1) twice_ -= samples_[i].area;
    }
}

double CoverageCounts::coverage() const { return relevantArea_ > 0.0 ? std::min(1.0, once_ / relevantArea_) : 1.0; }
double CoverageCounts::coverage2() const { return relevantArea_ > 0.0 ? std::min(1.0, twice_ / relevantArea_) : 1.0; }

double CoverageCounts::gain(std::span<const std::uint32_t> covered) const {
    double g = 0.0;
    for (const std::uint32_t i : covered)
        if (counts_[i] == 0) g += samples_[i].area;
    return g;
}

double CoverageCounts::gain2(std::span<const std::uint32_t> covered) const {
    double g = 0.0;
    for (const std::uint32_t i : covered)
        if (counts_[i] == 1) g += samples_[i].area;
    return g;
}

}  // namespace cubeao::placement
