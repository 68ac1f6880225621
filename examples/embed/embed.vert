// The example application's vertex shader: fdmsurf's vertex buffer (position, normal; 24
// bytes) and attribute buffer (atom, colour; 8 bytes, the colour at offset 4), an orthographic
// camera looking down -z.
#version 450

layout(push_constant) uniform Camera {
    vec4 center;  // xyz: the point at the image's centre; w: 1 / half the visible height (Å)
    vec4 scale;   // x: 1 / half the visible width (Å); y: 1 / the depth range (Å)
} camera;

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 color;

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_color;

void main() {
    vec3 p = position - camera.center.xyz;
    gl_Position = vec4(p.x * camera.scale.x, -p.y * camera.center.w, 0.5 - p.z * camera.scale.y, 1.0);
    out_normal = normal;
    out_color = color.rgb;
}
