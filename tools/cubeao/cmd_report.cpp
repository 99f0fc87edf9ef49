// `cubeao report DIR... --out report.html [--frames N,M,...] [--json]`: one self-contained HTML page for
// render/compare runs as tools/demo.sh and tools/walks.sh write them (issue 17). Everything is inline
// (images as data: URIs, CSS, SVG charts, a few lines of script that only mark the page as loaded), so
// the file can be mailed or archived and opens without a network. Per run, in the order a lead reads:
// the headline table, frames side by side with error heat maps, per-frame MAE and flicker charts, bake
// and render timings, and the probes over a top-down view of the scene coloured by the error each removed.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/metrics/image_metrics.h"
#include "cubeao/metrics/run_results.h"
#include "cubeao/reference/top_down.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "report_html.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using report::escape;
using report::format;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct ReportOptions {
    std::vector<std::string> dirs;
    std::string out, frames;
    bool json = false;
};

// ---- reading a run ------------------------------------------------------------------------------

// A run as the page shows it: its results and the HTML anchor of its section.
struct Run : RunResults {
    std::string id;
};

// ---- images -------------------------------------------------------------------------------------

std::string greyUri(const Image& im) { return report::pngDataUri(encodePng(im.width, im.height, 1, im.pixels)); }

Image absDiff(const Image& a, const Image& b) {
    Image d(a.width, a.height);
    for (std::size_t i = 0; i < a.pixels.size(); ++i) d.pixels[i] = std::fabs(a.pixels[i] - b.pixels[i]);
    return d;
}

std::string heatUri(const Image& diff) {
    std::vector<float> rgb(diff.pixels.size() * 3);
    for (std::size_t i = 0; i < diff.pixels.size(); ++i) {
        const report::Rgb c = report::heatColour(diff.pixels[i] / report::kHeatMax);
        rgb[3 * i] = c[0], rgb[3 * i + 1] = c[1], rgb[3 * i + 2] = c[2];
    }
    return report::pngDataUri(encodePng(diff.width, diff.height, 3, rgb));
}

// Small frames (tests, 160x90 walks) are scaled up by a whole factor, pixels kept sharp.
int upscale(int width) { return std::max(1, 320 / std::max(width, 1)); }

std::string imgTag(const std::string& uri, int w, int h, const std::string& alt) {
    const int s = upscale(w);
    return format("<img width=\"%d\" height=\"%d\"", w * s, h * s) + (s > 1 ? " class=\"px\"" : "") + " alt=\"" +
           escape(alt) + "\" src=\"" + uri + "\">";
}

// ---- the top-down view --------------------------------------------------------------------------

// The plan (reference/top_down.h) with what the page says about it.
struct TopDown : TopDownView {
    std::string uri;                // PNG
    const char* cutAbove = "";      // what the cut height is measured from
    std::string note;               // why the scene could not be drawn, when it could not
    std::vector<glm::vec3> probes;  // positions in the scene's local coordinates
    std::vector<glm::vec3> walk;    // the camera's eye per frame of the path placement used (probes.json "camera")
};

// The run's scene as recorded in info.json: a builtin name, an absolute path, or a path relative to where
// demo.sh ran (the repository root): tried as given, then against each folder above DIR.
std::optional<Scene> findScene(const Run& run, std::string& note) {
    const std::string spec = jsonString(run.info, "scene");
    if (spec.empty()) {
        note = "info.json names no scene";
        return std::nullopt;
    }
    std::vector<std::string> tries{spec};
    if (spec.rfind("builtin:", 0) != 0 && fs::path(spec).is_relative())
        for (fs::path d = fs::absolute(run.dir); d.has_relative_path(); d = d.parent_path())
            tries.push_back((d / spec).lexically_normal().string());
    for (const std::string& t : tries) {
        std::error_code ec;
        if (t.rfind("builtin:", 0) != 0 && !fs::exists(t, ec)) continue;
        try {
            Scene s = loadScene(t);
            const std::string hash = jsonString(run.info, "hash");
            if (!hash.empty() && hash != format("0x%016llx", static_cast<unsigned long long>(s.hash)))
                note = t + " has changed since the run (geometry hash " +
                       format("0x%016llx", static_cast<unsigned long long>(s.hash)) + ", the run's " + hash + ")";
            return s;
        } catch (const Error& e) {
            note = e.what();
            return std::nullopt;
        }
    }
    note = "the scene " + spec + " was not found from here";
    return std::nullopt;
}

// A file named in a run's JSON (relative to where demo.sh ran): as given, else against each folder above DIR.
std::optional<std::string> findFile(const Run& run, const std::string& spec) {
    std::error_code ec;
    if (fs::exists(spec, ec)) return spec;
    if (fs::path(spec).is_relative())
        for (fs::path d = fs::absolute(run.dir); d.has_relative_path(); d = d.parent_path())
            if (fs::exists(d / spec, ec)) return (d / spec).lexically_normal().string();
    return std::nullopt;
}

// The eyes of the camera path the probes were placed for (the walk demo.sh renders), when it can be found.
std::vector<glm::vec3> walkEyes(const Run& run, const Scene& scene, std::string& note) {
    const std::string spec = jsonString(run.probes, "camera");
    if (spec.empty()) return {};
    const std::optional<std::string> file = spec.rfind("builtin:", 0) == 0 ? spec : findFile(run, spec);
    if (!file) {
        note += (note.empty() ? "" : "; ") + std::string("the camera path ") + spec + " was not found from here";
        return {};
    }
    try {
        std::vector<glm::vec3> eyes;
        for (const CameraFrame& f : resolveCameraPath(*file, scene).frames) eyes.push_back(f.eye);
        return eyes;
    } catch (const Error& e) {
        note += (note.empty() ? "" : "; ") + std::string(e.what());
        return {};
    }
}

std::vector<glm::vec3> probePositions(const Run& run, const Scene* scene) {
    std::vector<glm::vec3> out;
    for (const json& p : run.probes.value("probes", json::array())) {
        if (!p.contains("pos") || !p["pos"].is_array() || p["pos"].size() != 3) continue;
        const glm::dvec3 file(p["pos"][0].get<double>(), p["pos"][1].get<double>(), p["pos"][2].get<double>());
        out.push_back(scene ? scene->toLocal(file) : glm::vec3(file));
    }
    return out;
}

// The run's plan: its scene (when found), probes and walk (reference/top_down.h).
TopDown renderTopDown(const Run& run, int maxSide) {
    TopDown td;
    std::optional<Scene> scene = findScene(run, td.note);
    td.probes = probePositions(run, scene ? &*scene : nullptr);
    if (scene) td.walk = walkEyes(run, *scene, td.note);
    static_cast<TopDownView&>(td) = cubeao::renderTopDown(scene ? &*scene : nullptr, td.probes, td.walk,
                                                          float(jsonNumber(run.reference, "radius")), maxSide);
    td.cutAbove = td.walk.empty() ? "the highest probe" : "the camera's highest eye";
    if (td.width > 0) td.uri = report::pngDataUri(encodePng(td.width, td.height, 3, td.rgb));
    return td;
}

// ---- HTML ---------------------------------------------------------------------------------------

std::string fmtNum(double v, const char* f) { return std::isfinite(v) ? format(f, v) : std::string("–"); }

const char* kPalette[] = {"#d62728", "#ff7f0e", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};

std::string methodColour(std::size_t k) { return kPalette[k % (sizeof kPalette / sizeof kPalette[0])]; }

std::string methodLabel(const RunMethod& m) {
    if (m.name == "probes") return "probes (traced bake)";
    if (m.name == "probes-hsplit") return "probes (horizon-split bake)";
    return m.name;
}

const char* kCss = R"CSS(
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;color:#1d2330;
  background:#f4f5f7;margin:0}
main{max-width:1240px;margin:0 auto;padding:18px 20px 40px}
header.page{background:#1d2330;color:#eef;padding:14px 20px}
header.page h1{margin:0;font-size:20px;font-weight:600}
header.page p{margin:2px 0 0;color:#aab;font-size:12px}
section.run{background:#fff;border-radius:8px;box-shadow:0 1px 3px rgba(0,0,0,.12);padding:16px 22px;margin:18px 0}
h2{font-size:19px;margin:4px 0 6px}
h3{font-size:15px;margin:22px 0 8px;border-bottom:1px solid #e3e5ea;padding-bottom:4px}
.facts{display:flex;flex-wrap:wrap;gap:8px 26px;margin:6px 0 12px;color:#445}
.facts b{color:#1d2330}
table{border-collapse:collapse;margin:6px 0;font-variant-numeric:tabular-nums}
th,td{padding:4px 10px;text-align:right;border-bottom:1px solid #eceef2;white-space:nowrap}
th{font-weight:600;color:#556;background:#f7f8fa}
td:first-child,th:first-child{text-align:left}
td.best{background:#dff3e2;font-weight:700;color:#0f5b22}
.swatch{display:inline-block;width:10px;height:10px;border-radius:2px;margin-right:6px;vertical-align:0}
.verdict{background:#eef4ff;border-left:4px solid #3b6fd8;padding:8px 12px;margin:10px 0;border-radius:0 6px 6px 0}
.note{color:#667;font-size:12.5px}
.warn{color:#9a4b00}
.frame{margin:10px 0 18px}
.trio{display:grid;grid-template-columns:repeat(3,minmax(0,1fr));gap:10px;align-items:start}
.trio figure img{width:100%;height:auto}
.trio figure img+img{margin-top:3px}
details.more{margin:6px 0 0}
details.more summary{cursor:pointer;color:#445;font-size:12.5px}
details.more .trio{margin-top:6px}
figure{margin:0}
figcaption{font-size:12px;color:#445;margin-top:2px}
figure img{display:block;background:#ddd}
img.px{image-rendering:pixelated}
.legend{display:flex;align-items:center;gap:8px;font-size:12px;color:#445;margin:4px 0}
figure .legend{flex-direction:column;align-items:flex-start;gap:2px;max-width:300px;margin-top:16px}
.charts{display:flex;flex-wrap:wrap;gap:8px 18px}
svg.chart text{font:11px system-ui,"DejaVu Sans",sans-serif;fill:#334}
svg.chart .ctitle{font-size:13px;font-weight:600}
svg.chart .grid{stroke:#e6e8ec}svg.chart .axis{stroke:#667}
.plan{position:relative;display:inline-block}
.plan img{display:block}
.plan svg{position:absolute;left:0;top:0}
nav a{margin-right:14px}
)CSS";

// Marks the page for headless checks (tests/cli/test_report.cpp): body data-images-ok="loaded/total" once
// loaded, data-errors for any script error.
const char* kScript = R"JS(
window.addEventListener('error', function (e) {
  document.body.dataset.errors = (document.body.dataset.errors || '') + (e.message || 'error') + ';';
});
window.addEventListener('load', function () {
  var imgs = Array.prototype.slice.call(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  document.body.dataset.imagesOk = ok + '/' + imgs.length;
});
)JS";

// Ticks of a colour bar: position along it (0..1) and label.
using BarTicks = std::vector<std::pair<double, std::string>>;

BarTicks linearTicks(double lo, double hi) {
    BarTicks ticks;
    const double step = report::niceStep(hi - lo, 5);
    for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
        ticks.emplace_back((v - lo) / std::max(hi - lo, 1e-12), report::tickLabel(v, step));
    return ticks;
}

// Ticks at 1, 2 and 5 times powers of ten between lo and hi (> 0) on a log bar.
BarTicks logTicks(double lo, double hi) {
    BarTicks ticks;
    const double span = std::log(hi / lo);
    for (double decade = std::pow(10.0, std::floor(std::log10(lo))); decade <= hi; decade *= 10.0)
        for (const double m : {1.0, 2.0, 5.0}) {
            const double v = m * decade;
            if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9))
                ticks.emplace_back(std::log(v / lo) / span, report::tickLabel(v, decade));
        }
    return ticks;
}

std::string legendBar(const std::string& id, bool heat, const BarTicks& ticks, const std::string& what) {
    // An SVG gradient sampled from the same ramp as the pictures.
    std::string svg =
        format("<svg width=\"260\" height=\"30\" viewBox=\"0 0 260 30\"><defs><linearGradient id=\"%s\">", id.c_str());
    for (int i = 0; i <= 10; ++i) {
        const double t = i / 10.0;
        svg += format("<stop offset=\"%.2f\" stop-color=\"", t) +
               report::cssColour(heat ? report::heatColour(t) : report::gainColour(t)) + "\"/>";
    }
    svg += format(
        "</linearGradient></defs><rect x=\"10\" y=\"2\" width=\"240\" height=\"12\" fill=\"url(#%s)\" "
        "stroke=\"#999\" stroke-width=\"0.5\"/>",
        id.c_str());
    for (const auto& [t, label] : ticks) {
        const double x = 10 + 240 * t;
        svg += format("<line x1=\"%.1f\" y1=\"14\" x2=\"%.1f\" y2=\"18\" stroke=\"#666\"/>", x, x);
        svg += format("<text x=\"%.1f\" y=\"28\" font-size=\"10\" text-anchor=\"middle\" fill=\"#445\">", x) + label +
               "</text>";
    }
    svg += "</svg>";
    return std::string("<div class=\"legend\">") + svg + "<span>" + what + "</span></div>";
}

// Section 1: what the run is (runFacts), the metric table (metricsTable) and the verdict (verdicts).
std::string runFacts(const Run& run) {
    std::string h;
    const json& ref = run.reference;
    const std::size_t probeCount = run.probes.value("probes", json::array()).size();
    h += "<div class=\"facts\">";
    h += "<span>triangles <b>" + format("%lld", run.info.value("triangles", 0LL)) + "</b></span>";
    h += "<span>probes <b>" + std::to_string(probeCount) + "</b> (" + escape(jsonString(run.probes, "method", "?")) +
         " placement: predicted MAE " + fmtNum(jsonNumber(run.probes, "predicted_mae"), "%.4f") + ", served " +
         fmtNum(100.0 * jsonNumber(run.probes, "served"), "%.1f") + " % of what the walk sees, fine coverage " +
         fmtNum(100.0 * jsonNumber(run.probes, "coverage"), "%.1f") + " %)</span>";
    h += "<span>walk <b>" + std::to_string(run.frames.size()) + " frames</b> at " +
         format("%lldx%lld", ref.value("width", 0LL), ref.value("height", 0LL)) + "</span>";
    h += "<span>AO radius <b>" + fmtNum(jsonNumber(ref, "radius"), "%.3g") + "</b> scene units</span>";
    h += "<span>reference <b>" + format("%lld", ref.value("spp", 0LL)) + " rays/pixel</b>, noise " +
         fmtNum(jsonNumber(ref, "noise"), "%.4f") + "</span>";
    h += "</div>";
    return h;
}

// The metric table, the best of each column marked, and what its figures are measured against.
std::string metricsTable(const Run& run) {
    std::string h;
    const json& ref = run.reference;
    struct Col {
        const char* title;
        const char* fmt;
        bool lowerIsBetter;
        std::function<double(const RunMethod&)> get;
    };
    const std::vector<Col> cols = {
        {"MAE", "%.4f", true, [](const RunMethod& m) { return jsonNumber(m.compare, "mae"); }},
        {"RMSE", "%.4f", true, [](const RunMethod& m) { return jsonNumber(m.compare, "rmse"); }},
        {"SSIM", "%.4f", false, [](const RunMethod& m) { return jsonNumber(m.compare, "ssim"); }},
        {"PSNR dB", "%.2f", false, [](const RunMethod& m) { return jsonNumber(m.compare, "psnr"); }},
        {"flicker", "%.4f", true, [](const RunMethod& m) { return jsonNumber(m.compare, "flicker"); }},
        {"AO ms", "%.1f", true, [](const RunMethod& m) { return jsonNumber(jsonObject(m.render, "timings_ms"), "ao"); }},
    };
    h += "<table class=\"metrics\"><tr><th>method</th>";
    for (const Col& c : cols) h += std::string("<th>") + c.title + "</th>";
    h += "<th>uncovered</th></tr>";
    std::vector<double> best(cols.size(), kNaN);
    for (std::size_t c = 0; c < cols.size(); ++c)
        for (const RunMethod& m : run.methods) {
            const double v = cols[c].get(m);
            if (std::isfinite(v) && (!std::isfinite(best[c]) || (cols[c].lowerIsBetter ? v < best[c] : v > best[c])))
                best[c] = v;
        }
    for (std::size_t k = 0; k < run.methods.size(); ++k) {
        const RunMethod& m = run.methods[k];
        h += "<tr><td><span class=\"swatch\" style=\"background:" + methodColour(k) + "\"></span>" +
             escape(methodLabel(m)) + "</td>";
        for (std::size_t c = 0; c < cols.size(); ++c) {
            const double v = cols[c].get(m);
            h += std::string("<td") +
                 (std::isfinite(v) && v == best[c] && run.methods.size() > 1 ? " class=\"best\"" : "") + ">" +
                 fmtNum(v, cols[c].fmt) + "</td>";
        }
        const double unc = jsonNumber(m.render, "uncovered_fraction");
        h += "<td>" + (std::isfinite(unc) ? format("%.1f %%", 100.0 * unc) : std::string("–")) + "</td></tr>";
    }
    h += "</table>";
    h += "<p class=\"note\">Every figure is against the Embree reference (1 = open, 0 = occluded). Lower is better "
         "for MAE, RMSE, flicker (frame-to-frame change the reference does not have) and time; higher for SSIM and "
         "PSNR. The best of each column is green. The reference's own noise (" +
         fmtNum(jsonNumber(ref, "noise"), "%.4f") + ") is part of every MAE.";
    const std::string renderer =
        run.methods.front().render.is_object() ? jsonString(run.methods.front().render, "renderer") : "";
    if (!renderer.empty())
        h += " AO ms: mean per frame on <b>" + escape(renderer) + "</b>" +
             (renderer.find("llvmpipe") != std::string::npos ? " (software rendering: compare the methods with each "
                                                               "other, not with a GPU budget)"
                                                             : "") +
             ".";
    h += "</p>";
    return h;
}

// The verdict: each probes method against the best screen-space baseline, spelled out.
std::string verdicts(const Run& run) {
    std::string h;
    const RunMethod* bestBase = bestBaseline(run, "mae");
    const RunMethod* bestFlicker = bestBaseline(run, "flicker");
    auto ratio = [](double probes, double base, const char* what) {
        if (!(probes > 0.0) || !(base > 0.0)) return std::string();
        return probes <= base ? format("<b>%.2f× lower</b> %s", base / probes, what)
                              : format("<b class=\"warn\">%.2f× higher</b> %s", probes / base, what);
    };
    for (const RunMethod& m : run.methods) {
        if (!isProbesMethod(m.name) || !bestBase) continue;
        h += "<div class=\"verdict\"><b>" + escape(methodLabel(m)) + "</b>: MAE " +
             fmtNum(jsonNumber(m.compare, "mae"), "%.4f") + ", " +
             ratio(jsonNumber(m.compare, "mae"), jsonNumber(bestBase->compare, "mae"), "than the best screen-space baseline, ") +
             "<b>" + escape(bestBase->name) + "</b> (" + fmtNum(jsonNumber(bestBase->compare, "mae"), "%.4f") + ")";
        if (bestFlicker)
            h += "; flicker " + fmtNum(jsonNumber(m.compare, "flicker"), "%.4f") + ", " +
                 ratio(jsonNumber(m.compare, "flicker"), jsonNumber(bestFlicker->compare, "flicker"),
                       "than the steadiest baseline, ") +
                 "<b>" + escape(bestFlicker->name) + "</b> (" + fmtNum(jsonNumber(bestFlicker->compare, "flicker"), "%.4f") +
                 ")";
        const double aoP = jsonNumber(jsonObject(m.render, "timings_ms"), "ao");
        const double aoB = jsonNumber(jsonObject(bestBase->render, "timings_ms"), "ao");
        if (std::isfinite(aoP) && std::isfinite(aoB) && aoP > 0.0)
            h += format("; the AO pass takes %.1f ms against %s's %.1f ms", aoP, escape(bestBase->name).c_str(), aoB);
        h += ".</div>";
    }
    return h;
}

// Section 2: each picked frame side by side, reference | probes | the best baseline by MAE, each method's
// error map under its frame (one scale for all, the legend under the reference); the other methods of
// the run (another bake, the other baselines) folded away under the three, in the same columns.
std::string methodFigure(const Run& run, std::size_t k, std::size_t p) {
    const RunMethod& m = run.methods[k];
    const Image& a = run.pictures[p][1 + k];
    const Image& ref = run.pictures[p][0];
    const std::string label = methodLabel(m), frame = std::to_string(run.frames[run.picked[p]].number);
    return "<figure>" + imgTag(greyUri(a), a.width, a.height, label + ", frame " + frame) +
           imgTag(heatUri(absDiff(a, ref)), a.width, a.height, label + " error, frame " + frame) +
           "<figcaption><span class=\"swatch\" style=\"background:" + methodColour(k) + "\"></span><b>" +
           escape(label) + "</b> · MAE " + fmtNum(m.mae[run.picked[p]], "%.4f") + "</figcaption></figure>";
}

std::string framesSection(const Run& run) {
    // The columns beside the reference: the first probes method (the methods come probes first) and
    // the best baseline; a run without one of them shows what it has.
    std::vector<std::size_t> shown, others;
    const RunMethod* base = bestBaseline(run, "mae");
    for (std::size_t k = 0; k < run.methods.size(); ++k) {
        const bool lead = (k == 0 && isProbesMethod(run.methods[k].name)) || &run.methods[k] == base;
        (lead || (shown.empty() && k + 1 == run.methods.size()) ? shown : others).push_back(k);
    }
    std::string h = "<h3>Frames: reference, probes and the best baseline, with |method − reference| below</h3>";
    for (std::size_t p = 0; p < run.picked.size(); ++p) {
        const RunFrame& f = run.frames[run.picked[p]];
        const Image& ref = run.pictures[p][0];
        h += "<div class=\"frame\"><div class=\"note\">frame <b>" + std::to_string(f.number) + "</b> (" +
             escape(f.name) + ")</div><div class=\"trio\">";
        h += "<figure>" + imgTag(greyUri(ref), ref.width, ref.height, "reference, frame " + std::to_string(f.number)) +
             "<figcaption><b>reference</b> (Embree)</figcaption>" +
             legendBar(run.id + "-heat" + std::to_string(p), true, linearTicks(0.0, report::kHeatMax),
                       format("|AO error| in the maps, one scale for all (%.2f and above: pale yellow)",
                              report::kHeatMax)) +
             "</figure>";
        for (const std::size_t k : shown) h += methodFigure(run, k, p);
        h += "</div>";
        if (!others.empty()) {
            std::string names;
            for (const std::size_t k : others) names += (names.empty() ? "" : ", ") + methodLabel(run.methods[k]);
            h += "<details class=\"more\"><summary>" + std::to_string(others.size()) + " more: " + escape(names) +
                 "</summary><div class=\"trio\">";
            for (const std::size_t k : others) h += methodFigure(run, k, p);
            h += "</div></details>";
        }
        h += "</div>";
    }
    return h;
}

// Section 3: per-frame MAE and flicker of every method.
std::string chartsSection(const Run& run) {
    report::LineChart mae, flicker;
    mae.title = "MAE per frame";
    mae.xLabel = flicker.xLabel = "frame";
    mae.yLabel = "MAE";
    flicker.title = "Flicker per frame (change from the previous frame)";
    flicker.yLabel = "flicker";
    mae.width = flicker.width = 565;
    for (std::size_t k = 0; k < run.methods.size(); ++k) {
        const RunMethod& m = run.methods[k];
        report::Series s{methodLabel(m), methodColour(k), {}, {}, m.name == "probes-hsplit"};
        for (const RunFrame& f : run.frames) s.x.push_back(f.number);
        s.y = m.mae;
        mae.series.push_back(s);
        s.y = m.flicker;
        flicker.series.push_back(std::move(s));
    }
    mae.right = flicker.right = 190;
    return "<h3>Per frame</h3><div class=\"charts\">" + report::lineChartSvg(mae) + report::lineChartSvg(flicker) +
           "</div><p class=\"note\">Flicker of frame <i>t</i>: mean |(a<sub>t</sub> − a<sub>t−1</sub>) − "
           "(ref<sub>t</sub> − ref<sub>t−1</sub>)| over the pixels, computed from the EXR frames.</p>";
}

// Section 4: bake and render timings.
std::string timingsSection(const Run& run) {
    std::string h = "<h3>Bake and render timings</h3>";
    if (!run.bakes.empty()) {
        h += "<table><tr><th>bake</th><th>device</th><th>probes</th><th>face</th><th>rays/texel</th><th>ms/probe</th>"
             "<th>verify MAE</th><th>AO PSNR dB</th><th>bytes/texel</th><th>cache</th></tr>";
        for (const auto& [est, b] : run.bakes) {
            json cache;
            for (const auto& [e, c] : run.caches)
                if (e == est) cache = c;
            const json settings = jsonObject(b, "settings");
            const std::string renderer = jsonString(b, "renderer");
            double bpt = jsonNumber(cache, "bytes_per_texel");
            if (!std::isfinite(bpt)) bpt = jsonNumber(b, "bytes_per_texel");
            double bytes = jsonNumber(cache, "file_bytes");
            if (!std::isfinite(bytes)) bytes = jsonNumber(b, "file_bytes");
            const double spp = jsonNumber(settings, "spp");
            h += "<tr><td>" + escape(est) + "</td><td>" +
                 escape(renderer.empty() ? "CPU (Embree)" : "GPU path, " + renderer) + "</td><td>" +
                 fmtNum(jsonNumber(b, "probes"), "%.0f") + "</td><td>" + fmtNum(jsonNumber(settings, "res"), "%.0f²") + "</td><td>" +
                 (est == "traced" ? fmtNum(spp, "%.0f") : std::string("–")) + "</td><td>" +
                 fmtNum(jsonNumber(b, "ms_per_probe"), "%.0f") + "</td><td>" + fmtNum(jsonNumber(b, "verify_mae"), "%.4f") +
                 "</td><td>" + fmtNum(jsonNumber(b, "ao_psnr"), "%.1f") + "</td><td>" + fmtNum(bpt, "%.3f") + "</td><td>" +
                 fmtNum(bytes / 1024.0, "%.0f KiB") +
                 (cache.is_object() && cache.value("verified", false) ? " ✓" : "") + "</td></tr>";
        }
        h += "</table><p class=\"note\">verify MAE: the bake against the Embree twin at every texel (– when the run "
             "skipped the check); ✓: every checksum of the cache verified (<code>cubeao info --verify</code>).</p>";
    } else {
        h += "<p class=\"note\">No bake-*.json in this run.</p>";
    }
    static const std::vector<std::pair<const char*, const char*>> kPasses = {
        {"gbuffer", "G-buffer"},  {"ao", "AO"},          {"blur", "blur"}, {"composite", "composite"},
        {"readback", "readback"}, {"gpu_total", "total"}};
    h += "<table><tr><th>render (ms per frame)</th>";
    for (const auto& [k, title] : kPasses) h += std::string("<th>") + title + "</th>";
    h += "<th>fetches/pixel</th></tr>";
    for (std::size_t k = 0; k < run.methods.size(); ++k) {
        const RunMethod& m = run.methods[k];
        const json t = jsonObject(m.render, "timings_ms");
        h += "<tr><td><span class=\"swatch\" style=\"background:" + methodColour(k) + "\"></span>" +
             escape(methodLabel(m)) + "</td>";
        for (const auto& [key, title] : kPasses) h += "<td>" + fmtNum(jsonNumber(t, key), "%.1f") + "</td>";
        h += "<td>" + fmtNum(jsonNumber(m.render, "fetches_per_pixel"), "%.1f") + "</td></tr>";
    }
    h += "</table>";
    const json& ref = run.reference;
    h += "<p class=\"note\">Reference: " + format("%lld", ref.value("spp", 0LL)) + " rays per pixel, " +
         fmtNum(jsonNumber(ref, "trace_s"), "%.0f") + " s of tracing (" + fmtNum(jsonNumber(ref, "rays_per_s") / 1e6, "%.2f") +
         " Mrays/s).</p>";
    return h;
}

// Section 5: the probes over the top-down view.
std::string planSection(const Run& run) {
    std::string h = "<h3>Probes over the scene from above, coloured by the error each removed</h3>";
    const TopDown td = renderTopDown(run, 720);
    if (td.width == 0) return h + "<p class=\"note\">No scene and no probes to draw.</p>";
    std::vector<double> gains;
    for (const json& p : run.probes.value("probes", json::array())) gains.push_back(jsonNumber(p, "gain"));
    double gMin = kNaN, gMax = kNaN;
    for (const double g : gains)
        if (std::isfinite(g))
            gMin = std::isfinite(gMin) ? std::min(gMin, g) : g, gMax = std::isfinite(gMax) ? std::max(gMax, g) : g;
    const std::vector<glm::vec3>& pos = td.probes;
    // The greedy order's first probe often removes several times what the last ones do: a log scale then
    // keeps the later probes apart.
    const bool logScale = gMin > 0.0 && gMax / gMin > 4.0;
    h += "<div class=\"plan\">" + imgTag(td.uri, td.width, td.height, "top-down view of the scene");
    // imgTag upscales small plans by its own rule; the overlay follows the image's displayed size.
    const int us = upscale(td.width);
    h += format("<svg width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">", td.width * us, td.height * us, td.width,
                td.height);
    if (td.walk.size() > 1) {
        // The walk under the probes: a white halo keeps the line readable on any shade.
        std::string points;
        for (const glm::vec3& e : td.walk) {
            const glm::vec2 p = td.toPixel(e);
            points += format("%.1f,%.1f ", p.x, p.y);
        }
        for (const auto& [colour, width] : {std::pair{"#fff", 4.0}, std::pair{"#c0392b", 1.8}})
            h += format("<polyline fill=\"none\" stroke-linejoin=\"round\" stroke-width=\"%.2f\" stroke=\"%s\" "
                        "points=\"%s\"/>",
                        width / us, colour, points.c_str());
    }
    const double r = std::max(3.5, 7.0 / us);
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const glm::vec2 p = td.toPixel(pos[i]);
        const double g = i < gains.size() ? gains[i] : kNaN;
        const double t = !std::isfinite(g) || !(gMax > gMin) ? 0.5
                         : logScale                          ? std::log(g / gMin) / std::log(gMax / gMin)
                                                             : (g - gMin) / (gMax - gMin);
        h +=
            format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%.1f\" fill=\"", p.x, p.y, r) +
            report::cssColour(report::gainColour(t)) +
            format("\" stroke=\"#fff\" stroke-width=\"%.2f\"><title>probe %zu: removed %.4f of the predicted MAE, height %.2f</title></circle>",
                   1.5 / us, i, g, double(glm::dot(pos[i], td.up)));
    }
    // The frames shown as pictures, by number, where the camera stood (over the probes).
    if (td.walk.size() > 1)
        for (const std::size_t i : run.picked) {
            const int n = run.frames[i].number;
            if (n < 0 || std::size_t(n) >= td.walk.size()) continue;
            const glm::vec2 p = td.toPixel(td.walk[std::size_t(n)]);
            h += format("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#c0392b\"/>",
                        p.x - 3.0 / us, p.y - 3.0 / us, 6.0 / us, 6.0 / us);
            h += format("<text x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\" fill=\"#c0392b\" stroke=\"#fff\" "
                        "stroke-width=\"%.2f\" paint-order=\"stroke\">frame %d</text>",
                        p.x + 6.0 / us, p.y - 5.0 / us, 11.0 / us, 3.0 / us, n);
        }
    // A scale bar of a round length, bottom left.
    const double barLen = report::niceStep(0.25 * td.width * td.pixel, 1);
    const double barPx = barLen / td.pixel, bx = 8.0 / us, by = td.height - 10.0 / us;
    h += format("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#fff\" opacity=\"0.8\"/>",
                bx - 3 / double(us), by - 14.0 / us, barPx + 6.0 / us, 20.0 / us);
    h += format("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#222\" stroke-width=\"%.2f\"/>", bx, by,
                bx + barPx, by, 2.0 / us);
    h += format("<text x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\" fill=\"#222\">%s</text>", bx, by - 4.0 / us, 11.0 / us,
                (report::tickLabel(barLen, barLen) + " units").c_str());
    h += "</svg></div>";
    if (std::isfinite(gMin) && gMax > gMin)
        h += legendBar(run.id + "-gain", false, logScale ? logTicks(gMin, gMax) : linearTicks(gMin, gMax),
                       std::string("predicted walk MAE the probe removed (after the probes placed before it)") +
                           (logScale ? ", log scale" : ""));
    h += "<p class=\"note\">Orthographic, from above";
    if (td.walk.size() > 1) h += "; red: the camera walk, squares where the frames above were taken";
    if (td.cutBelowTop)
        h += format("; cut at height %.2f (half an AO radius above %s) so that roofs do not hide the floor; probes "
                    "above the cut are drawn all the same",
                    double(td.cut), td.cutAbove);
    h += "; lighter is higher, dark edges are the feet of walls. Scale bar in scene units.";
    if (!td.note.empty()) h += " <span class=\"warn\">" + escape(td.note) + ".</span>";
    h += "</p>";
    return h;
}

std::string runSection(Run& run) {
    const std::string scene = jsonString(run.info, "scene", run.dir.string());
    std::string h = "<section class=\"run\" id=\"" + run.id + "\"><h2>" + escape(fs::path(scene).filename().string()) +
                    "</h2><div class=\"note\">" + escape(scene) + " · run " + escape(run.dir.string()) + "</div>";
    h += runFacts(run) + metricsTable(run) + verdicts(run);
    h += framesSection(run);
    run.pictures.clear();  // done with them: several runs need not all be in memory at once
    h += chartsSection(run);
    h += timingsSection(run);
    h += planSection(run);
    h += "</section>";
    return h;
}

void writeAtomically(const fs::path& out, const std::string& text) {
    const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw Error("cannot write " + out.string() + ": " + dir.string() + " is not a directory");
    writeFileDurably(out, text, "report");
}

void runReport(const ReportOptions& opt) {
    const std::vector<int> wantFrames = opt.frames.empty() ? std::vector<int>{} : parseFrameList(opt.frames);
    // Every run is checked before any work, so a typo in the last DIR fails at once.
    std::vector<Run> runs;
    for (std::size_t i = 0; i < opt.dirs.size(); ++i) {
        try {
            runs.push_back({loadRun(opt.dirs[i], wantFrames), ""});
        } catch (const json::exception& e) {
            throw Error(opt.dirs[i] + ": unexpected content in its JSON files: " + e.what());
        }
        runs.back().id = "run" + std::to_string(i + 1);
    }
    std::string body;
    std::size_t images = 0;
    for (Run& run : runs) {
        spdlog::info("report: {} ({} methods, {} frames)", run.dir.string(), run.methods.size(), run.frames.size());
        measureFrames(run);
        images += run.picked.size() * (1 + 2 * run.methods.size()) + 1;
        try {
            body += runSection(run);
        } catch (const json::exception& e) {  // a field of another type than demo.sh writes
            throw Error(run.dir.string() + ": unexpected content in its JSON files: " + e.what());
        }
    }
    std::string title = "cubeao report";
    if (runs.size() == 1) title += " — " + fs::path(jsonString(runs[0].info, "scene", "run")).filename().string();
    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escape(title) +
                       "</title><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>" +
                       kCss + "</style><script>" + kScript + "</script></head><body>";
    html += "<header class=\"page\"><h1>" + escape(title) +
            "</h1><p>Ambient occlusion from cube-map probes against "
            "screen-space baselines and an Embree reference · generated " +
            when + "</p></header><main>";
    if (runs.size() > 1) {
        html += "<nav>";
        for (const Run& run : runs)
            html += "<a href=\"#" + run.id + "\">" +
                    escape(fs::path(jsonString(run.info, "scene", run.dir.string())).filename().string()) + "</a>";
        html += "</nav>";
    }
    html += body + "</main></body></html>\n";
    writeAtomically(opt.out, html);
    std::printf("report: %s (%zu run%s, %zu images, %.1f MB)\n", opt.out.c_str(), runs.size(),
                runs.size() == 1 ? "" : "s", images, double(html.size()) / 1e6);
    if (opt.json) {
        json dirs = json::array();
        for (const Run& run : runs) dirs.push_back(run.dir.string());
        std::fflush(stdout);
        printJson({{"out", opt.out}, {"runs", dirs}, {"images", images}, {"bytes", html.size()}});
    }
}

}  // namespace

void addReport(CLI::App& app) {
    auto opt = std::make_shared<ReportOptions>();
    CLI::App* cmd =
        app.add_subcommand("report", "One self-contained HTML page for render/compare runs (tools/demo.sh)");
    // Plain strings: a DIR that is not a run is a failure naming the missing file (exit 1), not bad usage.
    cmd->add_option("DIR", opt->dirs, "Run directories (tools/demo.sh's CUBEAO_DEMO_OUT), one section each")
        ->required();
    cmd->add_option("--out", opt->out, "HTML file to write")->required();
    cmd->add_option("--frames", opt->frames,
                    "RunFrame numbers to show as pictures, N,M,... (default: first, middle, last)");
    cmd->add_flag("--json", opt->json, "Print one JSON object as the last line");
    cmd->callback([opt] { runReport(*opt); });
}

}  // namespace cubeao::cli
