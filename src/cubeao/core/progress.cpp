#include "cubeao/core/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace cubeao {
namespace {

constexpr std::int64_t kBarIntervalNs = 100'000'000;  // a terminal bar: ~10 redraws a second

// Seconds between lines when stderr is not a terminal: CUBEAO_PROGRESS_SECONDS, default 5.
std::int64_t lineIntervalNs() {
    double seconds = 5.0;
    if (const char* env = std::getenv("CUBEAO_PROGRESS_SECONDS"); env != nullptr && *env != '\0') {
        char* end = nullptr;
        const double v = std::strtod(env, &end);
        if (end != env && *end == '\0' && std::isfinite(v) && v >= 0.0 && v <= 86400.0) seconds = v;
    }
    return std::int64_t(seconds * 1e9);
}

// "1.2 s", "3 min 05 s", "2 h 07 min": durations people read at a glance.
std::string duration(double s) {
    char buf[48];
    if (!std::isfinite(s) || s < 0) return "?";
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s) / 3600, int(s) % 3600 / 60);
    return buf;
}

}  // namespace

Progress::Mode Progress::mode() {
    if (const char* env = std::getenv("CUBEAO_PROGRESS"); env != nullptr) {
        if (std::strcmp(env, "off") == 0) return Mode::Off;
        if (std::strcmp(env, "lines") == 0) return Mode::Lines;
        if (std::strcmp(env, "bar") == 0) return Mode::Bar;
    }
    return isatty(STDERR_FILENO) == 1 ? Mode::Bar : Mode::Lines;
}

bool Progress::enabled() { return mode() == Mode::Bar; }

std::string Progress::describe(std::uint64_t done, std::uint64_t total, double seconds, const std::string& unit) {
    const std::string units = unit.empty() ? "" : " " + unit;
    const double rate = seconds > 0 ? double(done) / seconds : 0.0;
    char buf[160];
    if (total > 0) {
        const double frac = double(done) / double(total);
        const double eta = done > 0 ? seconds * (1.0 - frac) / frac : NAN;
        std::snprintf(buf, sizeof buf, "%llu/%llu%s (%.1f %%), %.3g%s/s, %s, eta %s", (unsigned long long)done,
                      (unsigned long long)total, units.c_str(), 100.0 * frac, rate, unit.empty() ? "" : units.c_str(),
                      duration(seconds).c_str(), done >= total ? "0 s" : duration(eta).c_str());
    } else {
        std::snprintf(buf, sizeof buf, "%llu%s, %.3g%s/s, %s", (unsigned long long)done, units.c_str(), rate,
                      unit.empty() ? "" : units.c_str(), duration(seconds).c_str());
    }
    return buf;
}

Progress::Progress(std::string label, std::uint64_t total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      mode_(mode()),
      intervalNs_(mode_ == Mode::Bar ? kBarIntervalNs : lineIntervalNs()) {}

Progress::~Progress() {
    if (mode_ == Mode::Bar || (mode_ == Mode::Lines && printedLine_)) draw(true);
}

void Progress::advance(std::uint64_t n) {
    done_.fetch_add(n, std::memory_order_relaxed);
    if (mode_ == Mode::Off) return;
    const auto now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
    auto last = lastDrawNs_.load(std::memory_order_relaxed);
    if (now - last < intervalNs_) return;
    if (lastDrawNs_.compare_exchange_strong(last, now)) draw(false);
}

void Progress::draw(bool final) {
    std::lock_guard lock(drawMutex_);
    const std::uint64_t done = this->done();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (mode_ == Mode::Lines) {
        std::fprintf(stderr, "%s: %s%s\n", label_.c_str(), describe(done, total_, secs, unit_).c_str(),
                     final ? " (done)" : "");
        printedLine_ = true;
        std::fflush(stderr);
        return;
    }
    const double frac = total_ ? std::min(1.0, double(done) / double(total_)) : 0.0;
    constexpr int kWidth = 24;
    std::string bar(std::size_t(frac * kWidth + 0.5), '#');
    bar.resize(kWidth, total_ ? '.' : ' ');
    // \033[K clears what a longer previous line left.
    std::fprintf(stderr, "\r%-14s [%s] %s\033[K", label_.c_str(), bar.c_str(),
                 describe(done, total_, secs, unit_).c_str());
    if (final) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace cubeao
