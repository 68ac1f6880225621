// The exact SES field's per-point pieces (ses_distance.comp; ses_boxes.comp needs only the sphere
// bins and has its own depth loop): the sphere and arc bins, the distance to an exposed arc, and
// d evaluated from the bins at one point. The includer
// declares the buffers spheres (vec4: xyz, R), sphere_start, arcs (three vec4 per arc) and
// arc_start, and a push constant `pc` with the bin grid (bin_origin_*, bin_size, bin_n*), r_max
// and rho_max (shader_interface.h). CPU reference: src/grid/ses_distance_cpu.cpp.

const float kTwoPi = 6.283185307179586;

vec3 box_gap(vec3 c, vec3 lo, vec3 hi) { return max(max(lo - c, c - hi), vec3(0.0)); }
vec3 box_far(vec3 c, vec3 lo, vec3 hi) { return max(abs(c - lo), abs(c - hi)); }

ivec3 bin_dims() { return ivec3(pc.bin_nx, pc.bin_ny, pc.bin_nz); }
ivec3 bin_of(vec3 p) {
    vec3 o = vec3(pc.bin_origin_x, pc.bin_origin_y, pc.bin_origin_z);
    return clamp(ivec3(floor((p - o) / pc.bin_size)), ivec3(0), bin_dims() - 1);
}
uint bin_id(ivec3 b) { return (uint(b.z) * pc.bin_ny + uint(b.y)) * pc.bin_nx + uint(b.x); }

// Distance from p to the exposed arc (m, e1, e2) (mirrors arc_distance in ses_features.cpp),
// or a value >= `bound` when the arc is certainly not nearer than `bound` (cheap rejections
// first).
float arc_distance(vec4 m, vec4 e1, vec4 e2, vec3 p, float bound) {
    vec3 v = p - m.xyz;
    // No point of the circle is nearer than |v| - rho: the cheapest test, and most arcs of a
    // box's list fail it for any one of its points.
    float reach = m.w + bound;
    if (dot(v, v) >= reach * reach) return bound;
    float height = dot(v, cross(e1.xyz, e2.xyz));
    if (abs(height) >= bound) return bound;
    float x = dot(v, e1.xyz), y = dot(v, e2.xyz);
    float r = sqrt(x * x + y * y);
    float rr = r - m.w;
    if (abs(rr) >= bound) return bound;
    float rel = r > 0.0 ? atan(y, x) - e1.w : 0.0;
    rel -= kTwoPi * floor(rel / kTwoPi);
    // Off the arc, the nearer end (in angle) is the nearer point.
    float delta = rel <= e2.w ? 0.0 : min(rel - e2.w, kTwoPi - rel);
    float s = sin(0.5 * delta);
    return sqrt(height * height + rr * rr + 4.0 * r * m.w * s * s);
}

// Where the face distance |L - R| of sphere s is reached: the radial projection of p.
vec3 projection(vec4 s, vec3 p) {
    vec3 v = p - s.xyz;
    float len = length(v);
    return s.xyz + s.w * (len > 1e-6 ? v / len : vec3(1.0, 0.0, 0.0));
}

// Is q (a point of sphere `self`) inside another ball? From the bins around q.
bool buried_global(vec3 q, uint self) {
    ivec3 lo = bin_of(q - pc.r_max), hi = bin_of(q + pc.r_max);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                uint b = bin_id(ivec3(x, y, z));
                for (uint k = sphere_start[b]; k < sphere_start[b + 1u]; ++k) {
                    if (k == self) continue;
                    vec3 w = q - spheres[k].xyz;
                    if (dot(w, w) < spheres[k].w * spheres[k].w) return true;
                }
            }
    return false;
}

// d at p clamped to [-d_max, d_max], from the bins: the boxes of ses_distance.comp whose lists
// overflow shared memory.
float evaluate_global(vec3 p, float d_max) {
    float reach = pc.r_max + d_max;
    ivec3 lo = bin_of(p - reach), hi = bin_of(p + reach);
    float lb = -3.0e38;
    uint deepest = 0u;
    bool tie = false;
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                uint b = bin_id(ivec3(x, y, z));
                for (uint i = sphere_start[b]; i < sphere_start[b + 1u]; ++i) {
                    float depth = spheres[i].w - distance(p, spheres[i].xyz);
                    tie = depth == lb || (tie && depth < lb);
                    if (depth > lb) {
                        lb = depth;
                        deepest = i;
                    }
                }
            }
    if (lb <= 0.0) return max(lb, -d_max);
    if (lb >= d_max) return d_max;
    if (!buried_global(projection(spheres[deepest], p), deepest)) return lb;
    float best = d_max;
    ivec3 alo = bin_of(p - (pc.rho_max + d_max)), ahi = bin_of(p + (pc.rho_max + d_max));
    for (int z = alo.z; z <= ahi.z; ++z)
        for (int y = alo.y; y <= ahi.y; ++y)
            for (int x = alo.x; x <= ahi.x; ++x) {
                uint b = bin_id(ivec3(x, y, z));
                for (uint k = arc_start[b]; k < arc_start[b + 1u]; ++k)
                    best = min(best, arc_distance(arcs[3u * k], arcs[3u * k + 1u],
                                                  arcs[3u * k + 2u], p, best));
            }
    if (tie && lb < best) {
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) {
                    uint b = bin_id(ivec3(x, y, z));
                    for (uint i = sphere_start[b]; i < sphere_start[b + 1u]; ++i) {
                        vec4 s = spheres[i];
                        if (i == deepest || s.w - distance(p, s.xyz) != lb) continue;
                        if (!buried_global(projection(s, p), i)) return lb;
                    }
                }
    }
    return best;
}

