// Marching cubes, pass 1: the occupancy word of each segment (bit k set when point 32 w + k of
// the row is inside, value >= iso). The only pass that reads every field value.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;  // kMcGroup
layout(std430, binding = 1) writeonly buffer OccupancyOut { uint occ_out[]; };
#define MC_FIELD_BINDING 0
#include "mc_common.glsl"

void main() {
    uint s = invocation_index();
    if (s >= pc.segments) return;
    uvec3 c = segment_coords(s);
    uint x0 = 32u * c.x;
    uint n = min(32u, pc.nx - x0);
    uint base = (c.z * pc.ny + c.y) * pc.pitch + x0;
    uint bits = 0u;
    for (uint k = 0u; k < n; ++k)
        if (field[base + k] >= pc.iso) bits |= 1u << k;
    occ_out[s] = bits;
}
