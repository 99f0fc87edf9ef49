#include "cubeao/bake/horizon.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "cubeao/reference/sampling.h"

namespace cubeao {
namespace {

constexpr float kPi = 3.14159265358979323846f;

// Bisection steps for the height field's top above a march point: its height to R/32 at most.
constexpr int kBisections = 4;

// What the probe knows about point y (see horizon.h), judged from the texel at (p, n).
enum class Seen { Open, Solid, Unknown };

// One G-buffer lookup in the direction of y: the surface q the probe sees there, as evidence about y.
struct Lookup {
    Seen seen = Seen::Open;
    bool occluder = false;  // q lies within R of p and above its tangent plane
    bool hidden = false;    // GTAO's confidence rule (horizon.h)
    glm::vec3 v{0.0f};      // q − p
    float distance = 0.0f;  // |q − p|
};

Lookup look(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const glm::vec3& y, float radius) {
    Lookup m;
    const glm::vec3 d = y - g.probe;
    const cube::FacePoint fp = cube::faceOf(d);
    const glm::ivec2 t = cube::texelOf(fp.sc, g.res);
    const glm::vec4 texel = g.texels[cube::texelIndex(fp.face, t.x, t.y, g.res)];
    if (CubeGBuffer::empty(texel)) return m;  // the probe sees sky that way: open, and known
    const glm::vec3 q = g.probe + glm::normalize(cube::faceDirection(fp.face, cube::texelCentre(t.x, t.y, g.res))) * texel.w;
    m.v = q - p;
    m.distance = glm::length(m.v);
    const float dy = glm::length(d);
    // q above p's tangent plane by more than float rounding can fake: q and p are world positions
    // computed from the probe, so their error grows with the coordinates. (On a plane q comes out
    // ±1 ulp off it; with a strict > 0, GTAO took such q for occluders, and as a texel centre lies off
    // the slice its angle to the view is not the plane's: AO 0.81 on an open plane.)
    const bool above = glm::dot(m.v, n) > 1e-5f * (glm::length(g.probe) + dy);
    // 1e-4 R: q is p's own texel; its offset from p is sub-texel noise, not an occluder.
    m.occluder = above && m.distance <= radius && m.distance > 1e-4f * radius;
    // Two texel footprints of slack: the texel centre seen in y's direction is not y itself.
    const bool behind = texel.w < dy - dy * 4.0f / float(g.res);
    // A surface at or below the tangent plane hides only more of the half-space below it (the probe
    // is above the plane), where nothing occludes p: y is as good as open.
    m.hidden = behind && above && m.distance > radius;
    // y is inside or behind q; q belongs to p's surroundings when it lies within R of p or of y.
    const glm::vec3 w = q - y;
    if (behind && above) m.seen = m.distance <= radius || glm::dot(w, w) <= radius * radius ? Seen::Solid : Seen::Unknown;
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
    int doubtful = 0;
    std::uint32_t fetches = 0;
    const float cosWedge = std::cos(kPi / float(s.directions));
    for (int k = 0; k < s.directions; ++k) {
        const float phi = 2.0f * kPi * (float(k) + jitter.azimuth) / float(s.directions);
        const glm::vec3 dir = std::cos(phi) * t1 + std::sin(phi) * t2;
        float sin2 = 0.0f, tanH = 0.0f, slice = 0.0f;  // running horizon and falloff-weighted sum of rises
        const auto raise = [&](float e2, float distance) {
            if (!(e2 > sin2)) return;
            slice += (e2 - sin2) * occlusionWeight(s.ao.falloff, distance, radius);
            sin2 = e2;
            tanH = std::sqrt(e2 / std::max(1.0f - e2, 1e-12f));
        };
        // Every surface point the probe shows us within R, above the plane and inside this slice's
        // wedge of azimuths is an occluder of the slice in its own right (at small R, where texels
        // are coarse, it is most of the evidence). Outside the wedge it belongs to another slice.
        const auto seen = [&](const glm::vec3& y) {
            ++fetches;
            const Lookup m = look(g, p, n, y, radius);
            const glm::vec3 level = m.v - n * glm::dot(m.v, n);
            if (m.occluder && glm::dot(level, dir) >= cosWedge * glm::length(level)) {
                const float e = glm::dot(m.v, n) / m.distance;
                raise(e * e, m.distance);
            }
            return m.seen;
        };
        for (int step = 0; step < s.steps; ++step) {
            const float r = stepDistance(step, s.steps, jitter.step, radius);
            const glm::vec3 x = p + dir * r;
            const float top = std::sqrt(std::max(0.0f, radius * radius - r * r));  // the R-ball above x
            float lo = r * tanH;  // height of the current horizon above x: only more can raise it
            if (lo >= top) continue;
            const Seen atLo = seen(x + n * lo);
            if (atLo != Seen::Solid) {
                // Free at the horizon but solid above it: an overhang, which no height field describes.
                doubtful += atLo == Seen::Unknown || seen(x + n * top) == Seen::Solid ? 1 : 0;
                continue;
            }
            float hi = top;
            if (seen(x + n * top) != Seen::Solid) {
                for (int i = 0; i < kBisections; ++i) {
                    const float mid = 0.5f * (lo + hi);
                    (seen(x + n * mid) == Seen::Solid ? lo : hi) = mid;
                }
                hi = 0.5f * (lo + hi);
            }
            raise(hi * hi / (r * r + hi * hi), std::sqrt(r * r + hi * hi));  // the height field's top
        }
        obscurance += slice;  // = max sin² h without a falloff (Oswald eq. 4.3)
    }
    return {1.0f - obscurance / float(s.directions), 1.0f - float(doubtful) / float(s.directions * s.steps), fetches};
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
                const Lookup m = look(g, p, n, x, radius);
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
    return {ao, 1.0f - float(hidden) / float(s.directions * s.steps), std::uint32_t(s.directions * s.steps)};
}

}  // namespace cubeao
