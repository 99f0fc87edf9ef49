#include "cubeao/placement/coverage.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "common/coverage.h"
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
