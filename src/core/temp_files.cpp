// Tracked temporary files (temp_files.hpp): slots of fixed size, claimed and released with
// lock-free atomics, so that a signal handler may read them at any moment.
#include "core/temp_files.hpp"

#include <unistd.h>

#include <atomic>
#include <cstring>

namespace fdmsurf::detail {

namespace {

constexpr int kSlots = 32;
constexpr std::size_t kPathMax = 4096;

enum State : int { kFree = 0, kClaimed = 1, kReady = 2 };

struct Slot {
    std::atomic<int> state{kFree};
    char path[kPathMax];
};

Slot slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs lock-free atomics");

}  // namespace

bool track_temp_file(const std::string& path) {
    if (path.size() + 1 > kPathMax) return false;
    for (Slot& s : slots) {
        int expected = kFree;
        if (!s.state.compare_exchange_strong(expected, kClaimed)) continue;
        std::memcpy(s.path, path.c_str(), path.size() + 1);
        s.state.store(kReady);
        return true;
    }
    return false;
}

void untrack_temp_file(const std::string& path) {
    for (Slot& s : slots) {
        if (s.state.load() != kReady || std::strcmp(s.path, path.c_str()) != 0) continue;
        int expected = kReady;
        if (s.state.compare_exchange_strong(expected, kClaimed)) s.state.store(kFree);
        return;
    }
}

void remove_temp_files_from_signal_handler() {
    for (Slot& s : slots)
        if (s.state.load() == kReady) ::unlink(s.path);
}

}  // namespace fdmsurf::detail
