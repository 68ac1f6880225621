// A sum of doubles that comes out the same bits in any order of its terms, and in any grouping
// of them into partial sums: each term is split exactly into integers (its nearest integer, then
// the rest in two steps of 2^-50), and integers add exactly. A mesh's area and volume summed so
// are the same whatever the order of its triangles, so that removing some pieces leaves the
// sums of the others as they were (mesh/mesh_stats.cpp), and they are more exact than a running
// double sum: each term is rounded to a multiple of 2^-100 at most, the total once.
//
// Terms of magnitude 2^49 or more, infinities and NaN are summed as doubles beside, in the order
// given: for those alone the order counts. No triangle of a molecular surface comes near.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "base/cpu_features.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

namespace fdmsurf::detail {

__extension__ typedef __int128 FixedInt;
__extension__ typedef unsigned __int128 FixedUnsigned;

class FixedSum {
public:
    // Terms below this magnitude take the exact path.
    static constexpr double kLimit = 0x1p49;

    void add(double x) {
        if (!(std::abs(x) < kLimit)) {
            rest_ += x;
            return;
        }
        std::int64_t r[3];
        split(x, r);
        for (int k = 0; k < 3; ++k) level_[k] += r[k];
    }

    // The terms x[0..n), the same as adding them one by one.
    void add(const double* x, std::size_t n) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
        if (has_avx2()) return add_avx2(x, n);
#endif
        for (std::size_t i = 0; i < n; ++i) add(x[i]);
    }

    FixedSum& operator+=(const FixedSum& other) {
        for (int k = 0; k < 3; ++k) level_[k] += other.level_[k];
        rest_ += other.rest_;
        return *this;
    }

    // The exact sum of the exact-path terms rounded once to the nearest double, plus the others.
    double value() const {
        // The sign first, so that the magnitude's levels carry into non-negative ones.
        const bool negative = carried(level_[0], level_[1], level_[2]).whole < 0;
        const Carried m = negative ? carried(-level_[0], -level_[1], -level_[2])
                                   : carried(level_[0], level_[1], level_[2]);
        // m.whole + m.f1 2^-50 + m.f2 2^-100, whole >= 0, f1 and f2 in [0, 2^50): as one integer
        // where it fits in 128 bits, rounded by the conversion; else the bits below the
        // conversion's rounding (at least 24 of them) folded into a sticky lowest bit.
        const FixedUnsigned whole = FixedUnsigned(m.whole), f1 = FixedUnsigned(m.f1),
                            f2 = FixedUnsigned(m.f2);
        double magnitude;
        if (whole < (FixedUnsigned{1} << 26))
            magnitude = double((whole << 100) | (f1 << 50) | f2) * 0x1p-100;
        else if (whole < (FixedUnsigned{1} << 76))
            magnitude = double((whole << 50) | f1 | FixedUnsigned(f2 != 0)) * 0x1p-50;
        else
            magnitude = double(whole | FixedUnsigned((f1 | f2) != 0));
        if (magnitude == 0.0) return 0.0 + rest_;
        return (negative ? -magnitude : magnitude) + rest_;
    }

private:
    // Levels carried upwards: the lower two left in [0, 2^50).
    struct Carried {
        FixedInt whole, f1, f2;
    };
    static Carried carried(FixedInt l0, FixedInt l1, FixedInt l2) {
        constexpr FixedInt kMask = (FixedInt{1} << 50) - 1;
        l1 += l2 >> 50;  // floor division (C++20 shifts of negative values)
        l0 += l1 >> 50;
        return {l0, l1 & kMask, l2 & kMask};
    }

    // x (|x| < 2^49) as r[0] + r[1] 2^-50 + r[2] 2^-100, each rounded to the nearest by adding
    // and taking away 1.5 2^52 (its ulp is 1), every remainder exact; the last remainder (at
    // most 2^-101) is dropped.
    static void split(double x, std::int64_t r[3]) {
        constexpr double kMagic = 0x1.8p52;
        for (int k = 0; k < 3; ++k) {
            const double nearest = (x + kMagic) - kMagic;  // (no -ffast-math: not folded)
            r[k] = static_cast<std::int64_t>(nearest);
            x = (x - nearest) * 0x1p50;
        }
    }

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    // Four terms at a time: the same splits (the magic number's bits less its own are the
    // nearest integer), the levels summed in 64-bit lanes over blocks of up to 2^12 terms (2^10
    // a lane, each below 2^50 in magnitude), then into the 128-bit levels.
    __attribute__((target("avx2"))) void add_avx2(const double* x, std::size_t n) {
        const __m256d magic = _mm256_set1_pd(0x1.8p52), scale = _mm256_set1_pd(0x1p50);
        const __m256d limit = _mm256_set1_pd(kLimit);
        const __m256d sign = _mm256_set1_pd(-0.0);
        const __m256i magic_bits = _mm256_castpd_si256(magic);
        std::size_t i = 0;
        while (i + 4 <= n) {
            __m256i lane[3] = {_mm256_setzero_si256(), _mm256_setzero_si256(),
                               _mm256_setzero_si256()};
            const std::size_t stop = i + std::min<std::size_t>((n - i) & ~std::size_t{3}, 4096);
            for (; i < stop; i += 4) {
                __m256d v = _mm256_loadu_pd(x + i);
                const __m256d small = _mm256_cmp_pd(_mm256_andnot_pd(sign, v), limit, _CMP_LT_OQ);
                if (_mm256_movemask_pd(small) != 0xf) {
                    // A term off the exact path: these four one by one.
                    flush(lane);
                    for (int l = 0; l < 4; ++l) add(x[i + l]);
                    for (auto& s : lane) s = _mm256_setzero_si256();
                    continue;
                }
                for (int k = 0; k < 3; ++k) {
                    const __m256d shifted = _mm256_add_pd(v, magic);
                    const __m256d nearest = _mm256_sub_pd(shifted, magic);
                    lane[k] = _mm256_add_epi64(
                        lane[k], _mm256_sub_epi64(_mm256_castpd_si256(shifted), magic_bits));
                    v = _mm256_mul_pd(_mm256_sub_pd(v, nearest), scale);
                }
            }
            flush(lane);
        }
        for (; i < n; ++i) add(x[i]);
    }

    __attribute__((target("avx2"))) void flush(const __m256i lane[3]) {
        for (int k = 0; k < 3; ++k) {
            alignas(32) std::int64_t parts[4];
            _mm256_store_si256(reinterpret_cast<__m256i*>(parts), lane[k]);
            level_[k] += FixedInt{parts[0]} + parts[1] + parts[2] + parts[3];
        }
    }
#endif

    FixedInt level_[3] = {0, 0, 0};  // units of 1, 2^-50, 2^-100
    double rest_ = 0.0;
};

}  // namespace fdmsurf::detail
