// The engine's pure pieces, without a device: plan_slabs (how a grid too large for one field
// buffer is cut into z-slabs, slab_plan.hpp) and preflight_warnings (preflight.hpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

#include "engine/preflight.hpp"
#include "engine/slab_plan.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "grid/grid_plan.hpp"

namespace {

using fdmsurf::detail::plan_slabs;
using fdmsurf::detail::SlabInputs;
using fdmsurf::detail::SlabPlan;

std::uint64_t plane_bytes(const SlabInputs& in) {
    return std::uint64_t(in.pitch) * in.dims[1] * sizeof(float);
}
std::uint64_t mc_plane_bytes(const SlabInputs& in) {
    return std::uint64_t(in.dims[0]) * in.dims[1] * sizeof(float);
}

// What every plan must hold: the slabs cover the grid, each slab's field and each core with the
// three planes marching cubes reads beside it fit the limit, and one slab fewer would not do
// (the fewest slabs), with cores of at least 8 planes.
void expect_valid(const SlabInputs& in, const SlabPlan& p) {
    EXPECT_EQ(p.overlap, in.overlap);
    EXPECT_EQ(p.core + 2 * p.overlap, p.slab_planes);
    EXPECT_GE(std::uint64_t(p.core) * p.slabs, in.dims[2]);
    EXPECT_LT(std::uint64_t(p.core) * (p.slabs - 1), in.dims[2]);
    EXPECT_LE(std::uint64_t(p.slab_planes) * plane_bytes(in), in.limit);
    EXPECT_LE(std::uint64_t(p.core + 3) * mc_plane_bytes(in), in.limit);
    EXPECT_GE(p.slabs, 2u);
    if (in.filtered) {
        EXPECT_EQ(fdmsurf::detail::fft_friendly_size(p.slab_planes, false), p.slab_planes);
    }
}

SlabInputs inputs(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz, std::uint64_t limit) {
    SlabInputs in;
    in.dims = {nx, ny, nz};
    in.pitch = nx;
    in.limit = limit;
    return in;
}

TEST(SlabPlan, HalfTheGridFitsGivesTwoSlabs) {
    // 100 x 100 x 200 points, no filter: 200 planes of 40 kB; a limit of 110 planes.
    SlabInputs in = inputs(100, 100, 200, 110 * 40000);
    const SlabPlan p = plan_slabs(in);
    expect_valid(in, p);
    EXPECT_EQ(p.slabs, 2u);
    EXPECT_EQ(p.core, 100u);
    EXPECT_EQ(p.slab_planes, 100u);
}

TEST(SlabPlan, OverlapAndFftSizes) {
    // A filtered field: each slab holds its core and `overlap` planes on each side, rounded up
    // to a size whose factors are 2, 3, 5 and 7.
    SlabInputs in = inputs(128, 128, 500, std::uint64_t(200) * 128 * 128 * 4);
    in.pitch = 130;  // the R2C layout's padded rows
    in.filtered = true;
    in.overlap = 12;
    const SlabPlan p = plan_slabs(in);
    expect_valid(in, p);
    EXPECT_EQ(p.overlap, 12u);
    // The limit holds 196 planes at pitch 130: two slabs would need 250 + 24; three need
    // 167 + 24 = 191, rounded up to 192 = 2^6 3.
    EXPECT_EQ(p.slabs, 3u);
    EXPECT_EQ(p.slab_planes, 192u);
    EXPECT_EQ(p.core, 168u);
}

// The plan against a direct search: the first count of slabs (2, 3, ...; cores of 8 planes
// at least) whose slab, as rounded for the FFT, fits the limit and the grid's planes with its
// overlaps, and whose core with marching cubes' three planes fits too.
TEST(SlabPlan, TheFewestSlabsOverRandomGrids) {
    std::mt19937 rng(7);
    int planned = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        std::uniform_int_distribution<std::uint32_t> side(16, 400);
        SlabInputs in = inputs(side(rng), side(rng), side(rng) + 32, 0);
        in.filtered = rng() % 2 == 0;
        in.overlap = in.filtered ? rng() % 16 : 0;
        in.pitch = in.filtered ? 2 * (in.dims[0] / 2 + 1) : in.dims[0];
        // Between a twentieth of the field and nearly all of it.
        const std::uint64_t field = plane_bytes(in) * in.dims[2];
        in.limit = field / 20 + rng() % (field - field / 20);
        SCOPED_TRACE(std::to_string(in.dims[0]) + " x " + std::to_string(in.dims[1]) + " x " +
                     std::to_string(in.dims[2]) + ", overlap " + std::to_string(in.overlap) +
                     ", limit " + std::to_string(in.limit));
        std::uint32_t expected = 0;
        for (std::uint32_t count = 2; (in.dims[2] + count - 1) / count >= 8; ++count) {
            std::uint32_t n = (in.dims[2] + count - 1) / count + 2 * in.overlap;
            if (in.filtered) n = fdmsurf::detail::fft_friendly_size(n, false);
            if (std::uint64_t(n) * plane_bytes(in) <= in.limit &&
                n <= in.dims[2] + 2 * in.overlap &&
                std::uint64_t(n - 2 * in.overlap + 3) * mc_plane_bytes(in) <= in.limit) {
                expected = n;
                break;
            }
        }
        if (expected == 0) {
            EXPECT_THROW(plan_slabs(in), fdmsurf::Error);
            ++refused;
            continue;
        }
        const SlabPlan p = plan_slabs(in);
        EXPECT_EQ(p.slab_planes, expected);
        expect_valid(in, p);
        ++planned;
    }
    // Both outcomes are exercised.
    EXPECT_GT(planned, 1000);
    EXPECT_GT(refused, 10);
}

TEST(SlabPlan, TooWideForTheDeviceNamesASpacing) {
    // 8 planes of a 2000 x 2000 grid are 128 MB: a limit of 64 MiB cannot hold a slab.
    SlabInputs in = inputs(2000, 2000, 400, std::uint64_t(64) << 20);
    in.spacing = 0.5f;
    try {
        plan_slabs(in);
        FAIL() << "no error";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::DeviceLimit);
        const std::string what = e.what();
        EXPECT_NE(what.find("the grid of 2000 x 2000 x 400 points is too wide"), std::string::npos)
            << what;
        EXPECT_NE(what.find("(64 MiB); a spacing of "), std::string::npos) << what;
        EXPECT_NE(what.find(" Å would fit"), std::string::npos) << what;
    }
}

TEST(SlabPlan, HostMemoryBoundsTheGatheredField) {
    // Refinement of the filtered SES gathers the whole field on the host: 1.6 GB here, more than
    // half of a 2 GiB machine.
    SlabInputs in = inputs(400, 400, 2500, std::uint64_t(256) << 20);
    in.gather_field = true;
    in.host_memory = 2.0 * (1 << 30);
    try {
        plan_slabs(in);
        FAIL() << "no error";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::DeviceLimit);
        const std::string what = e.what();
        EXPECT_NE(what.find("is processed in slabs whose field needs 1.5 GiB of host memory, more "
                            "than half of this machine's 2.0 GiB"),
                  std::string::npos)
            << what;
    }
    // Without gathering, three cores at a time fit; an unknown memory size is not checked.
    in.gather_field = false;
    expect_valid(in, plan_slabs(in));
    in.gather_field = true;
    in.host_memory = 0.0;
    expect_valid(in, plan_slabs(in));
}

TEST(Preflight, CoarseSpacingAndFarCoordinates) {
    fdmsurf::Atoms atoms;
    atoms.xyz = {0.0f, 0.0f, 0.0f, 3.0f, 0.0f, 0.0f};
    atoms.radius = {1.7f, 1.7f};
    atoms.element = {"C", "C"};
    fdmsurf::SurfaceOptions options;
    auto warnings = [&] {
        return fdmsurf::detail::preflight_warnings(
            atoms, options, fdmsurf::detail::plan_grid(atoms, options));
    };
    EXPECT_TRUE(warnings().empty());
    // The default cut-off (0.232 1/Å at probe 1.4) acts for spacings up to 2.15 Å.
    options.spacing = 2.5f;
    auto w = warnings();
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("spacing 2.5 Å is too coarse for the filter cut-off"), std::string::npos)
        << w[0];
    // Far from the origin, single precision steps by 1/8 Å at 1e6 Å: a quarter of 0.5 Å.
    options.spacing = 0.5f;
    atoms.xyz = {1e6f, 0.0f, 0.0f, 1e6f + 3.0f, 0.0f, 0.0f};
    w = warnings();
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("coordinates reach 1e+06 Å from the origin, where single precision steps "
                        "by 0.062 Å (12% of the spacing)"),
              std::string::npos)
        << w[0];
}

}  // namespace
