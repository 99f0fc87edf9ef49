// Mesh files through loadScene (src/cubeao/scene/import.h): the header-count check, the text scan in
// front of OpenMesh, OpenMesh's OFF, PLY, STL and OBJ readers and the repair after them. The first input
// byte picks the extension, the rest is the file. cubeao::Error or a well-formed scene (finite
// positions, indices in range), never a crash, and never memory beyond libFuzzer's -rss_limit_mb.
#include <cmath>

#include "cubeao/core/error.h"
#include "cubeao/scene/import.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {"off", "ply", "stl", "obj"};
    const auto path = cubeao::fuzz::scratchFile(std::string("mesh.") + kExt[data[0] % 4], data + 1, size - 1);
    try {
        const cubeao::Scene s = cubeao::loadScene(path.string());
        for (std::uint32_t i : s.indices)
            if (i >= s.positions.size()) __builtin_trap();
        for (const auto& p : s.positions)
            if (!std::isfinite(p.x + p.y + p.z)) __builtin_trap();
    } catch (const cubeao::Error&) {
    }
    return 0;
}
