// Host timestamps for FDMSURF_TRACE=1 (trace.hpp).
#include "base/trace.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>

#include <sys/resource.h>
#include <unistd.h>

namespace fdmsurf::detail {

namespace {

bool trace_enabled() {
    static const bool enabled = [] {
        const char* v = std::getenv("FDMSURF_TRACE");
        return v != nullptr && std::strcmp(v, "1") == 0;
    }();
    return enabled;
}

// The process's CPU time (all threads), in ms: on a shared machine, the work apart from the wait.
double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

// The process's resident memory now, in MB (0 where /proc cannot tell).
double resident_mb() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (f == nullptr) return 0.0;
    unsigned long long size = 0, resident = 0;
    const int got = std::fscanf(f, "%llu %llu", &size, &resident);
    std::fclose(f);
    return got == 2 ? double(resident) * double(sysconf(_SC_PAGESIZE)) / 1e6 : 0.0;
}

}  // namespace

bool trace_on() { return trace_enabled(); }

void trace(const char* what) {
    if (!trace_enabled()) return;
    using Clock = std::chrono::steady_clock;
    static std::mutex mutex;
    static const Clock::time_point first = Clock::now();
    static Clock::time_point last = first;
    static double last_cpu = cpu_ms();
    std::lock_guard<std::mutex> lock(mutex);
    const Clock::time_point now = Clock::now();
    const double cpu = cpu_ms();
    // Resident memory and the minor page faults so far (a fresh page is one): on a VM whose fresh
    // pages cost more than the work on them (docs/performance.md), where a stage's memory comes
    // from.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::fprintf(stderr,
                 "fdmsurf: trace: %9.1f ms (+%7.1f, CPU +%7.1f) rss %6.0f MB, minor faults %7ld "
                 "%s\n",
                 std::chrono::duration<double, std::milli>(now - first).count(),
                 std::chrono::duration<double, std::milli>(now - last).count(), cpu - last_cpu,
                 resident_mb(), usage.ru_minflt, what);
    last = now;
    last_cpu = cpu;
}

}  // namespace fdmsurf::detail
