// Marching cubes, pass 3: exclusive prefix sum of the per-run (vertex, triangle) counts in one
// workgroup; each invocation scans a contiguous chunk. Writes the totals, also after the last
// run, so that run r holds run_sums[r + 1] - run_sums[r] vertices and triangles.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kScanGroup) in;
layout(std430, binding = 0) buffer RunSums { uvec2 run_sums[]; };
layout(std430, binding = 1) writeonly buffer Totals { uvec2 totals[]; };
layout(push_constant) uniform Push { ScanPush pc; };

shared uvec2 partial[kScanGroup];

void main() {
    uint t = gl_LocalInvocationID.x;
    uint chunk = (pc.count + kScanGroup - 1u) / kScanGroup;
    uint begin = min(t * chunk, pc.count);
    uint end = min(begin + chunk, pc.count);
    uvec2 sum = uvec2(0u);
    for (uint i = begin; i < end; ++i) sum += run_sums[i];
    partial[t] = sum;
    barrier();
    for (uint offset = 1u; offset < kScanGroup; offset <<= 1) {
        uvec2 add = t >= offset ? partial[t - offset] : uvec2(0u);
        barrier();
        partial[t] += add;
        barrier();
    }
    uvec2 running = partial[t] - sum;
    for (uint i = begin; i < end; ++i) {
        uvec2 v = run_sums[i];
        run_sums[i] = running;
        running += v;
    }
    if (t == kScanGroup - 1u) {
        totals[0] = partial[t];
        run_sums[pc.count] = partial[t];  // one past the last run: the total
    }
}
