// The compositing pass: the lit scene, its normals and depth in (at `samples` x `samples`
// samples per pixel), the picture out, each pixel the mean of its samples (in linear light;
// the sRGB attachment encodes it). Per sample: the background where nothing was drawn; else the
// lit colour darkened by screen-space ambient occlusion (the share of kAoSamples depth samples
// within ao_radius that lie nearer the viewer than the tangent plane of the sample's normal:
// crevices and pockets darken, open faces and slopes do not; each of a pixel's samples takes
// its share of them), by the depth cue (the far side of the framed sphere darker), and an outline
// where a neighbour at outline distance is background or lies more than outline_step Å away in
// depth. Premultiplied alpha (the host straightens it).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(push_constant) uniform Push { CompositePush pc; };
layout(binding = 0) uniform sampler2D scene;    // sRGB attachment: linear when fetched
layout(binding = 1) uniform sampler2D depth;    // 0 nearest .. 1 farthest (and the clear value)
layout(binding = 2) uniform sampler2D normals;  // view space, n * 0.5 + 0.5
layout(location = 0) out vec4 out_color;

const float kGoldenAngle = 2.39996323;

ivec2 size;

float depth_at(ivec2 q) {
    return texelFetch(depth, clamp(q, ivec2(0), size - 1), 0).r;
}

// The ambient light left at sample q of depth d (z Å behind the near plane), from the spiral's
// samples first, first + stride, ...: the samples of a pixel share the spiral between them, so
// that their mean sees all kAoSamples directions and no noise is needed to hide a pattern.
float ambient(ivec2 q, float d, uint first, uint stride) {
    float z = d * pc.depth_range;
    // The tangent plane from the scene's normal: the depth it predicts a sample offset
    // (ox, oy) samples away (image y points down, view y up), its slope bounded near the
    // silhouette, where the normal turns away from the viewer.
    vec3 n = texelFetch(normals, q, 0).xyz * 2.0 - 1.0;
    vec2 slope = vec2(n.x, -n.y) / max(n.z, 0.25) * pc.pixel_size;  // Å of depth per sample
    float radius = pc.ao_radius / pc.pixel_size;
    float occluded = 0.0, count = 0.0;
    for (uint i = first; i < kAoSamples; i += stride) {
        float t = (float(i) + 0.5) / float(kAoSamples);
        float a = kGoldenAngle * float(i);
        ivec2 offset = ivec2(round(vec2(cos(a), sin(a)) * (radius * sqrt(t))));
        count += 1.0;
        float dq = depth_at(q + offset);
        if (dq >= 1.0) continue;
        float plane = z + dot(slope, vec2(offset));
        float rise = plane - dq * pc.depth_range;  // > 0: the sample is nearer the viewer
        float reach = length(vec2(offset)) * pc.pixel_size + 0.05;
        occluded += smoothstep(0.05 * reach, 0.4 * reach, rise) *
                    (1.0 - smoothstep(2.0 * pc.ao_radius, 3.0 * pc.ao_radius, rise));
    }
    return 1.0 - pc.ao_strength * occluded / max(count, 1.0);
}

void main() {
    size = textureSize(depth, 0);
    int s = int(pc.samples);
    ivec2 base = ivec2(gl_FragCoord.xy) * s;
    vec4 background = vec4(pc.background_r, pc.background_g, pc.background_b, pc.background_a);
    int w = int(pc.outline);
    vec4 sum = vec4(0.0);
    for (int j = 0; j < s; ++j) {
        for (int i = 0; i < s; ++i) {
            ivec2 q = base + ivec2(i, j);
            float d = texelFetch(depth, q, 0).r;
            if (d >= 1.0) {
                sum += background;
                continue;
            }
            vec3 c = texelFetch(scene, q, 0).rgb;
            if (pc.ao_strength > 0.0) c *= ambient(q, d, uint(j * s + i), uint(s * s));
            c *= 1.0 - pc.depth_cue * clamp(d, 0.0, 1.0);
            if (w > 0) {
                // The four neighbours at the outline's width: background, or a step in depth.
                vec4 dn = vec4(depth_at(q + ivec2(w, 0)), depth_at(q - ivec2(w, 0)),
                               depth_at(q + ivec2(0, w)), depth_at(q - ivec2(0, w)));
                bvec4 edge = greaterThanEqual(dn, vec4(1.0));
                edge = bvec4(uvec4(edge) |
                             uvec4(greaterThan(abs(dn - d) * pc.depth_range, vec4(pc.outline_step))));
                if (any(edge)) c = vec3(0.02);
            }
            sum += vec4(c, 1.0);
        }
    }
    out_color = sum / float(s * s);
}
