// Separable Gaussian convolution of the field on the host (spatial_gaussian.hpp). Each pass
// adds shifted rows times a tap (x: within a row; y: rows of one plane; z: rows of the planes
// around), loops the compiler vectorises; x and y run plane by plane into a scratch of the
// planes the core needs, z row by row into the output.
#include "filter/spatial_gaussian.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "base/parallel.hpp"

namespace fdmsurf::detail {

double gaussian_sigma_points(double cutoff, double spacing) {
    return std::sqrt(std::log(2.0) / 2.0) / (std::numbers::pi * cutoff * spacing);
}

std::vector<float> gaussian_taps(double sigma, std::uint32_t radius) {
    std::vector<double> w(2 * std::size_t{radius} + 1);
    double sum = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) {
        const double k = double(i) - double(radius);
        sum += w[i] = std::exp(-0.5 * k * k / (sigma * sigma));
    }
    std::vector<float> taps(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) taps[i] = static_cast<float>(w[i] / sum);
    return taps;
}

void gaussian_filter_planes(const float* field, std::uint32_t nx, std::uint32_t ny,
                            std::uint32_t planes, std::uint32_t pitch,
                            const std::vector<float>& taps, std::uint32_t core_begin,
                            std::uint32_t core_end, float* out, std::vector<float>& scratch,
                            unsigned threads) {
    const auto radius = static_cast<std::int64_t>(taps.size() / 2);
    if (core_end <= core_begin) return;
    // The planes the core's z pass reads.
    const std::int64_t z0 = std::max<std::int64_t>(0, std::int64_t(core_begin) - radius);
    const std::int64_t z1 = std::min<std::int64_t>(planes, std::int64_t(core_end) + radius);
    const std::size_t plane = std::size_t(nx) * ny;
    std::vector<float>& xy = scratch;
    if (xy.size() < std::size_t(z1 - z0) * plane) xy.resize(std::size_t(z1 - z0) * plane);
    threads = thread_count(threads);
    // x, then y, plane by plane.
    parallel_chunks(std::size_t(z1 - z0), threads, [&](std::size_t p) {
        thread_local std::vector<float> rows;
        rows.assign(plane, 0.0f);
        const float* src = field + (std::size_t(z0) + p) * std::size_t(pitch) * ny;
        for (std::uint32_t y = 0; y < ny; ++y) {
            const float* in = src + std::size_t(y) * pitch;
            float* o = rows.data() + std::size_t(y) * nx;
            for (std::int64_t k = -radius; k <= radius; ++k) {
                const float w = taps[std::size_t(k + radius)];
                const std::int64_t lo = std::max<std::int64_t>(0, -k);
                const std::int64_t hi = std::min<std::int64_t>(nx, std::int64_t(nx) - k);
                for (std::int64_t x = lo; x < hi; ++x) o[x] += w * in[x + k];
            }
        }
        float* dst = xy.data() + p * plane;
        std::fill(dst, dst + plane, 0.0f);
        for (std::uint32_t y = 0; y < ny; ++y) {
            float* o = dst + std::size_t(y) * nx;
            const std::int64_t lo = std::max<std::int64_t>(-radius, -std::int64_t(y));
            const std::int64_t hi = std::min<std::int64_t>(radius, std::int64_t(ny) - 1 - y);
            for (std::int64_t k = lo; k <= hi; ++k) {
                const float w = taps[std::size_t(k + radius)];
                const float* r = rows.data() + std::size_t(std::int64_t(y) + k) * nx;
                for (std::uint32_t x = 0; x < nx; ++x) o[x] += w * r[x];
            }
        }
    });
    // z, for the core's planes, row by row.
    const std::size_t core_rows = std::size_t(core_end - core_begin) * ny;
    parallel_chunks((core_rows + 63) / 64, threads, [&](std::size_t chunk) {
        for (std::size_t r = chunk * 64; r < std::min(core_rows, chunk * 64 + 64); ++r) {
            const std::int64_t z = std::int64_t(core_begin) + std::int64_t(r / ny);
            const std::size_t y = r % ny;
            float* o = out + r * nx;
            std::fill(o, o + nx, 0.0f);
            const std::int64_t lo = std::max<std::int64_t>(-radius, -z);
            const std::int64_t hi = std::min<std::int64_t>(radius, std::int64_t(planes) - 1 - z);
            for (std::int64_t k = lo; k <= hi; ++k) {
                const float w = taps[std::size_t(k + radius)];
                const float* row = xy.data() + (std::size_t(z + k - z0) * ny + y) * nx;
                for (std::uint32_t x = 0; x < nx; ++x) o[x] += w * row[x];
            }
        }
    });
}

}  // namespace fdmsurf::detail
