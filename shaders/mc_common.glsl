// Shared by the marching-cubes passes (Lorensen & Cline 1987): field access, point indexing and
// edge crossings, with the conventions of src/isosurface/marching_cubes_cpu.cpp.
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

float value_at(uint x, uint y, uint z) { return field[(z * pc.ny + y) * pc.pitch + x]; }

// Linear index of the invocation's owned point, or ~0u past the end.
uint point_index() {
    uint block = gl_WorkGroupID.y * pc.blocks_x + gl_WorkGroupID.x;
    return block * kMcBlock + gl_LocalInvocationID.x;
}

uvec3 point_coords(uint i) {
    uint plane = pc.nx * pc.ny;
    return uvec3(i % pc.nx, (i / pc.nx) % pc.ny, pc.z_begin + i / plane);
}

// Bit a set when the point owns the edge along axis a and the iso-level crosses it.
uint crossed_edges(uvec3 p) {
    bool inside = value_at(p.x, p.y, p.z) >= pc.iso;
    uint bits = 0u;
    if (p.x + 1u < pc.nx && (value_at(p.x + 1u, p.y, p.z) >= pc.iso) != inside) bits |= 1u;
    if (p.y + 1u < pc.ny && (value_at(p.x, p.y + 1u, p.z) >= pc.iso) != inside) bits |= 2u;
    if (p.z < pc.z_end && (value_at(p.x, p.y, p.z + 1u) >= pc.iso) != inside) bits |= 4u;
    return bits;
}

// Cube index of the cell at p, or 0 (no triangles) when p starts no cell.
uint cube_index(uvec3 p) {
    if (p.x + 1u >= pc.nx || p.y + 1u >= pc.ny || p.z >= pc.z_end) return 0u;
    uint index = 0u;
    for (uint c = 0u; c < 8u; ++c) {
        uvec3 q = p + uvec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
        if (value_at(q.x, q.y, q.z) >= pc.iso) index |= 1u << c;
    }
    return index;
}

// Exclusive prefix sum of `v` over the workgroup; `total` gets the sum.
shared uvec2 scan_buf[kMcBlock];
uvec2 workgroup_exclusive_scan(uvec2 v, out uvec2 total) {
    uint t = gl_LocalInvocationID.x;
    scan_buf[t] = v;
    barrier();
    for (uint offset = 1u; offset < kMcBlock; offset <<= 1) {
        uvec2 add = t >= offset ? scan_buf[t - offset] : uvec2(0u);
        barrier();
        scan_buf[t] += add;
        barrier();
    }
    total = scan_buf[kMcBlock - 1u];
    return scan_buf[t] - v;
}
