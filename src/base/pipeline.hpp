// One thread's steps ahead of the work on all threads: a parallel loop whose items wait for
// their turn of a step that only one thread can take (see parallel.hpp for the plain loop).
#pragma once

#include <cstddef>
#include <functional>

namespace fdmsurf::detail {

// Runs prepare(0), prepare(1), ... in order on one thread while the other threads run body(i),
// each i once, as soon as prepare(i) has returned (its writes seen); the preparing thread joins
// them when done. For work behind one thread's step, such as a std::vector's construction of
// its elements (reserved first, then resized item by item; the bodies write through pointers
// taken before). Rethrows the first exception; after it, nothing further starts.
void parallel_prepared(std::size_t count, unsigned threads,
                       const std::function<void(std::size_t)>& prepare,
                       const std::function<void(std::size_t)>& body);

}  // namespace fdmsurf::detail
