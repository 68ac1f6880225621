// Density pass (Giard & Macq 2010; ALGORITHM.md §2): rho(p) = T exp(-pi(p)/sigma^2), with
// pi(p) = min_i |p - c_i|^2 - r_i^2 the power distance. Atoms are visited in shells of bins
// around p, stopping once no farther atom can lower pi: cost grows with atoms plus points.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kDensityGroupX, local_size_y = kDensityGroupY,
       local_size_z = kDensityGroupZ) in;

layout(std430, binding = 0) writeonly buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer AtomsBuf { vec4 atoms[]; };  // xyz, r^2
layout(std430, binding = 2) readonly buffer BinStart { uint bin_start[]; };
layout(std430, binding = 3) readonly buffer FirstShell { uint first_shell[]; };

layout(push_constant) uniform Push { DensityPush pc; };

float visit_bin(ivec3 b, vec3 p, vec3 bin_origin, float best) {
    // Skip a bin none of whose atoms can lower `best`: its box is too far from p.
    vec3 lo = bin_origin + vec3(b) * pc.bin_size;
    vec3 gap = max(max(lo - p, p - (lo + pc.bin_size)), vec3(0.0));
    if (dot(gap, gap) - pc.r2_max >= best) return best;
    uint id = (uint(b.z) * pc.bin_ny + uint(b.y)) * pc.bin_nx + uint(b.x);
    uint end = bin_start[id + 1];
    for (uint i = bin_start[id]; i < end; ++i) {
        vec4 a = atoms[i];
        vec3 d = p - a.xyz;
        best = min(best, dot(d, d) - a.w);
    }
    return best;
}

void main() {
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= pc.nx || g.y >= pc.ny || g.z >= pc.nz) return;
    vec3 p = vec3(pc.origin_x, pc.origin_y, pc.origin_z) + pc.spacing * vec3(g);
    ivec3 dims = ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz);
    vec3 bin_origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    ivec3 c = clamp(ivec3(floor((p - bin_origin) / pc.bin_size)), ivec3(0), dims - 1);
    // Distance from p to the faces of its own bin: atoms in shell s lie at least
    // (s - 1) bins plus this much away.
    vec3 in_bin = p - (bin_origin + vec3(c) * pc.bin_size);
    float margin = max(min(min(min(in_bin.x, in_bin.y), in_bin.z),
                           pc.bin_size - max(max(in_bin.x, in_bin.y), in_bin.z)), 0.0);
    int s0 = int(first_shell[(uint(c.z) * pc.bin_ny + uint(c.y)) * pc.bin_nx + uint(c.x)]);
    float best = 3.0e38;
    for (int s = s0; s <= int(pc.max_shell); ++s) {
        // Atoms in shell s or beyond are at least (s-1) bins away from p.
        float reach = float(max(s - 1, 0)) * pc.bin_size + (s > 0 ? margin : 0.0);
        float bound = reach * reach - pc.r2_max;
        if (s > 0 && (best <= bound || bound > pc.pi_cut)) break;
        ivec3 lo = max(c - s, ivec3(0));
        ivec3 hi = min(c + s, dims - 1);
        for (int z = lo.z; z <= hi.z; ++z) {
            bool zface = abs(z - c.z) == s;
            for (int y = lo.y; y <= hi.y; ++y) {
                bool face = zface || abs(y - c.y) == s;
                if (face) {
                    for (int x = lo.x; x <= hi.x; ++x) best = visit_bin(ivec3(x, y, z), p, bin_origin, best);
                } else {
                    // Inside the shell's cross-section only its two x faces are new.
                    if (c.x - s >= 0) best = visit_bin(ivec3(c.x - s, y, z), p, bin_origin, best);
                    if (s > 0 && c.x + s < dims.x) best = visit_bin(ivec3(c.x + s, y, z), p, bin_origin, best);
                }
            }
        }
    }
    float rho = best <= pc.pi_cut ? pc.level_t * exp(-best * pc.inv_sigma2) : 0.0;
    field[(g.z * pc.ny + g.y) * pc.pitch + g.x] = rho;
}
