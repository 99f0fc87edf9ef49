// A progress bar for long jobs. Draws on stderr only when stderr is a terminal (DESIGN.md §5),
// so logs and CI output stay clean. advance() is thread-safe and cheap (one atomic add); the bar is
// redrawn at most ~10 times a second.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace cubeao {

class Progress {
public:
    Progress(std::string label, std::uint64_t total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(std::uint64_t n = 1);
    std::uint64_t done() const { return done_.load(std::memory_order_relaxed); }
    static bool enabled();  // stderr is a terminal

private:
    void draw(bool final);

    std::string label_;
    std::uint64_t total_;
    std::atomic<std::uint64_t> done_{0};
    std::atomic<std::int64_t> lastDrawNs_{0};
    std::chrono::steady_clock::time_point start_;
    std::mutex drawMutex_;
    bool enabled_;
};

}  // namespace cubeao
