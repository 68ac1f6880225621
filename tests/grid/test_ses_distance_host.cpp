// Tests of the exact SES field on the host (src/grid/ses_distance_host.cpp) against its CPU
// reference (ses_field_cpu, src/grid/ses_distance_cpu.cpp) and the device's pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "support/gpu_fixture.hpp"
#include "support/ses_field_diff.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SesMethod;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::build_ses_features;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;
using fdmsurf::detail::SesHostField;
using fdmsurf::test::data_path;

using fdmsurf_test::compare_ses_fields;
using FieldDiff = fdmsurf_test::SesFieldDiff;
constexpr double kTolerance = fdmsurf_test::kSesFieldTolerance;

// Three normal draws, in order, into dir, and their length: dir / length is a random direction.
double random_direction(std::mt19937& rng, std::normal_distribution<double>& normal,
                        double dir[3]) {
    for (int k = 0; k < 3; ++k) dir[k] = normal(rng);
    return std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
}

// The depth of p in its deepest inflated ball (r + probe - |p - c|, every atom tried): where no
// face is the nearest feature, d lies above it.
double deepest_depth(const Atoms& atoms, float probe, const double p[3]) {
    double lb = -1e9;
    for (std::size_t k = 0; k < atoms.size(); ++k) {
        const float* c = &atoms.xyz[3 * k];
        lb = std::max(lb, atoms.radius[k] + probe -
                              std::sqrt((p[0] - c[0]) * (p[0] - c[0]) +
                                        (p[1] - c[1]) * (p[1] - c[1]) +
                                        (p[2] - c[2]) * (p[2] - c[2])));
    }
    return lb;
}

FieldDiff host_against_reference(const Atoms& atoms, float spacing, unsigned threads = 0,
                                 bool snap = true) {
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = spacing, .snap = snap};
    const GridPlan plan = plan_grid(atoms, options);
    EXPECT_TRUE(plan.exact_ses);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> cpu = fdmsurf::detail::ses_field_cpu(features, plan);
    const std::vector<float> host = SesHostField(features, 10.0, threads).field(plan);
    EXPECT_EQ(host.size(), cpu.size());
    const FieldDiff r = compare_ses_fields(host, cpu, plan);
    std::printf("  %.2f Å: %zu points, %zu in the band, max |host - cpu| %.3g Å\n", spacing,
                r.points, r.band, r.max_diff);
    return r;
}

TEST(SesDistanceHost, MatchesCpuReferenceOnCrambin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    // Both bands: one spacing each side where the snap follows, two without it.
    for (const bool snap : {true, false}) {
        const FieldDiff r = host_against_reference(atoms, 0.5f, 0, snap);
        EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
        EXPECT_GT(r.band, r.points / (snap ? 20 : 10));  // the surface band, not only clamps
    }
}

TEST(SesDistanceHost, MatchesCpuReferenceOnHemoglobinAtOneAngstrom) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const FieldDiff r = host_against_reference(atoms, 1.0f, 3);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    EXPECT_GT(r.band, r.points / 20);
}

TEST(SesDistanceHost, CoarseGridsReachOutsideTheBalls) {
    // At 3 Å without the snap the lower clamp r_s - 2h is -4.6 Å (with it r_s - h, -1.6 Å):
    // points outside the balls keep -(their distance to them) down to it, which the depths
    // must reach beyond the balls.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    for (const bool snap : {false, true}) {
        const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 3.0f, .snap = snap};
        ASSERT_LT(plan_grid(atoms, options).ses_d_min, snap ? -1.5f : -4.0f);
        const FieldDiff r = host_against_reference(atoms, 3.0f, 0, snap);
        EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    }
}

TEST(SesDistanceHost, TiesAndCentresOnGridPoints) {
    // Equal balls symmetric about grid planes: every point of the bisector planes is as deep in
    // two balls (the tie path), and the centres are grid points (the projection's special case).
    const Atoms atoms = fdmsurf_test::make_atoms({{0.0f, 0.0f, 0.0f, 1.5f},
                                                  {3.0f, 0.0f, 0.0f, 1.5f},
                                                  {1.5f, 2.5f, 0.0f, 1.5f},
                                                  {1.5f, 1.0f, 2.5f, 1.5f}});
    const FieldDiff r = host_against_reference(atoms, 0.25f);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    EXPECT_GT(r.band, r.points / 20);
}

TEST(SesDistanceHost, RandomAtomsMatchTheReference) {
    // Random balls packed closer than in proteins, radii 1-2.2 Å, one pair coincident and one
    // ball inside another: many buried faces, short arcs, three-ball points.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> pos(0.0f, 9.0f), rad(1.0f, 2.2f);
    Atoms atoms;
    for (int i = 0; i < 60; ++i) {
        atoms.xyz.insert(atoms.xyz.end(), {pos(rng), pos(rng), pos(rng)});
        atoms.radius.push_back(rad(rng));
    }
    atoms.xyz.insert(atoms.xyz.end(), {atoms.xyz[0], atoms.xyz[1], atoms.xyz[2]});
    atoms.radius.push_back(atoms.radius[0]);
    atoms.xyz.insert(atoms.xyz.end(), {atoms.xyz[3] + 0.1f, atoms.xyz[4], atoms.xyz[5]});
    atoms.radius.push_back(0.5f);
    for (float spacing : {0.3f, 0.7f}) {
        const FieldDiff r = host_against_reference(atoms, spacing);
        EXPECT_EQ(r.bad, 0u) << spacing << " Å: max |host - cpu| " << r.max_diff;
    }
}

// The arcs' step tries each arc on the rows of its ball alone, and in them on the points
// waiting for the arcs alone, but on spans wider than the ball. Every arc's row kernel on every
// row of the grid instead: where an arc decides a point, its value is the nearest arc's in
// float, clamped as the field's (bit for bit), and nowhere is the field above that (a face's
// depth, or a tie's reference, is at most any exposed arc's distance). Random balls shifted
// against three spacings, so that the balls' edges fall anywhere between the grid's rows.
TEST(SesDistanceHost, EveryArcOnEveryRowGivesTheSameField) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> pos(0.0f, 8.0f), rad(1.0f, 2.0f), shift(0.0f, 1.0f);
    std::size_t decided = 0, above = 0;
    for (int trial = 0; trial < 3; ++trial) {
        const float offset[3] = {shift(rng), shift(rng), shift(rng)};
        Atoms atoms;
        for (int i = 0; i < 40; ++i) {
            atoms.xyz.insert(atoms.xyz.end(),
                             {pos(rng) + offset[0], pos(rng) + offset[1], pos(rng) + offset[2]});
            atoms.radius.push_back(rad(rng));
        }
        for (float spacing : {0.31f, 0.5f, 0.83f}) {
            const SurfaceOptions options{.method = SesMethod::Edt, .spacing = spacing};
            const GridPlan plan = plan_grid(atoms, options);
            const auto features = build_ses_features(atoms, options.probe);
            const SesHostField field(features, plan.ses_d_max);
            const std::vector<float> host = field.field(plan);
            const auto& d = plan.info.dims;
            const float h = plan.info.spacing;
            std::vector<float> xs(d[0]), best(d[0]);
            for (std::uint32_t x = 0; x < d[0]; ++x) xs[x] = plan.info.origin[0] + h * float(x);
            for (std::uint32_t z = 0; z < d[2]; ++z)
                for (std::uint32_t y = 0; y < d[1]; ++y) {
                    std::fill(best.begin(), best.end(), plan.ses_d_max);
                    for (std::size_t k = 0; k < features.arcs.size(); ++k)
                        field.arc_row_distances(k, xs.data(), plan.info.origin[1] + h * float(y),
                                                plan.info.origin[2] + h * float(z), 0,
                                                int(d[0]) - 1, best.data());
                    const float* row = &host[(std::size_t(z) * d[1] + y) * plan.pitch];
                    for (std::uint32_t x = 0; x < d[0]; ++x) {
                        const float arcs = std::max(best[x], plan.ses_d_min);
                        decided += best[x] < plan.ses_d_max && row[x] == arcs;
                        above += row[x] > arcs + 1e-5f;
                    }
                }
        }
    }
    std::printf("  %zu points decided by an arc\n", decided);
    EXPECT_EQ(above, 0u);
    EXPECT_GT(decided, 10000u);
}

// The field's row kernel takes its float copy of an arc from the arc's kept doubles (the end
// directions) and the stored circle, recomputing the axis and the end points: the same floats,
// bit for bit, as copies made straight from the features' arc (double cosines and sines of its
// angles, the ends m + rho (cos e1 + sin e2), the axis e1 x e2, rounded to float), so the same
// distances as this scalar form of the kernel, on every arc of random atoms.
TEST(SesDistanceHost, TheRowKernelsArcIsTheStoredCirclesBitForBit) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> pos(0.0f, 8.0f), rad(1.0f, 2.0f), u(-3.0f, 3.0f);
    Atoms atoms;
    for (int i = 0; i < 60; ++i) {
        atoms.xyz.insert(atoms.xyz.end(), {pos(rng) - 20.0f, pos(rng) + 35.0f, pos(rng)});
        atoms.radius.push_back(rad(rng));
    }
    const auto features = build_ses_features(atoms, 1.4f);
    ASSERT_GT(features.arcs.size(), 50u);
    const SesHostField field(features, 3.4);
    std::size_t checked = 0;
    for (std::size_t k = 0; k < features.arcs.size(); ++k) {
        const fdmsurf::detail::SesArc& a = features.arcs[k];
        const double start = a.start, end = double(a.start) + double(a.length);
        const double sd[2] = {std::cos(start), std::sin(start)}, ed[2] = {std::cos(end), std::sin(end)};
        float fs[3], fe[3], fa[3];
        for (int c = 0; c < 3; ++c) {
            const double m = a.m[c], rho = a.rho, e1 = a.e1[c], e2 = a.e2[c];
            fs[c] = float(m + rho * (sd[0] * e1 + sd[1] * e2) - m);
            fe[c] = float(m + rho * (ed[0] * e1 + ed[1] * e2) - m);
            const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            fa[c] = float(double(a.e1[c1]) * double(a.e2[c2]) - double(a.e1[c2]) * double(a.e2[c1]));
        }
        const bool longer = double(a.length) > 0.5 * 6.283185307179586,
                   full = double(a.length) >= 6.283185307179586;
        for (int row = 0; row < 4; ++row) {
            const float y = a.m[1] + u(rng), z = a.m[2] + u(rng);
            float xs[16], best[16];
            for (int x = 0; x < 16; ++x) xs[x] = a.m[0] - 3.0f + 0.4f * float(x), best[x] = 5.0f;
            field.arc_row_distances(k, xs, y, z, 0, 15, best);
            for (int x = 0; x < 16; ++x) {
                const float v[3] = {xs[x] - a.m[0], y - a.m[1], z - a.m[2]};
                const float hh = v[0] * fa[0] + (v[1] * fa[1] + v[2] * fa[2]);
                const float aa = v[0] * a.e1[0] + (v[1] * a.e1[1] + v[2] * a.e1[2]);
                const float bb = v[0] * a.e2[0] + (v[1] * a.e2[1] + v[2] * a.e2[2]);
                const float rr = std::sqrt(aa * aa + bb * bb) - a.rho;
                const bool after = float(sd[0]) * bb - float(sd[1]) * aa >= 0.0f;
                const bool before = aa * float(ed[1]) - bb * float(ed[0]) >= 0.0f;
                const bool on = full || (longer ? after || before : after && before);
                auto end2 = [&](const float* q) {
                    const float dy = v[1] - q[1], dz = v[2] - q[2], dx = v[0] - q[0];
                    return dx * dx + (dy * dy + dz * dz);
                };
                const float ds = end2(fs), de = end2(fe);
                const float d = std::sqrt(on ? hh * hh + rr * rr : (ds < de ? ds : de));
                EXPECT_EQ(best[x], std::min(d, 5.0f)) << "arc " << k << " x " << x;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, features.arcs.size() * 64);
}

TEST(SesDistanceHost, PlaneRangesAndThreadCountsGiveTheSameValues) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.6f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> one = SesHostField(features, 10.0, 1).field(plan);
    const std::vector<float> many = SesHostField(features, 10.0, 7).field(plan);
    EXPECT_EQ(one, many);
    // Planes [5, 23) alone, in rows of nx + 3 floats: the whole field's planes, bit for bit.
    const auto& d = plan.info.dims;
    const std::size_t pitch = d[0] + 3;
    std::vector<float> part(std::size_t(18) * d[1] * pitch, -99.0f);
    SesHostField(features, 10.0, 2).evaluate(plan, 5, 23, part.data(), pitch);
    std::size_t differ = 0, padding = 0;
    for (std::uint32_t z = 5; z < 23; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y) {
            const float* row = &part[(std::size_t(z - 5) * d[1] + y) * pitch];
            for (std::uint32_t x = 0; x < d[0]; ++x)
                differ += row[x] != one[(std::size_t(z) * d[1] + y) * plan.pitch + x];
            for (std::size_t x = d[0]; x < pitch; ++x) padding += row[x] != -99.0f;
        }
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(padding, 0u);  // rows are written within nx
}

// evaluate keeps its scratch from call to call (one slab per call in the engine): larger and
// smaller plane ranges in turn, and after release_scratch, give a fresh object's values.
TEST(SesDistanceHost, KeptScratchGivesTheSameValuesFromCallToCall) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.6f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> fresh = SesHostField(features, 10.0, 2).field(plan);
    const SesHostField field(features, 10.0, 2);
    const auto& d = plan.info.dims;
    const std::size_t plane = std::size_t(d[1]) * plan.pitch;
    for (const auto& [z0, z1] : {std::pair<std::uint32_t, std::uint32_t>{0, d[2]}, {7, 9},
                                {3, d[2] - 2}, {0, 1}}) {
        std::vector<float> part(std::size_t(z1 - z0) * plane, 0.0f);
        field.evaluate(plan, z0, z1, part.data(), plan.pitch);
        EXPECT_TRUE(std::equal(part.begin(), part.end(), fresh.begin() + z0 * plane))
            << "planes " << z0 << " to " << z1;
    }
    field.release_scratch();
    EXPECT_EQ(field.field(plan), fresh);
}

TEST(SesDistanceHost, RejectsBadRanges) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 1.0f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const SesHostField field(features, plan.ses_d_max);
    std::vector<float> out(plan.field_floats());
    const auto& d = plan.info.dims;
    for (auto [a, b, pitch] : {std::tuple{3u, 3u, std::size_t(plan.pitch)},
                               std::tuple{0u, d[2] + 1, std::size_t(plan.pitch)},
                               std::tuple{0u, d[2], std::size_t(d[0] - 1)}}) {
        try {
            field.evaluate(plan, a, b, out.data(), pitch);
            ADD_FAILURE() << "no error for planes [" << a << ", " << b << ") pitch " << pitch;
        } catch (const fdmsurf::Error& e) {
            EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("host SES field"), std::string::npos) << e.what();
        }
    }
    GridPlan fdm = plan;
    fdm.exact_ses = false;
    EXPECT_THROW(field.evaluate(fdm, 0, d[2], out.data(), plan.pitch), fdmsurf::Error);
}

// SesHostField::distance (the snap and refine stages) against the reference it replaces,
// ses_distance(f, p, d_max, gradient, false), at random points around random atoms of
// hemoglobin and crambin, from a probe radius outside the balls to their depth of d_max: the
// same value to 1e-6 Å and the same gradient to 1e-5 wherever it is defined. The arcs are stored
// in float, so e1 and e2 are orthonormal to about 1e-7: the reference's distance off an arc (by
// the angle to its end, assuming them orthonormal) and the host's (to the end point itself)
// differ by up to a few 1e-8 Å.
TEST(SesDistanceHost, PointDistanceAndGradientMatchTheReference) {
    for (const char* name : {"4hhb.xyzr", "1crn.xyzr"}) {
        const Atoms atoms = fdmsurf::read_structure(data_path(name)).atoms;
        const float probe = 1.4f;
        const auto features = build_ses_features(atoms, probe);
        const double d_max = probe + 1.0;
        const SesHostField field(features, d_max);
        std::mt19937 rng(2711);
        std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
        std::normal_distribution<double> offset(0.0, 1.0);
        std::uniform_real_distribution<double> depth(-1.0, 2.3);
        std::size_t band = 0, arcs = 0, worst_at = 0, kinks = 0;
        double worst = 0.0, worst_gradient = 0.0;
        for (int n = 0; n < 20000; ++n) {
            const std::size_t i = pick(rng);
            double dir[3];
            const double len = random_direction(rng, offset, dir);
            const double r = atoms.radius[i] + probe * depth(rng);
            double p[3];
            for (int k = 0; k < 3; ++k) p[k] = atoms.xyz[3 * i + k] + r * dir[k] / len;
            double g_ref[3], g[3];
            const double ref = fdmsurf::detail::ses_distance(features, p, d_max, g_ref, false);
            const double fast = field.distance(p, d_max, g);
            if (std::abs(fast - ref) > worst) worst = std::abs(fast - ref), worst_at = n;
            ASSERT_NEAR(fast, ref, 1e-6) << name << " point " << p[0] << " " << p[1] << " " << p[2];
            if (ref > 0.0 && ref < d_max) {
                ++band;
                double diff = 0.0;
                for (int k = 0; k < 3; ++k) diff = std::max(diff, std::abs(g[k] - g_ref[k]));
                if (diff > 1e-5) {
                    // Two features as near to within float rounding (a kink of d, where the
                    // gradient jumps): the host's nearest point p - d g must be on E's boundary
                    // as well (d = 0 there by the reference).
                    ++kinks;
                    const double q[3] = {p[0] - fast * g[0], p[1] - fast * g[1], p[2] - fast * g[2]};
                    EXPECT_LE(std::abs(fdmsurf::detail::ses_distance(features, q, d_max)), 1e-5)
                        << name << " point " << p[0] << " " << p[1] << " " << p[2];
                } else {
                    worst_gradient = std::max(worst_gradient, diff);
                }
                // Where no face is the nearest feature: d above the deepest ball's depth.
                arcs += ref > deepest_depth(atoms, probe, p) + 1e-6;
            } else {
                for (int k = 0; k < 3; ++k) ASSERT_EQ(g[k], g_ref[k]) << name << " outside the band";
            }
        }
        std::printf("  %s: %zu in the band, %zu nearest to an arc, max |diff| %.3g Å (point %zu), "
                    "gradient %.3g, %zu at a kink\n",
                    name, band, arcs, worst, worst_at, worst_gradient, kinks);
        EXPECT_LE(worst_gradient, 1e-5);
        EXPECT_LE(kinks, band / 1000);
        EXPECT_GT(band, 5000u);
        EXPECT_GT(arcs, 1000u);
    }
}

// Points beyond the features' outer bins are looked up in the outer bin (clamped), whose arc
// list must hold every arc within reach of them: the lists leave out an arc only where no point
// of the bin comes within reach of its ball, and an outer bin's points reach on outwards.
// Points within the balls of the atoms at crambin's and hemoglobin's edges, pushed outwards.
TEST(SesDistanceHost, PointsBeyondTheOuterBinsFindTheirArcs) {
    for (const char* name : {"1crn.xyzr", "4hhb.xyzr"}) {
        const Atoms atoms = fdmsurf::read_structure(data_path(name)).atoms;
        const float probe = 1.4f;
        const auto features = build_ses_features(atoms, probe);
        const double d_max = probe + 1.0;
        const SesHostField field(features, d_max);
        std::mt19937 rng(4242);
        std::normal_distribution<double> offset(0.0, 1.0);
        std::uniform_real_distribution<double> depth(0.05, 0.95);
        std::size_t beyond = 0, arcs = 0;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            for (int n = 0; n < 200; ++n) {
                double dir[3];
                const double len = random_direction(rng, offset, dir);
                const double R = atoms.radius[i] + probe;
                double p[3];
                bool outside = false;
                for (int k = 0; k < 3; ++k) {
                    p[k] = atoms.xyz[3 * i + k] + R * depth(rng) * dir[k] / len;
                    const double lo = features.origin[k];
                    const double hi = lo + double(features.bin_size) * features.dims[k];
                    outside = outside || p[k] < lo || p[k] > hi;
                }
                if (!outside) continue;
                ++beyond;
                double g_ref[3], g[3];
                const double ref = fdmsurf::detail::ses_distance(features, p, d_max, g_ref, false);
                ASSERT_NEAR(field.distance(p, d_max, g), ref, 1e-6)
                    << name << " point " << p[0] << " " << p[1] << " " << p[2];
                SesHostField::Cursor cursor(field);
                ASSERT_NEAR(cursor.distance(p, d_max, g), ref, 1e-6)
                    << name << " point " << p[0] << " " << p[1] << " " << p[2];
                arcs += ref > 0.0 && ref < d_max && ref > deepest_depth(atoms, probe, p) + 1e-6;
            }
        }
        std::printf("  %s: %zu points beyond the outer bins, %zu nearest to an arc\n", name,
                    beyond, arcs);
        EXPECT_GT(arcs, 200u) << name;
    }
}

// SesHostField::Cursor (the snap's view, which keeps its last bins' balls and arcs) against
// distance(), bit for bit in value and gradient: walks of short steps around random atoms of
// hemoglobin and crambin (the cursor keeps its copies) and jumps between atoms (it gathers
// new ones), from outside the balls to below the clamp, at the snap's d_max and beyond the
// constructor's (the reference's path).
TEST(SesDistanceHost, CursorGivesTheSameValuesAsThePointDistance) {
    for (const char* name : {"4hhb.xyzr", "1crn.xyzr"}) {
        const Atoms atoms = fdmsurf::read_structure(data_path(name)).atoms;
        const float probe = 1.4f;
        const auto features = build_ses_features(atoms, probe);
        const double reach = probe + 1.0;
        const SesHostField field(features, reach);
        SesHostField::Cursor cursor(field);
        std::mt19937 rng(1709);
        std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
        std::normal_distribution<double> offset(0.0, 1.0);
        std::uniform_real_distribution<double> depth(-1.0, 2.3);
        std::size_t band = 0, arcs = 0, outside = 0;
        for (int walk = 0; walk < 2000; ++walk) {
            const std::size_t i = pick(rng);
            double dir[3];
            const double len = random_direction(rng, offset, dir);
            const double r = atoms.radius[i] + probe * depth(rng);
            double p[3];
            for (int k = 0; k < 3; ++k) p[k] = atoms.xyz[3 * i + k] + r * dir[k] / len;
            const double d_max = walk % 10 == 9 ? reach + 0.5 : walk % 2 ? reach : probe + 0.3;
            for (int step = 0; step < 12; ++step) {
                double g_ref[3] = {7, 7, 7}, g[3] = {9, 9, 9};
                const double ref = field.distance(p, d_max, g_ref);
                const double kept = cursor.distance(p, d_max, g);
                ASSERT_EQ(kept, ref) << name << " point " << p[0] << " " << p[1] << " " << p[2];
                for (int k = 0; k < 3; ++k) ASSERT_EQ(g[k], g_ref[k]) << name << " gradient";
                EXPECT_EQ(cursor.distance(p, d_max), ref);  // without a gradient
                outside += ref <= 0.0;
                if (ref > 0.0 && ref < d_max && ++band % 8 == 0) {
                    // Nearest to an arc (past the faces): d above the deepest ball's depth.
                    arcs += ref > deepest_depth(atoms, probe, p) + 1e-6;
                }
                for (int k = 0; k < 3; ++k) p[k] += 0.3 * offset(rng);
            }
        }
        std::printf("  %s: %zu in the band (%zu of an eighth nearest to an arc), %zu outside\n",
                    name, band, arcs, outside);
        EXPECT_GT(band, 5000u);
        EXPECT_GT(arcs, 100u);
        EXPECT_GT(outside, 500u);
    }
}

// The cursor finds the deepest ball and the loop's tie from all its balls' depths at once: on
// the bisector planes of equal balls (two or three as deep, the reference's path), a hair off
// them (one deeper: its face or the arcs), and where a tie lies below a deeper third ball (not
// a tie of the deepest), against distance(), bit for bit.
TEST(SesDistanceHost, CursorTakesTheDeepestAndItsTiesAsTheLoop) {
    const Atoms atoms = fdmsurf_test::make_atoms({{0.0f, 0.0f, 0.0f, 1.5f},
                                                  {3.0f, 0.0f, 0.0f, 1.5f},
                                                  {1.5f, 2.5f, 0.0f, 1.5f},
                                                  {1.5f, 1.0f, 2.5f, 1.5f},
                                                  {1.5f, -1.5f, 0.0f, 1.9f}});
    const float probe = 1.4f;
    const auto features = build_ses_features(atoms, probe);
    const double reach = probe + 1.0;
    const SesHostField field(features, reach);
    SesHostField::Cursor cursor(field);
    std::size_t faces = 0, band = 0;
    for (const double off : {0.0, 1e-12, -1e-9, 1e-6}) {
        for (int yi = -16; yi <= 16; ++yi)
            for (int zi = -16; zi <= 16; ++zi) {
                // The plane x = 1.5 bisects the first two balls and holds the other centres
                // (steps of 1/8 Å: exact, so the two depths are equal on it).
                const double p[3] = {1.5 + off, 0.125 * yi, 0.125 * zi};
                for (const double d_max : {reach, probe + 0.3}) {
                    double g_ref[3] = {7, 7, 7}, g[3] = {9, 9, 9};
                    const double ref = field.distance(p, d_max, g_ref);
                    const double kept = cursor.distance(p, d_max, g);
                    ASSERT_EQ(kept, ref) << "point " << p[0] << " " << p[1] << " " << p[2];
                    for (int k = 0; k < 3; ++k) ASSERT_EQ(g[k], g_ref[k]) << "gradient";
                    band += ref > 0.0 && ref < d_max;
                    // On the plane, at a face's depth: the tie's or the fifth ball's.
                    faces += off == 0.0 && ref > 0.0 && ref < d_max &&
                             std::abs(ref - deepest_depth(atoms, probe, p)) < 1e-12;
                }
            }
    }
    EXPECT_GT(band, 1000u);
    EXPECT_GT(faces, 10u);
}

// The cursor takes the last point's bins without bin_cell while a point stays more than the
// bin margin inside them: points stepping across the bins' faces (where bin_cell's rounding
// decides, and the block of bins p +- r_max changes with them), a hair to either side and
// on them, against distance(), bit for bit.
TEST(SesDistanceHost, CursorKeepsItsBinsOnlyWellInsideThem) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const float probe = 1.4f;
    const auto features = build_ses_features(atoms, probe);
    const double reach = probe + 1.0;
    const SesHostField field(features, reach);
    SesHostField::Cursor cursor(field);
    std::mt19937 rng(36);
    std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
    std::uniform_int_distribution<int> axis(0, 2);
    const double offsets[] = {-2e-3, -1e-3, -1e-6, -1e-12, 0.0, 1e-12, 1e-6, 1e-3, 2e-3};
    std::size_t band = 0;
    for (int walk = 0; walk < 1500; ++walk) {
        const std::size_t i = pick(rng);
        double p[3] = {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
        // Onto the nearest face of the bins along one axis, then across it.
        const int a = axis(rng);
        const double cell =
            std::round((p[a] - features.origin[a]) / double(features.bin_size));
        p[a] = double(features.origin[a]) + double(features.bin_size) * cell;
        p[(a + 1) % 3] += atoms.radius[i] + 0.5 * probe;  // near the surface
        for (const double offset : offsets) {
            double q[3] = {p[0], p[1], p[2]};
            q[a] += offset;
            for (const double d_max : {reach, probe + 0.3}) {
                double g_ref[3] = {7, 7, 7}, g[3] = {9, 9, 9};
                const double ref = field.distance(q, d_max, g_ref);
                const double kept = cursor.distance(q, d_max, g);
                ASSERT_EQ(kept, ref) << "point " << q[0] << " " << q[1] << " " << q[2];
                for (int k = 0; k < 3; ++k) ASSERT_EQ(g[k], g_ref[k]) << "gradient";
                band += ref > 0.0 && ref < d_max;
            }
        }
    }
    EXPECT_GT(band, 5000u);
}

// The cursor's arc step measures the arcs from a first bound (the arc the last point ended
// at, else the nearest ball's) and takes the least where distance()'s loop in order certainly
// ends at it: points on the saddles (a probe's radius from a point of an arc), the same point
// twice (the last arc first), midpoints of two arcs' points (two arcs about equally near)
// and jumps between arcs (a first bound from the balls), against distance(), bit for bit.
TEST(SesDistanceHost, CursorFindsTheArcDistanceTakes) {
    for (const char* name : {"4hhb.xyzr", "1crn.xyzr"}) {
        const Atoms atoms = fdmsurf::read_structure(data_path(name)).atoms;
        const float probe = 1.4f;
        const auto features = build_ses_features(atoms, probe);
        ASSERT_FALSE(features.arcs.empty());
        const double reach = probe + 1.0;
        const SesHostField field(features, reach);
        SesHostField::Cursor cursor(field);
        std::mt19937 rng(2026);
        std::uniform_int_distribution<std::size_t> pick(0, features.arcs.size() - 1);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        std::normal_distribution<double> offset(0.0, 1.0);
        auto on_saddle = [&](std::size_t k, double p[3]) {
            const fdmsurf::detail::SesArc& a = features.arcs[k];
            const double t = a.start + a.length * unit(rng);
            double dir[3];
            const double len = random_direction(rng, offset, dir);
            const double r = probe * (0.8 + 0.4 * unit(rng));
            for (int c = 0; c < 3; ++c)
                p[c] = a.m[c] + a.rho * (std::cos(t) * a.e1[c] + std::sin(t) * a.e2[c]) +
                       r * dir[c] / len;
        };
        std::size_t nearest_arc = 0;
        for (int round = 0; round < 3000; ++round) {
            double p[3], q[3], mid[3];
            on_saddle(pick(rng), p);
            on_saddle(pick(rng), q);
            for (int c = 0; c < 3; ++c) mid[c] = 0.5 * (p[c] + q[c]);
            for (const double* x : {p, p, mid, q, q}) {
                for (const double d_max : {reach, probe + 0.3}) {
                    double g_ref[3] = {7, 7, 7}, g[3] = {9, 9, 9};
                    const double ref = field.distance(x, d_max, g_ref);
                    const double kept = cursor.distance(x, d_max, g);
                    ASSERT_EQ(kept, ref) << name << " point " << x[0] << " " << x[1] << " " << x[2];
                    for (int c = 0; c < 3; ++c) ASSERT_EQ(g[c], g_ref[c]) << name << " gradient";
                    nearest_arc += ref > 0.0 && ref < d_max &&
                                   ref > deepest_depth(atoms, probe, x) + 1e-6;
                }
            }
        }
        std::printf("  %s: %zu nearest to an arc\n", name, nearest_arc);
        EXPECT_GT(nearest_arc, 3000u);
    }
}

// A pair of balls meets in one whole exposed circle, stored with the length float(2 pi), a hair
// above 2 pi: every direction is on it (arc_distance). Points exactly where the ends' test of a
// longer-than-half arc would put them off it (half a turn from the start, a hair to the side):
// the point distance and the field's row kernel give the circle's distance, as the reference.
TEST(SesDistanceHost, AWholeCircleHasNoGapAtTheRoundingOfItsLength) {
    const Atoms atoms = fdmsurf_test::make_atoms({{0.0f, 0.0f, 0.0f, 1.6f}, {2.3f, 0.4f, -0.2f, 1.7f}});
    const float probe = 1.4f;
    const auto features = build_ses_features(atoms, probe);
    ASSERT_EQ(features.arcs.size(), 1u);
    const fdmsurf::detail::SesArc& arc = features.arcs[0];
    ASSERT_GE(double(arc.length), 6.283185307179586);  // float(2 pi) rounds up
    const double d_max = probe + 1.0;
    const SesHostField field(features, d_max);
    std::size_t checked = 0;
    for (double side : {-1e-9, -1e-8, -5e-8, 0.0, 1e-8}) {
        for (double radial : {0.3, 0.9, 1.6}) {
            for (double height : {-0.4, 0.0, 0.5}) {
                // angle pi from the start (start 0: -e1), a hair towards -e2 (b < 0)
                double p[3];
                for (int k = 0; k < 3; ++k)
                    p[k] = arc.m[k] - (arc.rho - radial) * arc.e1[k] + side * arc.e2[k] +
                           height * (arc.e1[(k + 1) % 3] * arc.e2[(k + 2) % 3] -
                                     arc.e1[(k + 2) % 3] * arc.e2[(k + 1) % 3]);
                const double ref = fdmsurf::detail::arc_distance(arc, p);
                double g[3];
                const double reference = fdmsurf::detail::ses_distance(features, p, d_max, g, false);
                const double host = field.distance(p, d_max);
                EXPECT_NEAR(host, reference, 1e-6) << side << " " << radial << " " << height;
                // The kernel alone, on a row of one point.
                const float xs[1] = {float(p[0])};
                float best[1] = {100.0f};
                field.arc_row_distances(0, xs, float(p[1]), float(p[2]), 0, 0, best);
                EXPECT_NEAR(best[0], ref, 1e-5) << side << " " << radial << " " << height;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 45u);
    // And the whole field of the pair against the reference.
    const FieldDiff r = host_against_reference(atoms, 0.2f);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
}

// A third ball whose sphere buries exactly half of a circle. Two balls of radius R at distance
// 2a meet in a circle of radius rho, sqrt(R^2 - a^2); a third of radius R at |w| from the
// circle's centre in its plane, with |w|^2 + rho^2 = R^2, has E = 0 exactly: the buried
// interval's ends are antipodal, a pseudo-angle length of 2 that rounding puts a hair either
// side for some directions (with the 13-84-85 triangle, scaled by 1/16 to stay exact: offsets
// along (12, 5) and (5, -12)). The 5-12-13 and 13-84-85 triangles, offsets in eight directions
// each, the three axes as the circle's: the features give the brute force's distance at random
// points around, and the host field the reference's.
TEST(SesDistanceHost, HalfTurnBurialsKeepTheirArcs) {
    std::mt19937 rng(99);
    struct Triangle {
        float R, a;           // ball radius, half the distance of the first two
        float offset[2];      // |offset| = |w|, |w|^2 + (R^2 - a^2) = R^2, i.e. |w| = a
    };
    std::vector<Triangle> cases_in;
    for (float sx : {1.0f, -1.0f})
        for (float sy : {1.0f, -1.0f})
            for (bool swap : {false, true}) {
                const float p = swap ? 4 : 3, q = swap ? 3 : 4;
                cases_in.push_back({13.0f, 5.0f, {sx * p, sy * q}});
                const float u = swap ? 12 : 5, v = swap ? 5 : 12;
                cases_in.push_back({85.0f / 16, 13.0f / 16, {sx * u / 16, sy * v / 16}});
            }
    double worst = 0.0;
    std::size_t cases = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (const Triangle& t : cases_in) {
            // Coordinates (along the axis, first offset, second offset), permuted per axis.
            auto place = [&](float along, float a, float b) {
                float c[3];
                c[axis] = along, c[(axis + 1) % 3] = a, c[(axis + 2) % 3] = b;
                return std::array<float, 4>{c[0], c[1], c[2], t.R - 1.5f};  // + probe 1.5: R
            };
            Atoms atoms;
            for (const auto& ball : {place(0, 0, 0), place(2 * t.a, 0, 0),
                                     place(t.a, t.offset[0], t.offset[1])}) {
                atoms.xyz.insert(atoms.xyz.end(), {ball[0], ball[1], ball[2]});
                atoms.radius.push_back(ball[3]);
            }
            const float probe = 1.5f;
            const auto features = build_ses_features(atoms, probe);
            const double d_max = probe + 2.0;
            std::uniform_real_distribution<double> along(-0.2 * t.R, 2 * t.a + 0.2 * t.R),
                across(-1.1 * t.R, 1.1 * t.R);
            for (int k = 0; k < 200; ++k) {
                double p[3];
                p[axis] = along(rng), p[(axis + 1) % 3] = across(rng), p[(axis + 2) % 3] = across(rng);
                const double fast = fdmsurf::detail::ses_distance(features, p, d_max);
                const double brute = fdmsurf::detail::ses_distance_brute(atoms, probe, p, d_max);
                worst = std::max(worst, std::abs(fast - brute));
                ASSERT_NEAR(fast, brute, 1e-4) << "axis " << axis << " R " << t.R << " offset "
                                               << t.offset[0] << " " << t.offset[1] << " point "
                                               << p[0] << " " << p[1] << " " << p[2];
            }
            const FieldDiff r = host_against_reference(atoms, t.R > 10 ? 1.0f : 0.4f);
            EXPECT_EQ(r.bad, 0u) << "axis " << axis << ": max |host - cpu| " << r.max_diff;
            ++cases;
        }
    std::printf("  %zu half-turn burials: max |features - brute force| %.3g Å\n", cases, worst);
}

// The device's pass and the host's on hemoglobin at the default spacing: both within the
// tolerance of the reference, so within twice it of each other (the reference would take
// minutes on this grid).
class SesDistanceHostGpu : public GpuTest {};

TEST_F(SesDistanceHostGpu, MatchesTheDevicesPassOnHemoglobin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.5f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> gpu = impl().compute_ses_field(atoms, plan, options.probe);
    const std::vector<float> host = SesHostField(features, plan.ses_d_max).field(plan);
    ASSERT_EQ(gpu.size(), host.size());
    FieldDiff r = compare_ses_fields(host, gpu, plan);
    std::printf("  %zu points, %zu in the band, max |host - gpu| %.3g Å\n", r.points, r.band,
                r.max_diff);
    EXPECT_LE(r.max_diff, 2 * kTolerance);
    EXPECT_GT(r.band, r.points / 20);
}

// The engine with the field on the host against the device's pass, in one binding and in
// slabs, with marching cubes on the host and on the device (the host's field uploaded): the same
// surface to the fields' float rounding, snapped and not. Auto computes it on the host exactly on
// a CPU device, and never for a mesh left on the device.
TEST_F(SesDistanceHostGpu, EngineSurfacesMatchTheDevicesField) {
    using fdmsurf::Engine;
    using fdmsurf::EngineOptions;
    using fdmsurf::StagePlace;
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    SurfaceOptions raw{.method = SesMethod::Edt};
    raw.snap = false;
    const SurfaceOptions snapped{.method = SesMethod::Edt};
    for (std::uint64_t range : {std::uint64_t(0), std::uint64_t(1) << 20})
        for (StagePlace mc : {StagePlace::Host, StagePlace::Device})
            for (const SurfaceOptions& o : {raw, snapped}) {
                SCOPED_TRACE(std::string(range ? "slabs" : "one binding") +
                             (mc == StagePlace::Host ? ", host mc" : ", device mc") +
                             (o.snap ? ", snapped" : ""));
                fdmsurf::Mesh mesh[2];
                for (int host = 0; host < 2; ++host) {
                    Engine e(EngineOptions{
                        .validation = true,
                        .max_buffer_range = range,
                        .marching_cubes = mc,
                        .ses_distance = host ? StagePlace::Host : StagePlace::Device});
                    const fdmsurf::SurfaceResult r = e.make_surface(atoms, o);
                    EXPECT_EQ(r.grid.slabs > 1, range != 0);
                    EXPECT_EQ(r.grid.host_ses_distance, host == 1);
                    bool device_pass = false, host_pass = false;
                    for (const fdmsurf::StageTime& t : r.times) {
                        device_pass = device_pass || t.name == "ses-distance";
                        host_pass = host_pass || t.name == "ses-host";
                    }
                    EXPECT_EQ(device_pass, host == 0);
                    EXPECT_EQ(host_pass, host == 1);
                    EXPECT_TRUE(e.take_validation_messages().empty());
                    mesh[host] = r.mesh;
                }
                EXPECT_GT(mesh[1].triangle_count(), 10000u);
                EXPECT_TRUE(IsClosedManifold(mesh[1]));
                const fdmsurf::CompareResult c = fdmsurf::compare_meshes(mesh[0], mesh[1], {});
                EXPECT_LE(c.hausdorff, 1e-3);
                EXPECT_LE(std::abs(c.area_rel_error), 1e-6);
                EXPECT_LE(std::abs(mesh[1].triangle_count() - double(mesh[0].triangle_count())),
                          4.0);
            }
}

TEST_F(SesDistanceHostGpu, AutoComputesTheFieldOnTheHostExactlyOnACpuDevice) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    const SurfaceOptions edt{.method = SesMethod::Edt};
    const bool cpu = engine().device().type == "CPU";
    fdmsurf::Engine e;
    EXPECT_EQ(e.make_surface(atoms, edt).grid.host_ses_distance, cpu);
    fdmsurf::Engine slabs(fdmsurf::EngineOptions{.max_buffer_range = 1u << 20});
    const fdmsurf::SurfaceResult r = slabs.make_surface(atoms, edt);
    EXPECT_GT(r.grid.slabs, 1u);
    EXPECT_EQ(r.grid.host_ses_distance, cpu);
    EXPECT_FALSE(e.make_surface(atoms, SurfaceOptions{}).grid.host_ses_distance);  // fdm
    EXPECT_FALSE(e.make_device_surface(atoms, edt).grid.host_ses_distance);
}

}  // namespace
