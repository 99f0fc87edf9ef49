// Validation and repair of imported meshes. Validation lists every problem it finds at once
// (sokol style) and throws; repair fixes what is harmless to fix and counts it in SceneProblems.
#pragma once

#include "cubeao/scene/scene.h"

namespace cubeao {

// Throws cubeao::Error naming scene.source when the mesh is unusable: no triangles, an index count
// that is not a multiple of three, indices out of range, NaN/Inf coordinates, normals of the wrong count.
void validateMesh(const Scene& scene);

// Merges vertices identical in position and normal, removes zero-area triangles and unused vertices,
// and makes every normal unit length (computing area-weighted normals when `hasNormals` is false or a
// file normal is unusable). Finishes with finalizeScene(). Counts go to scene.problems.
void repairMesh(Scene& scene, bool hasNormals);

// validateMesh, then repairMesh, then validateMesh again (repair can leave nothing, e.g. a file of
// degenerate triangles only, which must be an error too).
void prepareScene(Scene& scene, bool hasNormals);

// Edges shared by exactly two triangles (vertices compared by position, so corner normals do not split
// an edge), and how many of them both triangles run in the same direction: a face whose winding is
// flipped against its neighbour. Rendering and AO use two-sided geometric normals and do not care;
// placement's inside test (free_space.h: rays that meet the back of a face) does, so `info` and `place`
// report it. Not part of load: it sorts every edge (O(n log n), about 24 bytes a triangle).
struct WindingCheck {
    std::size_t sharedEdges = 0;
    std::size_t flippedEdges = 0;
    double flippedShare() const { return sharedEdges ? double(flippedEdges) / double(sharedEdges) : 0.0; }
};
WindingCheck checkWinding(const Scene& scene);

}  // namespace cubeao
