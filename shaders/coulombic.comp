// Vertex properties, pass 2: the Coulomb potential with ChimeraX's distance-dependent
// dielectric (eps = 4 r), phi(x) = sum_i 332 q_i / (4 |x - c_i|²) in kcal/(mol e), at x = the
// vertex moved `offset` Å out along its normal; a direct sum over every charge site (atoms of
// zero charge are not sites), kCoulombTile sites at a time through shared memory. Optionally
// the red-white-blue colour of the potential. Mirrors coulombic_cpu() in vertex_atoms_cpu.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kVertexGroup) in;
layout(push_constant) uniform Push { CoulombPush pc; };
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Normals { float normals[]; };
layout(std430, binding = 2) readonly buffer Sites { vec4 sites[]; };  // x, y, z, q
layout(std430, binding = 3) writeonly buffer Out { uint out_words[]; };  // phi bits [, colour]

shared vec4 tile[kCoulombTile];

// Red (-range) through white (0) to blue (+range), packed r | g << 8 | b << 16.
uint ramp(float phi) {
    float t = clamp(phi / pc.color_range, -1.0, 1.0);
    vec3 c = t < 0.0 ? mix(vec3(1.0), vec3(1.0, 0.0, 0.0), -t) : mix(vec3(1.0), vec3(0.0, 0.0, 1.0), t);
    uvec3 b = uvec3(round(c * 255.0));
    return b.r | (b.g << 8) | (b.b << 16);
}

void main() {
    uint v = (gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x) * kVertexGroup +
             gl_LocalInvocationID.x;
    bool live = v < pc.vertex_count;
    vec3 x = vec3(0.0);
    if (live) {
        vec3 p = vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
        vec3 n = vec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        x = p + pc.offset * n;
    }
    float phi = 0.0;
    for (uint base = 0; base < pc.site_count; base += kCoulombTile) {
        uint count = min(kCoulombTile, pc.site_count - base);
        barrier();
        for (uint k = gl_LocalInvocationID.x; k < count; k += kVertexGroup) tile[k] = sites[base + k];
        barrier();
        for (uint k = 0; k < count; ++k) {
            vec3 d = x - tile[k].xyz;
            // A site on the evaluation point itself (impossible 1.4 Å outside a surface) would
            // divide by 0: at least 0.01 Å².
            phi += tile[k].w / max(dot(d, d), 1.0e-2);
        }
    }
    if (!live) return;
    phi *= pc.scale;
    if (pc.color != 0u) {
        out_words[2 * v] = floatBitsToUint(phi);
        out_words[2 * v + 1] = ramp(phi);
    } else {
        out_words[v] = floatBitsToUint(phi);
    }
}
