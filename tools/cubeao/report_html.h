// Pieces of `cubeao report`'s self-contained HTML page that have known answers, kept apart from the
// command so tests/cli/test_report.cpp can check them: base64 for data: URIs, HTML escaping, the fixed
// colour scales (error heat map, probe gain), a linear axis scale with round ticks, and the inline
// SVG line chart built on them. Header-only: the CLI and the test suite each compile it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace cubeao::cli::report {

// RFC 4648 base64 with padding (what a data: URI wants).
inline std::string base64(const unsigned char* data, std::size_t n) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((n + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 3 <= n; i += 3) {
        const unsigned v = unsigned(data[i]) << 16 | unsigned(data[i + 1]) << 8 | unsigned(data[i + 2]);
        out += kAlphabet[v >> 18 & 63], out += kAlphabet[v >> 12 & 63];
        out += kAlphabet[v >> 6 & 63], out += kAlphabet[v & 63];
    }
    if (n - i == 1) {
        const unsigned v = unsigned(data[i]) << 16;
        out += kAlphabet[v >> 18 & 63], out += kAlphabet[v >> 12 & 63], out += "==";
    } else if (n - i == 2) {
        const unsigned v = unsigned(data[i]) << 16 | unsigned(data[i + 1]) << 8;
        out += kAlphabet[v >> 18 & 63], out += kAlphabet[v >> 12 & 63], out += kAlphabet[v >> 6 & 63], out += '=';
    }
    return out;
}

inline std::string base64(const std::string& s) {
    return base64(reinterpret_cast<const unsigned char*>(s.data()), s.size());
}

inline std::string pngDataUri(const std::vector<unsigned char>& png) {
    return "data:image/png;base64," + base64(png.data(), png.size());
}

// Text and attribute values: the five characters HTML gives a meaning.
inline std::string escape(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&#39;"; break;
        default: out += c;
        }
    }
    return out;
}

// printf into a std::string (numbers in tables and SVG coordinates).
template <typename... Args>
std::string format(const char* fmt, Args... args) {
    char buf[256];
    const int n = std::snprintf(buf, sizeof buf, fmt, args...);
    if (n < int(sizeof buf)) return std::string(buf, std::size_t(std::max(n, 0)));
    std::string big(std::size_t(n) + 1, '\0');
    std::snprintf(big.data(), big.size(), fmt, args...);
    big.resize(std::size_t(n));
    return big;
}

using Rgb = std::array<float, 3>;  // 0..1 per channel

// Piecewise-linear colour ramp through evenly spaced stops; t is clamped to [0, 1].
template <std::size_t N>
Rgb ramp(const std::array<Rgb, N>& stops, double t) {
    if (!(t > 0.0)) return stops.front();  // also NaN
    if (t >= 1.0) return stops.back();
    const double x = t * double(N - 1);
    const std::size_t i = std::min(std::size_t(x), N - 2);
    const float f = float(x - double(i));
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = stops[i][k] + f * (stops[i + 1][k] - stops[i][k]);
    return c;
}

// The error heat map: inferno-like (black, purple, red, orange, pale yellow), dark where the method
// matches the reference, so the eye goes to the bright errors. A fixed scale, not per image: the
// same colour means the same error in every picture of the page.
inline constexpr double kHeatMax = 0.25;  // |AO error| at the top of the scale (and above: clamped)
inline Rgb heatColour(double t) {
    static constexpr std::array<Rgb, 5> kStops{{{0.0f, 0.0f, 4 / 255.0f},
                                                {87 / 255.0f, 16 / 255.0f, 110 / 255.0f},
                                                {188 / 255.0f, 55 / 255.0f, 84 / 255.0f},
                                                {249 / 255.0f, 142 / 255.0f, 9 / 255.0f},
                                                {252 / 255.0f, 255 / 255.0f, 164 / 255.0f}}};
    return ramp(kStops, t);
}

// Probe gain over the grey top-down view: viridis-like (dark blue to yellow), readable on grey.
inline Rgb gainColour(double t) {
    static constexpr std::array<Rgb, 5> kStops{{{68 / 255.0f, 1 / 255.0f, 84 / 255.0f},
                                                {59 / 255.0f, 82 / 255.0f, 139 / 255.0f},
                                                {33 / 255.0f, 145 / 255.0f, 140 / 255.0f},
                                                {94 / 255.0f, 201 / 255.0f, 98 / 255.0f},
                                                {253 / 255.0f, 231 / 255.0f, 37 / 255.0f}}};
    return ramp(kStops, t);
}

inline std::string cssColour(const Rgb& c) {
    auto byte = [](float v) { return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return format("#%02x%02x%02x", byte(c[0]), byte(c[1]), byte(c[2]));
}

// The step of round ticks (1, 2 or 5 times a power of ten) that splits `span` into about `count`.
inline double niceStep(double span, int count) {
    if (!(span > 0.0) || count < 1) return 1.0;
    const double raw = span / count, mag = std::pow(10.0, std::floor(std::log10(raw))), r = raw / mag;
    return (r <= 1.0 ? 1.0 : r <= 2.0 ? 2.0 : r <= 5.0 ? 5.0 : 10.0) * mag;
}

// Maps the domain [d0, d1] linearly onto the range [r0, r1] (pixels; r0 > r1 for a y axis).
struct LinearScale {
    double d0 = 0.0, d1 = 1.0, r0 = 0.0, r1 = 1.0;
    double operator()(double v) const { return d1 == d0 ? r0 : r0 + (v - d0) * (r1 - r0) / (d1 - d0); }
};

// Round ticks from `lo` up to the first tick at or above `hi` (so the axis ends on a tick).
inline std::vector<double> niceTicks(double lo, double hi, int count) {
    if (hi <= lo) hi = lo + 1.0;
    const double step = niceStep(hi - lo, count);
    std::vector<double> ticks;
    const double first = std::floor(lo / step + 1e-9) * step;
    for (int i = 0;; ++i) {
        const double t = first + i * step;
        ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
        if (t >= hi - step * 1e-9 || i > 1000) break;
    }
    return ticks;
}

struct Series {
    std::string name, colour;  // colour: any CSS colour
    std::vector<double> x, y;  // same length
    bool dashed = false;
};

struct LineChart {
    std::string title, xLabel, yLabel;
    std::vector<Series> series;
    int width = 600, height = 300;
    // Plot area inside the SVG: room for tick labels and axis titles on the left and below, and for
    // the title above; the legend sits to the right of the plot.
    int left = 64, right = 150, top = 30, bottom = 46;
};

// The chart's axis scales: x over the data's x range, y from 0 to a round tick above the largest y
// (errors are never negative, and a y axis from 0 shows ratios between methods honestly).
struct ChartScales {
    LinearScale x, y;
    std::vector<double> xTicks, yTicks;
};

inline ChartScales chartScales(const LineChart& c) {
    double x0 = 0.0, x1 = 0.0, y1 = 0.0;
    bool any = false;
    for (const Series& s : c.series)
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
            x0 = any ? std::min(x0, s.x[i]) : s.x[i], x1 = any ? std::max(x1, s.x[i]) : s.x[i];
            y1 = std::max(y1, s.y[i]);
            any = true;
        }
    if (x1 <= x0) x1 = x0 + 1.0;
    if (!(y1 > 0.0)) y1 = 1.0;
    ChartScales s;
    s.xTicks = niceTicks(x0, x1, 8);
    // x runs over the data exactly (frames have no room before the first); ticks outside are dropped.
    s.xTicks.erase(std::remove_if(s.xTicks.begin(), s.xTicks.end(),
                                  [&](double t) { return t < x0 - 1e-9 || t > x1 + 1e-9; }),
                   s.xTicks.end());
    s.yTicks = niceTicks(0.0, y1, 5);
    s.x = {x0, x1, double(c.left), double(c.width - c.right)};
    s.y = {0.0, s.yTicks.back(), double(c.height - c.bottom), double(c.top)};
    return s;
}

// A tick label without trailing zeros: 0.05, 0.1, 12.
inline std::string tickLabel(double v, double step) {
    const int decimals = step >= 1.0 ? 0 : int(std::ceil(-std::log10(step) - 1e-9));
    return format("%.*f", std::clamp(decimals, 0, 6), v);
}

inline std::string lineChartSvg(const LineChart& c) {
    const ChartScales s = chartScales(c);
    const double px0 = s.x.r0, px1 = s.x.r1, py0 = s.y.r0, py1 = s.y.r1;
    std::string svg = format("<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                             "viewBox=\"0 0 %d %d\" role=\"img\">",
                             c.width, c.height, c.width, c.height);
    svg += "<title>" + escape(c.title) + "</title>";
    svg += format("<text class=\"ctitle\" x=\"%.1f\" y=\"18\">", px0) + escape(c.title) + "</text>";
    // Grid and y ticks.
    const double yStep = s.yTicks.size() > 1 ? s.yTicks[1] - s.yTicks[0] : 1.0;
    for (const double t : s.yTicks) {
        const double y = s.y(t);
        svg += format("<line class=\"grid\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>", px0, y, px1, y);
        svg += format("<text class=\"tick\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">", px0 - 6, y + 4) +
               tickLabel(t, yStep) + "</text>";
    }
    const double xStep = s.xTicks.size() > 1 ? s.xTicks[1] - s.xTicks[0] : 1.0;
    for (const double t : s.xTicks) {
        const double x = s.x(t);
        svg += format("<line class=\"axis\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>", x, py0, x, py0 + 5);
        svg += format("<text class=\"tick\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", x, py0 + 18) +
               tickLabel(t, xStep) + "</text>";
    }
    svg += format("<line class=\"axis\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>", px0, py0, px1, py0);
    svg += format("<line class=\"axis\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>", px0, py0, px0, py1);
    svg += format("<text class=\"label\" x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">", 0.5 * (px0 + px1),
                  c.height - 8) + escape(c.xLabel) + "</text>";
    svg += format("<text class=\"label\" transform=\"translate(14 %.1f) rotate(-90)\" text-anchor=\"middle\">",
                  0.5 * (py0 + py1)) + escape(c.yLabel) + "</text>";
    // One polyline per series (a lone point gets a dot so it is still seen), then the legend.
    for (std::size_t k = 0; k < c.series.size(); ++k) {
        const Series& ser = c.series[k];
        std::string points;
        std::size_t count = 0;
        for (std::size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i) {
            if (!std::isfinite(ser.x[i]) || !std::isfinite(ser.y[i])) continue;
            points += format("%.1f,%.1f ", s.x(ser.x[i]), s.y(ser.y[i]));
            ++count;
        }
        if (!points.empty()) points.pop_back();
        svg += "<polyline class=\"series\" fill=\"none\" stroke=\"" + ser.colour + "\" stroke-width=\"2\"" +
               (ser.dashed ? " stroke-dasharray=\"6 3\"" : "") + " points=\"" + points + "\"><title>" +
               escape(ser.name) + "</title></polyline>";
        if (count == 1)
            svg += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"", s.x(ser.x[0]), s.y(ser.y[0])) +
                   ser.colour + "\"/>";
        const double ly = c.top + 8 + 20.0 * double(k), lx = px1 + 16;
        svg += format("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke-width=\"2\" stroke=\"", lx, ly,
                      lx + 22, ly) + ser.colour + "\"" + (ser.dashed ? " stroke-dasharray=\"6 3\"" : "") + "/>";
        svg += format("<text class=\"legend\" x=\"%.1f\" y=\"%.1f\">", lx + 28, ly + 4) + escape(ser.name) +
               "</text>";
    }
    svg += "</svg>";
    return svg;
}

}  // namespace cubeao::cli::report
