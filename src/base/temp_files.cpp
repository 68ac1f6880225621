// Tracked temporary files (temp_files.hpp): slots of fixed size, claimed and released with
// lock-free atomics, so that a signal handler may read them at any moment.
#include "base/temp_files.hpp"

#include <unistd.h>

#include <atomic>
#include <cstring>

namespace fdmsurf::detail {

namespace {

// Enough for every file of a run written together (fdmsurf msms -all_components holds two per
// cavity until all are complete). The states lie apart from the paths, so that a scan touches
// one page of them and a path's page only once it is used.
constexpr int kSlots = 1024;
constexpr std::size_t kPathMax = 4096;

enum State : int { kFree = 0, kClaimed = 1, kReady = 2 };

std::atomic<int> states[kSlots];
char paths[kSlots][kPathMax];
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs lock-free atomics");

// Creations in progress (TempFileCreation), and kSweeping once a handler has begun.
constexpr unsigned kSweeping = 1u << 31;
std::atomic<unsigned> creations{0};
static_assert(std::atomic<unsigned>::is_always_lock_free, "the handler needs lock-free atomics");

}  // namespace

bool track_temp_file(const std::string& path) {
    if (path.size() + 1 > kPathMax) return false;
    for (int i = 0; i < kSlots; ++i) {
        int expected = kFree;
        if (!states[i].compare_exchange_strong(expected, kClaimed)) continue;
        std::memcpy(paths[i], path.c_str(), path.size() + 1);
        states[i].store(kReady);
        return true;
    }
    return false;
}

void untrack_temp_file(const std::string& path) {
    for (int i = 0; i < kSlots; ++i) {
        if (states[i].load() != kReady || std::strcmp(paths[i], path.c_str()) != 0) continue;
        int expected = kReady;
        if (states[i].compare_exchange_strong(expected, kClaimed)) states[i].store(kFree);
        return;
    }
}

TempFileCreation::TempFileCreation() {
    unsigned now = creations.load();
    for (;;) {
        if (now & kSweeping) {
            // An interrupt is being handled on another thread, which exits the process: wait
            // for it (this thread has the signals blocked) rather than create a file it misses.
            for (;;) ::pause();
        }
        if (creations.compare_exchange_weak(now, now + 1)) return;
    }
}

TempFileCreation::~TempFileCreation() { creations.fetch_sub(1); }

void remove_temp_files_from_signal_handler() {
    creations.fetch_or(kSweeping);
    while ((creations.load() & ~kSweeping) != 0) {
        // another thread is between creating a temporary file and tracking it: microseconds
    }
    for (int i = 0; i < kSlots; ++i)
        if (states[i].load() == kReady) ::unlink(paths[i]);
}

}  // namespace fdmsurf::detail
