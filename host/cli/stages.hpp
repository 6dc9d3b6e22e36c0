// Stages of one msmcl command, timed for --verbose and shown as progress on a terminal.
//  - --verbose: one line per stage on stderr, "msmcl: <stage>: <ms> ms[ (<note>)]";
//  - stderr a terminal (and not --verbose): a progress line on stderr, redrawn while work
//    has run for more than half a second (MSMCL_PROGRESS_AFTER_MS), erased when the command
//    ends; nothing otherwise, so logs and pipes stay clean.
// The library never prints: the stages are timed here, around its calls; with --verbose a
// library call reports its own stages (upload, program, kernel, download: StageObserver).
#pragma once

#include "cli/progress.hpp"

#include <msmcl/types.hpp>

#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>

namespace msmcl::cli {

class Stages {
public:
    /// `planned`: how many stages the command will run (the progress bar's length).
    Stages(bool verbose, int planned);
    ~Stages();
    Stages(const Stages&) = delete;
    Stages& operator=(const Stages&) = delete;

    bool verbose() const { return verbose_; }

    /// Runs `work` as the stage `name` and returns what it returns.
    template <class Work>
    auto run(const std::string& name, Work&& work) -> decltype(work()) {
        begin(name);
        if constexpr (std::is_void_v<decltype(work())>) {
            work();
            end();
        } else {
            auto result = work();
            end();
            return result;
        }
    }
    /// Runs the library call `call(observer)` as the stage `name`; with --verbose the call
    /// is given an observer that prints the stages it reports instead.
    template <class Call>
    auto run_call(const std::string& name, Call&& call) -> decltype(call(StageObserver{})) {
        if (verbose_) return call(observer());
        return run(name, [&] { return call(StageObserver{}); });
    }

private:
    void begin(const std::string& name);
    void end();
    /// Prints the line of a finished stage (--verbose) and counts it.
    void finished(const std::string& name, double ms, const std::string& note);
    StageObserver observer();
    /// The progress line's text: the bar over the planned stages, the current one, the time.
    std::string progress_text(double elapsed_s);

    bool verbose_ = false;
    int planned_ = 1;
    int done_ = 0;
    std::chrono::steady_clock::time_point stage_start_;

    // What the progress line shows, read by its drawing thread.
    std::mutex mutex_;
    std::string stage_;
    std::unique_ptr<ProgressLine> progress_;
};

} // namespace msmcl::cli
