// Wall-clock stage timing for reports (`--json` timings): seconds since construction or the last
// restart(). Benchmarks use Google Benchmark; this is for the stages a command reports.
#pragma once

#include <chrono>

namespace cubeao {

class Stopwatch {
public:
    double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
    // Seconds since the last restart (or construction), and starts again.
    double restart() {
        const Clock::time_point now = Clock::now();
        const double s = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return s;
    }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_ = Clock::now();
};

}  // namespace cubeao
