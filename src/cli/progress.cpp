// The progress line: a thread redraws it five times a second once a run has lasted a second.
#include "cli/progress.hpp"
#include "base/text.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace fdmsurf::cli {

namespace {

// "K/N" at the end of `name` as K / N, or -1.
double ratio_at_end(std::string_view name) {
    const std::size_t slash = name.rfind('/');
    const std::size_t space = name.rfind(' ', slash);
    if (slash == std::string_view::npos || space == std::string_view::npos) return -1.0;
    const double k = std::atof(std::string(name.substr(space + 1, slash - space - 1)).c_str());
    const double n = std::atof(std::string(name.substr(slash + 1)).c_str());
    return n > 0 ? std::clamp(k / n, 0.0, 1.0) : -1.0;
}

}  // namespace

bool progress_wanted(bool quiet) {
    const char* env = std::getenv("FDMSURF_PROGRESS");
    if (quiet || (env && std::strcmp(env, "never") == 0)) return false;
    if (env && std::strcmp(env, "always") == 0) return true;
    return isatty(STDERR_FILENO) == 1;
}

double Progress::fraction_after(std::string_view name) {
    // Slabs: each slab's field, then marching cubes on the core before it, one after the other.
    if (name.starts_with("field slab") || name.starts_with("marching cubes, z"))
        return 0.15 + 0.60 * std::max(0.0, ratio_at_end(name));
    struct Mark {
        std::string_view prefix;
        double done;
    };
    static constexpr Mark marks[] = {
        {"parse", 0.05},     {"init", 0.10},          {"bin-atoms", 0.15},
        {"ses-features", 0.15}, {"density", 0.75},    {"ses-distance", 0.75},
        {"stitch", 0.76},    {"refine", 0.79},        {"snap", 0.81},
        {"pieces", 0.815},   {"cavities", 0.82},
        {"vertex properties", 0.92}, {"patch", 0.94}, {"write", 0.98},
        {"mesh-stats", 1.0},
    };
    for (const Mark& m : marks)
        if (name.starts_with(m.prefix)) return m.done;
    return 0.0;
}

double progress_delay() {
    const char* env = std::getenv("FDMSURF_PROGRESS_AFTER");
    if (!env || !*env) return 1.0;
    char* end = nullptr;
    const double seconds = std::strtod(env, &end);
    return end != env && *end == '\0' && seconds >= 0.0 ? seconds : 1.0;
}

Progress::Progress(bool enabled) : enabled_(enabled), after_(progress_delay()) {
    if (enabled_) thread_ = std::thread([this] { tick(); });
}

Progress::~Progress() {
    if (!enabled_) return;
    end();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void Progress::begin(const std::string& what) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    what_ = detail::printable(what);
    last_.clear();
    done_ = 0.0;
    start_ = std::chrono::steady_clock::now();
    running_ = true;
}

void Progress::stage(std::string_view name) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    last_ = std::string(name);
    done_ = std::max(done_, fraction_after(name));
    if (running_) draw_locked();  // each stage's end shows at once (after the delay)
}

void Progress::clear_locked() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
}

void Progress::clear() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    clear_locked();
}

void Progress::end() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
    clear_locked();
}

void Progress::draw_locked() {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (seconds < after_) return;
    constexpr int kWidth = 24;
    const int filled = static_cast<int>(done_ * kWidth + 0.5);
    std::string bar(std::size_t(filled), '#');
    bar.append(std::size_t(kWidth - filled), '.');
    std::fprintf(stderr, "\r\033[Kfdmsurf [%s] %3d%% %6.1f s  %s%s%s", bar.c_str(),
                 static_cast<int>(done_ * 100 + 0.5), seconds, what_.c_str(),
                 last_.empty() ? "" : ": ", last_.c_str());
    std::fflush(stderr);
    drawn_ = true;
}

void Progress::tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
        wake_.wait_for(lock, std::chrono::milliseconds(200));
        if (running_ && !stop_) draw_locked();
    }
}

}  // namespace fdmsurf::cli
