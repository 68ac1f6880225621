// Disjoint sets over dense indices, for connected pieces and the fans around each vertex.
#pragma once

#include <atomic>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace fdmsurf::detail {

// Path halving, and the smaller index always becomes the root: a set's root is its smallest
// member, which gives pieces a stable order (by their smallest vertex) at no extra cost.
class DisjointSets {
public:
    explicit DisjointSets(std::size_t count) : parent_(count) {
        std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
    }

    std::uint32_t find(std::uint32_t x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }

    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a < b) {
            parent_[b] = a;
        } else if (b < a) {
            parent_[a] = b;
        }
    }

private:
    std::vector<std::uint32_t> parent_;
};

// Disjoint sets that several threads may unite at once: a root links to a smaller root by
// compare-and-swap, and finds halve paths the same way, so every set's root is its smallest
// member whatever the order of the unions (as with DisjointSets).
class ConcurrentSets {
public:
    explicit ConcurrentSets(std::size_t count) : parent_(count) {
        std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
    }

    std::uint32_t find(std::uint32_t x) {
        for (;;) {
            std::uint32_t p = at(x).load(std::memory_order_relaxed);
            if (p == x) return x;
            const std::uint32_t g = at(p).load(std::memory_order_relaxed);
            // A plain store, no compare-and-swap: x is no root, so only such halvings change
            // its parent, and each writes an ancestor of x (links only join roots), so any of
            // them left standing is right; a locked operation would stall on each cache miss.
            if (g != p) at(x).store(g, std::memory_order_relaxed);
            x = g;
        }
    }

    void unite(std::uint32_t a, std::uint32_t b) {
        for (;;) {
            a = find(a);
            b = find(b);
            if (a == b) return;
            if (a < b) std::swap(a, b);  // the larger root a links to b
            std::uint32_t expected = a;
            if (at(a).compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
        }
    }

private:
    std::atomic_ref<std::uint32_t> at(std::uint32_t x) {
        return std::atomic_ref<std::uint32_t>(parent_[x]);
    }
    std::vector<std::uint32_t> parent_;
};

}  // namespace fdmsurf::detail
