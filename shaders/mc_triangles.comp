// Marching cubes, pass 4: the triangles of each cell, indexing the shared vertices of pass 3
// (the owner point's first vertex plus the rank of the edge's axis among its crossed edges).
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };  // from pass 1
layout(std430, binding = 2) readonly buffer BlockSums { uvec2 block_sums[]; };
layout(std430, binding = 3) writeonly buffer Indices { uint indices[]; };
#define MC_TABLES_BINDING 4
#include "mc_common.glsl"

uint vertex_of(uvec3 cell, int edge) {
    // Edge numbering of the tables: axis = edge / 4; the two other coordinates of the owner
    // offset are the low two bits of edge % 4, in axis order.
    uint axis = uint(edge) >> 2;
    uint lo = uint(edge) & 1u, hi = (uint(edge) >> 1) & 1u;
    uvec3 offset = axis == 0u ? uvec3(0u, lo, hi) : (axis == 1u ? uvec3(lo, 0u, hi) : uvec3(lo, hi, 0u));
    uvec3 owner = cell + offset;
    uint bits = crossed_edges(owner);
    uint rank = bitCount(bits & ((1u << axis) - 1u));
    uint owner_index = ((owner.z - pc.z_begin) * pc.ny + owner.y) * pc.nx + owner.x;
    return block_sums[owner_index / kMcBlock].x + (offsets[owner_index] & 0xffffu) + rank;
}

void main() {
    // Most blocks hold no surface: the whole workgroup leaves at once (uniformly, before any
    // barrier) when its block emits nothing.
    uint block = gl_WorkGroupID.y * pc.blocks_x + gl_WorkGroupID.x;
    if (block * kMcBlock >= pc.owned_points) return;  // past the last block of a 2D dispatch
    if (block_sums[block + 1u].y == block_sums[block].y) return;
    uint i = point_index();
    if (i >= pc.owned_points) return;
    uvec3 p = point_coords(i);
    uint cube = cube_index(p);
    uint count = mc_tri_count[cube];
    if (count == 0u) return;
    uint t = block_sums[block].y + (offsets[i] >> 16);
    int base = int(cube) * 3 * MC_MAX_TRIANGLES;
    for (uint k = 0u; k < count; ++k) {
        for (uint j = 0u; j < 3u; ++j)
            indices[3u * (t + k) + j] = vertex_of(p, mc_tri_edges[base + int(3u * k + j)]);
    }
}
