// Vertex properties, pass 1: the atom each vertex belongs to, the one of least power distance
// |p - c|² - r² (ties: the lower atom index): a first candidate from the nearest non-empty
// cells, then every cell within reach of a better atom, skipping those whose nearest point is
// too far for their largest atom; then the atom's attributes (packed colour, per-atom values)
// copied to the vertex. Mirrors vertex_atoms_cpu.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kVertexGroup) in;
layout(push_constant) uniform Push { VertexAtomsPush pc; };
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer BinAtoms { vec4 bin_atoms[]; };  // x, y, z, r²
layout(std430, binding = 2) readonly buffer BinIndex { uint bin_index[]; };  // atom index
layout(std430, binding = 3) readonly buffer BinStart { uint bin_start[]; };
layout(std430, binding = 4) readonly buffer Attributes { uint atom_attributes[]; };
layout(std430, binding = 5) writeonly buffer Out { uint out_words[]; };  // atom, attributes
layout(std430, binding = 6) readonly buffer BinR2 { float bin_r2_max[]; };  // largest r² per cell

float best_power;
uint best_atom;

void scan_cell(ivec3 c, vec3 p) {
    uint b = (uint(c.z) * pc.bin_ny + uint(c.y)) * pc.bin_nx + uint(c.x);
    for (uint k = bin_start[b]; k < bin_start[b + 1]; ++k) {
        vec4 a = bin_atoms[k];
        vec3 d = p - a.xyz;
        precise float pw = dot(d, d) - a.w;
        uint idx = bin_index[k];
        if (pw < best_power || (pw == best_power && idx < best_atom)) {
            best_power = pw;
            best_atom = idx;
        }
    }
}

// Skips a cell whose every atom is farther (in power) than the best so far.
void visit(ivec3 c, vec3 p, vec3 origin) {
    uint b = (uint(c.z) * pc.bin_ny + uint(c.y)) * pc.bin_nx + uint(c.x);
    vec3 lo = origin + vec3(c) * pc.bin_size;
    vec3 gap = max(max(lo - p, p - (lo + pc.bin_size)), vec3(0.0));
    if (dot(gap, gap) - bin_r2_max[b] > best_power) return;
    scan_cell(c, p);
}

void main() {
    uint v = (gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x) * kVertexGroup +
             gl_LocalInvocationID.x;
    if (v >= pc.vertex_count) return;
    uint at = pc.position_stride * v;
    vec3 p = vec3(positions[at], positions[at + 1], positions[at + 2]);
    ivec3 dims = ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz);
    vec3 origin = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    ivec3 home = clamp(ivec3(floor((p - origin) / pc.bin_size)), ivec3(0), dims - 1);
    best_power = 3.0e38;
    best_atom = 0xffffffffu;
    // A first candidate: rings of cells around the vertex's until one holds an atom (nearly
    // always the vertex's own cell).
    int max_shell = max(max(dims.x, dims.y), dims.z);
    int scanned = -1;  // rings 0..scanned around home are done
    for (int s = 0; s <= max_shell && best_atom == 0xffffffffu; ++s) {
        scanned = s;
        for (int z = -s; z <= s; ++z) {
            for (int y = -s; y <= s; ++y) {
                bool face = abs(z) == s || abs(y) == s;
                int step = face ? 1 : max(2 * s, 1);
                for (int x = -s; x <= s; x += step) {
                    ivec3 c = home + ivec3(x, y, z);
                    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, dims))) continue;
                    scan_cell(c, p);
                }
            }
        }
    }
    // Any atom that beats or ties it lies within sqrt(best + r2_max) of the vertex: the cells
    // that this ball touches, each skipped when its nearest point is too far for its atoms.
    float reach = sqrt(max(best_power + pc.r2_max, 0.0));
    ivec3 lo = clamp(ivec3(floor((p - reach - origin) / pc.bin_size)), ivec3(0), dims - 1);
    ivec3 hi = clamp(ivec3(floor((p + reach - origin) / pc.bin_size)), ivec3(0), dims - 1);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                ivec3 d = abs(ivec3(x, y, z) - home);
                if (max(max(d.x, d.y), d.z) > scanned) visit(ivec3(x, y, z), p, origin);
            }
    uint stride = 1 + pc.attributes;
    out_words[stride * v] = best_atom;
    for (uint k = 0; k < pc.attributes; ++k)
        out_words[stride * v + 1 + k] = atom_attributes[pc.attributes * best_atom + k];
}
