// The default Gaussian filter as a separable convolution in space, on the host: the low-pass of
// VkFFT forward, the mask 2^-(f/F)^2 and VkFFT inverse (a Gaussian of sigma = sqrt(ln 2 / 2) /
// (pi F) in space), for devices whose FFTs run on the same CPU cores
// (VK_PHYSICAL_DEVICE_TYPE_CPU: lavapipe), where three passes of a short kernel cost a fraction
// of the transforms (docs/performance.md). The sampled kernel's response is the mask plus its
// aliases, exp(-pi^2 sigma^2 / 2) of the mask at the Nyquist frequency: below 2e-5 from
// kMinHostSigma points on (0.54 Å at the default cut-off); 0.04 at 1 Å, where the surface is as
// close to the analytical SES as VkFFT's (docs/accuracy.md). Beyond the grid it reads zeros
// where the FFT wraps around. Only the stretches of rows within the kernel's reach of a
// non-zero value are convolved: a molecule's density is 0 in most of a large box.
#pragma once

#include <cstdint>
#include <vector>

namespace fdmsurf::detail {

// The spatial sigma of the Gaussian filter of cut-off `cutoff` (1/Å), in grid points of
// `spacing` Å.
double gaussian_sigma_points(double cutoff, double spacing);

// The smallest sigma (points) at which the sampled kernel is the mask's low-pass to 2e-5.
inline constexpr double kMinHostSigma = 1.5;

// Taps of the sampled Gaussian of `sigma` points over [-radius, radius], summing to 1.
std::vector<float> gaussian_taps(double sigma, std::uint32_t radius);

// Filters planes [core_begin, core_end) of a field of nx x ny x planes points (x fastest, rows
// `pitch` floats apart, so the R2C layout of the device's field reads as it is), with zero
// outside it, into `out` (nx x ny per plane, no padding, core planes in order), on `threads`
// threads (0: all). The radius is the taps' (taps.size() = 2 radius + 1): planes within it of
// the core must be in the field for the core to be exact. `scratch` holds the x-y filtered
// planes the z pass reads (kept by the caller from call to call: its pages are touched once).
void gaussian_filter_planes(const float* field, std::uint32_t nx, std::uint32_t ny,
                            std::uint32_t planes, std::uint32_t pitch,
                            const std::vector<float>& taps, std::uint32_t core_begin,
                            std::uint32_t core_end, float* out, std::vector<float>& scratch,
                            unsigned threads = 0);

}  // namespace fdmsurf::detail
