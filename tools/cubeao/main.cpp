// cubeao: one binary with subcommands (DESIGN.md §5). Exit codes: 0 done, 1 failed, 2 bad usage.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <cstdio>
#include <iostream>

#include "commands.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/context.h"
#include "cubeao/scenes/builtin_scenes.h"

namespace cubeao::cli {
void printJson(const nlohmann::json& j) {
    if (j.is_object() && !j.contains("peak_rss_mb")) {
        nlohmann::json withRss = j;
        withRss["peak_rss_mb"] = peakRssMib();
        std::cout << withRss.dump() << std::endl;
        return;
    }
    std::cout << j.dump() << std::endl;
}

double peakRssMib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}
}  // namespace cubeao::cli

int main(int argc, char** argv) {
    cubeao::scenes::registerBuiltinScenes();  // builtin:NAME for every subcommand (scene/builtin.h)
    spdlog::set_default_logger(spdlog::stderr_color_mt("cubeao"));  // stdout is for results and JSON
    spdlog::set_pattern("%^%l%$: %v");
    CLI::App app{"cubeao: ambient occlusion cached in cube-map probes"};
    app.require_subcommand(1);
    bool verbose = false;
    app.add_flag("-v,--verbose", verbose, "Debug logging");
    app.parse_complete_callback([&] { spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info); });
    cubeao::cli::addInfo(app);
    cubeao::cli::addReference(app);
    cubeao::cli::addPlace(app);
    cubeao::cli::addBake(app);
    cubeao::cli::addMerge(app);
    cubeao::cli::addExport(app);
    cubeao::cli::addCompare(app);
    cubeao::cli::addBench(app);
    cubeao::cli::addRender(app);
    cubeao::cli::addReport(app);
    try {
        app.parse(argc, argv);
        // A GL error is logged where it happens and the work goes on; the command still fails, naming
        // it, so no script takes its output for good (issue 15).
        if (const std::size_t errors = cubeao::gl::debugErrorCount(); errors > 0) {
            std::fprintf(stderr, "cubeao: error: %zu OpenGL error%s during the command; the first: %s\n", errors,
                         errors == 1 ? "" : "s", cubeao::gl::firstDebugError().c_str());
            return 1;
        }
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const cubeao::UsageError& e) {
        std::fprintf(stderr, "cubeao: usage: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cubeao: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
