#include "cubeao/runtime/probe_ranking.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "common/projection.h"
#include "common/runtime_layout.h"

namespace cubeao {

std::vector<ProbeId> ProbeRanking::wanted(const CameraView& view, const ProbeGrid& grid, const ProbeSet& probes,
                                          const ResidencyPlanner& residency) {
    const glm::mat4 worldFromView = view.worldFromView();
    const glm::vec3 eye(worldFromView[3]);
    if (haveEye_) motion_ = 0.5f * motion_ + 0.5f * (eye - lastEye_);
    lastEye_ = eye, haveEye_ = true;
    const glm::vec3 ahead = eye + motion_ * lookahead_;
    if (residency.resident() == probes.liveCount()) return {};  // nothing left to load
    const std::size_t n = probes.size();
    const float inf = std::numeric_limits<float>::infinity();
    score_.assign(n, inf);
    std::vector<ProbeId> listed;
    const auto list = [&](std::uint32_t id, float s) {
        if (score_[id] == inf) listed.push_back(ProbeId{id});
        score_[id] = std::min(score_[id], s);
    };
    const bool roomForAll = residency.slots() >= probes.liveCount();
    if (roomForAll) {
        for (std::uint32_t id = 0; id < n; ++id)
            if (probes.isLive(ProbeId{id})) list(id, glm::length(probes.position(ProbeId{id}) - eye));
    } else {
        const glm::ivec3 dims = grid.dims();
        const float cell = grid.cellSize();
        const glm::ivec3 centre = kernel::candidateCellOf(eye, grid.origin(), cell, dims);
        const int maxRadius = std::max({dims.x, dims.y, dims.z});
        // The view frustum widened by a cell's half-diagonal: what the camera can see of a cell.
        const float tanY = view.tanHalfFovY, tanX = view.tanHalfFovY * view.aspect(), margin = 0.87f * cell;
        const auto visible = [&](const glm::vec3& at) {
            const glm::vec3 v(view.viewFromWorld * glm::vec4(at, 1.0f));
            const float depth = -v.z;
            if (depth < -margin) return false;
            const float d = std::max(depth, 0.0f);
            return std::fabs(v.x) <= d * tanX + margin * (1.0f + tanX) && std::fabs(v.y) <= d * tanY + margin * (1.0f + tanY);
        };
        for (int r = 1;; r *= 2) {
            const glm::ivec3 lo = glm::max(centre - r, glm::ivec3(0)), hi = glm::min(centre + r, dims - 1);
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) {
                        const std::size_t c = grid.cellIndex({x, y, z});
                        const glm::vec3 at = grid.cellCentre(c);
                        // Cells in view by their distance; around the eye (a turn of the head away)
                        // and where the eye is heading at a premium.
                        float s = glm::length(at - eye);
                        if (!visible(at)) s = s < 2.0f * cell ? s * 2.0f : s * 4.0f;
                        s = std::min(s, 1.25f * glm::length(at - ahead));
                        // A pixel blends two candidates: the first ones of a farther cell before the
                        // last ones of a near cell.
                        int k = 0;
                        for (std::uint32_t id : grid.cellCandidates(c)) list(id, s * (1.0f + float(k++)));
                    }
            if (listed.size() >= residency.slots() || r >= maxRadius) break;
        }
    }
    // What the pixels asked for comes first, by how many asked; the rest by place.
    if (!roomForAll)
        for (std::uint32_t id = 0; id < n; ++id)
            if (residency.demand(ProbeId{id}) > 0 && score_[id] == inf) listed.push_back(ProbeId{id});
    std::sort(listed.begin(), listed.end(), [&](ProbeId a, ProbeId b) {
        const std::uint32_t da = residency.demand(a), db = residency.demand(b);
        if (da != db) return da > db;
        return score_[index(a)] != score_[index(b)] ? score_[index(a)] < score_[index(b)] : a < b;
    });
    return listed;
}

}  // namespace cubeao
