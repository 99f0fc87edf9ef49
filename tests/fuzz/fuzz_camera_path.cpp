// Camera-path JSON (src/cubeao/scene/camera_path.h, the format of ../shared/scenes/README.md) and the
// --frames ranges over it: cubeao::Error or a valid path, never a crash. The first input byte picks
// nothing; the whole input is the JSON text, and its length doubles as the frame-range text's seed.
#include <string>

#include "cubeao/core/error.h"
#include "cubeao/scene/camera_path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const cubeao::CameraPath path = cubeao::parseCameraPath(text, "fuzz.json");
        for (std::size_t f = 0; f < path.frames.size() && f < 4; ++f) (void)cubeao::PinholeCamera(path, f, 8, 8);
    } catch (const cubeao::Error&) {
    }
    return 0;
}
