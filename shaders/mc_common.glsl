// Shared by the marching-cubes passes (Lorensen & Cline 1987), with the conventions of
// src/isosurface/marching_cubes_cpu.cpp. The passes work on segments: 32 consecutive points of
// one x row (word w of row (y, z) holds points x = 32 w .. 32 w + 31). Bit k of a segment's
// occupancy word is set when point 32 w + k is inside (value >= iso); bits past the row's end
// are 0. Every crossed edge and every cell's cube index then follows from a few words by bit
// operations, so only the occupancy pass reads the whole field, and segments without surface
// cost a handful of word loads.
#include "shader_interface.h"
#include "mc_tables.glsl"

layout(push_constant) uniform Push { McPush pc; };

// The triangle table lives in a storage buffer (MC_TABLES_BINDING): as a GLSL const array it
// would be copied into every invocation's private memory on some drivers (lavapipe: 200x slower).
#ifdef MC_TABLES_BINDING
layout(std430, binding = MC_TABLES_BINDING) readonly buffer McTables {
    uint mc_tri_count[256];
    int mc_tri_edges[256 * 3 * MC_MAX_TRIANGLES];
};
#endif

#ifdef MC_FIELD_BINDING
layout(std430, binding = MC_FIELD_BINDING) readonly buffer Field { float field[]; };
float value_at(uint x, uint y, uint z) { return field[(z * pc.ny + y) * pc.pitch + x]; }
#endif

// Linear index of the invocation in the 2D grid of flat workgroups.
uint invocation_index() {
    return (gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x) * kMcGroup + gl_LocalInvocationID.x;
}

// Segment s -> (word, row y, buffer plane z); segments run x-word fastest, then y, then z.
uvec3 segment_coords(uint s) {
    uint row = s / pc.words;
    return uvec3(s - row * pc.words, row % pc.ny, pc.z_begin + row / pc.ny);
}

uint segment_index(uint w, uint y, uint z) { return ((z - pc.z_begin) * pc.ny + y) * pc.words + w; }

// Bits k of word w whose point has an x neighbour (32 w + k + 1 < nx).
uint x_mask(uint w) {
    uint n = pc.nx - 1u - 32u * w;
    return n >= 32u ? ~0u : (1u << n) - 1u;
}

#ifdef MC_OCC_BINDING
layout(std430, binding = MC_OCC_BINDING) readonly buffer Occupancy { uint occ[]; };

// Occupancy of word w of row (y, z); 0 past the row's end.
uint occ_word(uint w, uint y, uint z) { return w < pc.words ? occ[segment_index(w, y, z)] : 0u; }

// The word of the points one step along x: bit k = inside(32 w + k + 1).
uint shifted(uint a, uint w, uint y, uint z) { return (a >> 1) | (occ_word(w + 1u, y, z) << 31); }

// Crossed edges owned by the points of a segment, one word per axis: bit k of .x is set when
// point 32 w + k owns its +x edge and exactly one end is inside (likewise .y, .z).
uvec3 segment_edges(uint w, uint y, uint z) {
    uint a = occ_word(w, y, z);
    uvec3 e;
    e.x = (a ^ shifted(a, w, y, z)) & x_mask(w);
    e.y = y + 1u < pc.ny ? a ^ occ_word(w, y + 1u, z) : 0u;
    e.z = z < pc.z_end ? a ^ occ_word(w, y, z + 1u) : 0u;
    return e;
}

// The eight corner words of the cells starting on a segment (cells exist only for y + 1 < ny
// and z < z_end): bit k of corner c is the inside bit of corner c of cell (32 w + k, y, z),
// corner c at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1). Returns the cells that are crossed
// (some corners inside, some not).
uint segment_corners(uint w, uint y, uint z, out uint c0, out uint c1, out uint c2, out uint c3,
                     out uint c4, out uint c5, out uint c6, out uint c7) {
    c0 = occ_word(w, y, z);
    c1 = shifted(c0, w, y, z);
    c2 = occ_word(w, y + 1u, z);
    c3 = shifted(c2, w, y + 1u, z);
    c4 = occ_word(w, y, z + 1u);
    c5 = shifted(c4, w, y, z + 1u);
    c6 = occ_word(w, y + 1u, z + 1u);
    c7 = shifted(c6, w, y + 1u, z + 1u);
    uint any_in = c0 | c1 | c2 | c3 | c4 | c5 | c6 | c7;
    uint all_in = c0 & c1 & c2 & c3 & c4 & c5 & c6 & c7;
    return any_in & ~all_in & x_mask(w);
}

uint cube_index(uint k, uint c0, uint c1, uint c2, uint c3, uint c4, uint c5, uint c6, uint c7) {
    return ((c0 >> k) & 1u) | (((c1 >> k) & 1u) << 1) | (((c2 >> k) & 1u) << 2) |
           (((c3 >> k) & 1u) << 3) | (((c4 >> k) & 1u) << 4) | (((c5 >> k) & 1u) << 5) |
           (((c6 >> k) & 1u) << 6) | (((c7 >> k) & 1u) << 7);
}
#endif

// Rank of the vertex of point k's edge along `axis` among its segment's vertices (points in x
// order, then axes x, y, z): the order of the CPU reference.
uint vertex_rank(uvec3 e, uint k, uint axis) {
    uint below = (1u << k) - 1u;
    uint r = bitCount(e.x & below) + bitCount(e.y & below) + bitCount(e.z & below);
    if (axis > 0u) r += (e.x >> k) & 1u;
    if (axis > 1u) r += (e.y >> k) & 1u;
    return r;
}
