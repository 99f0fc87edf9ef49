// Embree view of a Scene: one triangle geometry, built once, queried from many threads.
#pragma once

#include <memory>

#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao {

struct RayHit {
    float t = 0.0f;             // distance along the (unit) direction; valid only when hit
    glm::vec3 normal{0.0f};     // unit geometric normal, as Embree reports it (not flipped)
    unsigned primitive = ~0u;
    bool hit = false;
};

// The ray-origin offset EmbreeScene uses for `s` (the GPU bake offsets its rays the same way).
float surfaceEpsilonFor(const Scene& s);

class EmbreeScene {
public:
    explicit EmbreeScene(const Scene& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Nearest hit in (tnear, tfar); `dir` must be unit length.
    RayHit intersect(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar) const;
    // Whether anything lies in (tnear, tfar) along the ray (cheaper than intersect).
    bool occluded(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar) const;
    // How far to push a ray origin off a surface so it does not hit its own triangle: scaled to the
    // scene (float spacing grows with coordinate magnitude).
    float surfaceEpsilon() const { return epsilon_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    float epsilon_;
};

}  // namespace cubeao
