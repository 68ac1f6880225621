// Tests of compute_stats and piece_stats on analytic shapes and on meshes broken in known ways.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_shapes.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "support/compensated_sum.hpp"
#include "support/test_data.hpp"
#include "support/mesh_checks.hpp"

namespace fdmsurf {
namespace {

constexpr double pi = std::numbers::pi;

double sphere_area(double r) { return 4 * pi * r * r; }
double sphere_volume(double r) { return 4.0 / 3.0 * pi * r * r * r; }

TEST(MeshStats, IcosphereAreaAndVolumeApproachTheSphereFromBelow) {
    // Level 4: 5120 triangles. An inscribed polyhedron loses O((edge / r)^2): measured 0.12 %
    // of the area and 0.22 % of the volume here.
    const double r = 3.0;
    const MeshStats s = compute_stats(test::icosphere(r, 4));
    EXPECT_LT(s.area, sphere_area(r));
    EXPECT_GT(s.area, sphere_area(r) * (1 - 2e-3));
    EXPECT_LT(s.volume, sphere_volume(r));
    EXPECT_GT(s.volume, sphere_volume(r) * (1 - 3e-3));
}

TEST(MeshStats, IcosphereErrorShrinksFourfoldPerSubdivision) {
    const double r = 1.0;
    const double coarse = sphere_area(r) - compute_stats(test::icosphere(r, 3)).area;
    const double fine = sphere_area(r) - compute_stats(test::icosphere(r, 4)).area;
    EXPECT_NEAR(coarse / fine, 4.0, 0.1);
}

TEST(MeshStats, IcosphereIsOneClosedPieceOfEulerCharacteristicTwo) {
    const Mesh mesh = test::icosphere(2.0, 3);
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.vertices, mesh.vertex_count());
    EXPECT_EQ(s.triangles, 1280u);
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_EQ(s.closed_pieces, 1u);
    EXPECT_EQ(s.euler_characteristic, 2);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    EXPECT_EQ(s.nonmanifold_vertices, 0u);
    EXPECT_EQ(s.inconsistent_edges, 0u);
    EXPECT_EQ(s.degenerate_triangles, 0u);
    EXPECT_TRUE(s.is_closed_manifold());
    EXPECT_TRUE(IsClosedManifold(mesh));
}

TEST(MeshStats, VolumeDoesNotDependOnWhereAClosedMeshSits) {
    const double at_origin = compute_stats(test::icosphere(2.0, 3)).volume;
    const double moved = compute_stats(test::icosphere(2.0, 3, {40.0, -25.0, 10.0})).volume;
    EXPECT_NEAR(moved, at_origin, 1e-6 * at_origin);
}

TEST(MeshStats, TorusHasEulerCharacteristicZero) {
    const double big_r = 3.0, r = 1.0;
    const MeshStats s = compute_stats(test::torus(big_r, r, 96, 48));
    EXPECT_EQ(s.euler_characteristic, 0);
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_TRUE(s.is_closed_manifold());
    EXPECT_NEAR(s.volume, 2 * pi * pi * big_r * r * r, 5e-3 * s.volume);
    EXPECT_NEAR(s.area, 4 * pi * pi * big_r * r, 5e-3 * s.area);
}

TEST(MeshStats, TwoDisjointSpheresAreTwoClosedPieces) {
    Mesh mesh = test::icosphere(1.0, 3);
    test::append(mesh, test::icosphere(2.0, 3, {10.0, 0.0, 0.0}));
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.pieces, 2u);
    EXPECT_EQ(s.closed_pieces, 2u);
    EXPECT_EQ(s.euler_characteristic, 4);
    EXPECT_TRUE(s.is_closed_manifold());
    EXPECT_NEAR(s.volume, sphere_volume(1.0) + sphere_volume(2.0), 1e-2 * s.volume);
}

TEST(MeshStats, InwardFacingCavityCountsNegativeVolume) {
    Mesh mesh = test::icosphere(3.0, 4);
    test::append(mesh, test::turned_inside_out(test::icosphere(1.0, 4)));
    const MeshStats s = compute_stats(mesh);
    const double outer = compute_stats(test::icosphere(3.0, 4)).volume;
    const double inner = compute_stats(test::icosphere(1.0, 4)).volume;
    EXPECT_NEAR(s.volume, outer - inner, 1e-9 * outer);
    EXPECT_NEAR(s.volume, sphere_volume(3.0) - sphere_volume(1.0), 3e-3 * s.volume);
    EXPECT_EQ(s.pieces, 2u);
    EXPECT_EQ(s.closed_pieces, 2u);
    EXPECT_TRUE(s.is_closed_manifold());
}

TEST(MeshStats, RemovedTriangleLeavesThreeBoundaryEdges) {
    Mesh mesh = test::icosphere(1.0, 2);
    test::remove_triangle(mesh, 7);
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.boundary_edges, 3u);
    EXPECT_EQ(s.closed_pieces, 0u);
    EXPECT_EQ(s.euler_characteristic, 1);   // a disc
    EXPECT_EQ(s.nonmanifold_vertices, 0u);  // boundary vertices still have one fan
    EXPECT_FALSE(s.is_closed_manifold());
    const auto result = IsClosedManifold(mesh);
    EXPECT_FALSE(result);
    EXPECT_NE(std::string(result.message()).find("3 boundary edges"), std::string::npos);
}

TEST(MeshStats, FinOfThreeTrianglesOnOneEdgeIsNonManifold) {
    Mesh mesh;
    test::add_vertex(mesh, 0, 0, 0);
    test::add_vertex(mesh, 1, 0, 0);
    test::add_vertex(mesh, 0.5, 1, 0);
    test::add_vertex(mesh, 0.5, -1, 0);
    test::add_vertex(mesh, 0.5, 0, 1);
    mesh.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.nonmanifold_edges, 1u);
    EXPECT_EQ(s.boundary_edges, 6u);
    EXPECT_EQ(s.nonmanifold_vertices, 0u);
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_EQ(s.closed_pieces, 0u);
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, ConesTouchingAtTheirApexMakeANonManifoldVertex) {
    Mesh mesh;
    const std::uint32_t apex = test::add_vertex(mesh, 0, 0, 0);
    test::add_cone(mesh, apex, 1.0, 1.0, 16);
    test::add_cone(mesh, apex, -1.0, 1.0, 16);
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.nonmanifold_vertices, 1u);
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.inconsistent_edges, 0u);
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_EQ(s.euler_characteristic, 3);  // two spheres (2 + 2) glued at one vertex
    EXPECT_GT(s.volume, 0.0);
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, OneFlippedTriangleGivesThreeInconsistentEdges) {
    Mesh mesh = test::icosphere(1.0, 2);
    test::flip_triangle(mesh, 11);
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.inconsistent_edges, 3u);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.closed_pieces, 1u);  // closed, but not orientable as given
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, InsideOutSphereIsNotAClosedManifold) {
    const MeshStats s = compute_stats(test::turned_inside_out(test::icosphere(1.0, 2)));
    EXPECT_LT(s.volume, 0.0);
    EXPECT_EQ(s.inconsistent_edges, 0u);
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, RepeatedIndexIsADegenerateTriangle) {
    Mesh mesh = test::icosphere(1.0, 1);
    mesh.indices.insert(mesh.indices.end(), {0, 0, 1});
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.degenerate_triangles, 1u);
    EXPECT_EQ(s.boundary_edges, 0u);  // degenerate triangles add no edges
    EXPECT_EQ(s.euler_characteristic, 2);
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, UnreferencedVerticesCountAsVerticesButNotInEulerOrPieces) {
    Mesh mesh = test::icosphere(1.0, 1);
    mesh.normals.clear();
    test::add_vertex(mesh, 5, 5, 5);
    const MeshStats s = compute_stats(mesh);
    EXPECT_EQ(s.vertices, mesh.vertex_count());
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_EQ(s.euler_characteristic, 2);
}

TEST(MeshStats, EmptyMeshHasNoPiecesAndIsNotClosed) {
    const MeshStats s = compute_stats(Mesh{});
    EXPECT_EQ(s.pieces, 0u);
    EXPECT_EQ(s.area, 0.0);
    EXPECT_FALSE(s.is_closed_manifold());
}

TEST(MeshStats, IndexOutOfRangeThrowsInvalidArgument) {
    Mesh mesh = test::icosphere(1.0, 0);
    mesh.indices.back() = std::uint32_t(mesh.vertex_count());
    try {
        compute_stats(mesh);
        FAIL() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    }
    EXPECT_FALSE(IsClosedManifold(mesh));
}

TEST(PieceStats, PiecesComeLargestAreaFirstAndSumToTheTotal) {
    Mesh mesh = test::icosphere(1.0, 3);
    test::append(mesh, test::icosphere(2.0, 3, {10.0, 0.0, 0.0}));
    Mesh holed = test::icosphere(0.5, 2, {-10.0, 0.0, 0.0});
    test::remove_triangle(holed, 0);
    test::append(mesh, holed);
    const auto pieces = piece_stats(mesh);
    const MeshStats total = compute_stats(mesh);
    ASSERT_EQ(pieces.size(), 3u);
    EXPECT_NEAR(pieces[0].area, sphere_area(2.0), 1e-2 * pieces[0].area);
    EXPECT_NEAR(pieces[1].area, sphere_area(1.0), 1e-2 * pieces[1].area);
    EXPECT_TRUE(pieces[0].is_closed_manifold());
    EXPECT_TRUE(pieces[1].is_closed_manifold());
    EXPECT_EQ(pieces[2].boundary_edges, 3u);
    EXPECT_EQ(pieces[2].closed_pieces, 0u);
    double area = 0, volume = 0;
    std::size_t vertices = 0, triangles = 0;
    for (const MeshStats& p : pieces) {
        EXPECT_EQ(p.pieces, 1u);
        area += p.area;
        volume += p.volume;
        vertices += p.vertices;
        triangles += p.triangles;
    }
    EXPECT_NEAR(area, total.area, 1e-9 * area);
    EXPECT_NEAR(volume, total.volume, 1e-9 * volume);
    EXPECT_EQ(vertices, total.vertices);
    EXPECT_EQ(triangles, total.triangles);
}

TEST(PieceStats, CavityIsASecondPieceWithNegativeVolume) {
    Mesh mesh = test::icosphere(3.0, 3);
    test::append(mesh, test::turned_inside_out(test::icosphere(1.0, 3)));
    const auto pieces = piece_stats(mesh);
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_GT(pieces[0].volume, 0.0);
    EXPECT_LT(pieces[1].volume, 0.0);
    EXPECT_EQ(pieces[1].euler_characteristic, 2);
    EXPECT_FALSE(pieces[1].is_closed_manifold());  // on its own, a cavity is inside out
}

}  // namespace
}  // namespace fdmsurf

// The statistics run on all threads, with sums taken chunk by chunk in a fixed order: one
// thread and many give the same figures, bit for bit, on a real surface (NanoShaper's 1CRN SES,
// with a pierced copy for boundary edges and a glued copy for non-manifold edges and vertices).
TEST(MeshStats, SameFiguresOnOneThreadAndMany) {
    const fdmsurf::Mesh ses = fdmsurf::read_mesh_any(fdmsurf::test::data_path("1crn-ses-nanoshaper.ply.gz"));
    fdmsurf::Mesh pierced = ses;
    pierced.indices.resize(pierced.indices.size() - 3 * 1000);
    fdmsurf::Mesh glued = ses;  // two copies sharing vertex 0's position index: fans meet there
    const auto n = static_cast<std::uint32_t>(ses.vertex_count());
    glued.positions.insert(glued.positions.end(), ses.positions.begin(), ses.positions.end());
    for (std::size_t c = 0; c < ses.indices.size(); ++c)
        glued.indices.push_back(ses.indices[c] == 0 ? 0 : ses.indices[c] + n);
    glued.normals.clear();
    for (const fdmsurf::Mesh* mesh : {&ses, static_cast<const fdmsurf::Mesh*>(&pierced), static_cast<const fdmsurf::Mesh*>(&glued)}) {
        const fdmsurf::MeshStats one = fdmsurf::detail::total_stats(*mesh, 1);
        for (unsigned threads : {2u, 3u, 8u, 0u}) {
            const fdmsurf::MeshStats many = fdmsurf::detail::total_stats(*mesh, threads);
            EXPECT_EQ(one.area, many.area) << threads;
            EXPECT_EQ(one.volume, many.volume) << threads;
            EXPECT_EQ(one.pieces, many.pieces);
            EXPECT_EQ(one.boundary_edges, many.boundary_edges);
            EXPECT_EQ(one.nonmanifold_edges, many.nonmanifold_edges);
            EXPECT_EQ(one.nonmanifold_vertices, many.nonmanifold_vertices);
            EXPECT_EQ(one.inconsistent_edges, many.inconsistent_edges);
            EXPECT_EQ(one.euler_characteristic, many.euler_characteristic);
        }
    }
    const fdmsurf::MeshStats s = fdmsurf::compute_stats(ses);
    EXPECT_TRUE(s.is_closed_manifold());
    EXPECT_GT(fdmsurf::compute_stats(pierced).boundary_edges, 100u);  // the rim of the hole
    const fdmsurf::MeshStats g = fdmsurf::compute_stats(glued);
    EXPECT_EQ(g.pieces, 2 * s.pieces - 1);  // the copy of vertex 0's piece hangs on it
    EXPECT_EQ(g.nonmanifold_vertices, 1u);
    EXPECT_EQ(g.boundary_edges, 0u);
    EXPECT_NEAR(g.area, 2 * s.area, 1e-9 * s.area);
}

TEST(MeshStats, AreaAndVolumeAreTheSameBitsInAnyTriangleOrder) {
    // The sums do not depend on the order of the triangles (base/fixed_sum.hpp): a removal of
    // some pieces leaves the others' figures as they were. And each piece's is the exact sum of
    // its triangles' terms, rounded once: a compensated long double sum agrees to a few ulps.
    const fdmsurf::Mesh ses =
        fdmsurf::read_mesh_any(fdmsurf::test::data_path("1crn-ses-nanoshaper.ply.gz"));
    fdmsurf::Mesh shuffled = ses;
    std::vector<std::size_t> order(ses.triangle_count());
    for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
    std::shuffle(order.begin(), order.end(), std::mt19937(11));
    for (std::size_t t = 0; t < order.size(); ++t)
        for (int k = 0; k < 3; ++k) shuffled.indices[3 * t + k] = ses.indices[3 * order[t] + k];
    const fdmsurf::MeshStats a = fdmsurf::compute_stats(ses);
    const fdmsurf::MeshStats b = fdmsurf::compute_stats(shuffled);
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.volume, b.volume);
    fdmsurf::test::CompensatedSum area, volume;
    for (std::size_t t = 0; t < ses.triangle_count(); ++t) {
        std::array<double, 3> p[3];
        for (int k = 0; k < 3; ++k)
            for (int x = 0; x < 3; ++x) p[k][x] = ses.positions[3 * ses.indices[3 * t + k] + x];
        const std::array<double, 3> u{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const std::array<double, 3> w{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const double c0 = u[1] * w[2] - u[2] * w[1], c1 = u[2] * w[0] - u[0] * w[2],
                     c2 = u[0] * w[1] - u[1] * w[0];
        area.add(0.5 * std::sqrt(c0 * c0 + c1 * c1 + c2 * c2));
        volume.add(
            (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) +
             p[0][1] * (p[1][2] * p[2][0] - p[1][0] * p[2][2]) +
             p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) /
                6.0);
    }
    EXPECT_NEAR(a.area, area.value(), 4e-16 * a.area);
    EXPECT_NEAR(a.volume, volume.value(), 4e-16 * a.volume);
}

namespace fdmsurf {
namespace {

TEST(MeshStats, EdgeCountsMatchAPlainEdgeTableOnARealSurface) {
    // Crambin's SES with a hole, a flipped triangle, a fin (a triangle added on an edge) and a
    // degenerate one: the edge figures against a table of every edge's uses, built plainly.
    Mesh m = read_mesh_any(test::data_path("1crn-ses-nanoshaper.ply.gz"));
    m.normals.clear();
    m.indices.resize(m.indices.size() - 3 * 50);                 // a hole
    std::swap(m.indices[3 * 100 + 1], m.indices[3 * 100 + 2]);   // a flipped triangle
    m.indices.insert(m.indices.end(), {m.indices[3 * 200], m.indices[3 * 200 + 1],
                                       m.indices[3 * 300 + 2]});  // a fin on an edge
    m.indices.insert(m.indices.end(), {m.indices[3 * 400], m.indices[3 * 400], 7});
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<bool>> uses;
    long faces = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const std::uint32_t* v = &m.indices[3 * t];
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
        ++faces;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = v[k], b = v[(k + 1) % 3];
            uses[{std::min(a, b), std::max(a, b)}].push_back(a < b);
        }
    }
    std::size_t boundary = 0, nonmanifold = 0, inconsistent = 0;
    for (const auto& [edge, dirs] : uses) {
        boundary += dirs.size() == 1;
        nonmanifold += dirs.size() > 2;
        inconsistent += dirs.size() == 2 && dirs[0] == dirs[1];
    }
    std::vector<bool> referenced(m.vertex_count(), false);
    for (std::uint32_t v : m.indices) referenced[v] = true;
    const long vertices = long(std::count(referenced.begin(), referenced.end(), true));
    for (unsigned threads : {1u, 2u, 0u}) {
        const MeshStats s = detail::total_stats(m, threads);
        EXPECT_EQ(s.boundary_edges, boundary);
        EXPECT_EQ(s.nonmanifold_edges, nonmanifold);
        EXPECT_EQ(s.inconsistent_edges, inconsistent);
        EXPECT_EQ(s.degenerate_triangles, 1u);
        EXPECT_EQ(s.euler_characteristic, vertices - long(uses.size()) + faces);
    }
    EXPECT_GT(boundary, 10u);
    EXPECT_EQ(inconsistent, 3u);
    EXPECT_GE(nonmanifold, 1u);
}

}  // namespace
}  // namespace fdmsurf
