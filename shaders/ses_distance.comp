// Exact SES field (--method edt; ALGORITHM.md §7, the closing of the atoms by the probe):
// d(p) = distance from p to the region E outside every ball of radius R_i = r_i + r_s, signed
// (-dist(p, balls) outside the balls), clamped to [d_min, d_max] = [r_s - b h, r_s + b h], b one
// or two spacings (ses_band_steps, grid_plan.hpp). The SES is d = r_s; marching cubes reads exact
// values only within 2h of it, and only within h where the snap replaces its normals.
//
// Inside the balls, the nearest point of E's boundary is (1) the radial projection of p onto a
// sphere, if no other ball buries it, or (2) the nearest point of an exposed arc where two
// spheres meet (its ends are the points where three meet); the arcs come from the host
// (src/grid/ses_features.cpp). Each workgroup copies into shared memory the spheres and arcs
// that can be within d_max of its box; every point then takes the least candidate distance.
// A box that ses_boxes.comp found wholly outside the balls below d_min (its class, binding 5)
// only writes d_min. CPU reference: src/grid/ses_distance_cpu.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(local_size_x = kSesGroupX, local_size_y = kSesGroupY, local_size_z = kSesGroupZ) in;

layout(std430, binding = 0) writeonly buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer Spheres { vec4 spheres[]; };  // xyz, R
layout(std430, binding = 2) readonly buffer SphereStart { uint sphere_start[]; };
layout(std430, binding = 3) readonly buffer Arcs {
    vec4 arcs[];
};  // (m, rho), (e1, start), (e2, length)
layout(std430, binding = 4) readonly buffer ArcStart { uint arc_start[]; };
layout(std430, binding = 5) readonly buffer BoxClass { uint box_class[]; };  // ses_boxes.comp

layout(push_constant) uniform Push { SesDistancePush pc; };

const uint kGroupSize = kSesGroupX * kSesGroupY * kSesGroupZ;

// The candidates' data itself, not indices: every point of the workgroup reads the same entries
// in the same order, and shared memory spares lavapipe the bounds-checked per-lane loads of a
// storage buffer.
shared vec4 sphere_list[kSesSphereCapacity];    // xyz, R
shared vec4 arc_list[3u * kSesArcCapacity];      // (m, rho), (e1, start), (e2, length)
shared uint sphere_count;
shared uint arc_count;
shared uint deep;  // 1: one ball holds the whole box d_max deep, so d = d_max throughout

#include "ses_common.glsl"

// Is q (a point of listed sphere `self`) inside another listed ball? A ball burying a point
// within d_max of the box is within R + d_max of it: it is on the list.
bool buried_shared(vec3 q, uint self, uint ns) {
    for (uint k = 0u; k < ns; ++k) {
        if (k == self) continue;
        vec4 o = sphere_list[k];
        vec3 w = q - o.xyz;
        if (dot(w, w) < o.w * o.w) return true;
    }
    return false;
}

// Whether the deepest ball's face, lb away, is exposed at p's radial projection: then d = lb, the
// least d can be (a contact patch, most of the surface).
bool face_exposed(vec3 p, uint deepest) {
    return !buried_shared(projection(sphere_list[deepest], p), deepest, sphere_count);
}

// d at p where the deepest ball's face is buried and an arc or a tied face is nearer than d_max:
// `best` is the least arc distance (the arcs loop in main). The other faces: a ball B not
// holding p cannot offer the nearest point y of E on its face: y would be p's radial
// projection, the segment from p to y (inside the balls, E's complement, but at y) leaves B's
// sphere outwards at y, so its points just before y lie in another ball, whose closure holds y:
// y is buried, or on a circle (an arc gives the same distance). The faces of the balls holding p
// are R - |p - c| <= lb away, and d >= lb: only a ball exactly as deep as the deepest can be
// nearer than the arcs. The CPU reference (ses_distance_cpu.cpp) still tries every face; the
// tests compare the two.
float finish_tied(vec3 p, float lb, uint deepest, bool tie, float best) {
    if (tie && lb < best) {
        uint ns = sphere_count;
        for (uint i = 0u; i < ns; ++i) {
            vec4 s = sphere_list[i];
            if (i == deepest || s.w - distance(p, s.xyz) != lb) continue;
            if (!buried_shared(projection(s, p), i, ns)) return lb;
        }
    }
    return best;
}

void main() {
    uint t = gl_LocalInvocationIndex;
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    uvec3 dims = uvec3(pc.nx, pc.ny, pc.nz);
    // The box: points_z layers of the workgroup along z, one point of each per invocation.
    uvec3 span = uvec3(kSesGroupX, kSesGroupY, kSesGroupZ * pc.points_z);
    uvec3 first = gl_WorkGroupID * span;
    // Wholly outside the balls below d_min (ses_boxes.comp): the whole workgroup writes d_min and
    // leaves (the class is the same for every invocation: no barrier is skipped by some only).
    uint box_index =
        (gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x +
        gl_WorkGroupID.x;
    uint cls = box_class[box_index];
    if (cls == kSesBoxOutside) {
        uvec3 g = first + gl_LocalInvocationID;
        if (any(greaterThanEqual(g.xy, dims.xy))) return;
        for (uint j = 0u; j < pc.points_z; ++j) {
            uint z = g.z + j * kSesGroupZ;
            if (z < pc.nz) field[(z * pc.ny + g.y) * pc.pitch + g.x] = pc.d_min;
        }
        return;
    }
    uvec3 last = min(first + span, dims) - 1u;
    vec3 box_lo = origin + pc.spacing * vec3(first);
    vec3 box_hi = origin + pc.spacing * vec3(last);

    if (t == 0u) {
        sphere_count = 0u;
        arc_count = 0u;
        deep = 0u;
    }
    barrier();
    // Candidates: spheres within R + d_max of the box, arcs within rho + d_max.
    float reach = pc.r_max + pc.d_max;
    ivec3 b_lo = bin_of(box_lo - reach), b_hi = bin_of(box_hi + reach);
    ivec3 b_n = b_hi - b_lo + 1;
    uint bins = uint(b_n.x * b_n.y * b_n.z);
    for (uint k = t; k < bins; k += kGroupSize) {
        ivec3 b = b_lo + ivec3(int(k) % b_n.x, (int(k) / b_n.x) % b_n.y, int(k) / (b_n.x * b_n.y));
        uint id = bin_id(b);
        for (uint i = sphere_start[id]; i < sphere_start[id + 1u]; ++i) {
            vec4 s = spheres[i];
            vec3 gap = box_gap(s.xyz, box_lo, box_hi);
            float r = s.w + pc.d_max;
            if (dot(gap, gap) >= r * r) continue;
            vec3 far = box_far(s.xyz, box_lo, box_hi);
            float inner = s.w - pc.d_max;
            if (inner > 0.0 && dot(far, far) <= inner * inner) deep = 1u;
            uint slot = atomicAdd(sphere_count, 1u);
            if (slot < kSesSphereCapacity) sphere_list[slot] = s;
        }
    }
    barrier();
    // Arcs within d_max of the box: near the circle's bounding ball, not wholly inside the ball
    // of radius rho - d_max around its centre, and within d_max of its plane. A deep box skips
    // this (deep is read after the barrier: the same for the whole workgroup).
    if (deep == 0u) {
        vec3 centre = 0.5 * (box_lo + box_hi), half_extent = 0.5 * (box_hi - box_lo);
        reach = pc.rho_max + pc.d_max;
        b_lo = bin_of(box_lo - reach);
        b_hi = bin_of(box_hi + reach);
        b_n = b_hi - b_lo + 1;
        bins = uint(b_n.x * b_n.y * b_n.z);
        for (uint k = t; k < bins; k += kGroupSize) {
            ivec3 b =
                b_lo + ivec3(int(k) % b_n.x, (int(k) / b_n.x) % b_n.y, int(k) / (b_n.x * b_n.y));
            uint id = bin_id(b);
            for (uint a = arc_start[id]; a < arc_start[id + 1u]; ++a) {
                vec4 m = arcs[3u * a];
                vec3 gap = box_gap(m.xyz, box_lo, box_hi);
                float r = m.w + pc.d_max;
                if (dot(gap, gap) >= r * r) continue;
                vec3 far = box_far(m.xyz, box_lo, box_hi);
                float inner = m.w - pc.d_max;
                if (inner > 0.0 && dot(far, far) < inner * inner) continue;
                vec4 e1 = arcs[3u * a + 1u], e2 = arcs[3u * a + 2u];
                vec3 axis = cross(e1.xyz, e2.xyz);
                if (abs(dot(centre - m.xyz, axis)) - dot(half_extent, abs(axis)) >= pc.d_max)
                    continue;
                uint slot = atomicAdd(arc_count, 1u);
                if (slot < kSesArcCapacity) {
                    arc_list[3u * slot] = m;
                    arc_list[3u * slot + 1u] = e1;
                    arc_list[3u * slot + 2u] = e2;
                }
            }
        }
    }
    barrier();

    uvec3 g0 = first + gl_LocalInvocationID;
    if (any(greaterThanEqual(g0, dims))) return;
    if (deep != 0u) {
        for (uint j = 0u; j < pc.points_z; ++j) {
            uint z = g0.z + j * kSesGroupZ;
            if (z < pc.nz) field[(z * pc.ny + g0.y) * pc.pitch + g0.x] = pc.d_max;
        }
        return;
    }
    vec3 p0 = origin + pc.spacing * vec3(g0);
    vec3 step = vec3(0.0, 0.0, pc.spacing * float(kSesGroupZ));
    if (sphere_count > kSesSphereCapacity || arc_count > kSesArcCapacity ||
        pc.force_global != 0u) {
        for (uint j = 0u; j < pc.points_z; ++j) {
            uint z = g0.z + j * kSesGroupZ;
            if (z < pc.nz)
                field[(z * pc.ny + g0.y) * pc.pitch + g0.x] =
                    max(evaluate_global(p0 + float(j) * step, pc.d_max), pc.d_min);
        }
        return;
    }
    // The invocation's points share each sphere read: the depths of all of them in one loop.
    float lb[kSesPointsZ];
    uint deepest[kSesPointsZ];
    bool tie[kSesPointsZ];
    for (uint j = 0u; j < kSesPointsZ; ++j) {
        lb[j] = -3.0e38;
        deepest[j] = 0u;
        tie[j] = false;
    }
    // (Arrays of the largest size, unrolled; the uniform test keeps them in registers.)
    for (uint i = 0u; i < sphere_count; ++i) {
        vec4 s = sphere_list[i];
        for (uint j = 0u; j < kSesPointsZ; ++j) {
            if (j >= pc.points_z) break;
            float depth = s.w - distance(p0 + float(j) * step, s.xyz);
            tie[j] = depth == lb[j] || (tie[j] && depth < lb[j]);
            if (depth > lb[j]) {
                lb[j] = depth;
                deepest[j] = i;
            }
        }
    }
    // d from lb where it can be (outside the balls, deep inside, or the deepest face exposed);
    // the other points need the arcs, which one loop reads once for all of them (in the same
    // order for each point, so each point's value is what a loop of its own would give).
    float value[kSesPointsZ];
    bool arcs_needed[kSesPointsZ];
    bool any_arcs = false;
    for (uint j = 0u; j < kSesPointsZ; ++j) {
        value[j] = pc.d_max;
        arcs_needed[j] = false;
        if (j >= pc.points_z) break;
        float l = lb[j];
        if (l <= 0.0)
            value[j] = max(l, -pc.d_max);
        else if (l >= pc.d_max)
            value[j] = pc.d_max;
        else if (face_exposed(p0 + float(j) * step, deepest[j]))
            value[j] = l;
        else
            arcs_needed[j] = true;
        any_arcs = any_arcs || arcs_needed[j];
    }
    if (any_arcs) {
        uint na = arc_count;
        for (uint k = 0u; k < na; ++k) {
            vec4 m = arc_list[3u * k], e1 = arc_list[3u * k + 1u], e2 = arc_list[3u * k + 2u];
            for (uint j = 0u; j < kSesPointsZ; ++j) {
                if (j >= pc.points_z) break;
                if (arcs_needed[j])
                    value[j] = min(value[j], arc_distance(m, e1, e2, p0 + float(j) * step, value[j]));
            }
        }
    }
    for (uint j = 0u; j < kSesPointsZ; ++j) {
        if (j >= pc.points_z) break;
        uint z = g0.z + j * kSesGroupZ;
        if (arcs_needed[j])
            value[j] = finish_tied(p0 + float(j) * step, lb[j], deepest[j], tie[j], value[j]);
        if (z < pc.nz) field[(z * pc.ny + g0.y) * pc.pitch + g0.x] = max(value[j], pc.d_min);
    }
}
