// Tests of the Gaussian filter in space on the host (src/filter/spatial_gaussian.cpp): against a
// direct convolution, its kernel against the spectral mask's, and the engine's slabs filtered on
// the host against the same slabs through VkFFT (tests/filter/test_spectral_filter.cpp compares
// it with FFTW on a whole grid).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "filter/spatial_gaussian.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

namespace {

using namespace fdmsurf;
using fdmsurf::detail::gaussian_filter_planes;
using fdmsurf::detail::gaussian_sigma_points;
using fdmsurf::detail::gaussian_taps;

TEST(SpatialGaussian, TapsAreTheMasksGaussianInSpace) {
    // 2^-(f/F)^2 = exp(-2 pi^2 sigma^2 f^2) for sigma = sqrt(ln 2 / 2) / (pi F): at F = 0.232
    // 1/Å and 0.5 Å, 1.6154 points.
    const double sigma = gaussian_sigma_points(0.232, 0.5);
    EXPECT_NEAR(sigma, 1.6154, 1e-4);
    const double f = 0.1;  // 1/Å
    EXPECT_NEAR(std::exp(-2.0 * std::numbers::pi * std::numbers::pi * (sigma * 0.5) *
                         (sigma * 0.5) * f * f),
                std::exp2(-(f / 0.232) * (f / 0.232)), 1e-12);
    const auto taps = gaussian_taps(sigma, 10);
    ASSERT_EQ(taps.size(), 21u);
    double sum = 0.0;
    for (std::size_t i = 0; i < taps.size(); ++i) {
        sum += taps[i];
        EXPECT_EQ(taps[i], taps[taps.size() - 1 - i]);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_GT(taps[10], taps[9]);
}

TEST(SpatialGaussian, MatchesADirectConvolutionOfTheCorePlanes) {
    // A random field with padded rows, zero outside it; cores that start at the first plane,
    // more than a radius in (the z pass then reads the scratch from a plane offset) and less
    // than a radius in (the kernel cut at the field's first planes), one scratch for all.
    const std::uint32_t nx = 13, ny = 9, planes = 12, pitch = 16;
    const int radius = 3;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> field(std::size_t(pitch) * ny * planes);
    for (float& v : field) v = u(rng);
    const auto taps = gaussian_taps(1.2, radius);
    std::vector<float> scratch;
    for (const auto& [c0, c1] : {std::pair{0u, 12u}, std::pair{3u, 9u}, std::pair{5u, 8u},
                                 std::pair{1u, 4u}, std::pair{10u, 12u}}) {
        SCOPED_TRACE(std::to_string(c0) + ".." + std::to_string(c1));
        std::vector<float> out(std::size_t(nx) * ny * (c1 - c0), -1.0f);
        gaussian_filter_planes(field.data(), nx, ny, planes, pitch, taps, c0, c1, out.data(),
                               scratch, 2);
        double worst = 0.0;
        for (std::uint32_t z = c0; z < c1; ++z)
            for (std::uint32_t y = 0; y < ny; ++y)
                for (std::uint32_t x = 0; x < nx; ++x) {
                    double sum = 0.0;
                    for (int k = -radius; k <= radius; ++k)
                        for (int j = -radius; j <= radius; ++j)
                            for (int i = -radius; i <= radius; ++i) {
                                const int xx = int(x) + i, yy = int(y) + j, zz = int(z) + k;
                                if (xx < 0 || yy < 0 || zz < 0 || xx >= int(nx) || yy >= int(ny) ||
                                    zz >= int(planes))
                                    continue;
                                sum += double(taps[i + radius]) * taps[j + radius] *
                                       taps[k + radius] *
                                       field[(std::size_t(zz) * ny + yy) * pitch + xx];
                            }
                    const double got = out[(std::size_t(z - c0) * ny + y) * nx + x];
                    worst = std::max(worst, std::abs(got - sum));
                }
        EXPECT_LT(worst, 1e-6);
    }
}

TEST(SpatialGaussian, ResponseIsTheMaskFromOneAndAHalfPointsOfSigma) {
    // The taps' frequency response against the mask 2^-(f/F)^2, f in cycles per point up to
    // Nyquist: the sampled kernel adds the mask's aliases, exp(-pi^2 sigma^2 / 2) at Nyquist.
    // At 0.5 Å (sigma 1.62 points) and at kMinHostSigma they are below 2e-5; at 1 Å (0.81
    // points) they are not (0.04 at Nyquist; the surface is as close to the analytical SES).
    const double cutoff = 0.232;
    auto worst = [cutoff](double spacing) {
        const double sigma = gaussian_sigma_points(cutoff, spacing);
        const auto taps = gaussian_taps(sigma, std::uint32_t(std::ceil(6.0 * sigma)));
        const int r = int(taps.size() / 2);
        double e = 0.0;
        for (int step = 0; step <= 100; ++step) {
            const double nu = 0.5 * step / 100.0;  // cycles per point
            double response = 0.0;
            for (int k = -r; k <= r; ++k)
                response += taps[std::size_t(k + r)] * std::cos(2.0 * std::numbers::pi * nu * k);
            const double q = nu / (cutoff * spacing);
            e = std::max(e, std::abs(response - std::exp2(-q * q)));
        }
        return e;
    };
    EXPECT_LT(worst(0.5), 2e-5);
    const double at_limit = std::sqrt(std::log(2.0) / 2.0) /
                            (std::numbers::pi * cutoff * fdmsurf::detail::kMinHostSigma);
    EXPECT_LT(worst(at_limit), 2e-5);
    EXPECT_GT(worst(1.0), 1e-3);
}

TEST(SpatialGaussian, ResultDoesNotDependOnTheThreadCount) {
    const std::uint32_t nx = 40, ny = 30, planes = 20, pitch = 42;
    std::vector<float> field(std::size_t(pitch) * ny * planes);
    for (std::size_t i = 0; i < field.size(); ++i) field[i] = float((i * 2654435761u) % 997);
    const auto taps = gaussian_taps(1.6, 10);
    std::vector<float> one(std::size_t(nx) * ny * 10), four(one.size()), scratch;
    gaussian_filter_planes(field.data(), nx, ny, planes, pitch, taps, 5, 15, one.data(), scratch,
                           1);
    gaussian_filter_planes(field.data(), nx, ny, planes, pitch, taps, 5, 15, four.data(), scratch,
                           4);
    EXPECT_EQ(one, four);
}

class HostFilterSlabs : public GpuTest {};

TEST_F(HostFilterSlabs, CrambinInSlabsGivesTheMeshOfTheFftFilter) {
    // 1CRN at 0.5 Å through slabs of at most 2 MiB, the Gaussian filter on the host and through
    // VkFFT: the same surface but for float rounding at a few crossings.
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    SurfaceOptions o;
    Mesh mesh[2];
    for (int host = 0; host < 2; ++host) {
        Engine e(EngineOptions{
            .validation = true,
            .max_buffer_range = 2u << 20,
            .gaussian_filter = host ? GaussianFilterPlace::Host : GaussianFilterPlace::Device});
        const SurfaceResult r = e.make_surface(atoms, o);
        EXPECT_GT(r.grid.slabs, 1u);
        EXPECT_EQ(r.grid.host_filter, host == 1);
        bool fft = false, on_host = false;
        for (const StageTime& t : r.times) {
            fft = fft || t.name == "fft-forward";
            on_host = on_host || t.name == "filter-host";
        }
        EXPECT_EQ(fft, host == 0);
        EXPECT_EQ(on_host, host == 1);
        EXPECT_TRUE(e.take_validation_messages().empty());
        mesh[host] = r.mesh;
    }
    const MeshStats a = compute_stats(mesh[0]), b = compute_stats(mesh[1]);
    EXPECT_NEAR(double(b.triangles), double(a.triangles), 1e-4 * double(a.triangles));
    EXPECT_NEAR(b.area, a.area, 1e-5 * a.area);
    EXPECT_NEAR(b.volume, a.volume, 1e-5 * a.volume);
    EXPECT_TRUE(b.is_closed_manifold());
    CompareOptions c;
    EXPECT_LT(compare_meshes(mesh[0], mesh[1], c).hausdorff, 0.01);
}

TEST_F(HostFilterSlabs, AutoFiltersOnTheHostExactlyOnACpuDevice) {
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    Engine e(EngineOptions{.max_buffer_range = 2u << 20});
    SurfaceOptions o;
    const SurfaceResult r = e.make_surface(atoms, o);
    ASSERT_GT(r.grid.slabs, 1u);
    const bool cpu = e.device().type == "CPU";
    EXPECT_EQ(r.grid.host_filter, cpu) << e.device().type;
    EXPECT_EQ(r.grid.host_density, cpu);
    // At 1 Å too (sigma 0.81 points), where the sampled kernel is a slightly different low-pass.
    Engine narrow(EngineOptions{.max_buffer_range = 512u << 10});
    o.spacing = 1.0f;
    const SurfaceResult coarse = narrow.make_surface(atoms, o);
    ASSERT_GT(coarse.grid.slabs, 1u);
    EXPECT_EQ(coarse.grid.host_filter, cpu);
    EXPECT_EQ(coarse.grid.host_density, cpu);
    o.spacing = 0.5f;
    // The ideal filter has no compact kernel: always VkFFT (its slabs overlap more, so they
    // need wider bindings).
    Engine wide(EngineOptions{.max_buffer_range = 4u << 20});
    o.filter = FilterShape::Ideal;
    const SurfaceResult ideal = wide.make_surface(atoms, o);
    ASSERT_GT(ideal.grid.slabs, 1u);
    EXPECT_FALSE(ideal.grid.host_filter);
    EXPECT_FALSE(ideal.grid.host_density);  // the FFT reads it on the device
}

}  // namespace
