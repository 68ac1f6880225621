// Disjoint sets over dense indices, for connected pieces and the fans around each vertex.
#pragma once

#include <cstdint>
#include <numeric>
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

}  // namespace fdmsurf::detail
