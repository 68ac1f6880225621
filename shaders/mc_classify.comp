// Marching cubes, pass 1: per owned point, the crossed edges it owns (one vertex each) and the
// triangles of the cell it starts; per block of points, the two sums, and per point of a block
// that has any surface, its offsets within the block (vertex offset in the low 16 bits, triangle
// offset in the high 16: at most 3 * 256 and 5 * 256), so that passes 3 and 4 need no scan.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Field { float field[]; };
layout(std430, binding = 1) writeonly buffer Counts { uint counts[]; };
layout(std430, binding = 2) writeonly buffer BlockSums { uvec2 block_sums[]; };
#define MC_TABLES_BINDING 3
#include "mc_common.glsl"

shared uvec2 block_total;

void main() {
    uint block = gl_WorkGroupID.y * pc.blocks_x + gl_WorkGroupID.x;
    if (block * kMcBlock >= pc.owned_points) return;  // past the last block of a 2D dispatch
    uint i = point_index();
    uvec2 n = uvec2(0u);
    if (i < pc.owned_points) {
        uvec3 p = point_coords(i);
        n.x = bitCount(crossed_edges(p));
        n.y = mc_tri_count[cube_index(p)];
    }
    // The block's sums by shared atomics; the scan (barrier-heavy on CPU drivers) only where the
    // block has any surface, which is uniform across the workgroup.
    if (gl_LocalInvocationID.x == 0u) block_total = uvec2(0u);
    barrier();
    if (n.x != 0u) atomicAdd(block_total.x, n.x);
    if (n.y != 0u) atomicAdd(block_total.y, n.y);
    barrier();
    uvec2 total = block_total;
    if (gl_LocalInvocationID.x == 0u) block_sums[block] = total;
    if (total.x == 0u && total.y == 0u) return;
    uvec2 sum;
    uvec2 offset = workgroup_exclusive_scan(n, sum);
    if (i < pc.owned_points) counts[i] = offset.x | (offset.y << 16);
}
