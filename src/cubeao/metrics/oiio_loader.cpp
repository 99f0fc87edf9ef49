// Loads libcubeao_oiio.so (oiio_module.h). The two paths are compile definitions of this file alone
// (CMakeLists.txt), like the shader directory's in gl/shader.cpp.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/metrics/oiio_module.h"

namespace cubeao::oiio {
namespace {

std::vector<std::string> candidates() {
    if (const char* env = std::getenv("CUBEAO_OIIO_MODULE"); env && *env)
        return {env};
    std::vector<std::string> paths;
    std::error_code ec;
    if (std::filesystem::exists(CUBEAO_OIIO_MODULE_BUILD, ec))
        paths.emplace_back(CUBEAO_OIIO_MODULE_BUILD);
    paths.emplace_back(CUBEAO_OIIO_MODULE_INSTALLED);
    return paths;
}

const Api* load() {
    std::string tried;
    for (const std::string& path : candidates()) {
        // RTLD_LOCAL: OIIO's symbols stay out of the program's namespace. Never closed: the table
        // lives as long as the process.
        if (void* module = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
            using Entry = const Api* (*)();
            const auto entry = reinterpret_cast<Entry>(::dlsym(module, "cubeao_oiio_api"));
            const Api* api = entry ? entry() : nullptr;
            if (api && api->version == kApiVersion)
                return api;
            tried += "\n  " + path + ": not this build's image module (no cubeao_oiio_api of version " +
                     std::to_string(kApiVersion) + ")";
            continue;
        }
        const char* why = ::dlerror();  // names the path itself
        tried += "\n  " + (why ? std::string(why) : path + ": dlopen failed");
    }
    throw Error("cannot load cubeao's image module (OpenImageIO), which reads and writes images; tried:" + tried +
                "\nset CUBEAO_OIIO_MODULE to the path of libcubeao_oiio.so");
}

}  // namespace

const Api& api() {
    // Thread-safe once; a failed load throws and is tried again on the next call.
    static const Api* const loaded = load();
    return *loaded;
}

}  // namespace cubeao::oiio
