#include "cubeao/reference/top_down.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

#include "cubeao/reference/embree_scene.h"

namespace cubeao {

glm::vec2 TopDownView::toPixel(const glm::vec3& p) const {
    return {(glm::dot(p, e1) - min1) / pixel, (glm::dot(p, e2) - min2) / pixel};
}

TopDownView renderTopDown(const Scene* scene, std::span<const glm::vec3> probes, std::span<const glm::vec3> walk,
                          float radius, int maxSide) {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    TopDownView td;
    if (scene) td.up = glm::normalize(scene->up);
    td.e1 = std::abs(td.up.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::normalize(glm::cross(glm::vec3(0, 1, 0), td.up));
    td.e2 = glm::normalize(glm::cross(td.e1, td.up));
    float lo1 = std::numeric_limits<float>::max(), hi1 = -lo1, lo2 = lo1, hi2 = -lo1, loH = lo1, hiH = -lo1;
    auto extend = [&](const glm::vec3& p) {
        lo1 = std::min(lo1, glm::dot(p, td.e1)), hi1 = std::max(hi1, glm::dot(p, td.e1));
        lo2 = std::min(lo2, glm::dot(p, td.e2)), hi2 = std::max(hi2, glm::dot(p, td.e2));
        loH = std::min(loH, glm::dot(p, td.up)), hiH = std::max(hiH, glm::dot(p, td.up));
    };
    if (scene)
        for (int c = 0; c < 8; ++c)
            extend({c & 1 ? scene->bounds.max.x : scene->bounds.min.x,
                    c & 2 ? scene->bounds.max.y : scene->bounds.min.y,
                    c & 4 ? scene->bounds.max.z : scene->bounds.min.z});
    if (!probes.empty()) {
        // The view frames the probes with a margin, within the scene: a building in a town model (Sibenik)
        // would otherwise be a few pixels in the middle of the town.
        const float s1 = lo1, t1 = hi1, s2 = lo2, t2 = hi2;
        lo1 = lo2 = std::numeric_limits<float>::max(), hi1 = hi2 = -lo1;
        for (const glm::vec3& p : probes) extend(p);
        for (const glm::vec3& p : walk) extend(p);
        const float margin =
            std::max(std::isfinite(radius) ? 3.0f * radius : 0.0f, 0.3f * std::max(hi1 - lo1, hi2 - lo2));
        lo1 -= margin, hi1 += margin, lo2 -= margin, hi2 += margin;
        if (scene) lo1 = std::max(lo1, s1), hi1 = std::min(hi1, t1), lo2 = std::max(lo2, s2), hi2 = std::min(hi2, t2);
    }
    if (lo1 > hi1) return td;  // neither scene nor points
    const float pad = 0.03f * std::max({hi1 - lo1, hi2 - lo2, 1e-3f});
    lo1 -= pad, hi1 += pad, lo2 -= pad, hi2 += pad;
    td.pixel = std::max(hi1 - lo1, hi2 - lo2) / float(maxSide);
    td.min1 = lo1, td.min2 = lo2;
    td.width = std::max(1, int(std::ceil((hi1 - lo1) / td.pixel)));
    td.height = std::max(1, int(std::ceil((hi2 - lo2) / td.pixel)));
    // The cut: half an AO radius above the highest eye of the walk (what the camera sees from, so galleries
    // and aisles show their floors), or above the highest probe when there is no walk.
    const std::span<const glm::vec3> viewers = walk.empty() ? probes : walk;
    float top = -std::numeric_limits<float>::max();
    for (const glm::vec3& p : viewers) top = std::max(top, glm::dot(p, td.up));
    td.cut = viewers.empty() ? hiH : std::min(hiH, top + (std::isfinite(radius) ? 0.5f * radius : 0.0f));
    td.cutBelowTop = td.cut < hiH - 1e-4f * (hiH - loH);
    td.cut += 1e-4f * (hiH - loH + 1.0f);
    td.rgb.assign(std::size_t(td.width) * td.height * 3, 0.97f);
    std::vector<float>& rgb = td.rgb;
    if (scene) {
        const EmbreeScene embree(*scene);
        std::vector<float> height(std::size_t(td.width) * td.height, kNaN);
        std::vector<float> shade(height.size(), 1.0f);
        const glm::vec3 light = glm::normalize(td.up + 0.6f * td.e1 - 0.4f * td.e2);
        for (int y = 0; y < td.height; ++y)
            for (int x = 0; x < td.width; ++x) {
                const glm::vec3 org = (td.min1 + (float(x) + 0.5f) * td.pixel) * td.e1 +
                                      (td.min2 + (float(y) + 0.5f) * td.pixel) * td.e2 + td.cut * td.up;
                const RayHit h = embree.intersect(org, -td.up, 0.0f, td.cut - loH + 1.0f);
                if (!h.hit) continue;
                const std::size_t i = std::size_t(y) * td.width + x;
                height[i] = td.cut - h.t;
                // Meshes disagree on winding: light either side of a face the same.
                const glm::vec3 n = glm::dot(h.normal, td.up) < 0.0f ? -h.normal : h.normal;
                shade[i] = 0.6f + 0.4f * std::max(0.0f, glm::dot(n, light));
            }
        const float span = std::max(td.cut - loH, 1e-6f);
        const float jump = std::isfinite(radius) ? 0.25f * radius : 0.02f * span;
        for (int y = 0; y < td.height; ++y)
            for (int x = 0; x < td.width; ++x) {
                const std::size_t i = std::size_t(y) * td.width + x;
                if (std::isnan(height[i])) continue;
                const float t = std::clamp((height[i] - loH) / span, 0.0f, 1.0f);
                float v = (0.55f + 0.4f * t) * shade[i];
                for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= td.width || ny >= td.height) continue;
                    const float hn = height[std::size_t(ny) * td.width + nx];
                    if (!std::isnan(hn) && hn - height[i] > jump) v *= 0.55f;  // the foot of something taller
                }
                // A faint warm tint, so the plan does not read as one more AO image.
                rgb[3 * i] = std::min(1.0f, v * 1.02f), rgb[3 * i + 1] = v, rgb[3 * i + 2] = v * 0.94f;
            }
    }
    return td;
}

}  // namespace cubeao
