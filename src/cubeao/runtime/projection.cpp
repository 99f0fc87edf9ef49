#include "cubeao/runtime/projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "cubeao/bake/cube.h"
#include "cubeao/cache/depth_cube.h"

namespace cubeao {

ProjectSettings resolveProjectSettings(ProjectSettings s) {
    if (s.depthTolerance == 0.0f) s.depthTolerance = depth::kDepthTolerance;
    if (s.depthSlope == 0.0f) s.depthSlope = depth::kDepthSlope;
    if (s.minFacing == 0.0f) s.minFacing = 0.05f;
    return s;
}

double texelFootprint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n, int res, float minFacing) {
    const glm::vec3 d = x - probe;
    const float distance = glm::length(d);
    if (!(distance > 0.0f)) return std::numeric_limits<double>::infinity();
    const float facing = -glm::dot(n, d) / distance;  // cos θ between the normal and the way to the probe
    if (!(facing > 0.0f)) return std::numeric_limits<double>::infinity();
    const cube::FacePoint fp = cube::faceOf(d);
    const double r2 = 1.0 + double(fp.sc.x) * fp.sc.x + double(fp.sc.y) * fp.sc.y;
    const double texel = 2.0 / double(res);
    const double solidAngle = texel * texel / (r2 * std::sqrt(r2));
    return solidAngle * double(distance) * distance / std::max(facing, minFacing);
}

bool probeSees(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n, const ProjectSettings& settings) {
    const glm::vec3 d = x - probe.position;
    const float stored = probe.distance[cube::texelIndex(d, probe.depthRes)];
    if (!(stored > 0.0f)) return false;  // the probe saw nothing there: x cannot be on a surface it saw
    const float distance = glm::length(d);
    const depth::DepthTest test{settings.depthTolerance, settings.depthSlope, true};
    return depth::visible(test, stored, distance, -glm::dot(n, d) / distance, probe.depthRes);
}

double visibleFootprint(const DecodedProbe& probe, const glm::vec3& x, const glm::vec3& n,
                        const ProjectSettings& settings) {
    if (!probeSees(probe, x, n, settings)) return std::numeric_limits<double>::infinity();
    return texelFootprint(probe.position, x, n, probe.res, settings.minFacing);
}

Projected projectAo(std::span<const DecodedProbe> candidates, const glm::vec3& x, const glm::vec3& n,
                    const ProjectSettings& settings) {
    struct Ranked {
        double quality = 0.0;
        float ao = 1.0f;
    };
    Ranked best[3];  // descending quality
    for (const DecodedProbe& probe : candidates) {
        const double area = visibleFootprint(probe, x, n, settings);
        if (!std::isfinite(area)) continue;
        const std::size_t t = cube::texelIndex(x - probe.position, probe.res);
        const Ranked r{double(probe.confidence[t]) / area, probe.ao[t]};
        if (!(r.quality > 0.0)) continue;
        if (r.quality > best[0].quality) {
            best[2] = best[1], best[1] = best[0], best[0] = r;
        } else if (r.quality > best[1].quality) {
            best[2] = best[1], best[1] = r;
        } else if (r.quality > best[2].quality) {
            best[2] = r;
        }
    }
    Projected out;
    const double w0 = best[0].quality - best[2].quality, w1 = best[1].quality - best[2].quality;
    if (!(best[0].quality > 0.0)) return out;  // uncovered: the caller decides the fallback
    out.covered = true;
    if (!(w0 + w1 > 0.0)) {  // three or more tie for first: their mean is as continuous as any choice
        out.ao = (best[0].ao + best[1].ao + best[2].ao) / 3.0f;
        out.used = 3;
        return out;
    }
    out.ao = float((w0 * best[0].ao + w1 * best[1].ao) / (w0 + w1));
    out.used = (w0 > 0.0) + (w1 > 0.0);
    return out;
}

}  // namespace cubeao
