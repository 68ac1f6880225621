// The scene pass, vertex stage: a device mesh's interleaved vertices (position, normal; 24
// bytes) and its attribute words (atom, packed sRGB colour) through the orthographic camera of
// RenderPush (shader_interface.h). With no attribute buffer the renderer binds one word pair
// holding the uniform colour, per instance. Colours are interpolated: flat ones draw the
// boundaries between atoms as staircases along the triangles' edges when zoomed in.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
#include "render_common.glsl"

layout(push_constant) uniform Push { RenderPush pc; };
layout(location = 0) in vec3 in_position;  // Å
layout(location = 1) in vec3 in_normal;    // outward, unit
layout(location = 2) in vec4 in_color;     // sRGB, R8G8B8A8_UNORM

layout(location = 0) out vec3 out_normal;  // view space: x right, y up, z towards the viewer
layout(location = 1) out vec3 out_color;   // linear

void main() {
    vec3 p = in_position - vec3(pc.center_x, pc.center_y, pc.center_z);
    vec3 r0 = vec3(pc.row0_x, pc.row0_y, pc.row0_z);
    vec3 r1 = vec3(pc.row1_x, pc.row1_y, pc.row1_z);
    vec3 r2 = vec3(pc.row2_x, pc.row2_y, pc.row2_z);
    vec3 v = vec3(dot(r0, p), dot(r1, p), dot(r2, p));
    gl_Position = vec4(v.x * pc.scale_x, -v.y * pc.scale_y, 0.5 - v.z * pc.depth_scale, 1.0);
    out_normal = vec3(dot(r0, in_normal), dot(r1, in_normal), dot(r2, in_normal));
    out_color = srgb_to_linear(in_color.rgb);
}
