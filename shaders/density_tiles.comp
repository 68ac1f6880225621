// Density pass, step 1 of 2 (Giard & Macq 2010; ALGORITHM.md §2): the candidate atoms of each
// tile, a box of kDensityGroup* grid points that some atom's Gaussian support reaches.
//
// One invocation per tile, no shared memory and no barrier (lavapipe emulates both slowly).
// With U = min_a max_{p in box} pi_a(p), an upper bound on pi everywhere in the box (capped at
// pi_cut), only atoms with min_{p in box} pi_a(p) <= U can be the minimiser at some point of the
// box, and they lie within sqrt(U + r_max^2) of it. Their indices go to a run of `candidates`' pool;
// density.comp then scans them for each point. Exact: no atom that can win is left out.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kDensityTileGroup) in;

#include "density_common.glsl"

vec3 box_gap(vec3 c, vec3 lo, vec3 hi) { return max(max(lo - c, c - hi), vec3(0.0)); }
vec3 box_far(vec3 c, vec3 lo, vec3 hi) { return max(abs(c - lo), abs(c - hi)); }

// Walks the bins within reach of the box and counts the atoms that can reach pi <= u somewhere in
// it; with `write`, stores their indices from candidates[first] on, at most `room` of them (the
// count pass and the write pass evaluate the same exact tests, so they agree; the bound keeps a
// disagreement from writing into another tile's run).
uint scan_candidates(Box box, float u, ivec3 b_lo, ivec3 b_hi, uint first, bool write, uint room) {
    vec3 bin_origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    uint count = 0u;
    for (int z = b_lo.z; z <= b_hi.z; ++z)
        for (int y = b_lo.y; y <= b_hi.y; ++y) {
            // A row of bins (contiguous atoms) whose y-z distance to the box already exceeds the
            // reach holds no candidate.
            vec2 lo = bin_origin.yz + vec2(y, z) * pc.bin_size;
            vec2 gap = max(max(lo - box.hi.yz, box.lo.yz - (lo + pc.bin_size)), vec2(0.0));
            if (dot(gap, gap) - pc.r2_max > u) continue;
            uint row = (uint(z) * pc.bin_ny + uint(y)) * pc.bin_nx;
            for (uint i = bin_start[row + uint(b_lo.x)]; i < bin_start[row + uint(b_hi.x) + 1u]; ++i) {
                vec4 a = atoms[i];
                vec3 d = box_gap(a.xyz, box.lo, box.hi);
                precise float gap2 = dot(d, d) - a.w;
                if (gap2 > u) continue;
                if (write && count < room) candidates[first + count] = i;
                ++count;
            }
        }
    return count;
}

void main() {
    uint tile = gl_WorkGroupID.y * (pc.groups_x * kDensityTileGroup) + gl_GlobalInvocationID.x;
    if (tile >= pc.tile_count) return;
    Box box = tile_box(tile);
    vec3 bin_origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    ivec3 dims = ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz);

    // 1. U from the atoms near the box (within r_max + half a bin).
    float near = sqrt(pc.r2_max) + 0.5 * pc.bin_size;
    ivec3 b_lo = clamp(ivec3(floor((box.lo - near - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    ivec3 b_hi = clamp(ivec3(floor((box.hi + near - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    float u = pc.pi_cut;
    for (int z = b_lo.z; z <= b_hi.z; ++z)
        for (int y = b_lo.y; y <= b_hi.y; ++y) {
            uint row = (uint(z) * pc.bin_ny + uint(y)) * pc.bin_nx;
            for (uint i = bin_start[row + uint(b_lo.x)]; i < bin_start[row + uint(b_hi.x) + 1u]; ++i) {
                vec3 f = box_far(atoms[i].xyz, box.lo, box.hi);
                u = min(u, dot(f, f) - atoms[i].w);
            }
        }
    // The slack keeps float rounding in the bounds below from dropping the true minimiser.
    u += 1e-3 * (1.0 + abs(u));

    // 2. The candidates: atoms that can reach pi <= u somewhere in the box. Counted first, then
    // given a run of the shared pool (a bump of the pool's top) and written: the lists take the
    // memory they need, not a fixed stride per tile.
    float reach = sqrt(max(u + pc.r2_max, 0.0));
    b_lo = clamp(ivec3(floor((box.lo - reach - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    b_hi = clamp(ivec3(floor((box.hi + reach - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    uint count = scan_candidates(box, u, b_lo, b_hi, 0u, false, 0u);
    uint first = 0u;
    // Once the pool is seen full no tile bumps its top further, which keeps the top far from
    // wrapping around (only the tiles running at that moment can overshoot).
    if (count == 0u) {
        // nothing to claim: no atomic on the pool's top
    } else if (count <= pc.capacity && count <= pc.pool_words &&
               candidates[pool_top_word()] <= pc.pool_words - count) {
        first = atomicAdd(candidates[pool_top_word()], count);
        if (first <= pc.pool_words - count) {
            // What the write pass found, were it ever fewer: no word of the list is left unwritten.
            count = min(count, scan_candidates(box, u, b_lo, b_hi, pool_first_word() + first, true,
                                               count));
        } else {
            count = kDensityOverflow;  // the pool is full: density.comp searches per point
        }
    } else {
        count = kDensityOverflow;
    }
    candidates[2u * tile] = count;
    candidates[2u * tile + 1u] = pool_first_word() + first;
}
