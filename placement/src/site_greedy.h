// The lazy greedy step both error-driven placements share (placement.h): voting over the whole walk
// and live placement over the walk seen so far (error_feedback.h) ask it for the site whose probe would
// remove the most predicted error, then take it or stop.
//
// A site's gain is known at three prices: from its voxel's votes (an estimate, a few rays per sample,
// no visibility test: cheap), from every sample its rays reach (PlacementScene::seen: a bound from
// above, the depth test only removes samples) and exactly (PlacementScene::served, the depth test too:
// dearest). Each site's views are computed once (visibility never changes, only the error state) and
// its gain is refreshed from the best of them known. An entry of the queue is trusted only when it is
// exact and of this round; an estimate is replaced by the bound, the bound by the exact gain, before a
// site is returned.
#pragma once

#include <cstdint>
#include <optional>
#include <queue>
#include <set>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/placement/placement.h"

namespace cubeao::placement {

// A place a probe may go: a free voxel's centre (`voxel` its candidate number, whose votes estimate
// it) or a point the walk stood on (voxel −1: priced from its bound at once).
struct Site {
    glm::vec3 position;
    std::int64_t voxel;
};

class SiteGreedy {
public:
    // `ps` must outlive this object; it holds the votes and the visibility. Sites at a position an
    // earlier one has are dropped.
    SiteGreedy(const PlacementScene& ps, const std::vector<Site>& sites);

    // Adds a site (after rank(), call rank() again for it to compete); false when one stands there.
    bool addSite(const Site& site);
    // Queues every untaken site by its gain under `error`. Needed before the first next() and whenever
    // the error's weights changed (a frame of the walk added): gains may have risen. Between calls,
    // `error` may only change by probes added (gains only fall: lazy evaluation stays exact).
    void rank(const ExpectedError& error);

    struct Pick {
        std::size_t site;
        double gain;  // exact: the predicted MAE removed
    };
    // The untaken site of largest exact gain, within kSlack of the best bound still queued; none when
    // no site gains anything. Asking again without take() returns the same site.
    std::optional<Pick> next(const ExpectedError& error);
    // A pick at a bounded price, for a frame's time (live placement, error_feedback.h): the `bounded`
    // untaken sites of largest gain as known (exact, else bound, else the votes' estimate) are bounded,
    // the `exact` largest of those bounds priced exactly, and the best exact gain returned; none when
    // none gains. At most bounded + exact sites priced anew; no rank() needed. What was priced stays
    // known, so later calls start from better than votes.
    std::optional<Pick> bestOfFew(const ExpectedError& error, std::size_t bounded, std::size_t exact);
    // Marks `site` taken; the caller adds served(site) to its error.
    void take(std::size_t site);

    const Site& site(std::size_t k) const { return sites_[k]; }
    const std::vector<Site>& sites() const { return sites_; }
    const std::vector<SampleView>& served(std::size_t k);  // exact views, computed once
    std::size_t boundEvaluations() const { return bounds_; }
    std::size_t exactEvaluations() const { return evaluations_; }

    // Neighbouring voxels gain nearly alike and a bound exceeds its exact gain by the ~8 % of samples
    // the depth test removes, so bounds crowd the top: the best exact gain of this round is taken once
    // no bound above it exceeds it by more than kSlack, far inside the model's own miss (~20 %).
    // FZK-Haus's walk at 6 probes: 2,069 depth tests and 86 s without a slack, 1,649 with 2 %, 276 and
    // 13 s with 10 % (predicted MAE 0.00587, 0.00587, 0.00579: greedy is a heuristic).
    static constexpr double kSlack = 0.10;

private:
    struct Entry {
        double gain;
        std::int64_t negativeSite;  // ties go to the lowest site
        std::size_t round;
        bool operator<(const Entry& o) const { return gain != o.gain ? gain < o.gain : negativeSite < o.negativeSite; }
    };
    const std::vector<SampleView>& seen(std::size_t k);
    double gainOf(std::size_t k, const ExpectedError& error);

    const PlacementScene& ps_;
    std::vector<Site> sites_;
    std::set<std::tuple<float, float, float>> positions_;
    std::vector<std::optional<std::vector<SampleView>>> seen_, exact_;
    std::vector<std::uint8_t> taken_;
    std::priority_queue<Entry> queue_;
    std::size_t round_ = 0;
    Entry best_{0.0, 0, 0};  // the largest exact gain of this round
    std::size_t bounds_ = 0, evaluations_ = 0;
};

}  // namespace cubeao::placement
