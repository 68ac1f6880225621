// A progress line on stderr for runs longer than a second (FDMSURF_PROGRESS_AFTER): a bar, the elapsed time and the stage
// that last ended, redrawn in place, cleared before the summary is printed.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

namespace fdmsurf::cli {

// Whether a run shows progress: not with --quiet or FDMSURF_PROGRESS=never; always with
// FDMSURF_PROGRESS=always (tests); else when stderr is a terminal.
bool progress_wanted(bool quiet);

// Seconds a run lasts before its line appears: FDMSURF_PROGRESS_AFTER (>= 0; tests set 0 so
// that a fast device still shows it), else 1.
double progress_delay();

class Progress {
public:
    explicit Progress(bool enabled);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // A new run (one input): the clock restarts, the bar empties.
    void begin(const std::string& what);
    // `name` has ended (a CLI stage or the engine's progress callback).
    void stage(std::string_view name);
    // Clears the line, for a warning to be printed; the next redraw brings it back.
    void clear();
    // Ends the run and clears the line (before the summary or an error is printed).
    void end();

    // The share of a run done when `name` has ended (0-1), from where the stage sits in the
    // pipeline; slab stages ("field slab 2/5", "marching cubes, z 120/400") by their count.
    static double fraction_after(std::string_view name);

private:
    void draw_locked();
    void clear_locked();
    void tick();

    bool enabled_;
    double after_;  // progress_delay()
    std::mutex mutex_;
    std::condition_variable wake_;
    bool running_ = false;  // a run between begin() and end()
    bool stop_ = false;
    bool drawn_ = false;    // something is on the line
    std::string what_, last_;
    double done_ = 0.0;
    std::chrono::steady_clock::time_point start_;
    std::thread thread_;
};

}  // namespace fdmsurf::cli
