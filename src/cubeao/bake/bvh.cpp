#include "cubeao/bake/bvh.h"

#include <algorithm>
#include <bit>
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
            bvh.triangles.push_back({glm::vec4(v0, std::bit_cast<float>(t)), glm::vec4(v1 - v0, 0.0f),
                                     glm::vec4(v2 - v0, 0.0f)});
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

// ---- traversal: the C++ twin of shaders/common/bvh.glsl; keep the two in step --------------------

// "Missed the box": the largest finite float rather than infinity, which GLSL does not promise.
constexpr float kMiss = std::numeric_limits<float>::max();
// Direction components smaller than this are replaced by ±kTinyDir before inversion: 1/0 = ∞ would
// turn (bound − org) · ∞ into NaN when the origin lies on a slab plane. 1/1e-20 = 1e20 keeps every
// slab distance finite for coordinates below 1e18 and still acts as "parallel to the slab".
constexpr float kTinyDir = 1e-20f;
// Robust slab test (Ize, "Robust BVH Ray Traversal", JCGT 2013; pbrt-v4 §6.8.2): the exit distance,
// rounded in three float operations, is pushed out by 1 + 2γ₃ ≈ 1 + 3.6e-7 so rounding never makes
// a ray miss a box that contains its hit. The literal rounds to 1 + 3·2⁻²³ as float.
constexpr float kSlabGrow = 1.00000036f;

glm::vec3 safeInverse(const glm::vec3& d) {
    glm::vec3 r;
    for (int k = 0; k < 3; ++k) {
        const float tiny = d[k] >= 0.0f ? kTinyDir : -kTinyDir;
        r[k] = 1.0f / (std::abs(d[k]) > kTinyDir ? d[k] : tiny);
    }
    return r;
}

// Entry distance of the ray into the node's box within [tnear, tfar], or kMiss.
// std::min/max pick the same operand as GLSL's min/max (the first unless the second is smaller/larger).
float slabEntry(const BvhNode& node, const glm::vec3& org, const glm::vec3& invDir, float tnear, float tfar) {
    const glm::vec3 t0 = (node.boundsMin - org) * invDir, t1 = (node.boundsMax - org) * invDir;
    const glm::vec3 tlo = glm::min(t0, t1), thi = glm::max(t0, t1);
    const float tEnter = std::max(std::max(tlo.x, tlo.y), std::max(tlo.z, tnear));
    const float tExit = std::min(std::min(std::min(thi.x, thi.y), thi.z) * kSlabGrow, tfar);
    return tEnter <= tExit ? tEnter : kMiss;
}

// Möller & Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 1997, without the
// backface cull (AO is occluded by either side). det == 0: the ray lies in the triangle's plane.
bool triangleHit(const BvhTriangle& tri, const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar,
                 float& t) {
    const glm::vec3 e1(tri.e1), e2(tri.e2);
    const glm::vec3 p = glm::cross(dir, e2);
    const float det = glm::dot(e1, p);
    if (det == 0.0f) return false;
    const float invDet = 1.0f / det;
    const glm::vec3 s = org - glm::vec3(tri.v0);
    const float u = glm::dot(s, p) * invDet;
    if (u < 0.0f || u > 1.0f) return false;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(dir, q) * invDet;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = glm::dot(e2, q) * invDet;
    return t > tnear && t < tfar;
}

// Stack traversal, nearer child first, the farther one pushed if the ray enters it before the
// current closest hit (J. Bikker, "How to build a BVH", part 2, 2022). Returns the BVH-order index.
template <bool kAnyHit>
bool traverse(const Bvh& bvh, const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar, float& t,
              std::uint32_t& triangle) {
    t = tfar;
    triangle = ~0u;
    if (bvh.nodes.empty() || (bvh.nodes[0].count == 0 && bvh.nodes[0].leftOrFirst == 0)) return false;
    const glm::vec3 invDir = safeInverse(dir);
    if (slabEntry(bvh.nodes[0], org, invDir, tnear, t) == kMiss) return false;
    std::uint32_t stack[kBvhMaxDepth];
    std::uint32_t sp = 0, index = 0;
    for (;;) {
        const BvhNode& node = bvh.nodes[index];
        if (node.count > 0) {
            for (std::uint32_t i = node.leftOrFirst; i < node.leftOrFirst + node.count; ++i) {
                float ti;
                if (triangleHit(bvh.triangles[i], org, dir, tnear, t, ti)) {
                    t = ti;
                    triangle = i;
                    if constexpr (kAnyHit) return true;
                }
            }
            if (sp == 0) break;
            index = stack[--sp];
            continue;
        }
        std::uint32_t nearChild = node.leftOrFirst, farChild = nearChild + 1;
        float dNear = slabEntry(bvh.nodes[nearChild], org, invDir, tnear, t);
        float dFar = slabEntry(bvh.nodes[farChild], org, invDir, tnear, t);
        if (dFar < dNear) {
            std::swap(nearChild, farChild);
            std::swap(dNear, dFar);
        }
        if (dNear == kMiss) {
            if (sp == 0) break;
            index = stack[--sp];
            continue;
        }
        index = nearChild;
        if (dFar != kMiss) stack[sp++] = farChild;
    }
    return triangle != ~0u;
}

}  // namespace

Bvh buildBvh(const Scene& scene) { return Builder(scene).build(); }

BvhHit bvhIntersect(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    BvhHit hit;
    float t;
    std::uint32_t triangle;
    if (!traverse<false>(bvh, org, dir, tnear, tfar, t, triangle)) return hit;
    hit.t = t;
    hit.triangle = bvh.primitive[triangle];
    hit.hit = true;
    return hit;
}

bool bvhOccluded(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    float t;
    std::uint32_t triangle;
    return traverse<true>(bvh, org, dir, tnear, tfar, t, triangle);
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
