// Test helper: a compensated (Neumaier) sum in long double, to check fdmsurf's sums against: for
// the sizes of the tests' meshes and term lists it is within a small part of a double's ulp of
// the exact sum.
#pragma once

#include <cmath>

namespace fdmsurf::test {

class CompensatedSum {
public:
    void add(long double v) {
        const long double t = sum_ + v;
        c_ += std::abs(sum_) >= std::abs(v) ? (sum_ - t) + v : (v - t) + sum_;
        sum_ = t;
    }
    double value() const { return static_cast<double>(sum_ + c_); }

private:
    long double sum_ = 0.0L, c_ = 0.0L;
};

}  // namespace fdmsurf::test
