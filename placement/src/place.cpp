#include "cubeao/placement/place.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/placement/coverage_feedback.h"
#include "cubeao/placement/error_feedback.h"
#include "cubeao/placement/live_placement.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/scene/camera_path.h"

namespace cubeao::placement {

Method parseMethod(const std::string& name) {
    for (const Method m : {Method::Voting, Method::Live, Method::Coverage, Method::Grid, Method::Path})
        if (name == methodName(m)) return m;
    throw UsageError("--method \"" + name + "\": expected voting, live, coverage, grid or path");
}

const char* methodName(Method method) {
    switch (method) {
    case Method::Voting: return "voting";
    case Method::Live: return "live";
    case Method::Coverage: return "coverage";
    case Method::Grid: return "grid";
    case Method::Path: return "path";
    }
    return "?";
}

bool needsWalk(Method method) { return method == Method::Path || method == Method::Coverage || method == Method::Live; }

void checkMethodSettings(Method method, const PlaceSettings& settings) {
    if (method == Method::Path && settings.budget == 0)
        throw UsageError("--method path needs --budget N (how many probes to spread along the path)");
}

Placement place(Method method, const PlacementScene& ps, const CameraPath* walk, GpuCoverageCount* gpu) {
    checkMethodSettings(method, ps.settings());
    if (needsWalk(method) && !walk)
        throw Error(std::string("place --method ") + methodName(method) + ": needs a camera path");
    switch (method) {
    case Method::Voting: {
        // The greedy adds probes until the budget or the stop: the budget is the most there can be.
        Progress progress("place voting", std::uint64_t(std::max(ps.settings().budget, 0)), "probes");
        return placeVoting(ps, &progress);
    }
    case Method::Grid: {
        Progress progress("place grid", 0, "spacings");
        return placeGrid(ps, &progress);
    }
    case Method::Live: {  // the viewer's live placement over the walk, frame by frame
        Progress progress("place live", walk->frames.size(), "frames");
        return placeFeedback(ps, *walk, LiveSettings{}.countEveryFrames, FeedbackSettings{}.maxPerFrame, &progress);
    }
    case Method::Coverage: {
        Progress progress("place coverage", walk->frames.size(), "frames");
        return placeCoverage(ps, *walk, {}, &progress, gpu);
    }
    case Method::Path:
        return evaluate(ps, positionsOf(probesAlongPath(*walk, std::size_t(ps.settings().budget))), "path");
    }
    throw Error("place: unknown method");
}

}  // namespace cubeao::placement
