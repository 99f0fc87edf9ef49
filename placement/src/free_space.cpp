#include "cubeao/placement/free_space.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/reference/embree_scene.h"
#include "solid_geometry.h"

namespace cubeao::placement {
namespace {

// kInsideRays directions spread evenly over the sphere (Fibonacci lattice): fixed, so the verdict of
// a point does not depend on a seed.
const std::vector<glm::vec3>& insideDirections() {
    static const std::vector<glm::vec3> directions = [] {
        std::vector<glm::vec3> d;
        const float golden = 2.39996323f;  // π (3 − √5)
        for (int i = 0; i < FreeSpace::kInsideRays; ++i) {
            const float z = 1.0f - (float(i) + 0.5f) * 2.0f / float(FreeSpace::kInsideRays);
            const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = golden * float(i);
            d.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
        }
        return d;
    }();
    return directions;
}

}  // namespace

VoxelGrid VoxelGrid::around(const Bounds& bounds, float voxel, std::size_t targetVoxels) {
    VoxelGrid g;
    const glm::vec3 extent = glm::max(bounds.max - bounds.min, glm::vec3(1e-6f));
    if (!(voxel > 0.0f)) {
        const double volume = double(extent.x) * double(extent.y) * double(extent.z);
        voxel = float(std::cbrt(volume / double(std::max<std::size_t>(targetVoxels, 1))));
        // A flat box (a plane) would get a tiny voxel from its volume: bound the count per axis instead.
        voxel = std::max(voxel, std::max({extent.x, extent.y, extent.z}) / 512.0f);
    }
    g.voxel = voxel;
    g.dims = glm::max(glm::ivec3(glm::ceil(extent / voxel)), glm::ivec3(1));
    g.origin = bounds.center() - 0.5f * glm::vec3(g.dims) * voxel;
    return g;
}

glm::ivec3 VoxelGrid::cell(std::size_t index) const {
    const std::size_t x = index % std::size_t(dims.x), yz = index / std::size_t(dims.x);
    return {int(x), int(yz % std::size_t(dims.y)), int(yz / std::size_t(dims.y))};
}

bool VoxelGrid::contains(const glm::ivec3& c) const {
    return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < dims.x && c.y < dims.y && c.z < dims.z;
}

FreeSpace::FreeSpace(const Scene& scene, const EmbreeScene& embree, float voxel, float clearance)
    : scene_(scene), embree_(embree), solid_(std::make_unique<SolidGeometry>(scene)),
      grid_(VoxelGrid::around(scene.bounds, voxel)), clearance_(clearance > 0.0f ? clearance : 0.5f * grid_.voxel) {
    std::vector<Verdict> verdict(grid_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid_.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) verdict[i] = classify(grid_.center(i));
    });
    candidateOf_.assign(grid_.size(), -1);
    for (std::size_t i = 0; i < grid_.size(); ++i) {
        switch (verdict[i]) {
            case Verdict::Free:
                candidateOf_[i] = std::int32_t(candidates_.size());
                candidates_.push_back(std::uint32_t(i));
                break;
            case Verdict::TooClose: ++stats_.tooClose; break;
            case Verdict::InsideClosed: ++stats_.insideClosed; break;
            case Verdict::InsideByRays: ++stats_.insideByRays; break;
            case Verdict::Outside: ++stats_.outside; break;
        }
    }
    stats_.voxels = grid_.size();
    stats_.candidates = candidates_.size();
    stats_.closedSolids = solid_->closedSolids();
    stats_.closedRooms = solid_->closedRooms();
    stats_.openComponents = solid_->openComponents();
}

FreeSpace::~FreeSpace() = default;

float FreeSpace::distanceToSurface(const glm::vec3& p) const { return solid_->distance(p); }

bool FreeSpace::insideClosedSolid(const glm::vec3& p) const { return solid_->insideClosedSolid(p); }

float FreeSpace::backFaceShare(const glm::vec3& p) const {
    int back = 0;
    for (const glm::vec3& d : insideDirections()) {
        const RayHit h = embree_.intersect(p, d, 0.0f, std::numeric_limits<float>::infinity());
        if (h.hit && glm::dot(h.normal, d) > 0.0f) ++back;
    }
    return float(back) / float(kInsideRays);
}

FreeSpace::Verdict FreeSpace::classify(const glm::vec3& p) const {
    const Bounds& b = scene_.bounds;
    if (glm::any(glm::lessThan(p, b.min)) || glm::any(glm::greaterThan(p, b.max))) return Verdict::Outside;
    if (distanceToSurface(p) < clearance_) return Verdict::TooClose;
    if (insideClosedSolid(p)) return Verdict::InsideClosed;
    if (backFaceShare(p) > 0.25f) return Verdict::InsideByRays;
    return Verdict::Free;
}

}  // namespace cubeao::placement
