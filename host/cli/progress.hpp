// A progress line on stderr for a person watching a terminal: redrawn every 100 ms once
// work has run longer than a delay (500 ms; MSMCL_PROGRESS_AFTER_MS, 0 draws at once),
// erased when the line is destroyed. Off when stderr is no terminal, so logs and pipes
// stay clean. The text comes from the owner (the stages of one command, the files of a
// batch) and is asked for from the drawing thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace msmcl::cli {

class ProgressLine {
public:
    /// `text(elapsed_seconds)`: the line without "\r"; called from the drawing thread, so it
    /// must lock what it reads. `wanted`: false keeps the line off (e.g. --verbose).
    ProgressLine(bool wanted, std::function<std::string(double)> text);
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    /// Whether the line is drawn at all (wanted and stderr a terminal).
    bool active() const { return active_; }

    /// Prints `line` and a newline on stderr, above the progress line (erased, redrawn at
    /// the next tick). Callable from any thread; must not be called holding a lock that
    /// `text` takes.
    void print(const std::string& line);

private:
    void paint();
    void draw(); ///< the caller holds mutex_ (or no painter runs yet)

    bool active_ = false;
    double after_ms_ = 500.0;
    std::function<std::string(double)> text_;
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    bool drawn_ = false;
    std::thread painter_;
};

/// -q/--quiet: no progress line in this process (nothing on stderr but errors).
void set_quiet(bool quiet);

/// "[#######.............]": `done` of `total` as a bar of `width` characters.
std::string progress_bar(std::size_t done, std::size_t total, int width = 20);

} // namespace msmcl::cli
