// Tests of grid placement (src/grid/grid_plan.cpp): FFT-friendly sizes, coverage, bad options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::canonical_grid_size;
using fdmsurf::detail::fft_friendly_size;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;
using fdmsurf::detail::r2c_axis_size;

using fdmsurf::test::data_path;

bool smooth_2357(std::uint32_t n) {
    if (n == 0) return false;
    for (std::uint32_t p : {2u, 3u, 5u, 7u})
        while (n % p == 0) n /= p;
    return n == 1;
}

Atoms one_atom() {
    Atoms a;
    a.xyz = {1.0f, -2.0f, 3.0f};
    a.radius = {1.5f};
    a.element = {"C"};
    return a;
}

// Expects plan_grid to throw Error(InvalidArgument).
void expect_invalid(const Atoms& atoms, const SurfaceOptions& options, const char* what) {
    SCOPED_TRACE(what);
    try {
        GridPlan plan = plan_grid(atoms, options);
        ADD_FAILURE() << "plan_grid accepted " << what << " and planned " << plan.info.dims[0]
                      << " x " << plan.info.dims[1] << " x " << plan.info.dims[2];
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
    }
}

TEST(GridPlan, FftFriendlySizeIsTheSmallest2357SmoothSize) {
    for (std::uint32_t n = 1; n <= 3000; ++n) {
        for (bool even : {false, true}) {
            const std::uint32_t m = fft_friendly_size(n, even);
            ASSERT_GE(m, n) << "n " << n;
            ASSERT_GE(m, 2u) << "n " << n;
            ASSERT_TRUE(smooth_2357(m)) << "n " << n << " gave " << m;
            if (even) {
                ASSERT_EQ(m % 2, 0u) << "n " << n << " gave " << m;
            }
            for (std::uint32_t k = std::max<std::uint32_t>(n, 2); k < m; ++k)
                ASSERT_FALSE(smooth_2357(k) && (!even || k % 2 == 0))
                    << "n " << n << ": " << k << " is smaller than " << m << " and fits";
        }
    }
    EXPECT_EQ(fft_friendly_size(11, false), 12u);
    EXPECT_EQ(fft_friendly_size(121, false), 125u);
    EXPECT_EQ(fft_friendly_size(125, true), 126u);
    EXPECT_EQ(fft_friendly_size(49, true), 50u);
}

TEST(GridPlan, R2cAxisSizeIsAFastFriendlySizeNotFarAbove) {
    std::uint32_t previous = 0;
    for (std::uint32_t n = 1; n <= 3000; ++n) {
        const std::uint32_t m = r2c_axis_size(n);
        ASSERT_GE(m, n) << "n " << n;
        ASSERT_TRUE(smooth_2357(m) && m % 2 == 0) << "n " << n << " gave " << m;
        ASSERT_GE(m, previous) << "n " << n << ": not monotone";
        previous = m;
        const std::uint32_t friendly = fft_friendly_size(n, true);
        if (friendly < 240 || friendly > 512) {
            ASSERT_EQ(m, friendly) << "n " << n;
        } else {
            // The sizes measured slow are avoided, and the move costs at most 15% more points
            // than the smallest friendly size.
            for (std::uint32_t slow : {270u, 294u, 336u, 350u, 378u, 400u})
                ASSERT_NE(m, slow) << "n " << n;
            ASSERT_LE(m, 1.15 * friendly + 1) << "n " << n;
        }
    }
    EXPECT_EQ(r2c_axis_size(330), 384u);  // 1AON's x axis at 0.5 Å (336 before)
    EXPECT_EQ(r2c_axis_size(190), 192u);  // 4HHB's
}

// Every atom's support lies inside the grid: the Gaussian support sqrt(r² + pi_cut) plus the
// padding for ses (the whole Gaussian enters the filter), the ball r (+ probe for sas) plus the
// padding otherwise.
void expect_covers(const Atoms& atoms, const SurfaceOptions& options) {
    const GridPlan plan = plan_grid(atoms, options);
    const auto& g = plan.info;
    const bool ses = options.surface == SurfaceKind::Ses;
    EXPECT_EQ(plan.filtered, ses);
    EXPECT_FLOAT_EQ(g.spacing, options.spacing);
    float padding = options.padding;
    if (padding < 0.0f) padding = ses ? 1.0f / g.cutoff : 1.0f;
    for (int a = 0; a < 3; ++a) {
        SCOPED_TRACE("axis " + std::to_string(a));
        ASSERT_GE(g.dims[a], 2u);
        if (ses) {
            EXPECT_TRUE(smooth_2357(g.dims[a])) << g.dims[a];
            if (a == 0) {
                EXPECT_EQ(g.dims[a] % 2, 0u) << "the R2C axis must be even";
            }
        }
    }
    if (ses) {
        EXPECT_EQ(plan.pitch, 2 * (g.dims[0] / 2 + 1));
        EXPECT_GT(g.cutoff, 0.0f);
    } else {
        EXPECT_GE(plan.pitch, g.dims[0]);
        EXPECT_EQ(g.cutoff, 0.0f);
    }
    EXPECT_EQ(plan.field_floats(), std::size_t(plan.pitch) * g.dims[1] * g.dims[2]);
    const double radius_add = options.surface == SurfaceKind::Sas ? options.probe : 0.0;
    EXPECT_DOUBLE_EQ(plan.density.radius_add, radius_add);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const double r = atoms.radius[i] + radius_add;
        const double reach = (ses ? std::sqrt(r * r + plan.density.pi_cut) : r) + padding;
        for (int a = 0; a < 3; ++a) {
            const double c = atoms.xyz[3 * i + a];
            const double lo = g.origin[a];
            const double hi = g.origin[a] + double(g.spacing) * (g.dims[a] - 1);
            // 1e-4 Å: the origin is stored as float.
            ASSERT_LE(lo, c - reach + 1e-4) << "atom " << i << " axis " << a;
            ASSERT_GE(hi, c + reach - 1e-4) << "atom " << i << " axis " << a;
        }
    }
}

TEST(GridPlan, GridContainsEveryAtomAndItsSupport) {
    const Atoms crambin = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    for (float h : {0.25f, 0.5f, 1.0f}) {
        SCOPED_TRACE("spacing " + std::to_string(h));
        expect_covers(crambin, {.surface = SurfaceKind::Ses, .spacing = h});
        expect_covers(crambin, {.surface = SurfaceKind::Vdw, .spacing = h});
        expect_covers(crambin, {.surface = SurfaceKind::Sas, .spacing = h});
        expect_covers(crambin, {.surface = SurfaceKind::Ses, .spacing = h, .sigma = 1.5f});
        expect_covers(crambin, {.surface = SurfaceKind::Ses, .spacing = h, .padding = 0.0f});
    }
    expect_covers(one_atom(), {.surface = SurfaceKind::Ses, .spacing = 0.3f});
    expect_covers(one_atom(), {.surface = SurfaceKind::Vdw, .spacing = 0.25f});
    expect_covers(one_atom(), {.surface = SurfaceKind::Sas, .spacing = 0.7f, .probe = 2.0f});
}

TEST(GridPlan, DensityParametersFollowTheOptions) {
    const GridPlan plan = plan_grid(one_atom(), {.sigma = 2.0f,
                                                 .level = 1.5f,
                                                 .filter = fdmsurf::FilterShape::Ideal,
                                                 .density_cut = 1e-2f});
    EXPECT_FLOAT_EQ(plan.density.sigma, 2.0f);
    EXPECT_NEAR(plan.density.pi_cut, 4.0 * std::log(100.0), 1e-4);
    EXPECT_FLOAT_EQ(plan.iso, 1.5f * plan.density.level_t);
    EXPECT_NEAR(plan.info.cutoff, 1.0 / (4.0 * 1.4), 1e-6);
}

TEST(GridPlan, RejectsBadOptionsWithInvalidArgument) {
    const Atoms atoms = one_atom();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    expect_invalid(atoms, {.spacing = 0.0f}, "spacing 0");
    expect_invalid(atoms, {.spacing = -0.5f}, "spacing -0.5");
    expect_invalid(atoms, {.spacing = nan}, "spacing NaN");
    expect_invalid(atoms, {.spacing = inf}, "spacing inf");
    expect_invalid(atoms, {.surface = SurfaceKind::Vdw, .spacing = 0.0f}, "vdw spacing 0");
    expect_invalid(atoms, {.surface = SurfaceKind::Ses, .probe = -1.0f}, "ses probe -1");
    expect_invalid(atoms, {.surface = SurfaceKind::Ses, .probe = nan}, "ses probe NaN");
    expect_invalid(atoms, {.surface = SurfaceKind::Sas, .probe = -1.0f}, "sas probe -1");
    expect_invalid(atoms, {.sigma = 0.0f}, "sigma 0");
    expect_invalid(atoms, {.sigma = -3.0f}, "sigma -3");
    expect_invalid(atoms, {.sigma = nan}, "sigma NaN");
    expect_invalid(atoms, {.surface = SurfaceKind::Vdw, .sigma = 0.0f}, "vdw sigma 0");
    // A sigma so small that T exp(-pi/σ²) overflows single precision. ses: through the FFT,
    // anywhere (radius 1.5 Å: sigma >= 1.5/√60 = 0.194 Å). vdw and sas: near the spheres only
    // (radius 1.5 Å at 0.5 Å: pi >= -(1.5² - 0.634²) = -1.848, sigma >= √(1.848/80) = 0.152 Å;
    // sas: 2.9² - 2.034² = 4.27, sigma >= 0.231 Å); a coarse-grained bead of 25 Å keeps the
    // default sigma. The exact SES has no density.
    expect_invalid(atoms, {.sigma = 0.19f}, "sigma 0.19");
    EXPECT_NO_THROW(plan_grid(atoms, {.sigma = 0.2f}));
    expect_invalid(atoms, {.surface = SurfaceKind::Vdw, .sigma = 0.15f}, "vdw sigma 0.15");
    EXPECT_NO_THROW(plan_grid(atoms, {.surface = SurfaceKind::Vdw, .sigma = 0.155f}));
    expect_invalid(atoms, {.surface = SurfaceKind::Sas, .sigma = 0.22f}, "sas sigma 0.22");
    EXPECT_NO_THROW(plan_grid(atoms, {.surface = SurfaceKind::Sas, .sigma = 0.235f}));
    EXPECT_NO_THROW(plan_grid(atoms, {.method = fdmsurf::SesMethod::Edt, .sigma = 1e-6f}));
    Atoms bead = one_atom();
    bead.radius[0] = 25.0f;
    EXPECT_NO_THROW(plan_grid(bead, {.surface = SurfaceKind::Vdw, .spacing = 2.0f}));
}

TEST(GridPlan, RejectsBadAtoms) {
    Atoms atoms = one_atom();
    atoms.radius[0] = 0.0f;
    expect_invalid(atoms, {}, "radius 0");
    atoms = one_atom();
    atoms.xyz[1] = std::numeric_limits<float>::quiet_NaN();
    expect_invalid(atoms, {}, "NaN coordinate");
    atoms = one_atom();
    atoms.xyz.push_back(0.0f);
    expect_invalid(atoms, {}, "xyz size not 3 per radius");
    try {
        plan_grid(Atoms{}, {});
        ADD_FAILURE() << "plan_grid accepted no atoms";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::EmptySelection) << e.what();
    }
}

}  // namespace

namespace {

TEST(GridPlan, MinGridGrowsTheGridAroundTheSameCentre) {
    const Atoms atoms = one_atom();
    SurfaceOptions natural;
    natural.canonical_grid = false;  // canonical sizes: GridPlan.CanonicalGrid* below
    const GridPlan own = plan_grid(atoms, natural);
    SurfaceOptions larger = natural;
    larger.min_grid = {own.info.dims[0] + 10, 0, own.info.dims[2] + 30};
    const GridPlan big = plan_grid(atoms, larger);
    EXPECT_GE(big.info.dims[0], own.info.dims[0] + 10);
    EXPECT_EQ(big.info.dims[1], own.info.dims[1]);
    EXPECT_GE(big.info.dims[2], own.info.dims[2] + 30);
    for (int a = 0; a < 3; ++a) {
        // FFT-friendly, and centred where the smaller grid was.
        EXPECT_EQ(fft_friendly_size(big.info.dims[a], a == 0), big.info.dims[a]);
        const double c_own = own.info.origin[a] + 0.5 * (own.info.dims[a] - 1) * own.info.spacing;
        const double c_big = big.info.origin[a] + 0.5 * (big.info.dims[a] - 1) * big.info.spacing;
        EXPECT_NEAR(c_big, c_own, 1e-4);
    }
    // A smaller minimum changes nothing; the public entry point agrees.
    SurfaceOptions smaller = natural;
    smaller.min_grid = {2, 2, 2};
    EXPECT_EQ(plan_grid(atoms, smaller).info.dims, own.info.dims);
    EXPECT_EQ(fdmsurf::plan_surface_grid(atoms, larger).dims, big.info.dims);
    SurfaceOptions absurd;
    absurd.min_grid = {70000, 0, 0};
    EXPECT_THROW(plan_grid(atoms, absurd), Error);
}


// A padding of 1e30 Å: the count past an integer's range reads in exponent form (it was
// -9223372036854775808), and the message names the padding.
TEST(GridPlan, AnAbsurdPaddingIsRefusedWithAReadableCount) {
    const fdmsurf::Structure s = fdmsurf::read_structure(data_path("1crn.pdb"));
    SurfaceOptions o;
    o.padding = 1e30f;
    try {
        plan_grid(s.atoms, o);
        ADD_FAILURE() << "a grid of 4e30 points was planned";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::DeviceLimit);
        const std::string what = e.what();
        EXPECT_NE(what.find("would have 4e+30 points"), std::string::npos) << what;
        EXPECT_NE(what.find("or a smaller --padding"), std::string::npos) << what;
        EXPECT_EQ(what.find("-9223372036854775808"), std::string::npos) << what;
    }
}

// A misplaced atom far from the rest: a refusal for the grid's size names it (issue: a HETATM
// at 9999 Å must not mean a grid of 20,000³ points); groups closer than 30 Å are not named.
TEST(GridPlan, IsolatedAtomsAreNamedWhenTheyStretchTheGrid) {
    fdmsurf::Structure s = fdmsurf::read_structure(data_path("1crn.pdb"));
    EXPECT_EQ(fdmsurf::detail::isolated_atoms_note(s.atoms), "");
    Atoms far = s.atoms;
    far.xyz.insert(far.xyz.end(), {9999.0f, 9999.0f, 9999.0f});
    far.radius.push_back(1.4f);
    far.element.push_back("ZN");
    fdmsurf::AtomMeta zn = far.meta.back();
    zn.serial = 9999;
    zn.name = "ZN";
    zn.residue_name = "ZN";
    zn.residue_number = 999;
    zn.hetero = true;
    far.meta.push_back(zn);
    const std::string note = fdmsurf::detail::isolated_atoms_note(far);
    EXPECT_NE(note.find("1 atom lies more than 30 Å from the other 327"), std::string::npos) << note;
    EXPECT_NE(note.find("atom 328 (HETATM serial 9999 ZN ZN"), std::string::npos) << note;
    EXPECT_NE(note.find("(9999.0, 9999.0, 9999.0)"), std::string::npos) << note;
    // At 0.1 Å the grid needs over 65536 points along an axis: refused before any device work,
    // with the note.
    SurfaceOptions fine;
    fine.spacing = 0.1f;
    try {
        plan_grid(far, fine);
        ADD_FAILURE() << "a 200,000-point axis was planned";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::DeviceLimit);
        EXPECT_NE(std::string(e.what()).find("atom 328"), std::string::npos) << e.what();
    }
    // Two proteins 25 Å apart are one structure as far as the note goes.
    Atoms two = s.atoms;
    for (std::size_t i = 0; i < s.atoms.size(); ++i) {
        two.xyz.insert(two.xyz.end(), {s.atoms.xyz[3 * i] + 55.0f, s.atoms.xyz[3 * i + 1],
                                       s.atoms.xyz[3 * i + 2]});
        two.radius.push_back(s.atoms.radius[i]);
        two.element.push_back(s.atoms.element[i]);
        two.meta.push_back(s.atoms.meta[i]);
    }
    EXPECT_EQ(fdmsurf::detail::isolated_atoms_note(two), "");
}

// Small FDM grids are rounded up to a canonical cube on their own lattice (SurfaceOptions::
// canonical_grid), so that their FFT plans are among the few Engine::prepare builds.
TEST(GridPlan, CanonicalGridSizeIsTheSmallestCubeThatHoldsTheGridUnlessFarLarger) {
    EXPECT_EQ(canonical_grid_size({108, 96, 105}), 112u);  // 1CRN at 0.5 Å: 1.40 / 1.09 M points
    EXPECT_EQ(canonical_grid_size({112, 112, 125}), 128u);
    EXPECT_EQ(canonical_grid_size({160, 160, 160}), 160u);
    EXPECT_EQ(canonical_grid_size({30, 20, 10}), 64u);     // tiny: at most 96³ always allowed
    EXPECT_EQ(canonical_grid_size({40, 40, 96}), 96u);
    EXPECT_EQ(canonical_grid_size({60, 60, 150}), 0u);     // 160³ would be 7.6 times the points
    EXPECT_EQ(canonical_grid_size({150, 150, 40}), 0u);    // 160³: 4.6 times
    EXPECT_EQ(canonical_grid_size({161, 100, 100}), 0u);   // beyond the largest cube
    for (std::uint32_t c : fdmsurf::detail::kCanonicalGridSizes) {
        EXPECT_EQ(c % 2, 0u) << c;  // the R2C axis must be even
        EXPECT_TRUE(smooth_2357(c)) << c;
        EXPECT_EQ(canonical_grid_size({c, c, c}), c);
    }
}

TEST(GridPlan, CanonicalGridKeepsTheNaturalGridsPointsWhereTheyWere) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    SurfaceOptions natural_options;
    natural_options.canonical_grid = false;
    const GridPlan natural = plan_grid(atoms, natural_options);
    const GridPlan canonical = plan_grid(atoms, SurfaceOptions{});
    ASSERT_EQ(natural.info.dims, (std::array<std::uint32_t, 3>{108, 96, 105}));
    ASSERT_EQ(canonical.info.dims, (std::array<std::uint32_t, 3>{112, 112, 112}));
    EXPECT_EQ(canonical.pitch, 2u * (112 / 2 + 1));
    const float h = natural.info.spacing;
    EXPECT_EQ(canonical.info.spacing, h);
    EXPECT_EQ(canonical.info.cutoff, natural.info.cutoff);
    for (int a = 0; a < 3; ++a) {
        // The natural grid's first point is canonical point k, k whole, and its last one lies
        // inside the canonical grid too: the points are added around it, half on each side.
        const double k = (double(natural.info.origin[a]) - canonical.info.origin[a]) / h;
        EXPECT_NEAR(k, std::round(k), 1e-3) << "axis " << a;
        EXPECT_EQ(std::lround(k), long((canonical.info.dims[a] - natural.info.dims[a]) / 2))
            << "axis " << a;
    }
    // Only the FFT's grid is rounded: the exact SES, vdw and sas keep theirs, and so does an
    // elongated grid that a cube would more than 2.5-fold beyond 96³.
    for (auto [kind, method] : {std::pair{SurfaceKind::Ses, fdmsurf::SesMethod::Edt},
                                std::pair{SurfaceKind::Vdw, fdmsurf::SesMethod::Fdm},
                                std::pair{SurfaceKind::Sas, fdmsurf::SesMethod::Fdm}}) {
        SurfaceOptions o;
        o.surface = kind;
        o.method = method;
        SurfaceOptions off = o;
        off.canonical_grid = false;
        EXPECT_EQ(plan_grid(atoms, o).info.dims, plan_grid(atoms, off).info.dims);
        EXPECT_EQ(plan_grid(atoms, o).info.origin, plan_grid(atoms, off).info.origin);
    }
    // The ideal mask is sampled on the box's frequencies: another box would change the mesh
    // (1CRN --paper: 0.05 Å RMS), so the paper's settings keep the natural grid.
    const SurfaceOptions paper = fdmsurf::paper_settings();
    SurfaceOptions paper_natural = paper;
    paper_natural.canonical_grid = false;
    EXPECT_EQ(plan_grid(atoms, paper).info.dims, plan_grid(atoms, paper_natural).info.dims);
    EXPECT_EQ(plan_grid(atoms, paper).info.origin, plan_grid(atoms, paper_natural).info.origin);
    Atoms rod;
    for (int i = 0; i < 30; ++i) {
        rod.xyz.insert(rod.xyz.end(), {0.0f, 0.0f, 1.5f * float(i)});
        rod.radius.push_back(1.7f);
        rod.element.push_back("C");
    }
    const GridPlan long_grid = plan_grid(rod, SurfaceOptions{});
    EXPECT_EQ(canonical_grid_size(long_grid.info.dims), 0u);
    EXPECT_EQ(long_grid.info.dims, plan_grid(rod, natural_options).info.dims);
}

}  // namespace
