#include "cubeao/placement/free_space.h"

#include <algorithm>
#include <atomic>
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

FreeSpace::FreeSpace(const Scene& scene, const EmbreeScene& embree, float voxel, float clearance,
                     std::span<const glm::vec3> seeds)
    : scene_(scene), embree_(embree), solid_(std::make_unique<SolidGeometry>(scene)),
      grid_(VoxelGrid::around(scene.bounds, voxel)), clearance_(clearance > 0.0f ? clearance : 0.5f * grid_.voxel) {
    const Bounds& b = scene_.bounds;
    std::vector<Verdict> verdict(grid_.size(), Verdict::Free);
    std::vector<std::uint8_t> clear(grid_.size(), 0);
    std::vector<float> depth(grid_.size(), 0.0f);  // distance to the nearest surface, for clear voxels
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid_.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const glm::vec3 p = grid_.center(i);
            if (glm::any(glm::lessThan(p, b.min)) || glm::any(glm::greaterThan(p, b.max))) {
                verdict[i] = Verdict::Outside;
                continue;
            }
            depth[i] = distanceToSurface(p);
            if (depth[i] < clearance_)
                verdict[i] = Verdict::TooClose;
            else
                clear[i] = 1;
        }
    });
    const std::vector<std::uint16_t> open = openSides(clear);
    std::vector<std::size_t> starts = seedVoxels(clear, open, seeds);
    // A sealed model without a walk (no seed, nothing open to the outside): its roomiest clear voxel
    // that sidedness calls free is taken as known free, or, where sidedness calls none of the roomiest
    // free (a model wound inside out), the roomiest of all: a building's largest empty volume is a
    // room, while a solid core the rooms wrap (sidedness: inside) is passed over.
    if (starts.empty()) {
        std::vector<std::size_t> roomy;
        for (std::size_t i = 0; i < grid_.size(); ++i)
            if (clear[i]) roomy.push_back(i);
        // Deepest first; at worst every clear voxel is tested, as sidedness alone would test them all.
        std::sort(roomy.begin(), roomy.end(),
                  [&](std::size_t a, std::size_t b) { return depth[a] > depth[b] || (depth[a] == depth[b] && a < b); });
        std::size_t chosen = roomy.empty() ? grid_.size() : roomy[0];
        for (std::size_t k = 0; k < roomy.size(); ++k) {
            const glm::vec3 p = grid_.center(roomy[k]);
            if (!insideClosedSolid(p) && backFaceShare(p) <= 0.25f) {
                chosen = roomy[k];
                break;
            }
        }
        if (chosen < grid_.size()) starts.push_back(chosen), stats_.roomiestSeed = true;
    }
    spread(open, starts);
    decideUnreached(clear, verdict);
    candidateOf_.assign(grid_.size(), -1);
    for (std::size_t i = 0; i < grid_.size(); ++i) {
        switch (verdict[i]) {
            case Verdict::Free:
                candidateOf_[i] = std::int32_t(candidates_.size());
                candidates_.push_back(std::uint32_t(i));
                if (reached_[i]) ++stats_.reached;
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

std::vector<std::uint16_t> FreeSpace::openSides(const std::vector<std::uint8_t>& clear) const {
    // Bit a: the segment from voxel i's centre to its +a neighbour's is clear of geometry (both voxels
    // clear); bit 3 + a / 6 + a: voxel i is on the box's −a / +a side and its segment out of the box,
    // one voxel long, is clear (the outside reaches it).
    std::vector<std::uint16_t> open(grid_.size(), 0);
    const float v = grid_.voxel;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid_.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!clear[i]) continue;
            const glm::ivec3 c = grid_.cell(i);
            const glm::vec3 p = grid_.center(c);
            std::uint16_t bits = 0;
            for (int a = 0; a < 3; ++a) {
                glm::vec3 e(0.0f);
                e[a] = 1.0f;
                glm::ivec3 n = c;
                ++n[a];
                if (grid_.contains(n) && clear[grid_.index(n)] && !embree_.occluded(p, e, 0.0f, v))
                    bits |= std::uint16_t(1u << a);
                if (c[a] == 0 && !embree_.occluded(p, -e, 0.0f, v)) bits |= std::uint16_t(1u << (3 + a));
                if (c[a] == grid_.dims[a] - 1 && !embree_.occluded(p, e, 0.0f, v)) bits |= std::uint16_t(1u << (6 + a));
            }
            open[i] = bits;
        }
    });
    return open;
}

std::vector<std::size_t> FreeSpace::seedVoxels(const std::vector<std::uint8_t>& clear,
                                               const std::vector<std::uint16_t>& open,
                                               std::span<const glm::vec3> seeds) {
    std::vector<std::size_t> starts;
    for (std::size_t i = 0; i < grid_.size(); ++i)
        if (open[i] >> 3) ++stats_.outsideSeeds, starts.push_back(i);
    // A seed point takes the nearest clear voxel centre among the 27 around it that it sees.
    const float v = grid_.voxel;
    for (const glm::vec3& s : seeds) {
        const glm::ivec3 home = glm::ivec3(glm::floor((s - grid_.origin) / v));
        std::size_t best = grid_.size();
        float bestDistance = std::numeric_limits<float>::infinity();
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::ivec3 c = home + glm::ivec3(dx, dy, dz);
                    if (!grid_.contains(c) || !clear[grid_.index(c)]) continue;
                    const glm::vec3 to = grid_.center(c) - s;
                    const float d = glm::length(to);
                    if (d < bestDistance && (d == 0.0f || !embree_.occluded(s, to / d, 0.0f, d)))
                        best = grid_.index(c), bestDistance = d;
                }
        if (best == grid_.size()) {
            ++stats_.seedsNotFree;
            continue;
        }
        ++stats_.seeds;
        starts.push_back(best);
    }
    return starts;
}

void FreeSpace::spread(const std::vector<std::uint16_t>& open, const std::vector<std::size_t>& starts) {
    reached_.assign(grid_.size(), 0);
    std::vector<std::size_t> queue;
    auto push = [&](std::size_t i) {
        if (!reached_[i]) reached_[i] = 1, queue.push_back(i);
    };
    for (const std::size_t i : starts) push(i);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t i = queue[head];
        const glm::ivec3 c = grid_.cell(i);
        for (int a = 0; a < 3; ++a) {
            glm::ivec3 up = c, down = c;
            ++up[a];
            --down[a];
            if (open[i] & (1u << a)) push(grid_.index(up));
            if (grid_.contains(down)) {
                const std::size_t j = grid_.index(down);
                if (open[j] & (1u << a)) push(j);
            }
        }
    }
}

void FreeSpace::decideUnreached(const std::vector<std::uint8_t>& clear, std::vector<Verdict>& verdict) {
    // The tie-break for clear voxels nobody reached, with the winding reached space has seen.
    std::vector<std::size_t> unreached;
    for (std::size_t i = 0; i < grid_.size(); ++i) {
        if (!clear[i]) continue;
        if (reached_[i])
            verdict[i] = Verdict::Free;
        else
            unreached.push_back(i);
    }
    if (!unreached.empty()) learnWinding();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, unreached.size(), 16), [&](const auto& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
            const glm::vec3 p = grid_.center(unreached[k]);
            verdict[unreached[k]] = insideClosedSolid(p)          ? Verdict::InsideClosed
                                    : backFaceShare(p) > 0.25f ? Verdict::InsideByRays
                                                               : Verdict::Free;
        }
    });
}

void FreeSpace::learnWinding() {
    // Every reached voxel casts the inside-test rays; a face hit from the side its normal points to
    // counts front, else back. A face seen mostly from behind is reversed; a face nobody saw takes the
    // majority of its connected component's seen faces (a wall box seen from outside tells its inner side).
    const std::size_t triangles = scene_.triangleCount();
    std::vector<std::atomic<std::uint32_t>> front(triangles), back(triangles);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid_.size(), 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!reached_[i]) continue;
            const glm::vec3 p = grid_.center(i);
            for (const glm::vec3& d : insideDirections()) {
                const RayHit h = embree_.intersect(p, d, 0.0f, std::numeric_limits<float>::infinity());
                if (!h.hit || h.primitive >= triangles) continue;
                (glm::dot(h.normal, d) > 0.0f ? back : front)[h.primitive].fetch_add(1, std::memory_order_relaxed);
            }
        }
    });
    const std::vector<std::uint32_t>& component = solid_->componentOfTriangle();
    std::vector<std::int64_t> componentVote(solid_->componentCount(), 0);  // Σ (back − front) of its faces
    for (std::size_t t = 0; t < triangles; ++t)
        if (component[t] != SolidGeometry::kNoComponent)
            componentVote[component[t]] += std::int64_t(back[t].load()) - std::int64_t(front[t].load());
    reversed_.assign(triangles, 0);
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t f = front[t].load(), k = back[t].load();
        const bool seen = f + k > 0;
        reversed_[t] = seen ? k > f : component[t] != SolidGeometry::kNoComponent && componentVote[component[t]] > 0;
        stats_.reversedFaces += reversed_[t];
    }
}

bool FreeSpace::backHit(const glm::vec3& dir, const glm::vec3& normal, unsigned primitive) const {
    const bool back = glm::dot(normal, dir) > 0.0f;
    return primitive < reversed_.size() && reversed_[primitive] ? !back : back;
}

float FreeSpace::distanceToSurface(const glm::vec3& p) const { return solid_->distance(p); }

bool FreeSpace::insideClosedSolid(const glm::vec3& p) const { return solid_->insideClosedSolid(p); }

float FreeSpace::backFaceShare(const glm::vec3& p) const {
    int back = 0;
    for (const glm::vec3& d : insideDirections()) {
        const RayHit h = embree_.intersect(p, d, 0.0f, std::numeric_limits<float>::infinity());
        if (h.hit && backHit(d, h.normal, h.primitive)) ++back;
    }
    return float(back) / float(kInsideRays);
}

FreeSpace::Verdict FreeSpace::classify(const glm::vec3& p) const {
    const Bounds& b = scene_.bounds;
    if (glm::any(glm::lessThan(p, b.min)) || glm::any(glm::greaterThan(p, b.max))) return Verdict::Outside;
    if (distanceToSurface(p) < clearance_) return Verdict::TooClose;
    const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((p - grid_.origin) / grid_.voxel)), glm::ivec3(0), grid_.dims - 1);
    if (reached_[grid_.index(c)]) {
        const glm::vec3 to = grid_.center(c) - p;
        const float d = glm::length(to);
        if (d == 0.0f || !embree_.occluded(p, to / d, 0.0f, d)) return Verdict::Free;
    }
    if (insideClosedSolid(p)) return Verdict::InsideClosed;
    if (backFaceShare(p) > 0.25f) return Verdict::InsideByRays;
    return Verdict::Free;
}

}  // namespace cubeao::placement
