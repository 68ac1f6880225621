// Tests of cavity removal (src/mesh/cavities.cpp): by volume, by predicate, and by whether the
// solvent probe fits in the void (the clearance between the atoms' spheres inside a cavity).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "mesh/cavities.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_shapes.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::Mesh;
using fdmsurf::detail::MeshPiece;

// An outer sphere of radius 10 with an inward-facing sphere of radius `r` at `c` inside.
Mesh shell_with_cavity(double r, std::array<double, 3> c) {
    Mesh outer = fdmsurf::test::icosphere(10.0, 3);
    Mesh inner = fdmsurf::test::icosphere(r, 3, c);
    const auto base = static_cast<std::uint32_t>(outer.vertex_count());
    outer.positions.insert(outer.positions.end(), inner.positions.begin(), inner.positions.end());
    if (!outer.normals.empty())
        for (float n : inner.normals) outer.normals.push_back(-n);
    for (std::size_t t = 0; t < inner.triangle_count(); ++t) {  // reversed: facing inwards
        outer.indices.push_back(base + inner.indices[3 * t]);
        outer.indices.push_back(base + inner.indices[3 * t + 2]);
        outer.indices.push_back(base + inner.indices[3 * t + 1]);
    }
    return outer;
}

std::vector<std::array<std::array<double, 3>, 3>> triangles_of(const Mesh& m, std::size_t first) {
    std::vector<std::array<std::array<double, 3>, 3>> out;
    for (std::size_t t = first; t < m.triangle_count(); ++t) {
        std::array<std::array<double, 3>, 3> tri;
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) tri[k][a] = m.positions[3 * m.indices[3 * t + k] + a];
        out.push_back(tri);
    }
    return out;
}

// The triangles of a void of radius 2 at the origin (inside a shell of radius 10).
std::vector<std::array<std::array<double, 3>, 3>> void_of_radius_2() {
    const Mesh m = shell_with_cavity(2.0, {0, 0, 0});
    return triangles_of(m, fdmsurf::test::icosphere(10.0, 3).triangle_count());
}

// Six atoms of radius 1 at +-3 Å on the axes.
Atoms six_atoms_on_the_axes() {
    Atoms atoms;
    atoms.xyz = {3, 0, 0, -3, 0, 0, 0, 3, 0, 0, -3, 0, 0, 0, 3, 0, 0, -3};
    atoms.radius.assign(6, 1.0f);
    return atoms;
}

TEST(Cavities, ClearanceIsTheLargestBallBetweenTheAtoms) {
    // A void of radius 2 at the origin between six atoms of radius 1 at +-3 Å on the axes: the
    // largest ball that fits is centred at the origin, radius 2.
    const auto cavity = void_of_radius_2();
    Atoms atoms = six_atoms_on_the_axes();
    EXPECT_NEAR(fdmsurf::detail::cavity_clearance(cavity, atoms), 2.0, 0.005);
    // With a cap: min(clearance, cap), the cap returned as soon as a sample reaches it.
    EXPECT_EQ(fdmsurf::detail::cavity_clearance(cavity, atoms, 0.3, 1.5), 1.5);
    EXPECT_NEAR(fdmsurf::detail::cavity_clearance(cavity, atoms, 0.3, 3.0), 2.0, 0.005);
    // The atoms moved by (0.2, 0.1, 0) and grown to 1.2 Å: the centre follows, the radius is 1.8.
    for (std::size_t i = 0; i < 6; ++i) {
        atoms.xyz[3 * i] += 0.2f;
        atoms.xyz[3 * i + 1] += 0.1f;
        atoms.radius[i] = 1.2f;
    }
    EXPECT_NEAR(fdmsurf::detail::cavity_clearance(cavity, atoms), 1.8, 0.005);
    // A maximum on the void's boundary (one atom only) is found from below, within 0.15 Å: the
    // pattern search stalls on a curved boundary. Voids of a real surface have their best point
    // inside (the probe centre sits r_s inside the SES), so this does not arise there.
    atoms.xyz = {3.0f, 0.0f, 0.0f};
    atoms.radius = {1.0f};
    const double c = fdmsurf::detail::cavity_clearance(cavity, atoms);
    EXPECT_LE(c, 4.0);
    EXPECT_GE(c, 3.85);
}

TEST(Cavities, AtomCellsGiveTheSameClearanceFromFewerAtoms) {
    // The index only narrows which atoms are visited and which samples are measured: the
    // answers are identical, with and without a cap, also with many far atoms on both sides
    // along x (which it skips).
    const auto cavity = void_of_radius_2();
    Atoms atoms = six_atoms_on_the_axes();
    for (int k = 0; k < 2000; ++k) {
        const float x = (k % 2 ? 1.0f : -1.0f) * (20.0f + 0.05f * float(k));
        atoms.xyz.insert(atoms.xyz.end(), {x, 0.3f * float(k % 7), -0.2f * float(k % 5)});
        atoms.radius.push_back(1.5f);
    }
    const fdmsurf::detail::AtomCells index(atoms);
    ASSERT_EQ(index.cells.items.size(), atoms.size());
    EXPECT_EQ(index.r_max, 1.5f);
    for (double cap : {std::numeric_limits<double>::infinity(), 1.5, 3.0}) {
        const double plain = fdmsurf::detail::cavity_clearance(cavity, atoms, 0.3, cap);
        const double indexed = fdmsurf::detail::cavity_clearance(cavity, atoms, 0.3, cap, &index);
        EXPECT_EQ(plain, indexed) << "cap " << cap;
    }
    EXPECT_NEAR(fdmsurf::detail::cavity_clearance(cavity, atoms, 0.3, 3.0, &index), 2.0, 0.005);
}

// The triangles of each piece of crambin's FDM surface (tests/data), as the search sees them.
std::vector<std::vector<std::array<std::array<double, 3>, 3>>> crambin_pieces() {
    const Mesh m = fdmsurf::read_mesh(fdmsurf::test::data_path("1crn-fdm-0.5.ply"));
    const fdmsurf::detail::VertexPieces parts = fdmsurf::detail::vertex_pieces(m);
    std::vector<std::vector<std::array<std::array<double, 3>, 3>>> pieces(parts.count);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        std::array<std::array<double, 3>, 3> tri;
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) tri[k][a] = m.positions[3 * m.indices[3 * t + k] + a];
        pieces[parts.of_vertex[m.indices[3 * t]]].push_back(tri);
    }
    return pieces;
}

TEST(Cavities, BinnedInsideTestMatchesThePlainOne) {
    // On a real surface: random points of its box, and the hard ones, on the surface itself
    // (vertices, edge midpoints and centroids), where a ray grazes edges and corners.
    for (const auto& tris : crambin_pieces()) {
        const fdmsurf::detail::RayBins bins(tris);
        std::vector<std::array<double, 3>> points;
        std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (const auto& t : tris) {
            for (int k = 0; k < 3; ++k) {
                points.push_back(t[k]);
                const auto& u = t[(k + 1) % 3];
                points.push_back({0.5 * (t[k][0] + u[0]), 0.5 * (t[k][1] + u[1]),
                                  0.5 * (t[k][2] + u[2])});
                for (int a = 0; a < 3; ++a)
                    lo[a] = std::min(lo[a], t[k][a]), hi[a] = std::max(hi[a], t[k][a]);
            }
            points.push_back({(t[0][0] + t[1][0] + t[2][0]) / 3.0,
                              (t[0][1] + t[1][1] + t[2][1]) / 3.0,
                              (t[0][2] + t[1][2] + t[2][2]) / 3.0});
        }
        std::mt19937 rng(7);
        for (int i = 0; i < 2000; ++i) {
            std::array<double, 3> p;
            for (int a = 0; a < 3; ++a)
                p[a] = std::uniform_real_distribution<double>(lo[a] - 1.0, hi[a] + 1.0)(rng);
            points.push_back(p);
        }
        std::size_t inside = 0;
        // (Every 37th surface point of the large outer piece: the plain test is slow there.)
        const std::size_t random_from = points.size() - 2000;
        for (std::size_t i = 0; i < points.size();
             i += tris.size() > 1000 && i < random_from ? 37 : 1) {
            const bool plain = fdmsurf::detail::inside_piece(points[i], tris);
            ASSERT_EQ(bins.inside(points[i]), plain) << "point " << i;
            inside += plain;
        }
        EXPECT_GT(inside, 0u);
    }
}

TEST(Cavities, IndexedClearanceMatchesThePlainSearchOnCrambin) {
    // The atoms' cells and the triangles' bins change only how fast the search runs: on every
    // piece of crambin's surface, with and without a cap, the same clearance to the last bit.
    const Atoms atoms = fdmsurf::read_structure(fdmsurf::test::data_path("1crn.xyzr")).atoms;
    const fdmsurf::detail::AtomCells index(atoms);
    // (The outer piece with a coarser step and one cap: the plain search is slow there.)
    for (const auto& tris : crambin_pieces()) {
        const bool outer = tris.size() > 5000;
        for (double cap : {1.4, 3.0, std::numeric_limits<double>::infinity()}) {
            if (outer && cap != 1.4) continue;
            const double step = outer ? 1.0 : 0.3;
            const double plain = fdmsurf::detail::cavity_clearance(tris, atoms, step, cap);
            const double indexed =
                fdmsurf::detail::cavity_clearance(tris, atoms, step, cap, &index);
            EXPECT_EQ(plain, indexed) << "cap " << cap << ", " << tris.size() << " triangles";
        }
    }
}

// The cavities of haemoglobin's FDM surface at 0.5 Å with every void kept, as the removal
// sees them (the candidates of remove_cavities_if).
class CavitySearch : public GpuTest {};

TEST_F(CavitySearch, IndexedClearanceMatchesThePlainSearchOnHaemoglobinVoids) {
    // The tiles' best-first order, their bounds and the pattern search's nearby atoms only
    // change how fast the search runs: on each of 4HHB's voids, with the probe as cap, with a
    // larger one and without, the same clearance to the last bit (so the same verdicts).
    const Atoms atoms = fdmsurf::read_structure(fdmsurf::test::data_path("4hhb.pdb.gz")).atoms;
    Mesh mesh = engine()
                    .make_surface(atoms, fdmsurf::SurfaceOptions{.spacing = 0.5f,
                                                                 .min_cavity_volume = 0.0f})
                    .mesh;
    std::vector<std::vector<std::array<std::array<double, 3>, 3>>> voids;
    fdmsurf::detail::remove_cavities_if(mesh, [&](const MeshPiece& c) {
        voids.push_back(c.triangles);
        return false;
    });
    ASSERT_GT(voids.size(), 20u);
    const fdmsurf::detail::AtomCells index(atoms);
    std::size_t fits = 0;
    for (const auto& tris : voids) {
        for (double cap : {1.4, 3.0, std::numeric_limits<double>::infinity()}) {
            const double plain = fdmsurf::detail::cavity_clearance(tris, atoms, 0.3, cap);
            const double indexed = fdmsurf::detail::cavity_clearance(tris, atoms, 0.3, cap, &index);
            EXPECT_EQ(plain, indexed) << "cap " << cap << ", " << tris.size() << " triangles";
            fits += cap == 1.4 && plain >= 1.4;
        }
    }
    // Both verdicts occur.
    EXPECT_GT(fits, 0u);
    EXPECT_LT(fits, voids.size());
}

TEST(Cavities, VoidsWithoutRoomForTheProbeAreRemoved) {
    // A void of radius 4 between six atoms of radius 1 at +-6 Å on the axes: a ball of radius 5
    // fits (centred at the origin). A probe of 4.5 Å is kept, one of 5.5 Å is not. A void below
    // half a probe ball's volume goes without a search (the radius-2 void: 33.5 Å³, less than
    // half of a 3 Å probe's 113 Å³, although its clearance, 5 Å, would admit the probe).
    Atoms atoms;
    atoms.xyz = {6, 0, 0, -6, 0, 0, 0, 6, 0, 0, -6, 0, 0, 0, 6, 0, 0, -6};
    atoms.radius.assign(6, 1.0f);
    for (double probe : {4.5, 5.5}) {
        Mesh m = shell_with_cavity(4.0, {0, 0, 0});
        const std::size_t before = m.triangle_count();
        const std::size_t removed = fdmsurf::detail::remove_cavities_without_probe(m, atoms, probe);
        EXPECT_EQ(removed, probe < 5.0 ? 0u : 1u) << probe;
        EXPECT_EQ(m.triangle_count() < before, probe > 5.0);
        EXPECT_EQ(fdmsurf::compute_stats(m).pieces, probe < 5.0 ? 2u : 1u);
    }
    Mesh small = shell_with_cavity(2.0, {0, 0, 0});
    EXPECT_EQ(fdmsurf::detail::remove_cavities_without_probe(small, atoms, 3.0), 1u);
}

TEST(Cavities, PredicateSeesEachCavityOnce) {
    Mesh m = shell_with_cavity(2.0, {1, 0, 0});
    std::size_t calls = 0;
    double volume = 0.0;
    const std::size_t removed = fdmsurf::detail::remove_cavities_if(m, [&](const MeshPiece& c) {
        ++calls;
        volume = -c.volume;
        return false;
    });
    EXPECT_EQ(removed, 0u);
    EXPECT_EQ(calls, 1u);  // the outer piece is not a cavity
    EXPECT_NEAR(volume, 4.0 / 3.0 * 3.14159265358979 * 8.0, 0.02 * 33.5);
    EXPECT_EQ(fdmsurf::remove_cavities(m, 1000.0), 1u);
    EXPECT_EQ(fdmsurf::compute_stats(m).pieces, 1u);
}

}  // namespace

namespace {

TEST(Cavities, SpecksOfEitherOrientationAreRemoved) {
    // A real cavity (radius 2), a speck facing outwards (radius 0.1 at (5, 0, 0)) and one
    // facing inwards (radius 0.1 at (-5, 0, 0)): only the specks go.
    Mesh m = shell_with_cavity(2.0, {0, 0, 0});
    const Mesh speck = fdmsurf::test::icosphere(0.1, 1, {5, 0, 0});
    const Mesh hole = fdmsurf::test::icosphere(0.1, 1, {-5, 0, 0});
    for (const Mesh* add : {&speck, &hole}) {
        const auto base = static_cast<std::uint32_t>(m.vertex_count());
        m.positions.insert(m.positions.end(), add->positions.begin(), add->positions.end());
        if (!m.normals.empty())
            m.normals.insert(m.normals.end(), add->normals.begin(), add->normals.end());
        for (std::size_t t = 0; t < add->triangle_count(); ++t) {
            const bool flip = add == &hole;
            m.indices.push_back(base + add->indices[3 * t]);
            m.indices.push_back(base + add->indices[3 * t + (flip ? 2 : 1)]);
            m.indices.push_back(base + add->indices[3 * t + (flip ? 1 : 2)]);
        }
    }
    ASSERT_EQ(fdmsurf::compute_stats(m).pieces, 4u);
    EXPECT_EQ(fdmsurf::detail::remove_specks(m, 0.01), 2u);
    const auto stats = fdmsurf::compute_stats(m);
    EXPECT_EQ(stats.pieces, 2u);
    EXPECT_TRUE(stats.is_closed_manifold());
}

}  // namespace
