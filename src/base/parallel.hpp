// A minimal parallel loop for the host stages (mesh comparison, refinement, SES arcs): chunks on
// plain std::threads, the first exception rethrown.
#pragma once

#include <cstddef>
#include <functional>

namespace fdmsurf::detail {

// `requested` threads, or (0) the hardware's, between 1 and 64.
unsigned thread_count(unsigned requested = 0);

// Runs body(i) for i in [0, count) on up to `threads` threads, chunks taken in order; rethrows
// the first exception (the remaining chunks are then skipped).
void parallel_chunks(std::size_t count, unsigned threads,
                     const std::function<void(std::size_t)>& body);

}  // namespace fdmsurf::detail
