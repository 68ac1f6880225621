// base/fixed_sum.hpp: the same sum, bit for bit, in any order and grouping of the terms, and
// nearer the exact sum than a running double sum.
#include "base/fixed_sum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "support/compensated_sum.hpp"

namespace {

using fdmsurf::detail::FixedSum;

std::uint64_t bits(double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// Terms of mixed signs over many magnitudes, as a mesh's signed volumes are (with some exact
// zeros, halves and the largest exact-path terms).
std::vector<double> mixed_terms(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-40, 30);
    std::vector<double> x(n);
    for (double& v : x) v = std::ldexp(mantissa(rng), exponent(rng));
    x[1] = 0.0, x[2] = -0.0, x[3] = 0.5, x[4] = -2.5;
    x[5] = std::nextafter(FixedSum::kLimit, 0.0), x[6] = -x[5];
    return x;
}

double reference_sum(const std::vector<double>& x) {
    fdmsurf::test::CompensatedSum sum;
    for (double v : x) sum.add(v);
    return sum.value();
}

double fixed_sum(const std::vector<double>& x) {
    FixedSum s;
    for (double v : x) s.add(v);
    return s.value();
}

TEST(FixedSum, AnyOrderAndAnyGroupingGiveTheSameBits) {
    std::vector<double> x = mixed_terms(100'003, 1);
    const double once = fixed_sum(x);
    std::mt19937 rng(2);
    for (int round = 0; round < 4; ++round) {
        std::shuffle(x.begin(), x.end(), rng);
        EXPECT_EQ(bits(fixed_sum(x)), bits(once));
        // In partial sums of uneven sizes, some added as arrays (the vectorised path), added
        // together in reverse.
        std::vector<FixedSum> parts;
        for (std::size_t i = 0; i < x.size();) {
            const std::size_t n = std::min<std::size_t>(x.size() - i, 1 + (i * 7919) % 9001);
            FixedSum part;
            if (n % 2 == 0) {
                part.add(x.data() + i, n);
            } else {
                for (std::size_t k = 0; k < n; ++k) part.add(x[i + k]);
            }
            parts.push_back(part);
            i += n;
        }
        FixedSum total;
        for (auto it = parts.rbegin(); it != parts.rend(); ++it) total += *it;
        EXPECT_EQ(bits(total.value()), bits(once));
    }
}

TEST(FixedSum, IsNearerTheExactSumThanARunningDoubleSum) {
    const std::vector<double> x = mixed_terms(200'000, 3);
    const double exact = reference_sum(x);
    double running = 0.0;
    for (double v : x) running += v;
    const double fixed = fixed_sum(x);
    EXPECT_LE(std::abs(fixed - exact), std::abs(running - exact));
    EXPECT_LE(std::abs(fixed - exact), 2 * std::numeric_limits<double>::epsilon() * std::abs(exact));
    // Terms that cancel exactly sum to +0, and small ones on the grid of 2^-100 exactly.
    FixedSum zero;
    for (double v : {0.1, -0.3, 0.2, -0.1, 0.3, -0.2}) zero.add(v);
    EXPECT_EQ(bits(zero.value()), bits(0.0));
    FixedSum small;
    for (double v : {0x1p-60, 0x1p-60, 1.0, -1.0, 0x1p-99}) small.add(v);
    EXPECT_EQ(small.value(), 0x1p-59 + 0x1p-99);
}

TEST(FixedSum, NegativeSumsAreRoundedOnceToo) {
    // The sum is carried as a magnitude and a sign: a small negative total comes out exactly
    // where it is a double on the grid of 2^-100, as a positive one does.
    for (double t : {-0.1, -0x1p-60, -5e-4, -0.3, -0x1.8p-70, -123456.789}) {
        FixedSum one;
        one.add(t);
        EXPECT_EQ(bits(one.value()), bits(t)) << t;
        FixedSum around;  // the same total through cancelling terms
        for (double v : {1.0, t, -1.0, 1e6, -1e6}) around.add(v);
        EXPECT_EQ(bits(around.value()), bits(t)) << t;
    }
    FixedSum small;
    for (double v : {3 * 0x1p-60, -1.0, 1.0, -0x1p-58}) small.add(v);
    EXPECT_EQ(small.value(), -0x1p-60);
}

TEST(FixedSum, TermsOffTheExactPathAreStillAdded) {
    // Large terms among full groups of four and near the end of a block of 4096 (the vectorised
    // path flushes its lanes before them and starts again after): the small integers sum
    // exactly, the large ones as doubles beside.
    std::vector<double> x(6000);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = double(i % 97) - 40.0;
    const double big = 3.0 * FixedSum::kLimit;
    for (std::size_t at : {9u, 4095u, 5998u}) x[at] = big;
    double small = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (x[i] != big) small += x[i];
    FixedSum as_array, one_by_one;
    as_array.add(x.data(), x.size());
    for (double v : x) one_by_one.add(v);
    EXPECT_EQ(as_array.value(), small + 3 * big);
    EXPECT_EQ(bits(one_by_one.value()), bits(as_array.value()));
    FixedSum inf;
    inf.add(std::numeric_limits<double>::infinity());
    inf.add(1.0);
    EXPECT_EQ(inf.value(), std::numeric_limits<double>::infinity());
    FixedSum nan;
    nan.add(std::nan(""));
    EXPECT_TRUE(std::isnan(nan.value()));
}

}  // namespace
