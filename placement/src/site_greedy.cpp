// The lazy greedy step of error-driven placement (site_greedy.h).
#include "site_greedy.h"

#include <algorithm>

namespace cubeao::placement {

SiteGreedy::SiteGreedy(const PlacementScene& ps, const std::vector<Site>& sites) : ps_(ps) {
    for (const Site& s : sites) addSite(s);
}

bool SiteGreedy::addSite(const Site& site) {
    if (!positions_.insert({site.position.x, site.position.y, site.position.z}).second) return false;
    sites_.push_back(site);
    seen_.emplace_back();
    exact_.emplace_back();
    taken_.push_back(0);
    return true;
}

const std::vector<SampleView>& SiteGreedy::seen(std::size_t k) {
    if (!seen_[k]) seen_[k] = ps_.seen(sites_[k].position), ++bounds_;
    return *seen_[k];
}

const std::vector<SampleView>& SiteGreedy::served(std::size_t k) {
    if (!exact_[k]) exact_[k] = ps_.served(sites_[k].position, seen(k)), ++evaluations_;
    return *exact_[k];
}

// Exact where evaluated, else the bound, else the votes' estimate (each voter scaled by the inverse of
// the chance its rays found the voxel); a site without votes is bounded at once.
double SiteGreedy::gainOf(std::size_t k, const ExpectedError& error) {
    if (exact_[k]) return error.gain(*exact_[k]);
    const std::int64_t c = sites_[k].voxel;
    if (seen_[k] || c < 0) return error.gain(seen(k));
    const PlacementScene::Votes& votes = ps_.votes();
    double g = 0.0;
    for (std::uint64_t v = votes.offsets[std::size_t(c)]; v < votes.offsets[std::size_t(c) + 1]; ++v) {
        const std::uint32_t s = votes.voters[v];
        const float e = ps_.expectedError(s, votes.area[v]);
        if (e < error.current(s)) g += double(votes.scale[v]) * double(error.weight(s)) * double(error.current(s) - e);
    }
    return error.totalWeight() > 0.0 ? g / error.totalWeight() : 0.0;
}

void SiteGreedy::rank(const ExpectedError& error) {
    queue_ = {};
    best_ = {0.0, 0, round_};
    for (std::size_t k = 0; k < sites_.size(); ++k) {
        if (taken_[k]) continue;
        const Entry e{gainOf(k, error), -std::int64_t(k), round_};
        if (exact_[k] && e.gain > best_.gain) best_ = e;
        queue_.push(e);
    }
}

std::optional<SiteGreedy::Pick> SiteGreedy::next(const ExpectedError& error) {
    while (!queue_.empty()) {
        Entry top = queue_.top();
        const bool slack = best_.gain > 0.0 && best_.round == round_ &&
                           !taken_[std::size_t(-best_.negativeSite)] && best_.gain >= (1.0 - kSlack) * top.gain;
        if (slack)
            top = best_;
        else
            queue_.pop();
        const std::size_t k = std::size_t(-top.negativeSite);
        if (taken_[k]) continue;
        if (top.round != round_ || !exact_[k]) {
            // Of an earlier round: refresh it from what is known. Of this round: learn more first.
            if (top.round == round_) seen_[k] ? served(k) : seen(k);
            const Entry refreshed{gainOf(k, error), top.negativeSite, round_};
            if (exact_[k] && refreshed.gain > best_.gain) best_ = refreshed;
            queue_.push(refreshed);
            continue;
        }
        if (!slack) queue_.push(top);  // stays queued until taken
        if (!(top.gain > 0.0)) return std::nullopt;
        return Pick{k, top.gain};
    }
    return std::nullopt;
}

std::optional<SiteGreedy::Pick> SiteGreedy::bestOfFew(const ExpectedError& error, std::size_t bounded,
                                                      std::size_t exact) {
    std::vector<std::pair<double, std::size_t>> ranked;
    for (std::size_t k = 0; k < sites_.size(); ++k)
        if (!taken_[k]) ranked.emplace_back(gainOf(k, error), k);
    // Largest first, ties to the lowest site (the order placeVoting's queue gives).
    const auto larger = [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; };
    const auto top = [&](std::size_t n) {
        n = std::min(n, ranked.size());
        std::partial_sort(ranked.begin(), ranked.begin() + std::ptrdiff_t(n), ranked.end(), larger);
        ranked.resize(n);
    };
    top(bounded);
    for (auto& [gain, k] : ranked) gain = error.gain(exact_[k] ? *exact_[k] : seen(k));
    top(exact);
    std::optional<Pick> best;
    for (const auto& [bound, k] : ranked) {
        const double g = error.gain(served(k));
        if (g > 0.0 && (!best || g > best->gain)) best = Pick{k, g};
    }
    return best;
}

void SiteGreedy::take(std::size_t site) {
    taken_[site] = 1;
    ++round_;
    best_ = {0.0, 0, round_};
}

}  // namespace cubeao::placement
