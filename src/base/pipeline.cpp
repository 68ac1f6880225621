// parallel_prepared on std::thread (see pipeline.hpp).
#include "base/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace fdmsurf::detail {

void parallel_prepared(std::size_t count, unsigned threads,
                       const std::function<void(std::size_t)>& prepare,
                       const std::function<void(std::size_t)>& body) {
    threads = unsigned(std::min<std::size_t>(threads, count));
    if (threads <= 1) {
        for (std::size_t i = 0; i < count; ++i) {
            prepare(i);
            body(i);
        }
        return;
    }
    std::atomic<std::size_t> prepared{0}, next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    auto fail = [&] {
        if (!failed.exchange(true)) error = std::current_exception();
        prepared.store(count);  // wakes the waiting threads, which then stop
        prepared.notify_all();
    };
    auto work = [&] {
        try {
            for (std::size_t i; !failed && (i = next++) < count;) {
                for (std::size_t p; (p = prepared.load(std::memory_order_acquire)) <= i;)
                    prepared.wait(p, std::memory_order_acquire);
                if (failed) break;
                body(i);
            }
        } catch (...) {
            fail();
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    try {
        for (std::size_t i = 0; i < count && !failed; ++i) {
            prepare(i);
            prepared.store(i + 1, std::memory_order_release);
            prepared.notify_all();
        }
    } catch (...) {
        fail();
    }
    work();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace fdmsurf::detail
