#include "solid_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

namespace cubeao::placement {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using TrianglePrimitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, TrianglePrimitive>>;
using Mesh = CGAL::Surface_mesh<Point>;
using SideOfMesh = CGAL::Side_of_triangle_mesh<Mesh, Kernel>;
using Polygon = std::array<std::size_t, 3>;

Point toPoint(const glm::vec3& p) {
    return Point(p.x, p.y, p.z);
}

bool finite(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// Exact position key for merging duplicated vertices. +0 is added so that -0 and +0 merge.
struct PositionKey {
    std::array<std::uint32_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};

PositionKey keyOf(const glm::vec3& p) {
    PositionKey key{};
    for (int i = 0; i < 3; ++i) {
        const float v = p[i] + 0.0f;
        std::memcpy(&key.bits[i], &v, sizeof v);
    }
    return key;
}

struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 0x9E3779B97F4A7C15ull;
        for (std::uint32_t b : k.bits) {
            h ^= b + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        }
        return static_cast<std::size_t>(h);
    }
};

struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// A closed outward component. The Side_of_triangle_mesh keeps a pointer to the mesh, so a Solid lives behind
// a unique_ptr and never moves.
struct Solid {
    Mesh mesh;
    std::optional<SideOfMesh> side;
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
};

}  // namespace

struct SolidGeometry::Impl {
    std::vector<Triangle> triangles;  // all finite scene triangles, for the distance tree
    TriangleTree tree;
    std::vector<std::unique_ptr<Solid>> solids;
    std::size_t rooms = 0;
    std::size_t open = 0;
    std::vector<std::uint32_t> componentOfTriangle;  // per scene triangle; kNoComponent when dropped
    std::size_t componentCount = 0;

    // Uniform grid over the solids' bounding boxes (CSR lists of solid indices per cell): scenes have
    // thousands of solids, and testing every bounding box per query costs far more than the exact test.
    glm::vec3 gridMin{0.0f};
    glm::vec3 gridMax{0.0f};
    glm::vec3 cellsPerUnit{0.0f};
    std::array<int, 3> dims{0, 0, 0};
    std::vector<std::uint32_t> cellStart;   // dims product + 1 entries
    std::vector<std::uint32_t> cellSolids;  // solid indices, grouped by cell

    explicit Impl(const Scene& scene);
    void buildGrid();
    std::array<int, 3> cellOf(const glm::vec3& p) const;
    void classifyComponent(const std::vector<glm::vec3>& merged, const std::vector<std::array<std::uint32_t, 3>>& tris);
};

SolidGeometry::Impl::Impl(const Scene& scene) {
    const std::size_t triangleCount = scene.indices.size() / 3;
    const std::size_t vertexCount = scene.positions.size();

    // Merge vertices by exact position; triangles with an out-of-range index or a non-finite corner are dropped.
    std::vector<std::uint32_t> mergedId(vertexCount, std::numeric_limits<std::uint32_t>::max());
    std::vector<glm::vec3> merged;
    {
        std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> ids;
        ids.reserve(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) {
            const glm::vec3& p = scene.positions[v];
            if (!finite(p)) continue;
            auto [it, inserted] = ids.try_emplace(keyOf(p), static_cast<std::uint32_t>(merged.size()));
            if (inserted) merged.push_back(p + 0.0f);
            mergedId[v] = it->second;
        }
    }

    std::vector<std::array<std::uint32_t, 3>> tris;  // in merged ids, the scene's own winding
    std::vector<std::uint32_t> sceneTriangle;       // the scene triangle of each entry of tris
    tris.reserve(triangleCount);
    triangles.reserve(triangleCount);
    for (std::size_t t = 0; t < triangleCount; ++t) {
        std::array<std::uint32_t, 3> tri{};
        bool valid = true;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t index = scene.indices[3 * t + c];
            if (index >= vertexCount || mergedId[index] == std::numeric_limits<std::uint32_t>::max()) {
                valid = false;
                break;
            }
            tri[c] = mergedId[index];
        }
        if (!valid) continue;
        triangles.emplace_back(toPoint(merged[tri[0]]), toPoint(merged[tri[1]]), toPoint(merged[tri[2]]));
        // Triangles that collapse to an edge or point after merging still matter for distance (kept above)
        // but are no polygons: they would break the soup orientation.
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
        tris.push_back(tri);
        sceneTriangle.push_back(static_cast<std::uint32_t>(t));
    }

    if (!triangles.empty()) {
        tree.insert(triangles.cbegin(), triangles.cend());
        // Both the tree and its distance-query KD-tree are built lazily on the first query otherwise.
        tree.build();
        tree.accelerate_distance_queries();
    }

    // Connected components by shared (merged) vertices.
    UnionFind uf(merged.size());
    for (const auto& tri : tris) {
        uf.unite(tri[0], tri[1]);
        uf.unite(tri[0], tri[2]);
    }
    std::unordered_map<std::uint32_t, std::uint32_t> componentOfRoot;
    std::vector<std::vector<std::array<std::uint32_t, 3>>> components;
    componentOfTriangle.assign(triangleCount, kNoComponent);
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const auto& tri = tris[k];
        const std::uint32_t root = uf.find(tri[0]);
        auto [it, inserted] = componentOfRoot.try_emplace(root, static_cast<std::uint32_t>(components.size()));
        if (inserted) components.emplace_back();
        components[it->second].push_back(tri);
        componentOfTriangle[sceneTriangle[k]] = it->second;
    }
    componentCount = components.size();
    for (const auto& component : components) classifyComponent(merged, component);
    buildGrid();
}

std::array<int, 3> SolidGeometry::Impl::cellOf(const glm::vec3& p) const {
    std::array<int, 3> cell{};
    for (int a = 0; a < 3; ++a) {
        const float f = (p[a] - gridMin[a]) * cellsPerUnit[a];
        cell[a] = std::clamp(static_cast<int>(f), 0, dims[a] - 1);
    }
    return cell;
}

void SolidGeometry::Impl::buildGrid() {
    if (solids.empty()) return;
    gridMin = solids.front()->min;
    gridMax = solids.front()->max;
    for (const auto& solid : solids) {
        gridMin = glm::min(gridMin, solid->min);
        gridMax = glm::max(gridMax, solid->max);
    }
    // About four cells per solid, roughly cubic cells, at most 128 per axis.
    const glm::dvec3 extent = glm::max(glm::dvec3(gridMax) - glm::dvec3(gridMin), glm::dvec3(1e-30));
    const double cellSize = std::cbrt(extent.x * extent.y * extent.z / (4.0 * static_cast<double>(solids.size())));
    std::size_t cellCount = 1;
    for (int a = 0; a < 3; ++a) {
        dims[a] = static_cast<int>(std::clamp(std::ceil(extent[a] / cellSize), 1.0, 128.0));
        cellsPerUnit[a] = static_cast<float>(dims[a] / extent[a]);
        cellCount *= static_cast<std::size_t>(dims[a]);
    }
    auto forEachCell = [&](const Solid& solid, auto&& f) {
        const std::array<int, 3> lo = cellOf(solid.min);
        const std::array<int, 3> hi = cellOf(solid.max);
        for (int z = lo[2]; z <= hi[2]; ++z) {
            for (int y = lo[1]; y <= hi[1]; ++y) {
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    f((static_cast<std::size_t>(z) * dims[1] + y) * dims[0] + x);
                }
            }
        }
    };
    cellStart.assign(cellCount + 1, 0);
    for (const auto& solid : solids) forEachCell(*solid, [&](std::size_t c) { ++cellStart[c + 1]; });
    for (std::size_t c = 0; c < cellCount; ++c) cellStart[c + 1] += cellStart[c];
    cellSolids.resize(cellStart.back());
    std::vector<std::uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
    for (std::size_t i = 0; i < solids.size(); ++i) {
        forEachCell(*solids[i], [&](std::size_t c) { cellSolids[fill[c]++] = static_cast<std::uint32_t>(i); });
    }
}

void SolidGeometry::Impl::classifyComponent(const std::vector<glm::vec3>& merged,
                                            const std::vector<std::array<std::uint32_t, 3>>& tris) {
    // The component's own soup, with local vertex ids.
    std::unordered_map<std::uint32_t, std::size_t> local;
    std::vector<Point> points;
    std::vector<Polygon> polygons;
    polygons.reserve(tris.size());
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{std::numeric_limits<float>::lowest()};
    for (const auto& tri : tris) {
        Polygon polygon{};
        for (int c = 0; c < 3; ++c) {
            auto [it, inserted] = local.try_emplace(tri[c], points.size());
            if (inserted) {
                const glm::vec3& p = merged[tri[c]];
                points.push_back(toPoint(p));
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            polygon[c] = it->second;
        }
        polygons.push_back(polygon);
    }

    // Signed volume with the scene's ORIGINAL winding (orient_polygon_soup may flip polygons below), taken
    // relative to the component's centre so that far-from-origin geometry does not lose precision. For a
    // closed surface the result does not depend on that reference point.
    const glm::dvec3 centre = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
    double volume6 = 0.0;
    for (const auto& tri : tris) {
        const glm::dvec3 a = glm::dvec3(merged[tri[0]]) - centre;
        const glm::dvec3 b = glm::dvec3(merged[tri[1]]) - centre;
        const glm::dvec3 c = glm::dvec3(merged[tri[2]]) - centre;
        volume6 += glm::dot(a, glm::cross(b, c));
    }
    const double volume = volume6 / 6.0;

    // orient_polygon_soup returns false when it had to duplicate points (non-manifold input): such a component
    // is not a clean closed surface, so it counts as open.
    if (!PMP::orient_polygon_soup(points, polygons) || !PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
        ++open;
        return;
    }
    auto solid = std::make_unique<Solid>();
    PMP::polygon_soup_to_polygon_mesh(points, polygons, solid->mesh);
    if (!CGAL::is_closed(solid->mesh)) {
        ++open;
        return;
    }
    // A closed but flat component (a double-sided quad) encloses nothing; the threshold is relative to the
    // component's size so that it does not depend on the scene's units.
    const double diagonal = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
    if (std::abs(volume) <= 1e-6 * diagonal * diagonal * diagonal) {
        ++open;
        return;
    }
    if (volume < 0.0) {
        ++rooms;
        return;
    }
    solid->min = lo;
    solid->max = hi;
    solid->side.emplace(solid->mesh);
    // Side_of_triangle_mesh builds its AABB tree on the first query inside its bounding box; do that now so
    // that later queries only read. The centre of the bounding box is always inside that box.
    (void)(*solid->side)(toPoint(glm::vec3(centre)));
    solids.push_back(std::move(solid));
}

SolidGeometry::SolidGeometry(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}

SolidGeometry::~SolidGeometry() = default;

float SolidGeometry::distance(const glm::vec3& p) const {
    if (impl_->triangles.empty()) return std::numeric_limits<float>::infinity();
    return static_cast<float>(std::sqrt(impl_->tree.squared_distance(toPoint(p))));
}

bool SolidGeometry::insideClosedSolid(const glm::vec3& p) const {
    if (!finite(p)) return false;
    const Impl& impl = *impl_;
    if (impl.solids.empty()) return false;
    if (p.x <= impl.gridMin.x || p.y <= impl.gridMin.y || p.z <= impl.gridMin.z || p.x >= impl.gridMax.x ||
        p.y >= impl.gridMax.y || p.z >= impl.gridMax.z) {
        return false;
    }
    const std::array<int, 3> cell = impl.cellOf(p);
    const std::size_t c = (static_cast<std::size_t>(cell[2]) * impl.dims[1] + cell[1]) * impl.dims[0] + cell[0];
    const Point point = toPoint(p);
    for (std::uint32_t i = impl.cellStart[c]; i < impl.cellStart[c + 1]; ++i) {
        const Solid* solid = impl.solids[impl.cellSolids[i]].get();
        // Strict bounding-box reject: a point on the box is at best on the boundary.
        if (p.x <= solid->min.x || p.y <= solid->min.y || p.z <= solid->min.z || p.x >= solid->max.x ||
            p.y >= solid->max.y || p.z >= solid->max.z) {
            continue;
        }
        if ((*solid->side)(point) == CGAL::ON_BOUNDED_SIDE) return true;
    }
    return false;
}

const std::vector<std::uint32_t>& SolidGeometry::componentOfTriangle() const {
    return impl_->componentOfTriangle;
}

std::size_t SolidGeometry::componentCount() const {
    return impl_->componentCount;
}

std::size_t SolidGeometry::closedSolids() const {
    return impl_->solids.size();
}

std::size_t SolidGeometry::closedRooms() const {
    return impl_->rooms;
}

std::size_t SolidGeometry::openComponents() const {
    return impl_->open;
}

}  // namespace cubeao::placement
