#include <cmath>

#include "cubeao/scenes/builtin_scenes.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao::scenes {

Scene makeSpherePlane() {
    MeshBuilder b;
    // The plane reaches far beyond any test radius so its edge never shows in the answer.
    b.addFloor(-50.0f, -50.0f, 50.0f, 50.0f, 0.0f);
    // 128 × 64 facets: the inscribed polyhedron's solid angle is within 0.1 % of the sphere's.
    b.addSphere({0.0f, kSphereHeight, 0.0f}, kSphereRadius, 128, 64);
    return b.take();
}

CameraPath spherePlanePath() {
    CameraPath p;
    p.scene = "builtin:sphere-plane";
    p.width = 320;
    p.height = 180;
    for (int i = 0; i < 24; ++i) {
        const float a = 0.6f + 0.03f * float(i);  // a slow orbit
        p.frames.push_back({{5.0f * std::cos(a), 1.6f, 5.0f * std::sin(a)}, {0.0f, 0.8f, 0.0f}});
    }
    return p;
}

}  // namespace cubeao::scenes
