#include "cubeao/core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace cubeao {

bool Progress::enabled() { return isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, std::uint64_t total)
    : label_(std::move(label)), total_(total), start_(std::chrono::steady_clock::now()), enabled_(enabled()) {}

Progress::~Progress() {
    if (enabled_) draw(true);
}

void Progress::advance(std::uint64_t n) {
    done_.fetch_add(n, std::memory_order_relaxed);
    if (!enabled_) return;
    const auto now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                         std::chrono::steady_clock::now() - start_).count();
    auto last = lastDrawNs_.load(std::memory_order_relaxed);
    if (now - last < 100'000'000) return;
    if (lastDrawNs_.compare_exchange_strong(last, now)) draw(false);
}

void Progress::draw(bool final) {
    std::lock_guard lock(drawMutex_);
    const double frac = total_ ? double(done()) / double(total_) : 1.0;
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = frac > 0 ? secs * (1.0 - frac) / frac : 0.0;
    constexpr int kWidth = 30;
    const int filled = int(frac * kWidth + 0.5);
    std::string bar(std::size_t(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%-12s [%s] %5.1f%%  %6.1fs  eta %6.1fs", label_.c_str(), bar.c_str(), 100.0 * frac,
                 secs, eta);
    if (final) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace cubeao
