// populate_pages (fresh_pages.hpp).
#include "base/fresh_pages.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

#include "base/parallel.hpp"

namespace fdmsurf::detail {

void populate_pages(const std::vector<FreshRange>& ranges) {
#if defined(__linux__) && __has_include(<sys/mman.h>)
#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23  // Linux 5.14; older kernels answer EINVAL
#endif
    // Whole pages only (madvise's ranges start at one), in chunks of 4 MiB: two huge pages.
    constexpr std::uintptr_t kPage = 4096, kChunk = std::uintptr_t{4} << 20;
    std::size_t total = 0;
    for (const FreshRange& r : ranges) total += r.bytes;
    if (total < kChunk) return;  // a few pages: their faults cost less than the calls
    std::vector<FreshRange> chunks;
    for (const FreshRange& r : ranges) {
        const auto begin = reinterpret_cast<std::uintptr_t>(r.data);
        const std::uintptr_t first = (begin + kPage - 1) & ~(kPage - 1);
        const std::uintptr_t last = (begin + r.bytes) & ~(kPage - 1);
        for (std::uintptr_t at = first; at < last; at += kChunk)
            chunks.push_back({reinterpret_cast<void*>(at), std::size_t(std::min(kChunk, last - at))});
    }
    std::atomic<bool> unsupported{false};
    parallel_chunks(chunks.size(), thread_count(), [&](std::size_t i) {
        if (!unsupported && ::madvise(chunks[i].data, chunks[i].bytes, MADV_POPULATE_WRITE) != 0)
            unsupported = true;  // an old kernel, or no memory: the writes fault as before
    });
#else
    (void)ranges;
#endif
}

}  // namespace fdmsurf::detail
