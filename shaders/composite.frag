// The compositing pass: the lit scene and its depth in, the picture out. Per sample: the
// background where nothing was drawn; else the lit colour darkened by screen-space ambient
// occlusion (the share of kAoSamples depth samples within ao_radius that lie nearer the viewer
// than the local tangent plane: crevices and pockets darken, open faces do not), by
// the depth cue (the far side of the framed sphere darker), and an outline where a neighbour
// at outline distance is background or lies more than outline_step Å away in depth.
// Premultiplied alpha (the host straightens it after the downsampling blit).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"

layout(push_constant) uniform Push { CompositePush pc; };
layout(binding = 0) uniform sampler2D scene;  // sRGB attachment: linear when fetched
layout(binding = 1) uniform sampler2D depth;  // 0 nearest .. 1 farthest (and the clear value)
layout(location = 0) out vec4 out_color;

const float kGoldenAngle = 2.39996323;

float depth_at(ivec2 p, ivec2 size) {
    return texelFetch(depth, clamp(p, ivec2(0), size - 1), 0).r;
}

void main() {
    ivec2 size = textureSize(depth, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = texelFetch(depth, p, 0).r;
    vec4 background = vec4(pc.background_r, pc.background_g, pc.background_b, pc.background_a);
    if (d >= 1.0) {
        out_color = background;
        return;
    }
    vec3 c = texelFetch(scene, p, 0).rgb;
    float z = d * pc.depth_range;  // Å behind the nearest point of the framed sphere

    if (pc.ao_strength > 0.0) {
        // The local tangent plane from the flatter of the one-sided depth differences along x
        // and y (background neighbours ignored): a sample occludes when it lies nearer the
        // viewer than that plane by more than about a third of its lateral distance, so that
        // slopes and convex faces stay bright and crevices darken.
        vec2 slope = vec2(0.0);
        for (int a = 0; a < 2; ++a) {
            ivec2 e = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
            float f = depth_at(p + e, size), b = depth_at(p - e, size);
            float df = f < 1.0 ? f - d : 1e9, db = b < 1.0 ? d - b : 1e9;
            float s = abs(df) < abs(db) ? df : db;
            slope[a] = abs(s) < 1e8 ? s * pc.depth_range : 0.0;  // Å per sample
        }
        // A spiral of samples turned by interleaved gradient noise per pixel.
        float turn = 6.2831853 * fract(52.9829189 * fract(dot(vec2(p), vec2(0.06711056, 0.00583715))));
        float radius_px = pc.ao_radius / pc.pixel_size;
        float occluded = 0.0;
        for (uint i = 0; i < kAoSamples; ++i) {
            float t = (float(i) + 0.5) / float(kAoSamples);
            float a = turn + kGoldenAngle * float(i);
            ivec2 offset = ivec2(round(vec2(cos(a), sin(a)) * (radius_px * sqrt(t))));
            float dq = depth_at(p + offset, size);
            if (dq >= 1.0) continue;
            float plane = z + dot(slope, vec2(offset));
            float rise = plane - dq * pc.depth_range;  // > 0: the sample is nearer the viewer
            float reach = length(vec2(offset)) * pc.pixel_size + 0.05;
            occluded += smoothstep(0.15 * reach, 0.5 * reach, rise) *
                        (1.0 - smoothstep(2.0 * pc.ao_radius, 3.0 * pc.ao_radius, rise));
        }
        c *= 1.0 - pc.ao_strength * occluded / float(kAoSamples);
    }
    c *= 1.0 - pc.depth_cue * clamp(d, 0.0, 1.0);

    if (pc.outline > 0.0) {
        int w = int(pc.outline);
        float edge = 0.0;
        ivec2 steps[4] = ivec2[](ivec2(w, 0), ivec2(-w, 0), ivec2(0, w), ivec2(0, -w));
        for (int k = 0; k < 4; ++k) {
            float dn = depth_at(p + steps[k], size);
            if (dn >= 1.0 || abs(dn - d) * pc.depth_range > pc.outline_step) edge = 1.0;
        }
        c = mix(c, vec3(0.02), edge);
    }
    out_color = vec4(c, 1.0);
}
