// Vertex properties, pass 2: the Coulomb potential with ChimeraX's distance-dependent
// dielectric (eps = 4 r), phi(x) = sum_i 332 q_i / (4 |x - c_i|²) in kcal/(mol e), at the
// evaluation points x (vertices moved out along their normals), sorted by cell on the host.
//
// One workgroup per target cell (a cell holding evaluation points). Sites (sorted by cell on
// the host) within near_cells cells (Chebyshev) of the target cell are summed exactly at each
// point, copied into shared memory kCoulombNearCapacity at a time in cell order; every other
// site adds to a second-order Taylor expansion of the kernel 1/r² about the cell's centre
// (value, gradient, Hessian: 10 terms) that each point evaluates. With 4 Å cells and 3 near
// cells a far site is at least 14 Å from the centre and a point at most 3.5 Å from it. Every
// sum runs in a fixed order: the result is the same on every run. Mirrors coulombic_cpu() in
// vertex_atoms_cpu.cpp, which sums every pair.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kVertexGroup) in;
layout(push_constant) uniform Push { CoulombPush pc; };
layout(std430, binding = 0) readonly buffer Points { float points[]; };  // x, y, z, by cell
layout(std430, binding = 1) readonly buffer Cells { uvec4 cells[]; };  // cell x, y, z; first point
layout(std430, binding = 2) readonly buffer Sites { vec4 sites[]; };  // x, y, z, q; by cell
layout(std430, binding = 3) readonly buffer SiteStart { uint site_start[]; };  // per cell
layout(std430, binding = 4) writeonly buffer Out { uint out_words[]; };  // phi bits [, colour]

const uint kMaxRows = 49;  // (2 near_cells + 1)² rows of cells along x; near_cells <= 3

shared vec4 tile[kCoulombTile];
shared vec4 near_sites[kCoulombNearCapacity];
shared uint row_first[kMaxRows], row_begin[kMaxRows + 1];  // site index; offset in the near list
shared float partial[10][kVertexGroup];

// Red (-range) through white (0) to blue (+range), packed r | g << 8 | b << 16.
uint ramp(float phi) {
    float t = clamp(phi / pc.color_range, -1.0, 1.0);
    vec3 c = t < 0.0 ? mix(vec3(1.0), vec3(1.0, 0.0, 0.0), -t) : mix(vec3(1.0), vec3(0.0, 0.0, 1.0), t);
    uvec3 b = uvec3(round(c * 255.0));
    return b.r | (b.g << 8) | (b.b << 16);
}

ivec3 cell_of(vec3 c) {
    ivec3 k = ivec3(floor((c - vec3(pc.cell_origin_x, pc.cell_origin_y, pc.cell_origin_z)) /
                          pc.cell_size));
    return clamp(k, ivec3(0), ivec3(pc.cell_nx, pc.cell_ny, pc.cell_nz) - 1);
}

float exact(vec3 x, vec4 s) {
    vec3 d = x - s.xyz;
    // A site on the evaluation point itself (impossible 1.4 Å outside a surface) would divide
    // by 0: at least 0.01 Å².
    return s.w / max(dot(d, d), 1.0e-2);
}

// Copies near sites [base, base + count) of the near list (rows in order) to shared memory.
void load_near(uint base, uint count, uint rows) {
    for (uint k = gl_LocalInvocationID.x; k < count; k += kVertexGroup) {
        uint n = base + k, r = 0;
        while (row_begin[r + 1] <= n) ++r;
        near_sites[k] = sites[row_first[r] + (n - row_begin[r])];
    }
}

void main() {
    uint cell_index = gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x;
    if (cell_index >= pc.cell_count) return;  // uniform over the workgroup
    uint lid = gl_LocalInvocationID.x;
    uvec4 cell_info = cells[cell_index];
    ivec3 cell = ivec3(cell_info.xyz);
    uint first = cell_info.w, last = cells[cell_index + 1].w;
    vec3 centre = vec3(pc.cell_origin_x, pc.cell_origin_y, pc.cell_origin_z) +
                  (vec3(cell) + 0.5) * pc.cell_size;
    int reach = int(pc.near_cells);

    // The near block as rows of cells along x: each row's sites are consecutive.
    if (lid == 0) {
        uint r = 0, total = 0;
        int x0 = max(cell.x - reach, 0), x1 = min(cell.x + reach, int(pc.cell_nx) - 1);
        for (int z = max(cell.z - reach, 0); z <= min(cell.z + reach, int(pc.cell_nz) - 1); ++z)
            for (int y = max(cell.y - reach, 0); y <= min(cell.y + reach, int(pc.cell_ny) - 1); ++y) {
                uint row = (uint(z) * pc.cell_ny + uint(y)) * pc.cell_nx;
                uint a = site_start[row + uint(x0)], b = site_start[row + uint(x1) + 1];
                row_first[r] = a;
                row_begin[r] = total;
                total += b - a;
                ++r;
            }
        for (; r <= kMaxRows; ++r) row_begin[r] = total;
    }

    // Far field: sum q K, q grad K, q Hess K at the centre, K = 1/r², over the far sites.
    float k0 = 0.0;
    vec3 k1 = vec3(0.0);
    vec3 kd = vec3(0.0);  // Hessian diagonal xx, yy, zz
    vec3 ko = vec3(0.0);  // off-diagonal xy, xz, yz
    for (uint base = 0; base < pc.site_count; base += kCoulombTile) {
        uint count = min(kCoulombTile, pc.site_count - base);
        barrier();
        for (uint k = lid; k < count; k += kVertexGroup) tile[k] = sites[base + k];
        barrier();
        for (uint k = lid; k < count; k += kVertexGroup) {
            vec4 s = tile[k];
            ivec3 d3 = abs(cell_of(s.xyz) - cell);
            if (max(max(d3.x, d3.y), d3.z) <= reach) continue;  // near: summed exactly
            vec3 d = centre - s.xyz;
            float inv = 1.0 / dot(d, d);
            float q = s.w * inv;                 // q / r²
            float q2 = q * inv;                  // q / r⁴
            k0 += q;
            k1 += -2.0 * q2 * d;                 // grad 1/r² = -2 d / r⁴
            float e = 8.0 * q2 * inv;            // Hess = (8 d dᵀ / r² - 2 I) / r⁴
            kd += e * d * d - 2.0 * q2;
            ko += e * vec3(d.x * d.y, d.x * d.z, d.y * d.z);
        }
    }
    partial[0][lid] = k0;
    partial[1][lid] = k1.x;
    partial[2][lid] = k1.y;
    partial[3][lid] = k1.z;
    partial[4][lid] = kd.x;
    partial[5][lid] = kd.y;
    partial[6][lid] = kd.z;
    partial[7][lid] = ko.x;
    partial[8][lid] = ko.y;
    partial[9][lid] = ko.z;
    barrier();
    for (uint stride = kVertexGroup / 2; stride > 0; stride /= 2) {
        if (lid < stride)
            for (int t = 0; t < 10; ++t) partial[t][lid] += partial[t][lid + stride];
        barrier();
    }
    float a0 = partial[0][0];
    vec3 g = vec3(partial[1][0], partial[2][0], partial[3][0]);
    vec3 hd = vec3(partial[4][0], partial[5][0], partial[6][0]);
    vec3 ho = vec3(partial[7][0], partial[8][0], partial[9][0]);
    uint total = row_begin[kMaxRows];
    bool single = total <= kCoulombNearCapacity;
    if (single) {
        load_near(0, total, kMaxRows);
        barrier();
    }

    uint rounds = (last - first + kVertexGroup - 1) / kVertexGroup;
    for (uint round = 0; round < rounds; ++round) {
        uint p = first + round * kVertexGroup + lid;
        bool live = p < last;
        vec3 x = live ? vec3(points[3 * p], points[3 * p + 1], points[3 * p + 2]) : centre;
        vec3 t = x - centre;
        float phi = a0 + dot(g, t) +
                    0.5 * (dot(hd, t * t) + 2.0 * (ho.x * t.x * t.y + ho.y * t.x * t.z +
                                                   ho.z * t.y * t.z));
        if (single) {
            for (uint k = 0; k < total; ++k) phi += exact(x, near_sites[k]);
        } else {  // more near sites than shared memory holds: in batches
            for (uint base = 0; base < total; base += kCoulombNearCapacity) {
                uint count = min(kCoulombNearCapacity, total - base);
                barrier();
                load_near(base, count, kMaxRows);
                barrier();
                for (uint k = 0; k < count; ++k) phi += exact(x, near_sites[k]);
            }
        }
        if (!live) continue;
        phi *= pc.scale;
        if (pc.color != 0u) {
            out_words[2 * p] = floatBitsToUint(phi);
            out_words[2 * p + 1] = ramp(phi);
        } else {
            out_words[p] = floatBitsToUint(phi);
        }
    }
}
