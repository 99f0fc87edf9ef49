#include "cubeao/bake/bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace cubeao {

namespace {

// ---- build ---------------------------------------------------------------------------------------

struct Box {
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{std::numeric_limits<float>::lowest()};

    void grow(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    // Half the surface area: the SAH only compares areas, so the factor 2 is left out.
    float halfArea() const {
        if (lo.x > hi.x) return 0.0f;
        const glm::vec3 d = hi - lo;
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

// 16 bins per axis: Wald (2007) reports 8–16 bins within a few percent of the full sweep SAH.
constexpr int kBins = 16;
// SAH cost of visiting a node relative to one ray–triangle test, as in pbrt-v4's BVHAggregate (1/2).
constexpr float kTraversalCost = 0.5f;
// From this depth on, splits are object medians instead of SAH: each halves the node, so no leaf ends
// deeper than 32 + log2(2^32) = kBvhMaxDepth and the traversal stack cannot overflow, whatever the
// geometry does to the SAH (e.g. peeling one triangle per level off a fan).
constexpr std::uint32_t kMedianDepth = 32;
static_assert(kMedianDepth + 32 <= kBvhMaxDepth);

struct SahSplit {
    int axis = -1;  // -1: no split with triangles on both sides (all centroids equal)
    int bin = 0;    // triangles in bins < bin go left
    float lo = 0.0f, scale = 0.0f;
    float cost = std::numeric_limits<float>::max();  // Σ count · halfArea over the two children
};

int binOf(float c, float lo, float scale) { return std::clamp(int((c - lo) * scale), 0, kBins - 1); }

class Builder {
public:
    explicit Builder(const Scene& scene) : scene_(scene) {
        const std::size_t n = scene.triangleCount();
        triBox_.resize(n);
        centroid_.resize(n);
        order_.resize(n);
        for (std::size_t t = 0; t < n; ++t) {
            for (int k = 0; k < 3; ++k) triBox_[t].grow(scene.positions[scene.indices[3 * t + k]]);
            centroid_[t] = 0.5f * (triBox_[t].lo + triBox_[t].hi);
            order_[t] = std::uint32_t(t);
        }
    }

    Bvh build() {
        Bvh bvh;
        const auto n = std::uint32_t(order_.size());
        if (n == 0) {
            bvh.nodes.push_back(BvhNode{glm::vec3(0.0f), 0, glm::vec3(0.0f), 0});  // the empty root (bvh.h)
            return bvh;
        }
        bvh.nodes.reserve(2 * std::size_t(n) - 1);
        bvh.nodes.emplace_back();
        struct Task {
            std::uint32_t node, begin, end, depth;
        };
        std::vector<Task> tasks{{0, 0, n, 0}};
        while (!tasks.empty()) {
            const Task task = tasks.back();
            tasks.pop_back();
            Box bounds, centroids;
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                bounds.grow(triBox_[order_[i]]);
                centroids.grow(centroid_[order_[i]]);
            }
            const std::uint32_t mid = split(task.begin, task.end, task.depth, bounds, centroids);
            BvhNode& node = bvh.nodes[task.node];
            node.boundsMin = bounds.lo;
            node.boundsMax = bounds.hi;
            if (mid == task.begin) {  // leaf
                node.leftOrFirst = task.begin;
                node.count = task.end - task.begin;
                continue;
            }
            const auto left = std::uint32_t(bvh.nodes.size());
            node.leftOrFirst = left;
            node.count = 0;
            bvh.nodes.resize(bvh.nodes.size() + 2);
            // Right pushed first so the left subtree is laid out right after its parent's children.
            tasks.push_back({left + 1, mid, task.end, task.depth + 1});
            tasks.push_back({left, task.begin, mid, task.depth + 1});
        }
        bvh.triangles.reserve(n);
        bvh.primitive = order_;
        for (const std::uint32_t t : order_) {
            const glm::vec3 v0 = scene_.positions[scene_.indices[3 * t]];
            const glm::vec3 v1 = scene_.positions[scene_.indices[3 * t + 1]];
            const glm::vec3 v2 = scene_.positions[scene_.indices[3 * t + 2]];
            bvh.triangles.push_back({v0, t, v1 - v0, 0.0f, v2 - v0, 0.0f});
        }
        return bvh;
    }

private:
    // Where to split order_[begin, end): the first index of the right child, or begin for a leaf.
    std::uint32_t split(std::uint32_t begin, std::uint32_t end, std::uint32_t depth, const Box& bounds,
                        const Box& centroids) {
        const std::uint32_t count = end - begin;
        if (count <= 1 || depth >= kBvhMaxDepth) return begin;
        if (depth >= kMedianDepth) return count <= kBvhMaxLeafSize ? begin : medianSplit(begin, end, centroids);
        const SahSplit s = bestSahSplit(begin, end, centroids);
        const float leafCost = float(count) * bounds.halfArea();
        const bool splitPays = s.axis >= 0 && kTraversalCost * bounds.halfArea() + s.cost < leafCost;
        if (count <= kBvhMaxLeafSize && !splitPays) return begin;
        if (s.axis < 0) return medianSplit(begin, end, centroids);  // all centroids equal: middle of the list
        const auto first = order_.begin() + begin;
        const auto mid = std::partition(first, order_.begin() + end, [&](std::uint32_t t) {
            return binOf(centroid_[t][s.axis], s.lo, s.scale) < s.bin;
        });
        return begin + std::uint32_t(mid - first);
    }

    SahSplit bestSahSplit(std::uint32_t begin, std::uint32_t end, const Box& centroids) const {
        SahSplit best;
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
            if (!(extent > 0.0f)) continue;
            const float scale = float(kBins) / extent;
            Box binBox[kBins];
            std::uint32_t binCount[kBins] = {};
            for (std::uint32_t i = begin; i < end; ++i) {
                const std::uint32_t t = order_[i];
                const int b = binOf(centroid_[t][axis], lo, scale);
                ++binCount[b];
                binBox[b].grow(triBox_[t]);
            }
            // Sweep from the left, then from the right: split k puts bins [0, k) left, [k, kBins) right.
            float leftArea[kBins];
            std::uint32_t leftCount[kBins];
            Box acc;
            std::uint32_t n = 0;
            for (int k = 1; k < kBins; ++k) {
                acc.grow(binBox[k - 1]);
                n += binCount[k - 1];
                leftArea[k] = acc.halfArea();
                leftCount[k] = n;
            }
            acc = Box{};
            n = 0;
            for (int k = kBins - 1; k >= 1; --k) {
                acc.grow(binBox[k]);
                n += binCount[k];
                if (leftCount[k] == 0 || n == 0) continue;
                const float cost = float(leftCount[k]) * leftArea[k] + float(n) * acc.halfArea();
                if (cost < best.cost) best = {axis, k, lo, scale, cost};
            }
        }
        return best;
    }

    // Object median along the longest centroid axis; with all centroids equal, just the middle.
    std::uint32_t medianSplit(std::uint32_t begin, std::uint32_t end, const Box& centroids) {
        const glm::vec3 extent = centroids.hi - centroids.lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](std::uint32_t a, std::uint32_t b) { return centroid_[a][axis] < centroid_[b][axis]; });
        return mid;
    }

    const Scene& scene_;
    std::vector<Box> triBox_;
    std::vector<glm::vec3> centroid_;
    std::vector<std::uint32_t> order_;  // BVH order → scene triangle, permuted in place by the build
};

}  // namespace

Bvh buildBvh(const Scene& scene) { return Builder(scene).build(); }

// The traversal is the shared kernel shaders/common/bvh.h (its GLSL compilation is the GPU bake's).
BvhHit bvhIntersect(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    BvhHit hit;
    float t;
    std::uint32_t triangle;
    if (bvh.nodes.empty() ||
        !kernel::bvhTrace({bvh.nodes.data(), bvh.triangles.data()}, org, dir, tnear, tfar, false, t, triangle))
        return hit;
    hit.t = t;
    hit.triangle = bvh.primitive[triangle];
    hit.hit = true;
    return hit;
}

bool bvhOccluded(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    float t;
    std::uint32_t triangle;
    return !bvh.nodes.empty() &&
           kernel::bvhTrace({bvh.nodes.data(), bvh.triangles.data()}, org, dir, tnear, tfar, true, t, triangle);
}

std::uint32_t bvhDepth(const Bvh& bvh) {
    if (bvh.nodes.empty()) return 0;
    std::uint32_t deepest = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{0, 0}};  // node, depth
    while (!stack.empty()) {
        const auto [index, depth] = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[index];
        deepest = std::max(deepest, depth);
        if (node.count == 0 && node.leftOrFirst != 0) {
            stack.push_back({node.leftOrFirst, depth + 1});
            stack.push_back({node.leftOrFirst + 1, depth + 1});
        }
    }
    return deepest;
}

}  // namespace cubeao
