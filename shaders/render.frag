// The scene pass, fragment stage: Lambert and Blinn-Phong lighting from a key light above left
// of the viewer and a dim fill light, both fixed to the camera. Both sides of a triangle are
// lit (an open patch shows its inside). Output is linear; the sRGB attachment encodes it. The
// normal goes to a second attachment for the ambient occlusion, which, with the depth cue and
// the outline, comes later, in composite.frag.
#version 450

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_color;
layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_normal;  // the lit side's view-space normal, n * 0.5 + 0.5

const vec3 kKey = normalize(vec3(-0.35, 0.45, 1.0));
const vec3 kFill = normalize(vec3(0.6, -0.35, 0.6));
const vec3 kHalf = normalize(kKey + vec3(0.0, 0.0, 1.0));

void main() {
    vec3 n = normalize(in_normal);
    if (!gl_FrontFacing) n = -n;
    float key = max(dot(n, kKey), 0.0);
    float fill = max(dot(n, kFill), 0.0);
    float spec = key > 0.0 ? pow(max(dot(n, kHalf), 0.0), 40.0) : 0.0;
    vec3 c = in_color * (0.24 + 0.66 * key + 0.14 * fill) + vec3(0.20 * spec);
    out_color = vec4(c, 1.0);
    out_normal = vec4(n * 0.5 + 0.5, 1.0);
}
