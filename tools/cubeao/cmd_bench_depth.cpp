// cubeao bench depth: what storing a probe's distance cube smaller costs the run-time depth test
// (DESIGN.md §4 "Storage"), to choose depthRes, format and filter by measurement (the choice and the
// figures are in src/cubeao/cache/depth_cube.h). Probes go along the camera path as `place --method
// path` puts them; the points are what the camera sees (primary rays of a few small frames); every
// point is paired with its nearest probes, as the run time's candidate selection would. Truth for a
// pair: an Embree ray from the probe to the point. Each variant downsamples the probe's full-res
// distances (Embree primary rays, the CPU bake's G-buffer), quantises, decodes and runs the
// run-time test depth::visible at several tolerances, slopes and lifts.
#include <algorithm>
#include <cstdio>
#include <memory>

#include <glm/geometric.hpp>

#include "cli_util.h"
#include "commands.h"
#include "cubeao/bake/bake.h"
#include "cubeao/core/cube.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

struct DepthArgs {
    std::string scene = "builtin:cloister", camera;
    int res = 512, probes = 8, frames = 8, width = 160, height = 90, candidates = 4;
    std::vector<int> divisors{1, 2, 4, 8};
    std::vector<float> tolerances{0.002f, 0.005f, 0.01f, 0.02f}, slopes{0.0f, depth::kDepthSlope},
        offsets{0.0f, depth::kThinWallLift};
    bool json = false;
};

// The run-time tests compared: every offset × slope × facing × tolerance.
std::vector<depth::DepthTest> testsFor(const DepthArgs& a) {
    std::vector<depth::DepthTest> tests;
    for (const float offset : a.offsets)
        for (const float slope : a.slopes)
            for (const bool facing : {false, true})
                for (const float tolerance : a.tolerances) tests.push_back({tolerance, slope, facing, offset});
    return tests;
}

struct Variant {
    int divisor = 1;
    DepthFormat format = DepthFormat::R32Float;
    depth::Filter filter = depth::Filter::Min;
    std::vector<std::uint64_t> falseVisible, falseHidden;  // per test

    std::string name() const {
        return "res/" + std::to_string(divisor) + " " + depthFormatName(format) + " " + depth::filterName(filter);
    }
};

struct Pair {
    glm::vec3 point, normal;  // normal turned towards the camera
    float cosine;  // between the point's normal (towards the camera) and the direction to the probe
    bool visible;  // truth
};

struct Point {
    glm::vec3 position, normal;  // normal turned towards the camera that sees the point
};

// Surface points the camera sees: primary rays of `frames` frames spread along the path.
std::vector<Point> cameraPoints(const EmbreeScene& rt, const CameraPath& path, const DepthArgs& a) {
    std::vector<Point> points;
    const std::size_t n = std::min<std::size_t>(std::size_t(a.frames), path.frames.size());
    for (std::size_t k = 0; k < n; ++k) {
        const PinholeCamera camera(path, (2 * k + 1) * path.frames.size() / (2 * n), a.width, a.height);
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                const glm::vec3 dir = camera.rayDirection(x, y);
                const RayHit hit = rt.intersect(camera.eye, dir, 0.0f, path.farPlane);
                if (hit.hit)
                    points.push_back({camera.eye + dir * hit.t, glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal});
            }
    }
    return points;
}

// For every probe the (point, truth) pairs of the points that have it among their nearest probes.
std::vector<std::vector<Pair>> pairsByProbe(const EmbreeScene& rt, const std::vector<glm::vec3>& probes,
                                            const std::vector<Point>& points, int candidates) {
    std::vector<std::vector<Pair>> byProbe(probes.size());
    std::vector<std::size_t> order(probes.size());
    const std::size_t k = std::min(order.size(), std::size_t(candidates));
    for (const Point& point : points) {
        const glm::vec3 p = point.position;
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(k), order.end(), [&](std::size_t x, std::size_t y) {
            return glm::distance(p, probes[x]) < glm::distance(p, probes[y]);
        });
        for (std::size_t c = 0; c < k; ++c) {
            const glm::vec3 probe = probes[order[c]];
            const float distance = glm::distance(p, probe);
            if (!(distance > 0.0f)) continue;
            // Stop short of the point's own surface: anything before it hides it.
            const float margin = std::max(rt.surfaceEpsilon(), 1e-4f * distance);
            const bool hidden = rt.occluded(probe, (p - probe) / distance, 0.0f, distance - margin);
            byProbe[order[c]].push_back({p, point.normal, glm::dot(point.normal, (probe - p) / distance), !hidden});
        }
    }
    return byProbe;
}

std::vector<Variant> variantsFor(const DepthArgs& a) {
    std::vector<Variant> out;
    for (const int d : a.divisors)
        for (const DepthFormat f : {DepthFormat::R32Float, DepthFormat::R16Float, DepthFormat::R16Unorm})
            for (const depth::Filter filter : {depth::Filter::Min, depth::Filter::Nearest}) {
                if (d == 1 && filter == depth::Filter::Nearest) continue;  // same as min at full res
                Variant v{d, f, filter, {}, {}};
                v.falseVisible.assign(testsFor(a).size(), 0);
                v.falseHidden.assign(testsFor(a).size(), 0);
                out.push_back(v);
            }
    return out;
}

void evaluate(Variant& v, const CubeGBuffer& g, const std::vector<Pair>& pairs, const std::vector<depth::DepthTest>& tests) {
    const int depthRes = std::max(1, g.res / v.divisor);
    const std::vector<float> coarse = depth::downsample(g.texels, g.res, depthRes, v.filter);
    const float maxDistance = depth::maxDistance(coarse);
    std::vector<float> stored;
    depth::decode(depth::encode(coarse, v.format, maxDistance), depthRes, v.format, maxDistance, stored);
    for (const Pair& p : pairs) {
        for (std::size_t t = 0; t < tests.size(); ++t) {
            const glm::vec3 d = p.point - g.probe;
            const glm::vec3 lifted = depth::liftedPoint(tests[t], g.probe, p.point, p.normal, depthRes) - g.probe;
            const bool visible =
                depth::visible(tests[t], stored[cube::texelIndex(d, depthRes)], glm::length(d), p.cosine, depthRes,
                               {stored[cube::texelIndex(lifted, depthRes)], glm::length(lifted)});
            v.falseVisible[t] += visible && !p.visible;
            v.falseHidden[t] += !visible && p.visible;
        }
    }
}

// Pair counts: the denominators of the two rates.
struct Totals {
    std::uint64_t visible = 0, hidden = 0;
    double falseVisible(std::uint64_t n) const { return hidden ? double(n) / double(hidden) : 0.0; }
    double falseHidden(std::uint64_t n) const { return visible ? double(n) / double(visible) : 0.0; }
};

double bytesPerAoTexel(const Variant& v) { return double(depthBytesPerTexel(v.format)) / double(v.divisor * v.divisor); }

// One table per (slope, facing): variants down, tolerances across; and the same as JSON rows.
nlohmann::json printTables(const std::vector<Variant>& variants, const std::vector<depth::DepthTest>& tests,
                           std::size_t perBlock, const Totals& n) {
    for (std::size_t block = 0; block < tests.size(); block += perBlock) {
        std::printf("\nfalse visible (of %llu hidden) / false hidden (of %llu visible), %%; offset %g, slope %g, facing "
                    "%s; at tolerance:\n%-28s %8s", (unsigned long long)n.hidden, (unsigned long long)n.visible,
                    tests[block].offset, tests[block].slope, tests[block].facing ? "on" : "off", "variant", "B/texel");
        for (std::size_t t = block; t < block + perBlock; ++t) std::printf("  %13.3f", tests[t].tolerance);
        std::printf("\n");
        for (const Variant& v : variants) {
            std::printf("%-28s %8.4f", v.name().c_str(), bytesPerAoTexel(v));
            for (std::size_t t = block; t < block + perBlock; ++t)
                std::printf("  %6.3f/%6.3f", 100.0 * n.falseVisible(v.falseVisible[t]), 100.0 * n.falseHidden(v.falseHidden[t]));
            std::printf("\n");
        }
    }
    nlohmann::json rows = nlohmann::json::array();
    for (const Variant& v : variants) {
        nlohmann::json perTest = nlohmann::json::array();
        for (std::size_t t = 0; t < tests.size(); ++t)
            perTest.push_back({{"tolerance", tests[t].tolerance},
                               {"slope", tests[t].slope},
                               {"facing", tests[t].facing},
                               {"offset", tests[t].offset},
                               {"false_visible", n.falseVisible(v.falseVisible[t])},
                               {"false_hidden", n.falseHidden(v.falseHidden[t])}});
        rows.push_back({{"variant", v.name()},
                        {"divisor", v.divisor},
                        {"format", depthFormatName(v.format)},
                        {"filter", depth::filterName(v.filter)},
                        {"bytes_per_ao_texel", bytesPerAoTexel(v)},
                        {"tests", perTest}});
    }
    return rows;
}

// The bake's choice against full resolution under the default test.
nlohmann::json printDefaults(const Variant& full, const Variant& chosen, const Totals& n) {
    const depth::DepthTest d;
    std::printf("\ndefault test (tolerance %g, slope %g, facing %s, offset %g), false visible / false hidden %%:\n",
                d.tolerance, d.slope, d.facing ? "on" : "off", d.offset);
    nlohmann::json out = {{"tolerance", d.tolerance}, {"slope", d.slope}, {"facing", d.facing}, {"offset", d.offset}};
    for (const Variant* v : {&full, &chosen}) {
        const double fv = n.falseVisible(v->falseVisible[0]), fh = n.falseHidden(v->falseHidden[0]);
        std::printf("  %-28s %6.3f/%6.3f%s\n", v->name().c_str(), 100.0 * fv, 100.0 * fh,
                    v == &chosen ? "   (what the bake stores)" : "");
        out[v == &chosen ? "bake" : "full_res"] = {{"variant", v->name()}, {"false_visible", fv}, {"false_hidden", fh}};
    }
    return out;
}

void run(const DepthArgs& a) {
    checkRange("--res", a.res, 8, 4096);
    checkRange("--probes", a.probes, 1, 1024);
    checkRange("--frames", a.frames, 1, 10'000);
    checkRange("--width", a.width, 1, 4096);
    checkRange("--height", a.height, 1, 4096);
    checkRange("--candidates", a.candidates, 1, 64);
    // Every pixel of every frame is a camera point held in memory.
    constexpr std::uint64_t kMaxPoints = std::uint64_t(1) << 24;
    if (std::uint64_t(a.frames) * std::uint64_t(a.width) * std::uint64_t(a.height) > kMaxPoints)
        throw UsageError("--frames x --width x --height must be at most " + std::to_string(kMaxPoints) + " camera points (got " +
                         std::to_string(std::uint64_t(a.frames) * std::uint64_t(a.width) * std::uint64_t(a.height)) + ")");
    for (const int d : a.divisors)
        if (d < 1 || d > a.res) throw UsageError("--divisor " + std::to_string(d) + ": expected 1..res");
    const Scene scene = loadScene(a.scene);
    const CameraPath path = resolveCameraPath(a.camera, scene);
    const EmbreeScene rt(scene);
    std::vector<glm::vec3> probes;
    for (const ProbeSpec& p : probesAlongPath(path, std::size_t(a.probes))) probes.push_back(p.position);
    const std::vector<Point> points = cameraPoints(rt, path, a);
    const auto pairs = pairsByProbe(rt, probes, points, a.candidates);
    Totals n;
    for (const auto& ps : pairs)
        for (const Pair& p : ps) (p.visible ? n.visible : n.hidden) += 1;
    std::printf("%s: %zu probes along the path, %zu camera points (%d frames at %dx%d), %llu pairs (%llu visible, "
                "%llu hidden)\n",
                scene.source.c_str(), probes.size(), points.size(), a.frames, a.width, a.height,
                (unsigned long long)(n.visible + n.hidden), (unsigned long long)n.visible, (unsigned long long)n.hidden);

    const std::vector<depth::DepthTest> tests = testsFor(a), defaultTest{depth::DepthTest{}};
    std::vector<Variant> variants = variantsFor(a);
    Variant full{1, DepthFormat::R32Float, depth::Filter::Min, {0}, {0}};
    Variant chosen{depth::kResDivisor, depth::kDefaultFormat, depth::kFilter, {0}, {0}};
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const CubeGBuffer g = renderGBufferCpu(rt, probes[i], a.res);
        for (Variant& v : variants) evaluate(v, g, pairs[i], tests);
        evaluate(full, g, pairs[i], defaultTest);
        evaluate(chosen, g, pairs[i], defaultTest);
    }
    const nlohmann::json rows = printTables(variants, tests, a.tolerances.size(), n);
    const nlohmann::json defaults = printDefaults(full, chosen, n);
    if (a.json)
        printJson({{"bench", "depth"},
                   {"scene", scene.source},
                   {"res", a.res},
                   {"probes", probes.size()},
                   {"points", points.size()},
                   {"pairs_visible", n.visible},
                   {"pairs_hidden", n.hidden},
                   {"default", defaults},
                   {"variants", rows}});
}

}  // namespace

void addBenchDepth(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("depth", "Distance cube: depth-test disagreement with Embree per resolution, format, filter");
    auto a = std::make_shared<DepthArgs>();
    cmd->add_option("--scene", a->scene, "Scene")->capture_default_str();
    cmd->add_option("--camera", a->camera, "Camera path (default for built-in scenes: their own)");
    cmd->add_option("--res", a->res, "Bake face resolution the cube is downsampled from")->capture_default_str();
    cmd->add_option("--probes", a->probes, "Probes along the path")->capture_default_str();
    cmd->add_option("--frames", a->frames, "Camera frames the points come from")->capture_default_str();
    cmd->add_option("--width", a->width, "Frame width")->capture_default_str();
    cmd->add_option("--height", a->height, "Frame height")->capture_default_str();
    cmd->add_option("--candidates", a->candidates, "Nearest probes per point")->capture_default_str();
    cmd->add_option("--divisor", a->divisors, "depthRes = res / divisor (repeatable)")->capture_default_str();
    cmd->add_option("--tolerance", a->tolerances, "Relative tolerances of the test (repeatable)")->capture_default_str();
    cmd->add_option("--slope", a->slopes, "Slope-scaled bias factors of the test (repeatable)")->capture_default_str();
    cmd->add_option("--offset", a->offsets, "Lifts of the test's second half, in coarse texel widths; 0: none (repeatable)")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
