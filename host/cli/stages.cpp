#include "cli/stages.hpp"

#include <algorithm>
#include <cstdio>

namespace msmcl::cli {
namespace {

double milliseconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

Stages::Stages(bool verbose, int planned) : verbose_(verbose), planned_(planned > 0 ? planned : 1) {
    // --verbose prints lines instead of the progress line.
    progress_ = std::make_unique<ProgressLine>(!verbose_, [this](double elapsed_s) { return progress_text(elapsed_s); });
}

Stages::~Stages() = default;

void Stages::begin(const std::string& name) {
    stage_start_ = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    stage_ = name;
}

void Stages::end() {
    std::string name;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        name = stage_;
    }
    finished(name, milliseconds_since(stage_start_), "");
}

void Stages::finished(const std::string& name, double ms, const std::string& note) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++done_;
    }
    if (verbose_) {
        std::fprintf(stderr, "msmcl: %s: %.1f ms%s\n", name.c_str(), ms, note.empty() ? "" : (" (" + note + ")").c_str());
        std::fflush(stderr);
    }
}

StageObserver Stages::observer() {
    return [this](const StageTime& time) { finished(time.stage, time.milliseconds, time.note); };
}

std::string Stages::progress_text(double elapsed_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    char text[256];
    std::snprintf(text, sizeof text, "msmcl: %s %d/%d %s %.1f s",
                  progress_bar(static_cast<std::size_t>(done_), static_cast<std::size_t>(planned_)).c_str(),
                  std::min(done_ + 1, planned_), planned_, stage_.c_str(), elapsed_s);
    return text;
}

} // namespace msmcl::cli
