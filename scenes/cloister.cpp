// builtin:cloister — a small cloister, the default demo scene. All sizes in metres, +y up.
//
// The garth (open courtyard, with a fountain) is the square |x|, |z| < kGarth. Each of the four sides
// is built in a local frame (u along the arcade, v outwards from the garth, y up) and rotated into
// place, so one function describes all four walks: plinths and columns at every pier, a low
// stylobate wall between them (one bay left open as the entrance), round arches with spandrel walls
// above, a lean-to roof whose hips meet on the diagonals, and the outer wall with pilasters.
#include <cmath>

#include <glm/common.hpp>
#include <glm/gtc/constants.hpp>

#include "cubeao/scenes/builtin_scenes.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao::scenes {
namespace {

constexpr float kGarth = 8.0f;        // half size of the garth, to the arcade's axis
constexpr float kBay = 2.0f;          // pier spacing
constexpr int kBays = 8;              // bays per side (2 · kGarth / kBay)
constexpr float kWalk = 3.5f;         // from the arcade axis to the outer wall's inner face
constexpr float kSpring = 2.45f;      // arches spring from the capitals
constexpr float kWallTop = 3.8f;      // top of the spandrel wall
constexpr float kArcadeHalf = 0.25f;  // half thickness of the arcade wall
constexpr int kArchSegments = 32;

// Maps the local frame of side k (quarter turns about +y: a proper rotation, so winding is kept).
struct Side {
    int k;
    glm::vec3 operator()(float u, float y, float v) const {
        float x = u, z = -kGarth - v;
        for (int i = 0; i < k; ++i) {
            const float t = x;
            x = z;
            z = -t;
        }
        return {x, y, z};
    }
};

void addLocalBox(MeshBuilder& b, const Side& s, float u0, float u1, float y0, float y1, float v0, float v1) {
    const glm::vec3 p0 = s(u0, y0, v0), p1 = s(u1, y1, v1);
    b.addBox(glm::min(p0, p1), glm::max(p0, p1), false, y0 > 0.0f);
}

void addColumn(MeshBuilder& b, const Side& s, float u) {
    addLocalBox(b, s, u - 0.3f, u + 0.3f, 0.0f, 0.45f, -0.3f, 0.3f);        // plinth
    b.addCylinder(s(u, 0.45f, 0.0f), 0.18f, 1.8f, kArchSegments, 8, false);  // shaft
    addLocalBox(b, s, u - 0.28f, u + 0.28f, 2.25f, kSpring, -0.28f, 0.28f);  // capital
}

// One bay's spandrel wall: two faces with a semicircular opening, the soffit under the arch, and the
// solid pieces over the piers.
void addArchBay(MeshBuilder& b, const Side& s, float u0, float u1) {
    const float p = kArcadeHalf, r = 0.5f * (u1 - u0) - p, mid = 0.5f * (u0 + u1);
    auto arc = [&](int i, float v) {
        const float a = glm::pi<float>() * (1.0f - float(i) / float(kArchSegments));
        return s(mid + r * std::cos(a), kSpring + r * std::sin(a), v);
    };
    const float vf = -kArcadeHalf, vb = kArcadeHalf;  // garth side, walk side
    for (int i = 0; i < kArchSegments; ++i) {
        const float ua = mid + r * std::cos(glm::pi<float>() * (1.0f - float(i) / kArchSegments));
        const float ub = mid + r * std::cos(glm::pi<float>() * (1.0f - float(i + 1) / kArchSegments));
        b.addQuad(arc(i, vf), arc(i + 1, vf), s(ub, kWallTop, vf), s(ua, kWallTop, vf));
        b.addQuad(arc(i + 1, vb), arc(i, vb), s(ua, kWallTop, vb), s(ub, kWallTop, vb));
        b.addQuad(arc(i, vb), arc(i + 1, vb), arc(i + 1, vf), arc(i, vf));  // soffit, facing the opening
    }
    for (float e : {u0, u1 - p}) {  // over the piers
        addLocalBox(b, s, e, e + p, kSpring, kWallTop, vf, vb);
    }
}

void addSide(MeshBuilder& b, int k) {
    const Side s{k};
    for (int i = 0; i < kBays; ++i) {
        const float u0 = -kGarth + kBay * float(i), u1 = u0 + kBay;
        addColumn(b, s, u0);
        if (i != kBays / 2 - 1) addLocalBox(b, s, u0, u1, 0.0f, 0.45f, -0.2f, 0.2f);  // stylobate; one bay open
        addArchBay(b, s, u0, u1);
        // Pilaster on the outer wall opposite the pier.
        addLocalBox(b, s, u0 - 0.2f, u0 + 0.2f, 0.0f, 4.2f, kWalk - 0.2f, kWalk);
    }
    // Outer wall and the lean-to roof (hips on the diagonals u = ±(kGarth + v)).
    const float vOut = kWalk + 0.5f, vIn = -0.4f, yOut = 5.2f, yIn = 3.55f;
    addLocalBox(b, s, -kGarth - vOut, kGarth + vOut, 0.0f, 6.0f, kWalk, vOut);
    b.addQuad(s(-kGarth - vIn, yIn, vIn), s(kGarth + vIn, yIn, vIn), s(kGarth + vOut, yOut, vOut),
              s(-kGarth - vOut, yOut, vOut));
}

}  // namespace

Scene makeCloister() {
    MeshBuilder b;
    const float e = kGarth + kWalk + 0.5f;
    b.addFloor(-e, -e, e, e, 0.0f);
    for (int k = 0; k < 4; ++k) addSide(b, k);
    // Fountain: a drum, a pillar and a ball.
    b.addCylinder({0.0f, 0.0f, 0.0f}, 1.5f, 0.5f, 64, 2, true);
    b.addCylinder({0.0f, 0.5f, 0.0f}, 0.2f, 0.9f, 32, 4, false);
    b.addSphere({0.0f, 1.7f, 0.0f}, 0.35f, 64, 32);
    return b.take();
}

// Along the south walk (z ≈ −9.75), glancing into the garth through the arcade, then turning the corner.
CameraPath cloisterPath() {
    CameraPath p;
    p.scene = "builtin:cloister";
    p.width = 640;
    p.height = 360;
    p.fovYDeg = 60.0f;
    const float zWalk = -kGarth - 0.5f * kWalk;
    constexpr int kStraight = 36, kTurn = 12;
    for (int i = 0; i < kStraight; ++i) {
        const float x = -7.0f + 16.0f * float(i) / float(kStraight - 1);
        p.frames.push_back({{x, 1.6f, zWalk}, {x + 10.0f, 1.3f, zWalk + 3.0f}});
    }
    for (int i = 1; i <= kTurn; ++i) {
        const float t = float(i) / float(kTurn);
        const float a = 0.29f + t * (glm::half_pi<float>() - 0.29f);  // heading, from +x (with glance) to +z
        const glm::vec3 eye{9.0f + 0.75f * t, 1.6f, zWalk + 0.5f * t};
        p.frames.push_back({eye, eye + glm::vec3(10.0f * std::cos(a), -0.3f, 10.0f * std::sin(a))});
    }
    return p;
}

}  // namespace cubeao::scenes
