#include "cli/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace msmcl::cli {
namespace {
std::atomic<bool> quiet_process{false};
} // namespace

void set_quiet(bool quiet) { quiet_process = quiet; }

ProgressLine::ProgressLine(bool wanted, std::function<std::string(double)> text) : text_(std::move(text)) {
    start_ = std::chrono::steady_clock::now();
    // Progress only for a person watching a terminal.
    active_ = wanted && !quiet_process && ::isatty(STDERR_FILENO) == 1;
    // MSMCL_PROGRESS_AFTER_MS: how long work runs before the line appears (500).
    if (const char* delay = std::getenv("MSMCL_PROGRESS_AFTER_MS")) after_ms_ = std::strtod(delay, nullptr);
    if (!active_) return;
    // A delay of 0 draws at once: the line then shows however short the command is.
    if (after_ms_ <= 0.0) draw();
    painter_ = std::thread([this] { paint(); });
}

ProgressLine::~ProgressLine() {
    if (!active_) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    painter_.join();
    // Erase the line so that what follows starts on a clean line.
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

void ProgressLine::paint() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
        wake_.wait_for(lock, std::chrono::milliseconds(100));
        if (stop_) break;
        // Long work only: nothing for commands that finish within the delay.
        const double elapsed_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
        if (elapsed_ms < after_ms_) continue;
        draw();
    }
}

void ProgressLine::draw() {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "\r\033[K%s", text_(elapsed_s).c_str());
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressLine::print(const std::string& line) {
    if (!active_) {
        std::fprintf(stderr, "%s\n", line.c_str());
        std::fflush(stderr);
        return;
    }
    // Erase the progress line, print, and leave the redrawing to the next tick.
    std::lock_guard<std::mutex> lock(mutex_);
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

std::string progress_bar(std::size_t done, std::size_t total, int width) {
    const std::size_t columns = static_cast<std::size_t>(width);
    const std::size_t filled = total == 0 ? 0 : std::min(columns, done * columns / total);
    std::string bar(filled, '#');
    bar.resize(columns, '.');
    return "[" + bar + "]";
}

} // namespace msmcl::cli
