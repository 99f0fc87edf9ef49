#include "cubeao/bake/horizon.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "cubeao/reference/sampling.h"

namespace cubeao {
namespace {

constexpr float kPi = 3.14159265358979323846f;

// What the probe sees in the direction of march point x, judged from the texel at (p, n).
struct MarchSample {
    bool occluder = false;  // a surface within R of p and above its tangent plane
    bool hidden = false;    // see horizon.h
    glm::vec3 v{0.0f};      // q − p
    float distance = 0.0f;  // |q − p|
};

MarchSample marchSample(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const glm::vec3& x,
                        float radius) {
    MarchSample m;
    const glm::vec3 d = x - g.probe;
    const cube::FacePoint fp = cube::faceOf(d);
    const glm::ivec2 t = cube::texelOf(fp.sc, g.res);
    const glm::vec4 texel = g.texels[cube::texelIndex(fp.face, t.x, t.y, g.res)];
    if (CubeGBuffer::empty(texel)) return m;  // the probe sees sky that way: open, and known
    const glm::vec3 q = g.probe + glm::normalize(cube::faceDirection(fp.face, cube::texelCentre(t.x, t.y, g.res))) * texel.w;
    m.v = q - p;
    m.distance = glm::length(m.v);
    const float dx = glm::length(d);
    // q above p's tangent plane by more than float rounding can fake: q and p are world positions
    // computed from the probe, so their error grows with the coordinates. (On a plane q comes out
    // ±1 ulp off it; with a strict > 0, GTAO took such q for occluders, and as a texel centre lies off
    // the slice its angle to the view is not the plane's: AO 0.81 on an open plane, fixed here.)
    const bool above = glm::dot(m.v, n) > 1e-5f * (glm::length(g.probe) + dx);
    // 1e-4 R: q is p's own texel; its offset from p is sub-texel noise, not an occluder.
    m.occluder = above && m.distance <= radius && m.distance > 1e-4f * radius;
    // Two texel footprints of slack: the texel centre seen in x's direction is not x itself.
    const float slack = dx * 4.0f / float(g.res);
    // Only a surface above the tangent plane can hide an occluder: the probe is above that plane
    // (it sees p from the side n points to), so behind a q at or below it lies only more of the
    // half-space below, where nothing occludes p.
    m.hidden = texel.w < dx - slack && above && m.distance > radius;
    return m;
}

float stepDistance(int step, int steps, float jitter, float radius) {
    return radius * (float(step) + jitter) / float(steps);
}

}  // namespace

HorizonJitter horizonJitter(std::uint32_t key) {
    return {sampling::toUnitFloat(sampling::hash32(key)), sampling::toUnitFloat(sampling::hash32(key ^ 0x68e31da4u))};
}

HorizonEstimate horizonSplitAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                               std::uint32_t key) {
    const HorizonJitter jitter = horizonJitter(key);
    const float radius = s.ao.radius;
    glm::vec3 t1, t2;
    sampling::basis(n, t1, t2);
    float obscurance = 0.0f;
    int hidden = 0;
    for (int k = 0; k < s.directions; ++k) {
        const float phi = 2.0f * kPi * (float(k) + jitter.azimuth) / float(s.directions);
        const glm::vec3 dir = std::cos(phi) * t1 + std::sin(phi) * t2;
        float sin2 = 0.0f, slice = 0.0f;  // running sin² h and its falloff-weighted sum of rises
        for (int step = 0; step < s.steps; ++step) {
            const MarchSample m = marchSample(g, p, n, p + dir * stepDistance(step, s.steps, jitter.step, radius), radius);
            hidden += m.hidden ? 1 : 0;
            if (!m.occluder) continue;
            const float e = glm::dot(m.v, n) / m.distance, e2 = e * e;
            if (e2 > sin2) {
                slice += (e2 - sin2) * occlusionWeight(s.ao.falloff, m.distance, radius);
                sin2 = e2;
            }
        }
        obscurance += slice;  // = max sin² h without a falloff (Oswald eq. 4.3)
    }
    return {1.0f - obscurance / float(s.directions), 1.0f - float(hidden) / float(s.directions * s.steps)};
}

HorizonEstimate gtaoAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                       std::uint32_t key) {
    const HorizonJitter jitter = horizonJitter(key);
    const float radius = s.ao.radius;
    const glm::vec3 view = glm::normalize(g.probe - p);
    glm::vec3 a1, a2;
    sampling::basis(view, a1, a2);
    const int slices = s.directions / 2;
    float visibility = 0.0f;
    int hidden = 0;
    for (int k = 0; k < slices; ++k) {
        const float phi = kPi * (float(k) + jitter.azimuth) / float(slices);
        const glm::vec3 dir = std::cos(phi) * a1 + std::sin(phi) * a2;  // ⟂ view: the slice's "screen" direction
        const glm::vec3 axis = glm::cross(dir, view);
        const glm::vec3 projected = n - axis * glm::dot(n, axis);
        const float projectedLength = glm::length(projected);
        if (!(projectedLength > 1e-6f)) continue;  // normal ⟂ slice plane: the slice carries no weight
        const float cosN = std::clamp(glm::dot(projected, view) / projectedLength, -1.0f, 1.0f);
        const float angleN = (glm::dot(projected, dir) >= 0.0f ? 1.0f : -1.0f) * std::acos(cosN);
        float arcs = 0.0f;
        for (int side = -1; side <= 1; side += 2) {
            const float low = std::cos(angleN + float(side) * 0.5f * kPi);  // horizon at the tangent plane
            float horizonCos = low;
            for (int step = 0; step < s.steps; ++step) {
                const glm::vec3 x = p + float(side) * dir * stepDistance(step, s.steps, jitter.step, radius);
                const MarchSample m = marchSample(g, p, n, x, radius);
                hidden += m.hidden ? 1 : 0;
                if (!m.occluder) continue;
                const float c = glm::dot(m.v, view) / m.distance;
                const float w = occlusionWeight(s.ao.falloff, m.distance, radius);
                horizonCos = std::max(horizonCos, low + (c - low) * w);
            }
            // Horizon angle from the view vector, clamped to the hemisphere around n (paper 002 §4).
            float h = float(side) * std::acos(std::clamp(horizonCos, -1.0f, 1.0f));
            h = angleN + std::clamp(h - angleN, -0.5f * kPi, 0.5f * kPi);
            arcs += (cosN + 2.0f * h * std::sin(angleN) - std::cos(2.0f * h - angleN)) * 0.25f;  // eq. 10
        }
        visibility += projectedLength * arcs;
    }
    const float ao = std::clamp(visibility / float(slices), 0.0f, 1.0f);
    return {ao, 1.0f - float(hidden) / float(s.directions * s.steps)};
}

}  // namespace cubeao
