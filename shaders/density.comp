// Density pass (Giard & Macq 2010; ALGORITHM.md §2): rho(p) = T exp(-pi(p)/sigma^2), with
// pi(p) = min_i |p - c_i|^2 - r_i^2 the power distance, 0 where pi > pi_cut.
//
// Each workgroup covers a small box of grid points and first gathers, into shared memory, the
// atoms that can be the minimiser for some point of the box: with U = min_a max_{p in box} pi_a(p)
// (an upper bound on pi everywhere in the box), only atoms with min_{p in box} pi_a(p) <= U can
// win, and they lie within sqrt(U + r_max^2) of the box. Every point then scans that short list.
// The result is exact; cost grows with points plus atoms, never with their product.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kDensityGroupX, local_size_y = kDensityGroupY,
       local_size_z = kDensityGroupZ) in;

layout(std430, binding = 0) writeonly buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer AtomsBuf { vec4 atoms[]; };  // xyz, r^2
layout(std430, binding = 2) readonly buffer BinStart { uint bin_start[]; };
layout(std430, binding = 3) readonly buffer FirstShell { uint first_shell[]; };
layout(std430, binding = 4) readonly buffer Reached { uint reached[]; };

layout(push_constant) uniform Push { DensityPush pc; };

const uint kGroupSize = kDensityGroupX * kDensityGroupY * kDensityGroupZ;
const uint kCapacity = 1536u;  // atoms in shared memory (24 KiB)

shared vec4 list[kCapacity];
shared uint list_count;
shared uint upper_bits;  // U as an order-preserving uint

// Order-preserving map between floats and uints, for atomicMin on floats of any sign.
uint to_ordered(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}
float from_ordered(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? (u & 0x7fffffffu) : ~u);
}

vec3 box_gap(vec3 c, vec3 lo, vec3 hi) { return max(max(lo - c, c - hi), vec3(0.0)); }
vec3 box_far(vec3 c, vec3 lo, vec3 hi) { return max(abs(c - lo), abs(c - hi)); }

// Fallback when the list overflows: per-point search in shells of bins.
float shell_search(vec3 p) {
    ivec3 dims = ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz);
    vec3 bin_origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    ivec3 c = clamp(ivec3(floor((p - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    float best = 3.0e38;
    for (int s = int(first_shell[(uint(c.z) * pc.bin_ny + uint(c.y)) * pc.bin_nx + uint(c.x)]);
         s <= int(pc.max_shell); ++s) {
        float reach = float(max(s - 1, 0)) * pc.bin_size;
        float bound = reach * reach - pc.r2_max;
        if (s > 0 && (best <= bound || bound > pc.pi_cut)) break;
        ivec3 lo = max(c - s, ivec3(0));
        ivec3 hi = min(c + s, dims - 1);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) {
                    if (max(max(abs(x - c.x), abs(y - c.y)), abs(z - c.z)) != s) continue;
                    uint id = (uint(z) * pc.bin_ny + uint(y)) * pc.bin_nx + uint(x);
                    for (uint i = bin_start[id]; i < bin_start[id + 1]; ++i) {
                        vec3 d = p - atoms[i].xyz;
                        best = min(best, dot(d, d) - atoms[i].w);
                    }
                }
    }
    return best;
}

void main() {
    uvec3 g = gl_GlobalInvocationID;
    uint t = gl_LocalInvocationIndex;
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    vec3 bin_origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    ivec3 dims = ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz);
    uvec3 first = gl_WorkGroupID * gl_WorkGroupSize;
    uvec3 last = min(first + gl_WorkGroupSize, uvec3(pc.nx, pc.ny, pc.nz)) - 1u;
    vec3 box_lo = origin + pc.spacing * vec3(first);
    vec3 box_hi = origin + pc.spacing * vec3(last);

    uint group_id = (gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x +
                    gl_WorkGroupID.x;
    if (reached[group_id] == 0u) {
        if (all(lessThan(g, uvec3(pc.nx, pc.ny, pc.nz))))
            field[(g.z * pc.ny + g.y) * pc.pitch + g.x] = 0.0;
        return;
    }

    if (t == 0u) {
        list_count = 0u;
        upper_bits = to_ordered(pc.pi_cut);
    }
    barrier();

    // 1. U from the atoms near the box (within r_max + half a bin).
    float near = sqrt(pc.r2_max) + 0.5 * pc.bin_size;
    ivec3 b_lo = clamp(ivec3(floor((box_lo - near - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    ivec3 b_hi = clamp(ivec3(floor((box_hi + near - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    ivec3 b_n = b_hi - b_lo + 1;
    uint bins = uint(b_n.x * b_n.y * b_n.z);
    float local_u = 3.0e38;
    for (uint k = t; k < bins; k += kGroupSize) {
        ivec3 b = b_lo + ivec3(int(k) % b_n.x, (int(k) / b_n.x) % b_n.y, int(k) / (b_n.x * b_n.y));
        uint id = (uint(b.z) * pc.bin_ny + uint(b.y)) * pc.bin_nx + uint(b.x);
        for (uint i = bin_start[id]; i < bin_start[id + 1]; ++i) {
            vec3 f = box_far(atoms[i].xyz, box_lo, box_hi);
            local_u = min(local_u, dot(f, f) - atoms[i].w);
        }
    }
    if (local_u < 3.0e38) atomicMin(upper_bits, to_ordered(local_u));
    barrier();
    // <= pi_cut: beyond it nothing counts. The slack keeps float rounding in the bounds below
    // from dropping the true minimiser.
    float u = from_ordered(upper_bits);
    u += 1e-3 * (1.0 + abs(u));

    // 2. The candidates: atoms that can reach pi <= u somewhere in the box.
    float reach = sqrt(max(u + pc.r2_max, 0.0));
    b_lo = clamp(ivec3(floor((box_lo - reach - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    b_hi = clamp(ivec3(floor((box_hi + reach - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    b_n = b_hi - b_lo + 1;
    bins = uint(b_n.x * b_n.y * b_n.z);
    for (uint k = t; k < bins; k += kGroupSize) {
        ivec3 b = b_lo + ivec3(int(k) % b_n.x, (int(k) / b_n.x) % b_n.y, int(k) / (b_n.x * b_n.y));
        vec3 lo = bin_origin + vec3(b) * pc.bin_size;
        vec3 gap = max(max(lo - box_hi, box_lo - (lo + pc.bin_size)), vec3(0.0));
        if (dot(gap, gap) - pc.r2_max > u) continue;
        uint id = (uint(b.z) * pc.bin_ny + uint(b.y)) * pc.bin_nx + uint(b.x);
        for (uint i = bin_start[id]; i < bin_start[id + 1]; ++i) {
            vec4 a = atoms[i];
            vec3 d = box_gap(a.xyz, box_lo, box_hi);
            if (dot(d, d) - a.w > u) continue;
            uint slot = atomicAdd(list_count, 1u);
            if (slot < kCapacity) list[slot] = a;
        }
    }
    barrier();

    if (any(greaterThanEqual(g, uvec3(pc.nx, pc.ny, pc.nz)))) return;
    vec3 p = origin + pc.spacing * vec3(g);
    float best = 3.0e38;
    uint n = list_count;
    if (n <= kCapacity) {
        for (uint i = 0u; i < n; ++i) {
            vec3 d = p - list[i].xyz;
            best = min(best, dot(d, d) - list[i].w);
        }
    } else {
        best = shell_search(p);
    }
    float rho = best <= pc.pi_cut ? pc.level_t * exp(-best * pc.inv_sigma2) : 0.0;
    field[(g.z * pc.ny + g.y) * pc.pitch + g.x] = rho;
}
