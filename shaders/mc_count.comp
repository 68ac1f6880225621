// Marching cubes, pass 2: per run of kMcRun consecutive segments, each segment's first vertex and
// first triangle relative to its run (vertices in the low 16 bits, triangles in the high 16: at
// most 32 * 3 and 32 * 5 per segment), and the run's totals, to be scanned by mc_scan.comp. No
// barrier, no shared memory: a segment without crossed edges or cells costs its word loads.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;  // kMcGroup
layout(std430, binding = 1) writeonly buffer Local { uint local_offsets[]; };
layout(std430, binding = 2) writeonly buffer RunSums { uvec2 run_sums[]; };
#define MC_OCC_BINDING 0
#define MC_TABLES_BINDING 3
#include "mc_common.glsl"

void main() {
    uint run = invocation_index();
    uint first = run * kMcRun;
    if (first >= pc.segments) return;
    uint last = min(first + kMcRun, pc.segments);
    uvec2 sum = uvec2(0u);
    for (uint s = first; s < last; ++s) {
        local_offsets[s] = sum.x | (sum.y << 16);
        uvec3 c = segment_coords(s);
        uvec3 e = segment_edges(c.x, c.y, c.z);
        sum.x += bitCount(e.x) + bitCount(e.y) + bitCount(e.z);
        if (c.y + 1u >= pc.ny || c.z >= pc.z_end) continue;
        uint c0, c1, c2, c3, c4, c5, c6, c7;
        uint cells = segment_corners(c.x, c.y, c.z, c0, c1, c2, c3, c4, c5, c6, c7);
        while (cells != 0u) {
            uint k = uint(findLSB(cells));
            cells &= cells - 1u;
            sum.y += mc_tri_count[cube_index(k, c0, c1, c2, c3, c4, c5, c6, c7)];
        }
    }
    run_sums[run] = sum;
}
