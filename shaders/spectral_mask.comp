// Spectral filter (Giard & Macq 2010; ALGORITHM.md §3): multiplies the half spectrum of the R2C
// transform by the low-pass mask and by 1/N, the normalisation of the inverse transform.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shader_interface.h"
layout(local_size_x = kMaskGroupX, local_size_y = kMaskGroupY) in;
layout(std430, binding = 0) buffer Spectrum { vec2 spectrum[]; };
layout(push_constant) uniform Push { SpectralMaskPush pc; };

void main() {
    uint kx = gl_GlobalInvocationID.x;
    uint ky = gl_GlobalInvocationID.y;
    uint kz = gl_GlobalInvocationID.z;
    if (kx >= pc.cx || ky >= pc.ny || kz >= pc.nz) return;
    uint row = kz * pc.ny + ky;
    // Signed frequencies: indices past n/2 are negative frequencies.
    float sy = float(int(ky) - (ky > pc.ny / 2u ? int(pc.ny) : 0));
    float sz = float(int(kz) - (kz > pc.nz / 2u ? int(pc.nz) : 0));
    vec3 f = vec3(float(kx) * pc.fx, sy * pc.fy, sz * pc.fz);
    float fr = length(f);
    float gain;
    if (pc.shape == kFilterGaussian) {
        float q = fr / pc.cutoff;
        gain = exp2(-q * q);
    } else {
        gain = fr <= pc.cutoff ? 1.0 : 0.0;
    }
    uint index = row * pc.cx + kx;
    spectrum[index] *= gain * pc.scale;
}
