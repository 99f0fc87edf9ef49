#include "cubeao/scene/builtin.h"

#include <map>
#include <mutex>
#include <utility>

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

// "builtin:NAME[:ARG]" (or "NAME[:ARG]") split at the first ':' after the prefix.
struct Spec {
    std::string name, arg;
};
Spec splitSpec(const std::string& spec) {
    const std::string rest = isBuiltinSpec(spec) ? spec.substr(std::string(kPrefix).size()) : spec;
    const std::size_t colon = rest.find(':');
    if (colon == std::string::npos) return {rest, ""};
    return {rest.substr(0, colon), rest.substr(colon + 1)};
}

// The entry for `spec` and its argument; Error when the name is unknown or takes no argument but has one.
std::pair<BuiltinScene, std::string> lookup(const std::string& spec) {
    const Spec s = splitSpec(spec);
    {
        Registry& r = registry();
        std::lock_guard lock(r.mutex);
        const auto it = r.scenes.find(s.name);
        if (it != r.scenes.end()) {
            if (!s.arg.empty() && !it->second.takesArgument)
                throw Error(spec + ": builtin:" + s.name + " takes no argument (got '" + s.arg + "')");
            return {it->second, s.arg};
        }
        if (r.scenes.empty())
            throw Error(spec + ": no built-in scenes are registered (the program must call "
                               "cubeao::scenes::registerBuiltinScenes() from cubeao_scenes first)");
    }
    throw Error(spec + ": no such built-in scene (have: " + nameList() + ")");
}

}  // namespace

BuiltinScene::BuiltinScene(std::function<Scene()> scene, std::function<CameraPath()> path) {
    if (scene) makeScene = [f = std::move(scene)](const std::string&) { return f(); };
    if (path) cameraPath = [f = std::move(path)](const std::string&) { return f(); };
}

BuiltinScene::BuiltinScene(MakeScene scene, MakePath path)
    : makeScene(std::move(scene)), cameraPath(std::move(path)), takesArgument(true) {}

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
    const auto [entry, arg] = lookup(spec);
    Scene scene = entry.makeScene(arg);
    scene.source = isBuiltinSpec(spec) ? spec : kPrefix + spec;
    prepareScene(scene, true);
    return scene;
}

CameraPath builtinCameraPath(const std::string& spec) {
    const auto [entry, arg] = lookup(spec);
    return entry.cameraPath(arg);
}

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
