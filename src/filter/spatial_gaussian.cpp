// Separable Gaussian convolution of the field on the host (spatial_gaussian.hpp). Each pass
// adds shifted rows times a tap (x: within a row; y: rows of one plane; z: rows of the planes
// around), loops the compiler vectorises; x and y run plane by plane into a scratch of the
// planes the core needs, z row by row into the output.
#include "filter/spatial_gaussian.hpp"

#include <algorithm>
#include <bit>
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

namespace {

// Which stretches of a row hold a non-zero value: bit s of a row's word covers the points
// [s w, s w + w) of the row, w = width (at least 8 points, at most 64 stretches a row). A
// convolution reads zeros outside the marked stretches and writes zeros outside their reach, so
// each pass visits only the marked stretches grown by the kernel's radius: the density of a
// molecule (0 beyond every atom's Gaussian support) fills a fraction of a large box.
struct Stretches {
    std::uint32_t width = 8;
    std::uint32_t count = 1;
    explicit Stretches(std::uint32_t nx) {
        width = std::max<std::uint32_t>(8, (nx + 63) / 64);
        width = (width + 7) / 8 * 8;
        count = (nx + width - 1) / width;
    }
    std::uint64_t of_row(const float* row, std::uint32_t nx) const {
        std::uint64_t bits = 0;
        for (std::uint32_t s = 0; s < count; ++s) {
            const std::uint32_t x1 = std::min(nx, (s + 1) * width);
            bool any = false;
            for (std::uint32_t x = s * width; x < x1; ++x) any |= row[x] != 0.0f;
            bits |= std::uint64_t{any} << s;
        }
        return bits;
    }
    // The stretches within `radius` points of a marked one.
    std::uint64_t grown(std::uint64_t bits, std::int64_t radius) const {
        const std::uint32_t steps = std::uint32_t((radius + width - 1) / width);
        std::uint64_t out = bits;
        for (std::uint32_t k = 1; k <= steps && k < 64; ++k) out |= (bits << k) | (bits >> k);
        return count == 64 ? out : out & ((std::uint64_t{1} << count) - 1);
    }
    // Calls f(x0, x1) for each run of marked stretches, as points [x0, x1) of a row of nx.
    template <class F>
    void for_each_run(std::uint64_t bits, std::uint32_t nx, F&& f) const {
        while (bits) {
            const int s0 = std::countr_zero(bits);
            const std::uint64_t from = bits >> s0;
            const int len = from == ~std::uint64_t{0} ? 64 - s0 : std::countr_one(from);
            f(std::uint32_t(s0) * width, std::min(nx, std::uint32_t(s0 + len) * width));
            bits = s0 + len >= 64 ? 0 : bits & ~((std::uint64_t{1} << (s0 + len)) - 1);
        }
    }
};

}  // namespace

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
    const Stretches st(nx);
    // The x-y filtered rows' stretches, for the z pass.
    std::vector<std::uint64_t> xy_bits(std::size_t(z1 - z0) * ny);
    threads = thread_count(threads);
    // x, then y, plane by plane.
    parallel_chunks(std::size_t(z1 - z0), threads, [&](std::size_t p) {
        thread_local std::vector<float> rows;
        thread_local std::vector<std::uint64_t> x_bits;
        rows.assign(plane, 0.0f);
        x_bits.assign(ny, 0);
        const float* src = field + (std::size_t(z0) + p) * std::size_t(pitch) * ny;
        for (std::uint32_t y = 0; y < ny; ++y) {
            const float* in = src + std::size_t(y) * pitch;
            const std::uint64_t bits = st.of_row(in, nx);
            if (!bits) continue;
            x_bits[y] = st.grown(bits, radius);
            float* o = rows.data() + std::size_t(y) * nx;
            st.for_each_run(x_bits[y], nx, [&](std::uint32_t a, std::uint32_t b) {
                for (std::int64_t k = -radius; k <= radius; ++k) {
                    const float w = taps[std::size_t(k + radius)];
                    const std::int64_t lo = std::max<std::int64_t>(a, -k);
                    const std::int64_t hi = std::min<std::int64_t>(b, std::int64_t(nx) - k);
                    for (std::int64_t x = lo; x < hi; ++x) o[x] += w * in[x + k];
                }
            });
        }
        float* dst = xy.data() + p * plane;
        for (std::uint32_t y = 0; y < ny; ++y) {
            float* o = dst + std::size_t(y) * nx;
            std::fill(o, o + nx, 0.0f);
            const std::int64_t lo = std::max<std::int64_t>(-radius, -std::int64_t(y));
            const std::int64_t hi = std::min<std::int64_t>(radius, std::int64_t(ny) - 1 - y);
            std::uint64_t bits = 0;
            for (std::int64_t k = lo; k <= hi; ++k) bits |= x_bits[std::size_t(y + k)];
            xy_bits[p * ny + y] = bits;
            st.for_each_run(bits, nx, [&](std::uint32_t a, std::uint32_t b) {
                for (std::int64_t k = lo; k <= hi; ++k) {
                    const float w = taps[std::size_t(k + radius)];
                    const float* r = rows.data() + std::size_t(std::int64_t(y) + k) * nx;
                    for (std::uint32_t x = a; x < b; ++x) o[x] += w * r[x];
                }
            });
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
            std::uint64_t bits = 0;
            for (std::int64_t k = lo; k <= hi; ++k) bits |= xy_bits[std::size_t(z + k - z0) * ny + y];
            st.for_each_run(bits, nx, [&](std::uint32_t a, std::uint32_t b) {
                for (std::int64_t k = lo; k <= hi; ++k) {
                    const float w = taps[std::size_t(k + radius)];
                    const float* row = xy.data() + (std::size_t(z + k - z0) * ny + y) * nx;
                    for (std::uint32_t x = a; x < b; ++x) o[x] += w * row[x];
                }
            });
        }
    });
}

}  // namespace fdmsurf::detail
