// Host timestamps for FDMSURF_TRACE=1 (trace.hpp).
#include "base/trace.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace fdmsurf::detail {

namespace {

bool trace_enabled() {
    static const bool enabled = [] {
        const char* v = std::getenv("FDMSURF_TRACE");
        return v != nullptr && std::strcmp(v, "1") == 0;
    }();
    return enabled;
}

}  // namespace

bool trace_on() { return trace_enabled(); }

void trace(const char* what) {
    if (!trace_enabled()) return;
    using Clock = std::chrono::steady_clock;
    static std::mutex mutex;
    static const Clock::time_point first = Clock::now();
    static Clock::time_point last = first;
    std::lock_guard<std::mutex> lock(mutex);
    const Clock::time_point now = Clock::now();
    std::fprintf(stderr, "fdmsurf: trace: %9.1f ms (+%7.1f) %s\n",
                 std::chrono::duration<double, std::milli>(now - first).count(),
                 std::chrono::duration<double, std::milli>(now - last).count(), what);
    last = now;
}

}  // namespace fdmsurf::detail
