// The temporary files being written (AtomicFile), for an interrupt handler to remove: a fixed
// table that a signal handler can walk without allocating or locking.
#pragma once

#include <string>

namespace fdmsurf::detail {

// Adds `path` (false when the table's 32 slots are all taken or the path is too long: the file
// is then written as usual, only not removed by an interrupt).
bool track_temp_file(const std::string& path);
// Removes `path` from the table (after it was renamed into place or removed).
void untrack_temp_file(const std::string& path);
// Unlinks every tracked file. Async-signal-safe: for a SIGINT/SIGTERM handler.
void remove_temp_files_from_signal_handler();

}  // namespace fdmsurf::detail
