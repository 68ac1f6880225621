// Shared by the renderer's shaders: the sRGB transfer function.
#ifndef FDMSURF_RENDER_COMMON_GLSL
#define FDMSURF_RENDER_COMMON_GLSL

// sRGB-encoded to linear light, by Ian Taylor's cubic fit (within 0.5% of the exact curve over
// [0, 1]): per vertex, three pow() calls cost more than the rest of the vertex shader on
// lavapipe.
vec3 srgb_to_linear(vec3 c) {
    return c * (c * (c * 0.305306011 + 0.682171111) + 0.012522878);
}

#endif
