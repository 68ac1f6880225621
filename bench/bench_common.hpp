// Small helpers shared by the C++ benchmarks under bench/: the median of timed runs and a
// stage's time from a submission's stage list.
#pragma once

#include <algorithm>
#include <vector>

#include "fdmsurf/surface.hpp"

namespace fdmsurf::bench {

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// The time (ms) of the stage named `name`, 0 when the list has none.
inline double stage(const std::vector<fdmsurf::StageTime>& times, const char* name) {
    for (const auto& t : times)
        if (t.name == name) return t.ms;
    return 0.0;
}

}  // namespace fdmsurf::bench
