// SolidGeometry: what CGAL does for placement. Distance from a point to the surface (AABB tree) and an
// exact inside test for closed solids. CGAL stays inside solid_geometry.cpp (pimpl): it is heavy to
// compile and must not leak into the rest of the placement library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao::placement {

// Connectivity is rebuilt by position, not by index: flat faces in our scenes carry their own duplicated
// vertices (hard edges), so a box arrives as six disconnected quads by index.
// Everything is built in the constructor; afterwards all queries are const and safe to call from many
// threads at once.
class SolidGeometry {
public:
    explicit SolidGeometry(const Scene& scene);
    ~SolidGeometry();
    SolidGeometry(const SolidGeometry&) = delete;
    SolidGeometry& operator=(const SolidGeometry&) = delete;

    // Unsigned distance from p to the nearest triangle; +infinity when the scene has no triangles.
    float distance(const glm::vec3& p) const;

    // Whether p lies strictly inside a closed connected component whose triangles, as wound in the scene,
    // face outward (a solid: a closed box, a pillar). Components wound inward (a room modelled as an
    // inward-facing closed box) and open components never count: their inside is free space or unknown.
    // Exact (CGAL::Side_of_triangle_mesh); points on the boundary count as not inside.
    bool insideClosedSolid(const glm::vec3& p) const;

    // The connected component (by shared vertex positions) of every scene triangle, in [0,
    // componentCount()), or kNoComponent for a triangle dropped as degenerate or non-finite. Free space
    // spreads the winding it learns from the faces it sees over the rest of their component.
    static constexpr std::uint32_t kNoComponent = ~0u;
    const std::vector<std::uint32_t>& componentOfTriangle() const;
    std::size_t componentCount() const;

    std::size_t closedSolids() const;     // closed outward components
    std::size_t closedRooms() const;      // closed inward components (ignored by insideClosedSolid)
    std::size_t openComponents() const;   // everything else, including closed but flat (zero-volume) ones

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cubeao::placement
