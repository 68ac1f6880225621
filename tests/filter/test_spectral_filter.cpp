// Tests of the GPU spectral filter (src/filter/spectral_filter.cpp, shaders/spectral_mask.comp)
// against FFTW3 in double precision, and on pure cosines (Giard & Macq 2010; ALGORITHM.md §3).
#include <fftw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/grid_plan.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::FilterShape;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;

using fdmsurf::test::data_path;

// Signed frequency index of FFT bin k of n: bins past n/2 are negative frequencies.
long signed_bin(std::uint32_t k, std::uint32_t n) {
    return k > n / 2 ? long(k) - long(n) : long(k);
}

// The mask of ALGORITHM.md §3 at frequency magnitude |f| (1/Å).
double gain(double f, double cutoff, FilterShape shape) {
    if (shape == FilterShape::Gaussian) return std::exp2(-(f / cutoff) * (f / cutoff));
    return f <= cutoff ? 1.0 : 0.0;
}

struct Reference {
    std::vector<double> field;   // nx * ny * nz, x fastest (no row padding)
    std::size_t borderline = 0;  // ideal mask: bins with |f| within 1e-6 relative of the cut-off
};

// Low-pass of a field in plan layout with FFTW in double precision: r2c, mask, c2r, / N.
Reference fftw_filter(const std::vector<float>& in, const GridPlan& plan, FilterShape shape) {
    const auto& d = plan.info.dims;
    const std::uint32_t nx = d[0], ny = d[1], nz = d[2], cx = nx / 2 + 1;
    const std::size_t n = std::size_t(nx) * ny * nz;
    Reference ref;
    double* real = fftw_alloc_real(n);
    fftw_complex* spectrum = fftw_alloc_complex(std::size_t(cx) * ny * nz);
    // FFTW is row-major with the last index fastest: dimensions (z, y, x).
    fftw_plan forward =
        fftw_plan_dft_r2c_3d(int(nz), int(ny), int(nx), real, spectrum, FFTW_ESTIMATE);
    fftw_plan inverse =
        fftw_plan_dft_c2r_3d(int(nz), int(ny), int(nx), spectrum, real, FFTW_ESTIMATE);
    for (std::uint32_t z = 0; z < nz; ++z)
        for (std::uint32_t y = 0; y < ny; ++y)
            for (std::uint32_t x = 0; x < nx; ++x)
                real[(std::size_t(z) * ny + y) * nx + x] =
                    in[(std::size_t(z) * ny + y) * plan.pitch + x];
    fftw_execute(forward);
    const double h = plan.info.spacing, cutoff = plan.info.cutoff;
    for (std::uint32_t kz = 0; kz < nz; ++kz)
        for (std::uint32_t ky = 0; ky < ny; ++ky)
            for (std::uint32_t kx = 0; kx < cx; ++kx) {
                const double fx = kx / (nx * h), fy = signed_bin(ky, ny) / (ny * h),
                             fz = signed_bin(kz, nz) / (nz * h);
                const double f = std::sqrt(fx * fx + fy * fy + fz * fz);
                if (std::abs(f - cutoff) <= 1e-6 * cutoff) ++ref.borderline;
                const double g = gain(f, cutoff, shape) / double(n);
                fftw_complex& c = spectrum[(std::size_t(kz) * ny + ky) * cx + kx];
                c[0] *= g;
                c[1] *= g;
            }
    fftw_execute(inverse);  // c2r destroys its input; the spectrum is not needed again
    ref.field.assign(real, real + n);
    fftw_destroy_plan(forward);
    fftw_destroy_plan(inverse);
    fftw_free(real);
    fftw_free(spectrum);
    return ref;
}

struct Errors {
    double rel_l2 = 0.0;
    double max_abs = 0.0;
};

Errors compare(const std::vector<float>& gpu, const Reference& ref, const GridPlan& plan) {
    const auto& d = plan.info.dims;
    double num = 0.0, den = 0.0;
    Errors e;
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                const double r = ref.field[(std::size_t(z) * d[1] + y) * d[0] + x];
                const double g = gpu[(std::size_t(z) * d[1] + y) * plan.pitch + x];
                num += (g - r) * (g - r);
                den += r * r;
                e.max_abs = std::max(e.max_abs, std::abs(g - r));
            }
    e.rel_l2 = std::sqrt(num / den);
    return e;
}

class SpectralFilter : public GpuTest {
protected:
    // The GPU filter of the GPU density of crambin against FFTW on the same input.
    void check_crambin(float spacing, FilterShape shape) {
        const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
        const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = spacing});
        ASSERT_TRUE(plan.filtered);
        const std::vector<float> density = impl().compute_field(atoms, plan, false);
        std::vector<float> gpu = density;
        impl().filter_field(gpu, plan, shape);
        const Reference ref = fftw_filter(density, plan, shape);
        const Errors e = compare(gpu, ref, plan);
        std::printf(
            "  filter %s, h %.2f, grid %u x %u x %u: relative L2 %.3g, max abs %.3g, "
            "%zu borderline bins\n",
            shape == FilterShape::Ideal ? "ideal" : "gaussian", spacing, plan.info.dims[0],
            plan.info.dims[1], plan.info.dims[2], e.rel_l2, e.max_abs, ref.borderline);
        RecordProperty("relative_l2", std::to_string(e.rel_l2));
        // float FFT of ~1.5 million points: rounding grows like log N, ~1e-7 per pass.
        EXPECT_LT(e.rel_l2, 1e-5);
        // The filter must also leave the field identical through compute_field(filtered).
        const std::vector<float> fused = impl().compute_field(atoms, plan, true, shape);
        const Errors f = compare(fused, ref, plan);
        EXPECT_LT(f.rel_l2, 1e-5) << "compute_field(filtered = true)";
    }
};

TEST_F(SpectralFilter, IdealMatchesFftwOnCrambinAtHalfAngstrom) {
    check_crambin(0.5f, FilterShape::Ideal);
}

TEST_F(SpectralFilter, IdealMatchesFftwOnCrambinAtOneAngstrom) {
    check_crambin(1.0f, FilterShape::Ideal);
}

TEST_F(SpectralFilter, GaussianMatchesFftwOnCrambinAtHalfAngstrom) {
    check_crambin(0.5f, FilterShape::Gaussian);
}

TEST_F(SpectralFilter, GaussianMatchesFftwOnCrambinAtOneAngstrom) {
    check_crambin(1.0f, FilterShape::Gaussian);
}

TEST_F(SpectralFilter, HostGaussianInSpaceMatchesFftwOnCrambin) {
    // The Gaussian filter as a separable convolution on the host (spatial_gaussian.cpp, what
    // slabs use on a CPU device) against FFTW's spectral mask on the same density: zero rather
    // than periodic outside the grid, a sampled kernel cut at 6 sigma. Measured: relative L2
    // 1e-7 at 0.5 Å.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = 0.5f});
    const std::vector<float> density = impl().compute_field(atoms, plan, false);
    const Reference ref = fftw_filter(density, plan, FilterShape::Gaussian);
    const auto& d = plan.info.dims;
    const double sigma =
        fdmsurf::detail::gaussian_sigma_points(plan.info.cutoff, plan.info.spacing);
    const auto taps = fdmsurf::detail::gaussian_taps(sigma, std::uint32_t(std::ceil(6.0 * sigma)));
    std::vector<float> host(static_cast<std::size_t>(d[0]) * d[1] * d[2]);
    std::vector<float> scratch;
    fdmsurf::detail::gaussian_filter_planes(density.data(), d[0], d[1], d[2], plan.pitch, taps, 0,
                                            d[2], host.data(), scratch);
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < host.size(); ++i) {
        num += (host[i] - ref.field[i]) * (host[i] - ref.field[i]);
        den += ref.field[i] * ref.field[i];
    }
    const double rel = std::sqrt(num / den);
    std::printf("  host gaussian, h 0.50: relative L2 %.3g against FFTW\n", rel);
    EXPECT_LT(rel, 1e-5);
}

// A synthetic grid: 64 x 48 x 40 points at 0.5 Å (fx step 1/32, fy 1/24, fz 1/20 per Å), the
// default cut-off 1/(4 * 1.4) = 0.1786 1/Å.
GridPlan synthetic_plan() {
    GridPlan plan;
    plan.info.dims = {64, 48, 40};
    plan.info.spacing = 0.5f;
    plan.info.origin = {-3.0f, 2.0f, 7.5f};  // must not matter
    plan.info.cutoff = 1.0f / (4.0f * 1.4f);
    plan.filtered = true;
    plan.pitch = 2 * (plan.info.dims[0] / 2 + 1);
    return plan;
}

// A cosine with integer bin frequencies (bx, by, bz) (signed) on the plan's grid.
struct Wave {
    int b[3];
    double amplitude;
    double phase;
    double frequency(const GridPlan& plan) const {
        double s = 0.0;
        for (int a = 0; a < 3; ++a) {
            const double f = b[a] / (plan.info.dims[a] * double(plan.info.spacing));
            s += f * f;
        }
        return std::sqrt(s);
    }
    double at(const GridPlan& plan, std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
        const auto& d = plan.info.dims;
        const double arg =
            2.0 * std::numbers::pi *
            (double(b[0]) * x / d[0] + double(b[1]) * y / d[1] + double(b[2]) * z / d[2]);
        return amplitude * std::cos(arg + phase);
    }
};

TEST_F(SpectralFilter, CosinesBelowTheCutOffPassAndAboveAreRemoved) {
    const GridPlan plan = synthetic_plan();
    const auto& d = plan.info.dims;
    const double fc = plan.info.cutoff;
    // Below: |f| = 0.090, 0.166 (close to the cut, negative y bin) and 0.156 (x only).
    const std::vector<Wave> below = {
        {{2, 1, 1}, 0.7, 0.3}, {{2, -1, 3}, 0.5, 1.1}, {{5, 0, 0}, 0.4, -0.6}};
    // Above: |f| = 0.233, 0.188 (x only, just past the cut), 0.250 (z only, negative).
    const std::vector<Wave> above = {
        {{1, 5, -2}, 0.6, 0.2}, {{6, 0, 0}, 0.8, 0.0}, {{0, 0, -5}, 0.3, 2.0}};
    for (const Wave& w : below) ASSERT_LT(w.frequency(plan), fc);
    for (const Wave& w : above) ASSERT_GT(w.frequency(plan), fc);

    for (FilterShape shape : {FilterShape::Ideal, FilterShape::Gaussian}) {
        SCOPED_TRACE(shape == FilterShape::Ideal ? "ideal" : "gaussian");
        std::vector<float> field(plan.field_floats(), 0.0f);
        for (std::uint32_t z = 0; z < d[2]; ++z)
            for (std::uint32_t y = 0; y < d[1]; ++y)
                for (std::uint32_t x = 0; x < d[0]; ++x) {
                    double v = 1.25;  // the mean passes both shapes unchanged
                    for (const Wave& w : below) v += w.at(plan, x, y, z);
                    for (const Wave& w : above) v += w.at(plan, x, y, z);
                    field[(std::size_t(z) * d[1] + y) * plan.pitch + x] = float(v);
                }
        impl().filter_field(field, plan, shape);
        double max_err = 0.0;
        for (std::uint32_t z = 0; z < d[2]; ++z)
            for (std::uint32_t y = 0; y < d[1]; ++y)
                for (std::uint32_t x = 0; x < d[0]; ++x) {
                    double expect = 1.25;
                    for (const Wave& w : below)
                        expect += gain(w.frequency(plan), fc, shape) * w.at(plan, x, y, z);
                    for (const Wave& w : above)
                        if (shape == FilterShape::Gaussian)
                            expect += gain(w.frequency(plan), fc, shape) * w.at(plan, x, y, z);
                    const double got = field[(std::size_t(z) * d[1] + y) * plan.pitch + x];
                    max_err = std::max(max_err, std::abs(got - expect));
                }
        std::printf("  cosines, %s: max |error| %.3g\n",
                    shape == FilterShape::Ideal ? "ideal" : "gaussian", max_err);
        EXPECT_LT(max_err, 1e-5);
    }
}

}  // namespace
