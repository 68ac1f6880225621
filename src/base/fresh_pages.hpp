// Memory that is allocated but not yet written: its pages provided ahead, on all threads.
#pragma once

#include <cstddef>
#include <vector>

namespace fdmsurf::detail {

// A range of memory allocated and not yet written (a std::vector's reserved room).
struct FreshRange {
    void* data;
    std::size_t bytes;
};

// Has the kernel provide the pages of `ranges` now, in chunks on all threads (Linux's
// MADV_POPULATE_WRITE; nothing where the system has no such call), the contents untouched. On
// the VM of docs/performance.md a fresh page costs more than what is then written to it, and a
// std::vector's elements are constructed on one thread: so that thread finds its pages there.
void populate_pages(const std::vector<FreshRange>& ranges);

// The room of `v` past its elements up to `n` of them (reserve n first: v.capacity() >= n), for
// populate_pages before a resize to n writes it on one thread.
template <class T>
FreshRange room_up_to(std::vector<T>& v, std::size_t n) {
    return {v.data() + v.size(), n > v.size() ? (n - v.size()) * sizeof(T) : 0};
}

}  // namespace fdmsurf::detail
