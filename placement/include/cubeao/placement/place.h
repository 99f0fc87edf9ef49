// One entry to every placement method (issue 32): `cubeao place` parses its options and calls place();
// the method, its progress and the `path` method's probes along the walk live here, not in the tool.
#pragma once

#include <string>

#include "cubeao/placement/placement.h"

namespace cubeao {
struct CameraPath;
}

namespace cubeao::placement {

class GpuCoverageCount;

enum class Method { Voting, Live, Coverage, Grid, Path };

// "voting", "live", "coverage", "grid", "path"; UsageError listing them for any other name.
Method parseMethod(const std::string& name);
const char* methodName(Method method);
// path, coverage and live walk a camera path; voting and grid use one when given.
bool needsWalk(Method method);
// What a method needs of the settings, checked before any work (UsageError): path a budget.
void checkMethodSettings(Method method, const PlaceSettings& settings);

// The probes of `method` over `ps` (built with the same walk), with a progress bar each. `walk` may be
// null only for voting and grid. `gpu`: coverage's frame counts on the GPU (a current GL context);
// null: traced with Embree.
Placement place(Method method, const PlacementScene& ps, const CameraPath* walk, GpuCoverageCount* gpu = nullptr);

}  // namespace cubeao::placement
