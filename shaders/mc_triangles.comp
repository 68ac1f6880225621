// Marching cubes, pass 5: the triangles of each crossed cell, indexing the shared vertices of
// pass 4: the owner segment's first vertex plus the rank of the owner point's edge
// (vertex_rank), found from the owner's occupancy words.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;  // kMcGroup
layout(std430, binding = 1) readonly buffer Local { uint local_offsets[]; };
layout(std430, binding = 2) readonly buffer RunSums { uvec2 run_sums[]; };
layout(std430, binding = 3) writeonly buffer Indices { uint indices[]; };
#define MC_OCC_BINDING 0
#define MC_TABLES_BINDING 4
#include "mc_common.glsl"

uint vertex_of(uvec3 cell, int edge) {
    // Edge numbering of the tables: axis = edge / 4; the two other coordinates of the owner
    // offset are the low two bits of edge % 4, in axis order.
    uint axis = uint(edge) >> 2;
    uint lo = uint(edge) & 1u, hi = (uint(edge) >> 1) & 1u;
    uvec3 offset = axis == 0u ? uvec3(0u, lo, hi) : (axis == 1u ? uvec3(lo, 0u, hi) : uvec3(lo, hi, 0u));
    uvec3 owner = cell + offset;
    uint w = owner.x >> 5;
    uvec3 e = segment_edges(w, owner.y, owner.z);
    uint s = segment_index(w, owner.y, owner.z);
    return run_sums[s / kMcRun].x + (local_offsets[s] & 0xffffu) + vertex_rank(e, owner.x & 31u, axis);
}

void main() {
    uint s = invocation_index();
    if (s >= pc.segments) return;
    uvec3 c = segment_coords(s);
    if (c.y + 1u >= pc.ny || c.z >= pc.z_end) return;
    uint c0, c1, c2, c3, c4, c5, c6, c7;
    uint cells = segment_corners(c.x, c.y, c.z, c0, c1, c2, c3, c4, c5, c6, c7);
    if (cells == 0u) return;
    uint t = run_sums[s / kMcRun].y + (local_offsets[s] >> 16);
    while (cells != 0u) {
        uint k = uint(findLSB(cells));
        cells &= cells - 1u;
        uint cube = cube_index(k, c0, c1, c2, c3, c4, c5, c6, c7);
        uint count = mc_tri_count[cube];
        uvec3 p = uvec3(32u * c.x + k, c.y, c.z);
        int base = int(cube) * 3 * MC_MAX_TRIANGLES;
        for (uint j = 0u; j < count; ++j) {
            for (uint i = 0u; i < 3u; ++i)
                indices[3u * (t + j) + i] = vertex_of(p, mc_tri_edges[base + int(3u * j + i)]);
        }
        t += count;
    }
}
