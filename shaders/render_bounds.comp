// The framing sphere of a device mesh, from its own vertex buffer (6 floats per vertex): pass 0
// the box (float bits turned into uints of the same order, so that atomicMin and atomicMax
// compare them as floats), pass 1 the largest squared distance from the box's centre
// (non-negative floats order as their bits). Each invocation reduces a strided share of the
// chunk first, so that few atomics are issued.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kBoundsGroup) in;
layout(push_constant) uniform Push { BoundsPush pc; };
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };
// 0-2: the box's lower corner, 3-5: its upper corner (ordered uints), 6: the largest squared
// distance (float bits), 7: unused.
layout(std430, binding = 1) buffer Bounds { uint bounds[]; };

uint ordered(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

float unordered(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

void main() {
    uint invocations = pc.groups_x * gl_NumWorkGroups.y * kBoundsGroup;
    uint first = (gl_WorkGroupID.y * pc.groups_x + gl_WorkGroupID.x) * kBoundsGroup +
                 gl_LocalInvocationID.x;
    if (first >= pc.vertex_count) return;
    if (pc.pass == 0u) {
        vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
        for (uint v = first; v < pc.vertex_count; v += invocations) {
            vec3 p = vec3(vertices[6 * v], vertices[6 * v + 1], vertices[6 * v + 2]);
            lo = min(lo, p);
            hi = max(hi, p);
        }
        for (int a = 0; a < 3; ++a) {
            atomicMin(bounds[a], ordered(lo[a]));
            atomicMax(bounds[3 + a], ordered(hi[a]));
        }
    } else {
        vec3 lo = vec3(unordered(bounds[0]), unordered(bounds[1]), unordered(bounds[2]));
        vec3 hi = vec3(unordered(bounds[3]), unordered(bounds[4]), unordered(bounds[5]));
        vec3 centre = 0.5 * (lo + hi);
        float far2 = 0.0;
        for (uint v = first; v < pc.vertex_count; v += invocations) {
            vec3 p = vec3(vertices[6 * v], vertices[6 * v + 1], vertices[6 * v + 2]);
            vec3 d = p - centre;
            far2 = max(far2, dot(d, d));
        }
        atomicMax(bounds[6], floatBitsToUint(far2));
    }
}
