#include "cubeao/scene/builtin.h"

#include <functional>
#include <map>

#include "cubeao/core/error.h"
#include "cubeao/scene/repair.h"
#include "scenes/builtin_scenes.h"

namespace cubeao {
namespace {

constexpr const char* kPrefix = "builtin:";

struct Entry {
    std::function<Scene()> scene;
    std::function<CameraPath()> path;
};

const std::map<std::string, Entry>& registry() {
    static const std::map<std::string, Entry> r = {
        {"sphere-plane", {scenes::makeSpherePlane, scenes::spherePlanePath}},
        {"box-room", {scenes::makeBoxRoom, scenes::boxRoomPath}},
        {"cloister", {scenes::makeCloister, scenes::cloisterPath}},
    };
    return r;
}

const Entry& lookup(const std::string& spec) {
    const std::string name = isBuiltinSpec(spec) ? spec.substr(std::string(kPrefix).size()) : spec;
    const auto it = registry().find(name);
    if (it == registry().end()) {
        std::string names;
        for (const auto& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
        throw Error(spec + ": no such built-in scene (have: " + names + ")");
    }
    return it->second;
}

}  // namespace

bool isBuiltinSpec(const std::string& spec) { return spec.rfind(kPrefix, 0) == 0; }

std::vector<std::string> builtinSceneNames() {
    std::vector<std::string> names;
    for (const auto& [name, entry] : registry()) names.push_back(name);
    return names;
}

Scene makeBuiltinScene(const std::string& spec) {
    Scene scene = lookup(spec).scene();
    scene.source = isBuiltinSpec(spec) ? spec : kPrefix + spec;
    prepareScene(scene, true);
    return scene;
}

CameraPath builtinCameraPath(const std::string& spec) { return lookup(spec).path(); }

CameraPath resolveCameraPath(const std::string& cameraArg, const std::string& sceneSpec) {
    if (isBuiltinSpec(cameraArg)) return builtinCameraPath(cameraArg);
    if (!cameraArg.empty()) return readCameraPath(cameraArg);
    if (isBuiltinSpec(sceneSpec)) return builtinCameraPath(sceneSpec);
    throw UsageError("--camera PATH.json is required for " + sceneSpec + " (only built-in scenes have a default path)");
}

}  // namespace cubeao
