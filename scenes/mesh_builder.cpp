#include "cubeao/scenes/mesh_builder.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

namespace cubeao::scenes {

std::uint32_t MeshBuilder::vertex(const glm::vec3& p, const glm::vec3& n) {
    positions_.push_back(p);
    normals_.push_back(n);
    return std::uint32_t(positions_.size() - 1);
}

void MeshBuilder::addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    indices_.insert(indices_.end(), {vertex(a, n), vertex(b, n), vertex(c, n)});
}

void MeshBuilder::addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    const glm::vec3 n = glm::normalize(glm::cross(c - a, d - b));
    const std::uint32_t ia = vertex(a, n), ib = vertex(b, n), ic = vertex(c, n), id = vertex(d, n);
    indices_.insert(indices_.end(), {ia, ib, ic, ia, ic, id});
}

void MeshBuilder::addBox(const glm::vec3& lo, const glm::vec3& hi, bool inward, bool bottom) {
    const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                            {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    // Outward-facing corner order per face: -z, +z, -x, +x, +y, -y.
    const int faces[6][4] = {{1, 0, 3, 2}, {4, 5, 6, 7}, {0, 4, 7, 3}, {5, 1, 2, 6}, {3, 7, 6, 2}, {0, 1, 5, 4}};
    for (int f = 0; f < 6; ++f) {
        if (f == 5 && !bottom) continue;
        const int* q = faces[f];
        if (inward)
            addQuad(c[q[3]], c[q[2]], c[q[1]], c[q[0]]);
        else
            addQuad(c[q[0]], c[q[1]], c[q[2]], c[q[3]]);
    }
}

void MeshBuilder::addSphere(const glm::vec3& center, float r, int slices, int stacks) {
    const auto base = std::uint32_t(positions_.size());
    for (int i = 0; i <= stacks; ++i) {
        const float theta = glm::pi<float>() * float(i) / float(stacks);
        for (int j = 0; j <= slices; ++j) {
            const float phi = glm::two_pi<float>() * float(j) / float(slices);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            vertex(center + r * n, n);
        }
    }
    const auto row = std::uint32_t(slices + 1);
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const std::uint32_t a = base + std::uint32_t(i) * row + std::uint32_t(j), b = a + 1, c = a + row,
                                d = c + 1;
            // Counter-clockwise seen from outside; the triangles at the poles degenerate and are removed on load.
            indices_.insert(indices_.end(), {a, b, d, a, d, c});
        }
}

void MeshBuilder::addCylinder(const glm::vec3& base, float r, float h, int segments, int rings, bool capTop) {
    const auto first = std::uint32_t(positions_.size());
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const float phi = glm::two_pi<float>() * float(j) / float(segments);
            const glm::vec3 n(std::cos(phi), 0.0f, -std::sin(phi));
            vertex(base + glm::vec3(0.0f, h * float(i) / float(rings), 0.0f) + r * n, n);
        }
    const auto row = std::uint32_t(segments + 1);
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const std::uint32_t a = first + std::uint32_t(i) * row + std::uint32_t(j), b = a + 1, c = a + row,
                                d = c + 1;
            indices_.insert(indices_.end(), {a, b, d, a, d, c});
        }
    if (!capTop) return;
    const glm::vec3 top = base + glm::vec3(0.0f, h, 0.0f), up(0.0f, 1.0f, 0.0f);
    const std::uint32_t centre = vertex(top, up);
    for (int j = 0; j < segments; ++j) {
        const float p0 = glm::two_pi<float>() * float(j) / float(segments);
        const float p1 = glm::two_pi<float>() * float(j + 1) / float(segments);
        const std::uint32_t a = vertex(top + r * glm::vec3(std::cos(p0), 0.0f, -std::sin(p0)), up);
        const std::uint32_t b = vertex(top + r * glm::vec3(std::cos(p1), 0.0f, -std::sin(p1)), up);
        indices_.insert(indices_.end(), {centre, a, b});
    }
}

void MeshBuilder::addFloor(float x0, float z0, float x1, float z1, float y) {
    addQuad({x0, y, z1}, {x1, y, z1}, {x1, y, z0}, {x0, y, z0});
}

Scene MeshBuilder::take() {
    Scene s;
    s.positions = std::move(positions_);
    s.normals = std::move(normals_);
    s.indices = std::move(indices_);
    finalizeScene(s);
    return s;
}

}  // namespace cubeao::scenes
