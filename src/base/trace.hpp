// FDMSURF_TRACE=1: host timestamps on stderr at the steps of a run ("fdmsurf: trace: 812.4 ms
// (+3.1, CPU +5.9) marching cubes: buffers"), to find host time that no stage accounts for, on
// machines without a profiler. Off (one branch per call) otherwise.
#pragma once

namespace fdmsurf::detail {

// Whether FDMSURF_TRACE=1 (to skip building a trace message otherwise).
bool trace_on();

// Prints `what` with the time since the process's first trace call and since the last one, and
// the process's CPU time (all threads) since the last one.
void trace(const char* what);

}  // namespace fdmsurf::detail
