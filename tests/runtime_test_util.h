// Helpers shared by the run-time tests (test_camera_gbuffer.cpp, test_ssao.cpp, test_blur.cpp,
// test_composite.cpp, test_cli_render.cpp): small scenes, cameras and settings, one copy here.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/image.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/scene.h"
#include "cubeao/ssao/ssao_settings.h"
#include "gl_fixture.h"

// The GL suite of the run-time tests: one suite (one fixture type) across their files.
class RuntimeGl : public GlTest {};

namespace cubeao::test {

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // a b c d counter-clockwise
        const auto base = std::uint32_t(positions.size());
        positions.insert(positions.end(), {a, b, c, d});
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
};

inline const Scene& boxRoom() {
    static const Scene scene = makeBuiltinScene("builtin:box-room");
    return scene;
}
inline const CameraPath& boxRoomPath() {
    static const CameraPath path = builtinCameraPath("builtin:box-room");
    return path;
}

// A camera path of one frame.
inline CameraPath singleFrame(glm::vec3 eye, glm::vec3 target, float fovYDeg = 60.0f) {
    CameraPath p;
    p.fovYDeg = fovYDeg;
    p.frames.push_back({eye, target});
    return p;
}

inline CameraView viewOf(const CameraPath& path, std::size_t frame, int w, int h) {
    return CameraView::fromPinhole(PinholeCamera(path, frame, w, h), path.nearPlane);
}

inline SsaoSettings methodSettings(SsaoMethod m, float radius) {
    SsaoSettings s;
    s.method = m;
    s.radius = radius;
    return resolveSsaoSettings(s, radius);
}

inline CompositeSettings compositeSettings() {
    CompositeSettings c;
    c.lightDirection = defaultLightDirection({0.0f, 1.0f, 0.0f});
    return c;
}

inline constexpr std::array<SsaoMethod, 3> kMethods = {SsaoMethod::Alchemy, SsaoMethod::Hbao, SsaoMethod::Gtao};

inline double meanAbsoluteDifference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    return sum / double(a.pixels.size());
}

}  // namespace cubeao::test
