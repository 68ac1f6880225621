// Exact SES field, first pass: which boxes of ses_distance.comp (a workgroup's points) lie wholly
// outside the balls, beyond the field's lower clamp d_min, so that the second pass writes d_min
// there without gathering candidates. d is 1-Lipschitz (a signed distance), so over a box of
// half-diagonal r around its centre c it stays below d(c) + r; where c is outside every ball,
// d(c) is lb(c) = max_i (R_i - |c - c_i|), and the box is outside when lb(c) <= min(d_min - r,
// 0) - slack (slack: a margin for float rounding). Only the spheres within R - that bound of c
// can reach it: the depth loop over them is all a box costs here, about one point's work in the
// second pass. (Boxes wholly deeper than d_max are not worth the evaluation: about 1% of them on
// hemoglobin, and ses_distance.comp's own `deep` test takes the deepest.)
// CPU reference: ses_box_classes_cpu (src/grid/ses_distance_cpu.cpp).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kSesBoxGroup) in;

layout(std430, binding = 0) writeonly buffer BoxClass { uint box_class[]; };
layout(std430, binding = 1) readonly buffer Spheres { vec4 spheres[]; };  // xyz, R
layout(std430, binding = 2) readonly buffer SphereStart { uint sphere_start[]; };

layout(push_constant) uniform Push { SesBoxesPush pc; };

ivec3 bin_of(vec3 p) {
    vec3 o = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    return clamp(ivec3(floor((p - o) / pc.bin_size)), ivec3(0),
                 ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz) - 1);
}

void main() {
    // A flat dispatch folded into rows of workgroups (Commands::fold_groups).
    uint box = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * kSesBoxGroup +
               gl_LocalInvocationID.x;
    uint count = pc.boxes_x * pc.boxes_y * pc.boxes_z;
    if (box >= count) return;
    uvec3 b = uvec3(box % pc.boxes_x, (box / pc.boxes_x) % pc.boxes_y,
                    box / (pc.boxes_x * pc.boxes_y));
    uvec3 span = uvec3(kSesGroupX, kSesGroupY, kSesGroupZ * pc.points_z);
    uvec3 first = b * span;
    uvec3 last = min(first + span, uvec3(pc.nx, pc.ny, pc.nz)) - 1u;
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    // The box's corners as ses_distance.comp computes its points (origin + spacing * index).
    vec3 lo = origin + pc.spacing * vec3(first), hi = origin + pc.spacing * vec3(last);
    vec3 c = 0.5 * (lo + hi);
    float r = 0.5 * length(hi - lo);
    float bound = min(pc.d_min - r, 0.0) - pc.slack;  // < 0
    // lb(c) > bound needs a sphere within R - bound of c.
    ivec3 blo = bin_of(c - (pc.r_max - bound)), bhi = bin_of(c + (pc.r_max - bound));
    bool outside = true;
    for (int z = blo.z; z <= bhi.z && outside; ++z)
        for (int y = blo.y; y <= bhi.y && outside; ++y)
            for (int x = blo.x; x <= bhi.x && outside; ++x) {
                uint id = (uint(z) * pc.bin_ny + uint(y)) * pc.bin_nx + uint(x);
                for (uint i = sphere_start[id]; i < sphere_start[id + 1u]; ++i) {
                    vec4 s = spheres[i];
                    if (s.w - distance(c, s.xyz) > bound) {
                        outside = false;
                        break;
                    }
                }
            }
    box_class[box] = outside ? kSesBoxOutside : kSesBoxBand;
}
