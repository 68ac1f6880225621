// The example application's fragment shader: Lambert lighting from the viewer's side.
#version 450

layout(location = 0) in vec3 normal;
layout(location = 1) in vec3 color;
layout(location = 0) out vec4 out_color;

void main() {
    float light = max(dot(normalize(normal), normalize(vec3(-0.3, 0.4, 1.0))), 0.0);
    out_color = vec4(color * (0.3 + 0.7 * light), 1.0);
}
