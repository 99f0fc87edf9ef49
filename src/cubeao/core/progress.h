// Progress of a long job (reference, place, bake, render, merge, export) on stderr (DESIGN.md §5):
// - stderr a terminal: a bar redrawn in place at most ~10 times a second, with rate and ETA;
// - otherwise (logs, CI, Slurm): one plain line every few seconds (CUBEAO_PROGRESS_SECONDS, default
//   5; 0 = every step, for tests) and a closing line, only for a job that ran that long, so short jobs
//   stay quiet;
// - CUBEAO_PROGRESS=off: nothing; =lines or =bar: that mode whatever stderr is.
// advance() is thread-safe and cheap (an atomic add and a clock read).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace cubeao {

class Progress {
public:
    // total 0: unknown (count and rate, no percentage or ETA). unit names what is counted ("probes").
    Progress(std::string label, std::uint64_t total, std::string unit = "");
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(std::uint64_t n = 1);
    std::uint64_t done() const { return done_.load(std::memory_order_relaxed); }

    enum class Mode { Off, Bar, Lines };
    static Mode mode();     // CUBEAO_PROGRESS, else whether stderr is a terminal
    static bool enabled();  // mode() == Bar (kept for callers that print around a bar)

    // The text after the label for `done` of `total` after `seconds` (the line mode's line, and the bar's
    // figures); public for tests.
    static std::string describe(std::uint64_t done, std::uint64_t total, double seconds, const std::string& unit);

private:
    void draw(bool final);

    std::string label_;
    std::string unit_;
    std::uint64_t total_;
    std::atomic<std::uint64_t> done_{0};
    std::atomic<std::int64_t> lastDrawNs_{0};
    std::chrono::steady_clock::time_point start_;
    std::mutex drawMutex_;
    Mode mode_;
    std::int64_t intervalNs_;
    bool printedLine_ = false;  // line mode: a closing line only after a periodic one
};

}  // namespace cubeao
