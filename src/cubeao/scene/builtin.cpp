#include "cubeao/scene/builtin.h"

#include <map>
#include <mutex>

#include "cubeao/core/error.h"
#include "cubeao/scene/repair.h"

namespace cubeao {
namespace {

constexpr const char* kPrefix = "builtin:";

// A function-local static, so registration from any translation unit, at any time, finds it built.
struct Registry {
    std::mutex mutex;
    std::map<std::string, BuiltinScene> scenes;  // sorted: builtinSceneNames() lists them in order
};
Registry& registry() {
    static Registry r;
    return r;
}

std::string nameList() {
    std::string names;
    for (const auto& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
    return names;
}

BuiltinScene lookup(const std::string& spec) {
    const std::string name = isBuiltinSpec(spec) ? spec.substr(std::string(kPrefix).size()) : spec;
    {
        Registry& r = registry();
        std::lock_guard lock(r.mutex);
        const auto it = r.scenes.find(name);
        if (it != r.scenes.end()) return it->second;
        if (r.scenes.empty())
            throw Error(spec + ": no built-in scenes are registered (the program must call "
                               "cubeao::scenes::registerBuiltinScenes() from cubeao_scenes first)");
    }
    throw Error(spec + ": no such built-in scene (have: " + nameList() + ")");
}

}  // namespace

void registerBuiltinScene(const std::string& name, BuiltinScene scene) {
    if (name.empty() || name.find(':') != std::string::npos)
        throw Error("built-in scene name '" + name + "' must be non-empty and free of ':'");
    if (!scene.makeScene || !scene.cameraPath) throw Error(kPrefix + name + ": registered without a scene or a camera path");
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    if (!r.scenes.emplace(name, std::move(scene)).second) throw Error(kPrefix + name + ": registered twice");
}

bool isBuiltinSpec(const std::string& spec) { return spec.rfind(kPrefix, 0) == 0; }

std::vector<std::string> builtinSceneNames() {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    std::vector<std::string> names;
    for (const auto& [name, entry] : r.scenes) names.push_back(name);
    return names;
}

Scene makeBuiltinScene(const std::string& spec) {
    Scene scene = lookup(spec).makeScene();
    scene.source = isBuiltinSpec(spec) ? spec : kPrefix + spec;
    prepareScene(scene, true);
    return scene;
}

CameraPath builtinCameraPath(const std::string& spec) { return lookup(spec).cameraPath(); }

CameraPath resolveCameraPath(const std::string& cameraArg, const std::string& sceneSpec) {
    if (isBuiltinSpec(cameraArg)) return builtinCameraPath(cameraArg);
    if (!cameraArg.empty()) return readCameraPath(cameraArg);
    if (isBuiltinSpec(sceneSpec)) return builtinCameraPath(sceneSpec);
    throw UsageError("--camera PATH.json is required for " + sceneSpec + " (only built-in scenes have a default path)");
}

CameraPath resolveCameraPath(const std::string& cameraArg, const Scene& scene) {
    // A file is read against the origin directly (its doubles never pass through float file coordinates).
    CameraPath path = !cameraArg.empty() && !isBuiltinSpec(cameraArg) ? readCameraPath(cameraArg, scene.origin)
                                                                       : resolveCameraPath(cameraArg, scene.source);
    rebaseCameraPath(path, scene.origin);
    return path;
}

}  // namespace cubeao
