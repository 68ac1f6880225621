// Density pass, step 2 of 2 (Giard & Macq 2010; ALGORITHM.md §2): rho(p) = T exp(-pi(p)/sigma^2),
// with pi(p) = min_i |p - c_i|^2 - r_i^2 the power distance, 0 where pi > pi_cut.
//
// Only the tiles (boxes of grid points that some atom's Gaussian support reaches) are visited;
// the host zero-fills the field first. Each point scans the candidates density_tiles.comp found
// for its tile, or, when they overflowed (the tile's capacity or the pool), searches shells of bins around
// itself. Exact either way.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

// kDensityTileLanes invocations per tile, each evaluating kQuads quads (4 consecutive points
// along x) and loading each candidate once for all of them: on lavapipe every storage-buffer load
// is a per-lane scalar loop, and that is what costs. A workgroup holds kDensityPointGroup /
// kDensityTileLanes tiles in a flat local size (lavapipe vectorises along local x only, so a 3D
// local size would leave lanes idle).
const uint kQuadsX = kDensityGroupX / 4u;
const uint kQuads = kQuadsX * kDensityGroupY * kDensityGroupZ / kDensityTileLanes;
layout(local_size_x = kDensityPointGroup) in;

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
                        // The list path's expression, to the bit: which tiles take this path
                        // can depend on scheduling (a full pool), the field must not.
                        vec4 a = atoms[i];
                        float dx = p.x - a.x;
                        vec2 dyz = p.yz - a.yz;
                        precise float pw = dx * dx + (dot(dyz, dyz) - a.w);
                        best = min(best, pw);
                    }
                }
    }
    return best;
}

void main() {
    uint group = gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationIndex % kDensityTileLanes;
    uint tile = group * (kDensityPointGroup / kDensityTileLanes) + gl_LocalInvocationIndex / kDensityTileLanes;
    if (tile >= pc.tile_count) return;
    Box box = tile_box(tile);
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    uvec3 g[kQuads];
    vec4 px[kQuads];
    vec2 pyz[kQuads];
    vec4 best[kQuads];
    for (uint j = 0u; j < kQuads; ++j) {
        uint q = lane + kDensityTileLanes * j;
        g[j] = box.first + uvec3(4u * (q % kQuadsX), (q / kQuadsX) % kDensityGroupY,
                                 q / (kQuadsX * kDensityGroupY));
        px[j] = vec4(origin.x) + pc.spacing * vec4(g[j].x, g[j].x + 1u, g[j].x + 2u, g[j].x + 3u);
        pyz[j] = origin.yz + pc.spacing * vec2(g[j].yz);
        best[j] = vec4(3.0e38);
    }
    uint n = candidates[2u * tile];
    if (n != kDensityOverflow) {
        uint base = candidates[2u * tile + 1u];
        for (uint k = 0u; k < n; ++k) {
            vec4 a = atoms[candidates[base + k]];
            for (uint j = 0u; j < kQuads; ++j) {
                vec2 dyz = pyz[j] - a.yz;
                vec4 dx = px[j] - a.x;
                precise vec4 pw = dx * dx + (dot(dyz, dyz) - a.w);  // as in shell_search
                best[j] = min(best[j], pw);
            }
        }
    } else {
        for (uint j = 0u; j < kQuads; ++j)
            best[j] = vec4(shell_search(vec3(px[j].x, pyz[j])), shell_search(vec3(px[j].y, pyz[j])),
                           shell_search(vec3(px[j].z, pyz[j])), shell_search(vec3(px[j].w, pyz[j])));
    }
    for (uint j = 0u; j < kQuads; ++j) {
        if (g[j].y >= pc.ny || g[j].z >= pc.nz) continue;
        vec4 rho = pc.level_t * exp(-best[j] * pc.inv_sigma2);
        rho = mix(vec4(0.0), rho, lessThanEqual(best[j], vec4(pc.pi_cut)));
        uint at = (g[j].z * pc.ny + g[j].y) * pc.pitch + g[j].x;
        if (g[j].x < pc.nx) field[at] = rho.x;
        if (g[j].x + 1u < pc.nx) field[at + 1u] = rho.y;
        if (g[j].x + 2u < pc.nx) field[at + 2u] = rho.z;
        if (g[j].x + 3u < pc.nx) field[at + 3u] = rho.w;
    }
}
