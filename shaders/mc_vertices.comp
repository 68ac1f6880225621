// Marching cubes, pass 4: one vertex per crossed owned edge, at the linear interpolation of the
// iso-level, with the normal -grad(rho) interpolated from central differences. A segment's first
// vertex is its run's offset (mc_scan.comp) plus its offset in the run (mc_count.comp).
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;  // kMcGroup
layout(std430, binding = 2) readonly buffer Local { uint local_offsets[]; };
layout(std430, binding = 3) readonly buffer RunSums { uvec2 run_sums[]; };
layout(std430, binding = 4) writeonly buffer Vertices { float vertices[]; };  // pos, normal
#define MC_FIELD_BINDING 0
#define MC_OCC_BINDING 1
#include "mc_common.glsl"

vec3 gradient(uvec3 p) {
    uvec3 lo = uvec3(max(ivec3(p) - 1, ivec3(0)));
    uvec3 hi = min(p + 1u, uvec3(pc.nx, pc.ny, pc.nz) - 1u);
    vec3 g;
    g.x = (value_at(hi.x, p.y, p.z) - value_at(lo.x, p.y, p.z)) / (float(hi.x - lo.x) * pc.spacing);
    g.y = (value_at(p.x, hi.y, p.z) - value_at(p.x, lo.y, p.z)) / (float(hi.y - lo.y) * pc.spacing);
    g.z = (value_at(p.x, p.y, hi.z) - value_at(p.x, p.y, lo.z)) / (float(hi.z - lo.z) * pc.spacing);
    return g;
}

// Mirrors edge_crossing() in src/isosurface/marching_cubes_cpu.cpp.
float edge_crossing(float v0, float v1) {
    float t = (pc.iso - v0) / (v1 - v0);
    if (pc.power_sigma2 > 0.0 && v0 > 0.0 && v1 > 0.0) {
        float pi0 = -pc.power_sigma2 * log(v0 / pc.power_t);
        float pi1 = -pc.power_sigma2 * log(v1 / pc.power_t);
        float pii = -pc.power_sigma2 * log(pc.iso / pc.power_t);
        float a = pc.spacing * pc.spacing;
        float b = pi1 - pi0 - a;
        float c = pi0 - pii;
        float disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {
            float s = sqrt(disc);
            float r1 = (-b - s) / (2.0 * a), r2 = (-b + s) / (2.0 * a);
            bool ok1 = r1 >= 0.0 && r1 <= 1.0, ok2 = r2 >= 0.0 && r2 <= 1.0;
            if (ok1 && ok2)
                t = abs(r1 - t) <= abs(r2 - t) ? r1 : r2;
            else if (ok1)
                t = r1;
            else if (ok2)
                t = r2;
        }
    }
    return clamp(t, 0.001, 0.999);
}

void main() {
    uint s = invocation_index();
    if (s >= pc.segments) return;
    uvec3 c = segment_coords(s);
    uvec3 e = segment_edges(c.x, c.y, c.z);
    uint points = e.x | e.y | e.z;
    if (points == 0u) return;
    uint v = run_sums[s / kMcRun].x + (local_offsets[s] & 0xffffu);
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    while (points != 0u) {
        uint k = uint(findLSB(points));
        points &= points - 1u;
        uvec3 p = uvec3(32u * c.x + k, c.y, c.z);
        uint bits = ((e.x >> k) & 1u) | (((e.y >> k) & 1u) << 1) | (((e.z >> k) & 1u) << 2);
        float v0 = value_at(p.x, p.y, p.z);
        vec3 g0 = gradient(p);
        for (uint axis = 0u; axis < 3u; ++axis) {
            if ((bits & (1u << axis)) == 0u) continue;
            uvec3 d = uvec3(axis == 0u ? 1u : 0u, axis == 1u ? 1u : 0u, axis == 2u ? 1u : 0u);
            uvec3 q = p + d;
            float v1 = value_at(q.x, q.y, q.z);
            float t = edge_crossing(v0, v1);
            vec3 pos = origin + pc.spacing * (vec3(p) + t * vec3(d));
            vec3 g = (1.0 - t) * g0 + t * gradient(q);
            float len = length(g);
            vec3 n = len > 1e-20 ? -g / len : (v0 >= pc.iso ? vec3(d) : -vec3(d));
            vertices[6u * v + 0u] = pos.x;
            vertices[6u * v + 1u] = pos.y;
            vertices[6u * v + 2u] = pos.z;
            vertices[6u * v + 3u] = n.x;
            vertices[6u * v + 4u] = n.y;
            vertices[6u * v + 5u] = n.z;
            ++v;
        }
    }
}
