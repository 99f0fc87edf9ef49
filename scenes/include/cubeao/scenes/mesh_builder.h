// MeshBuilder: the few primitives the procedural scenes are made of. Flat faces get their own
// vertices (hard edges, as in architecture models); curved surfaces share smooth normals.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao::scenes {

class MeshBuilder {
public:
    // Quad a-b-c-d, counter-clockwise seen from the side its normal points to.
    void addQuad(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);
    void addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);
    // Axis-aligned box; `inward` turns the faces to the inside (a room). `bottom` = false leaves out
    // the face that would sit on the floor.
    void addBox(const glm::vec3& min, const glm::vec3& max, bool inward = false, bool bottom = true);
    void addSphere(const glm::vec3& center, float radius, int slices, int stacks);
    // Vertical cylinder (+y), open at both ends unless capped; `rings` subdivides the side.
    void addCylinder(const glm::vec3& baseCenter, float radius, float height, int segments, int rings,
                     bool capTop);
    // Axis-aligned floor rectangle at height y, facing +y.
    void addFloor(float x0, float z0, float x1, float z1, float y);

    std::size_t triangleCount() const { return indices_.size() / 3; }
    // Moves the arrays into a Scene (bounds and hash are set by finalizeScene / prepareScene).
    Scene take();

private:
    std::uint32_t vertex(const glm::vec3& p, const glm::vec3& n);

    std::vector<glm::vec3> positions_, normals_;
    std::vector<std::uint32_t> indices_;
};

}  // namespace cubeao::scenes
