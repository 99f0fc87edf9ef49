#include "cubeao/metrics/run_results.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/metrics/image_metrics.h"

namespace cubeao {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

json readJsonFile(const fs::path& path, const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw Error(dir.string() + " is not a cubeao run: " + path.string() +
                    " is missing (tools/demo.sh and tools/walks.sh write it)");
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find_first_not_of(" \t\r\n") == std::string::npos)
        throw Error(path.string() + " is empty (did the step that writes it fail?)");
    json j;
    try {
        j = json::parse(text.str());
    } catch (const json::exception& e) {
        throw Error(path.string() + ": not valid JSON: " + e.what());
    }
    if (!j.is_object()) throw Error(path.string() + ": expected a JSON object");
    return j;
}

}  // namespace

double jsonNumber(const json& j, const char* key) {
    if (!j.is_object()) return kNaN;
    const auto it = j.find(key);
    return it != j.end() && it->is_number() ? it->get<double>() : kNaN;
}

std::string jsonString(const json& j, const char* key, const std::string& fallback) {
    if (!j.is_object()) return fallback;
    const auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : fallback;
}

json jsonObject(const json& j, const char* key) {
    if (!j.is_object()) return json::object();
    const auto it = j.find(key);
    return it != j.end() && it->is_object() ? *it : json::object();
}

bool isProbesMethod(const std::string& name) { return name == "probes" || name.rfind("probes-", 0) == 0; }

namespace {

// Probes first (the subject), then the baselines in the order demo.sh renders them.
int methodRank(const std::string& name) {
    if (name == "probes") return 0;
    if (isProbesMethod(name)) return 1;
    static const std::vector<std::string> kBaselines = {"gtao", "hbao", "alchemy"};
    const auto it = std::find(kBaselines.begin(), kBaselines.end(), name);
    return it == kBaselines.end() ? 9 : 2 + int(it - kBaselines.begin());
}

int frameNumberOf(const std::string& name) {
    // ao_NNNN.exr
    try {
        return std::stoi(name.substr(3, name.size() - 7));
    } catch (const std::exception&) {
        return -1;
    }
}

}  // namespace

std::vector<int> parseFrameList(const std::string& spec) {
    std::vector<int> out;
    std::stringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        std::size_t used = 0;
        int v = -1;
        try {
            v = std::stoi(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size() || v < 0)
            throw UsageError("--frames: \"" + item + "\" is not a frame number (expected N,M,... e.g. 0,12,47)");
        out.push_back(v);
    }
    if (out.empty()) throw UsageError("--frames: no frame numbers in \"" + spec + "\"");
    return out;
}

RunResults loadRun(const fs::path& dir, const std::vector<int>& wantFrames) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(dir.string() + " is not a cubeao run: no such directory");
    RunResults run;
    run.dir = dir;
    run.info = readJsonFile(dir / "info.json", dir);
    run.probes = readJsonFile(dir / "probes.json", dir);
    run.reference = readJsonFile(dir / "reference.json", dir);
    if (!fs::is_directory(dir / "reference", ec))
        throw Error(dir.string() + " is not a cubeao run: " + (dir / "reference").string() + "/ is missing");
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string f = entry.path().filename().string();
        if (f.rfind("compare-", 0) == 0 && entry.path().extension() == ".json") {
            RunMethod m;
            m.name = f.substr(8, f.size() - 8 - 5);
            m.dir = dir / ("render-" + m.name);
            m.compare = readJsonFile(entry.path(), dir);
            if (!fs::is_directory(m.dir, ec))
                throw Error(dir.string() + ": " + f + " has no frames beside it: " + m.dir.string() + "/ is missing");
            if (fs::is_regular_file(dir / ("render-" + m.name + ".json"), ec))
                m.render = readJsonFile(dir / ("render-" + m.name + ".json"), dir);
            run.methods.push_back(std::move(m));
        } else if (f.rfind("bake-", 0) == 0 && f.size() > 10 && f.substr(f.size() - 10) == "-info.json") {
            run.caches.emplace_back(f.substr(5, f.size() - 5 - 10), readJsonFile(entry.path(), dir));
        } else if (f.rfind("bake-", 0) == 0 && entry.path().extension() == ".json") {
            run.bakes.emplace_back(f.substr(5, f.size() - 5 - 5), readJsonFile(entry.path(), dir));
        }
    }
    if (run.methods.empty())
        throw Error(dir.string() +
                    " is not a cubeao run: no compare-METHOD.json in it (tools/demo.sh writes "
                    "compare-probes.json and one per baseline)");
    std::sort(run.methods.begin(), run.methods.end(), [](const RunMethod& a, const RunMethod& b) {
        return methodRank(a.name) != methodRank(b.name) ? methodRank(a.name) < methodRank(b.name) : a.name < b.name;
    });
    std::sort(run.bakes.begin(), run.bakes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    // The frames: those the first compare paired (all compares cover the same reference).
    const json& frames = run.methods.front().compare.value("frames", json::array());
    for (const json& f : frames) {
        const std::string name = jsonString(f, "name");
        if (!name.empty() && f.is_object()) run.frames.push_back({name, f.value("frame", frameNumberOf(name))});
    }
    if (run.frames.empty()) {
        for (const auto& entry : fs::directory_iterator(dir / "reference")) {
            const std::string f = entry.path().filename().string();
            if (f.rfind("ao_", 0) == 0 && entry.path().extension() == ".exr")
                run.frames.push_back({f, frameNumberOf(f)});
        }
        std::sort(run.frames.begin(), run.frames.end(),
                  [](const RunFrame& a, const RunFrame& b) { return a.number < b.number; });
    }
    if (run.frames.empty()) throw Error(dir.string() + ": the reference has no ao_NNNN.exr frames");
    if (wantFrames.empty()) {
        const std::size_t n = run.frames.size();
        run.picked = {0, n / 2, n - 1};
        run.picked.erase(std::unique(run.picked.begin(), run.picked.end()), run.picked.end());
    } else {
        for (const int want : wantFrames) {
            const auto it =
                std::find_if(run.frames.begin(), run.frames.end(), [&](const RunFrame& f) { return f.number == want; });
            if (it == run.frames.end())
                throw Error(dir.string() + ": --frames " + std::to_string(want) + " is not a frame of this run (" +
                            std::to_string(run.frames.size()) + " frames, " +
                            std::to_string(run.frames.front().number) + " to " +
                            std::to_string(run.frames.back().number) + ")");
            run.picked.push_back(std::size_t(it - run.frames.begin()));
        }
    }
    return run;
}

void measureFrames(RunResults& run) {
    std::vector<Image> reference;
    reference.reserve(run.frames.size());
    for (const RunFrame& f : run.frames) reference.push_back(readImage(run.dir / "reference" / f.name));
    run.pictures.assign(run.picked.size(), std::vector<Image>(1 + run.methods.size()));
    for (std::size_t p = 0; p < run.picked.size(); ++p) run.pictures[p][0] = reference[run.picked[p]];
    for (std::size_t k = 0; k < run.methods.size(); ++k) {
        RunMethod& m = run.methods[k];
        std::map<std::string, double> fromJson;
        for (const json& f : m.compare.value("frames", json::array()))
            if (f.is_object() && f.contains("name")) fromJson[jsonString(f, "name")] = jsonNumber(f, "mae");
        Image prev;
        for (std::size_t i = 0; i < run.frames.size(); ++i) {
            const fs::path path = m.dir / run.frames[i].name;
            Image a = readImage(path);
            const Image& b = reference[i];
            if (!a.sameSize(b))
                throw Error(path.string() + ": " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                            ", the reference frame is " + std::to_string(b.width) + "x" + std::to_string(b.height));
            const auto known = fromJson.find(run.frames[i].name);
            m.mae.push_back(known != fromJson.end() && std::isfinite(known->second) ? known->second
                                                                                    : imageDiff(a, b).mae);
            m.flicker.push_back(i == 0 || !prev.sameSize(a) ? kNaN : flickerPair(prev, a, reference[i - 1], b));
            for (std::size_t p = 0; p < run.picked.size(); ++p)
                if (run.picked[p] == i) run.pictures[p][1 + k] = a;
            prev = std::move(a);
        }
    }
}

const RunMethod* bestBaseline(const RunResults& run, const char* metric) {
    const RunMethod* best = nullptr;
    for (const RunMethod& m : run.methods)
        if (!isProbesMethod(m.name) && std::isfinite(jsonNumber(m.compare, metric)) &&
            (!best || jsonNumber(m.compare, metric) < jsonNumber(best->compare, metric)))
            best = &m;
    return best;
}

}  // namespace cubeao
