// Shared by the renderer's shaders: sRGB transfer functions.
#ifndef FDMSURF_RENDER_COMMON_GLSL
#define FDMSURF_RENDER_COMMON_GLSL

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

#endif
