// Exact sphere-patch areas (atom_exact_areas): closed forms for one, two and three balls, balls
// covered all round, twins, random clusters against dense Shrake-Rupley sampling, crambin.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "fdmsurf/fdmsurf.hpp"
#include "support/ball_union.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using fdmsurf_test::make_atoms;

namespace {

constexpr double kPi = std::numbers::pi;

double cut_sphere(double a, double b, double d) {
    const double x = (d * d + a * a - b * b) / (2 * d);
    return 2 * kPi * a * (a + std::clamp(x, -a, a));
}

// A ball's radius as the areas see it: the float radius and probe, added in double.
double ball(float r, float probe) { return double(r) + double(probe); }

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

}  // namespace

TEST(AtomExactAreas, OneAndTwoBallsAreTheirClosedForms) {
    const std::vector<double> one = atom_exact_areas(make_atoms({{1, 2, 3, 1.7f}}), 1.4f);
    EXPECT_NEAR(one[0], 4 * kPi * ball(1.7f, 1.4f) * ball(1.7f, 1.4f), 1e-12 * one[0]);
    // Two balls cutting each other, and (probe 0) the bare radii; the two caps are less and
    // more than a hemisphere.
    for (const float probe : {0.0f, 1.4f}) {
        for (const float d : {0.5f, 1.0f, 3.0f, 4.5f}) {
            const Atoms two = make_atoms({{0, 0, 0, 1.5f}, {d, 0, 0, 1.9f}});
            const std::vector<double> a = atom_exact_areas(two, probe);
            const double r1 = ball(1.5f, probe), r2 = ball(1.9f, probe);
            if (d + r1 <= r2) {
                EXPECT_EQ(a[0], 0.0);
                continue;
            }
            EXPECT_NEAR(a[0], cut_sphere(r1, r2, d), 1e-11 * r1 * r1) << d << " " << probe;
            EXPECT_NEAR(a[1], cut_sphere(r2, r1, d), 1e-11 * r2 * r2) << d << " " << probe;
        }
    }
}

TEST(AtomExactAreas, ThreeBallsWithCornersMatchGaussBonnet) {
    // The middle ball's two caps overlap (the spheres meet at two corners): sphere less both
    // caps plus their overlap (ball_union.hpp's closed form, itself checked by Monte Carlo).
    const std::vector<test::Ball> balls{
        {{0, 0, 0}, 1.7}, {{2.2, 0.6, 0}, 1.6}, {{0.9, 2.1, 0.4}, 1.8}};
    Atoms atoms;
    for (const test::Ball& b : balls) {
        atoms.xyz.insert(atoms.xyz.end(), {float(b.c[0]), float(b.c[1]), float(b.c[2])});
        atoms.radius.push_back(float(b.r));
    }
    const std::vector<double> a = atom_exact_areas(atoms, 0.0f);
    // The reference in double from the float atoms.
    std::vector<test::Ball> f = test::balls_of(atoms, 0.0);
    EXPECT_NEAR(sum(a), test::union_area(f), 1e-9 * sum(a));
    for (std::size_t i = 0; i < 3; ++i) {
        const std::vector<test::Ball> one{f[i]};
        const double r = f[i].r;
        std::vector<std::pair<test::V3, double>> caps;
        for (std::size_t j = 0; j < 3; ++j) {
            if (j == i) continue;
            const test::V3 e = test::sub3(f[j].c, f[i].c);
            const double d = test::norm3(e);
            const double x = (d * d + r * r - f[j].r * f[j].r) / (2 * d);
            caps.push_back({{e[0] / d, e[1] / d, e[2] / d}, std::acos(x / r)});
        }
        const double between =
            std::acos(std::clamp(test::dot3(caps[0].first, caps[1].first), -1.0, 1.0));
        const double exposed = 4 * kPi - 2 * kPi * (1 - std::cos(caps[0].second)) -
                               2 * kPi * (1 - std::cos(caps[1].second)) +
                               test::cap_overlap(caps[0].second, caps[1].second, between);
        EXPECT_NEAR(a[i], r * r * exposed, 1e-9 * r * r) << i;
    }
}

TEST(AtomExactAreas, CoveredTwinsAndContainedBallsHaveNone) {
    // A ball with six larger neighbours along the axes is covered all round: its caps leave no
    // boundary arc.
    Atoms covered = make_atoms({{0, 0, 0, 1.0f},
                                {1.2f, 0, 0, 1.6f},
                                {-1.2f, 0, 0, 1.6f},
                                {0, 1.2f, 0, 1.6f},
                                {0, -1.2f, 0, 1.6f},
                                {0, 0, 1.2f, 1.6f},
                                {0, 0, -1.2f, 1.6f}});
    EXPECT_EQ(atom_exact_areas(covered, 0.0f)[0], 0.0);
    const Atoms atoms =
        make_atoms({{0, 0, 0, 1.5f}, {0, 0, 0, 1.5f}, {10, 0, 0, 2.0f}, {10.2f, 0, 0, 0.5f}});
    const std::vector<double> a = atom_exact_areas(atoms, 1.4f);
    EXPECT_NEAR(a[0], 4 * kPi * ball(1.5f, 1.4f) * ball(1.5f, 1.4f), 1e-12 * a[0]);
    EXPECT_EQ(a[1], 0.0);
    EXPECT_EQ(a[3], 0.0);
    // the small ball inside buries none
    EXPECT_NEAR(a[2], 4 * kPi * ball(2.0f, 1.4f) * ball(2.0f, 1.4f), 1e-12 * a[2]);
    EXPECT_THROW(atom_exact_areas(atoms, -1.0f), Error);
    EXPECT_TRUE(atom_exact_areas(Atoms{}, 1.4f).empty());
}

TEST(AtomExactAreas, TwoCapsLargerThanHemispheresCanCoverASphere) {
    // Each neighbour buries more than half of the middle ball (h = -1/3, 109.5° from its
    // centre) and the two overlap round the back: nothing is left, though neither circle
    // crosses the other. The outer two keep the sphere less the other's cap (which holds the
    // middle one's).
    const Atoms atoms = make_atoms({{0, 0, 0, 1.0f}, {1.2f, 0, 0, 1.8f}, {-1.2f, 0, 0, 1.8f}});
    const std::vector<double> a = atom_exact_areas(atoms, 0.0f);
    const double r = ball(1.8f, 0.0f), d = 2.0 * double(1.2f);
    EXPECT_EQ(a[0], 0.0);
    EXPECT_NEAR(a[1], cut_sphere(r, r, d), 1e-11 * r * r);
    EXPECT_NEAR(a[2], a[1], 1e-11 * r * r);
    // Smaller neighbours leave a band round the middle: its two circles are whole.
    const Atoms band = make_atoms({{0, 0, 0, 1.0f}, {0, 1.5f, 0, 1.2f}, {0, -1.5f, 0, 1.2f}});
    const double cap = 4 * kPi - cut_sphere(1.0, ball(1.2f, 0.0f), 1.5);
    EXPECT_NEAR(atom_exact_areas(band, 0.0f)[0], 4 * kPi - 2 * cap, 1e-11);
}

TEST(AtomExactAreas, RandomClustersAgreeWithDenseSampling) {
    // Clusters of 12 balls of radius 1.2-2 Å in a 5 Å box (many arcs, corners, covered caps):
    // every atom against Shrake-Rupley with 200,000 points (sampling error about 0.02 Å²).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(0.0f, 5.0f), rad(1.2f, 2.0f);
    double worst = 0.0;
    for (int trial = 0; trial < 6; ++trial) {
        Atoms atoms;
        for (int k = 0; k < 12; ++k) {
            atoms.xyz.insert(atoms.xyz.end(), {pos(rng), pos(rng), pos(rng)});
            atoms.radius.push_back(rad(rng));
        }
        const float probe = trial % 2 ? 1.4f : 0.0f;
        const std::vector<double> exact = atom_exact_areas(atoms, probe);
        const std::vector<double> sampled = atom_sas_areas(atoms, probe, 200000);
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const double r = atoms.radius[i] + probe;
            const double tolerance = 2e-4 * 4 * kPi * r * r + 1e-3;
            EXPECT_NEAR(exact[i], sampled[i], tolerance) << "trial " << trial << " atom " << i;
            worst = std::max(worst, std::abs(exact[i] - sampled[i]));
        }
    }
    std::printf("  largest difference from 200,000-point Shrake-Rupley: %.4f Å²\n", worst);
}

TEST(AtomExactAreas, CrambinMatchesFineSampling) {
    // 1CRN: the exact total within 0.02% of Shrake-Rupley with 20,000 points, every atom
    // within 0.3 Å².
    const Atoms atoms = read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    const std::vector<double> exact = atom_exact_areas(atoms, 1.4f);
    const std::vector<double> fine = atom_sas_areas(atoms, 1.4f, 20000);
    EXPECT_NEAR(sum(exact), sum(fine), 2e-4 * sum(fine));
    double worst = 0.0;
    for (std::size_t i = 0; i < atoms.size(); ++i)
        worst = std::max(worst, std::abs(exact[i] - fine[i]));
    EXPECT_LT(worst, 0.3);
    std::printf(
        "  1CRN SASA exact %.2f Å², Shrake-Rupley 20,000 points %.2f Å², worst atom %.3f Å²\n",
        sum(exact), sum(fine), worst);
}

TEST(AtomExactAreas, TwinNeighboursChangeNothing) {
    // Every fifth atom of crambin doubled (the same centre and radius): the first of each pair
    // keeps the area it had alone, the twin gets none, and no other atom moves (its two equal
    // caps are one).
    const Atoms atoms = read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    Atoms doubled = atoms;
    std::vector<std::size_t> twin_of;
    for (std::size_t i = 0; i < atoms.size(); i += 5) {
        twin_of.push_back(i);
        doubled.xyz.insert(doubled.xyz.end(), atoms.xyz.begin() + std::ptrdiff_t(3 * i),
                           atoms.xyz.begin() + std::ptrdiff_t(3 * i + 3));
        doubled.radius.push_back(atoms.radius[i]);
    }
    for (const float probe : {0.0f, 1.4f}) {
        const std::vector<double> alone = atom_exact_areas(atoms, probe);
        const std::vector<double> with = atom_exact_areas(doubled, probe);
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const double r = atoms.radius[i] + probe;
            EXPECT_NEAR(with[i], alone[i], 1e-9 * 4 * kPi * r * r) << "atom " << i << " " << probe;
        }
        for (std::size_t t = 0; t < twin_of.size(); ++t)
            EXPECT_EQ(with[atoms.size() + t], 0.0) << "twin of " << twin_of[t];
    }
}

TEST(AtomExactAreas, LatticeAtomsAreAlikeAndMatchSampling) {
    // A simple cubic lattice (5³ balls 3 Å apart, radius 2.3 Å, no probe): each inner ball meets
    // its six face neighbours (overlapping caps) and twelve edge neighbours, all in exactly
    // symmetric places, so planes pass through the cell's vertices. The 27 inner balls have one
    // area, which dense sampling confirms.
    Atoms atoms;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) {
                atoms.xyz.insert(atoms.xyz.end(), {3.0f * i, 3.0f * j, 3.0f * k});
                atoms.radius.push_back(2.3f);
            }
    const std::vector<double> exact = atom_exact_areas(atoms, 0.0f);
    const std::vector<double> sampled = atom_sas_areas(atoms, 0.0f, 200000);
    const std::size_t centre = (2 * 5 + 2) * 5 + 2;
    EXPECT_GT(exact[centre], 1.0);
    for (int i = 1; i < 4; ++i)
        for (int j = 1; j < 4; ++j)
            for (int k = 1; k < 4; ++k) {
                const std::size_t a = std::size_t((i * 5 + j) * 5 + k);
                EXPECT_NEAR(exact[a], exact[centre], 1e-12 * exact[centre]) << a;
                EXPECT_NEAR(exact[a], sampled[a], 2e-4 * 4 * kPi * 2.3 * 2.3 + 1e-3) << a;
            }
}

