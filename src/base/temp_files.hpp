// The temporary files being written (AtomicFile), for an interrupt handler to remove: a fixed
// table that a signal handler can walk without allocating or locking.
#pragma once

#include <string>

namespace fdmsurf::detail {

// Adds `path` (false when the table's 1024 slots are all taken or the path is too long: the file
// is then written as usual, only not removed by an interrupt).
bool track_temp_file(const std::string& path);
// Removes `path` from the table (after it was renamed into place or removed).
void untrack_temp_file(const std::string& path);
// Unlinks every tracked file. Async-signal-safe: for a SIGINT/SIGTERM handler. It first waits
// for any TempFileCreation in progress on another thread (a signal sent to the process may run
// its handler on any thread), and from then on a new TempFileCreation never returns: the
// process is about to exit, and no temporary file can appear after the sweep.
void remove_temp_files_from_signal_handler();

// Held (with SIGINT, SIGTERM and SIGHUP blocked on this thread) from just before a temporary
// file is created until it is tracked, so that an interrupt handled on another thread cannot
// sweep in between and leave the file behind.
class TempFileCreation {
public:
    TempFileCreation();
    ~TempFileCreation();
    TempFileCreation(const TempFileCreation&) = delete;
    TempFileCreation& operator=(const TempFileCreation&) = delete;
};

}  // namespace fdmsurf::detail
