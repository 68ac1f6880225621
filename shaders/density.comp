// Density pass, step 2 of 2 (Giard & Macq 2010; ALGORITHM.md §2): rho(p) = T exp(-pi(p)/sigma^2),
// with pi(p) = min_i |p - c_i|^2 - r_i^2 the power distance, 0 where pi > pi_cut.
//
// One workgroup per tile (a box of grid points that some atom's Gaussian support reaches; the
// host zero-fills the field, so the other boxes are never visited), one invocation per point.
// Each point scans the candidates density_tiles.comp found for its tile, or, when they overflowed
// the tile's capacity, searches shells of bins around itself. Exact either way.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kDensityGroupX, local_size_y = kDensityGroupY,
       local_size_z = kDensityGroupZ) in;

#include "density_common.glsl"

// Fallback when the candidates overflow: per-point search in shells of bins.
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
    uint tile = gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x;
    if (tile >= pc.tile_count) return;
    Box box = tile_box(tile);
    uvec3 g = box.first + gl_LocalInvocationID;
    if (any(greaterThanEqual(g, uvec3(pc.nx, pc.ny, pc.nz)))) return;
    vec3 p = vec3(pc.origin_x, pc.origin_y, pc.origin_z) + pc.spacing * vec3(g);
    uint base = tile * (pc.capacity + 1u);
    uint n = candidates[base];
    float best = 3.0e38;
    if (n <= pc.capacity) {
        for (uint k = 0u; k < n; ++k) {
            vec4 a = atoms[candidates[base + 1u + k]];
            vec3 d = p - a.xyz;
            best = min(best, dot(d, d) - a.w);
        }
    } else {
        best = shell_search(p);
    }
    float rho = best <= pc.pi_cut ? pc.level_t * exp(-best * pc.inv_sigma2) : 0.0;
    field[(g.z * pc.ny + g.y) * pc.pitch + g.x] = rho;
}
