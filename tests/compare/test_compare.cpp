// Tests of compare_meshes and its parts: analytic spheres, brute force, welding, meshstat.py.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/meshstat_tool.hpp"
#include "cli/json_check.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "compare/compare_detail.hpp"
#include "mesh/mesh_shapes.hpp"

namespace fdmsurf {
namespace {

namespace fs = std::filesystem;
using detail::Vec3;

#ifdef FDMSURF_TEST_DATA_DIR
const std::string kDataDir = FDMSURF_TEST_DATA_DIR;
#else
const std::string kDataDir = "tests/data";
#endif

ErrorCode code_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.code();
    }
    ADD_FAILURE() << "no fdmsurf::Error thrown";
    return ErrorCode::Internal;
}

// The smallest distance from the origin to the plane of any triangle: the radius of the ball
// the (convex, origin-centred) polyhedron holds.
double inscribed_radius(const Mesh& m) {
    double r = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        Vec3 v[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t i = m.indices[3 * t + std::size_t(k)];
            v[k] = {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
        }
        const Vec3 e1 = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
        const Vec3 e2 = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
        const Vec3 n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        r = std::min(r, std::fabs(n[0] * v[0][0] + n[1] * v[0][1] + n[2] * v[0][2]) / len);
    }
    return r;
}

// A triangle soup: every triangle with its own three vertices.
Mesh unwelded(const Mesh& m) {
    Mesh soup;
    for (std::uint32_t i : m.indices) {
        soup.positions.insert(soup.positions.end(), m.positions.begin() + 3 * i,
                              m.positions.begin() + 3 * i + 3);
        soup.indices.push_back(std::uint32_t(soup.indices.size()));
    }
    return soup;
}

void expect_same(const CompareResult& a, const CompareResult& b, double tolerance) {
    EXPECT_NEAR(a.rmsd_weighted, b.rmsd_weighted, tolerance);
    EXPECT_NEAR(a.mean_unsigned, b.mean_unsigned, tolerance);
    EXPECT_NEAR(a.mean_signed, b.mean_signed, tolerance);
    EXPECT_NEAR(a.share_beyond_spacing, b.share_beyond_spacing, tolerance);
    EXPECT_NEAR(a.hausdorff, b.hausdorff, tolerance);
    EXPECT_NEAR(a.rmsd_tested_to_reference, b.rmsd_tested_to_reference, tolerance);
    EXPECT_NEAR(a.area_rel_error, b.area_rel_error, tolerance);
    EXPECT_NEAR(a.volume_rel_error, b.volume_rel_error, tolerance);
    EXPECT_EQ(a.ref_vertices, b.ref_vertices);
    EXPECT_EQ(a.test_vertices, b.test_vertices);
}

// ---------------------------------------------------------------------------------------------

TEST(ClosestPointOnTriangle, FindsTheFaceEdgeOrVertexRegion) {
    const Vec3 a = {0, 0, 0}, b = {2, 0, 0}, c = {0, 2, 0};
    auto near = [](const Vec3& x, const Vec3& y) {
        return std::fabs(x[0] - y[0]) + std::fabs(x[1] - y[1]) + std::fabs(x[2] - y[2]) < 1e-15;
    };
    EXPECT_TRUE(near(detail::closest_point_on_triangle({0.5, 0.5, 3}, a, b, c), {0.5, 0.5, 0}));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({-1, -1, 1}, a, b, c), a));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({3, -1, 0}, a, b, c), b));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({-1, 5, 0}, a, b, c), c));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({1, -2, 1}, a, b, c), {1, 0, 0}));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({-3, 1, 0}, a, b, c), {0, 1, 0}));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({2, 2, -1}, a, b, c), {1, 1, 0}));
    // Degenerate triangles: a segment (collinear) and a point.
    EXPECT_TRUE(near(detail::closest_point_on_triangle({1, 1, 0}, a, b, {1, 0, 0}), {1, 0, 0}));
    EXPECT_TRUE(near(detail::closest_point_on_triangle({1, 1, 1}, a, a, a), a));
}

TEST(CompareMeshes, IdenticalMeshesAreAtDistanceZero) {
    const Mesh sphere = test::icosphere(3.0, 4);
    const CompareResult r = compare_meshes(sphere, sphere, {});
    EXPECT_EQ(r.rmsd_weighted, 0.0);
    EXPECT_EQ(r.mean_unsigned, 0.0);
    EXPECT_EQ(r.mean_signed, 0.0);
    EXPECT_EQ(r.share_beyond_spacing, 0.0);
    EXPECT_EQ(r.hausdorff, 0.0);
    EXPECT_EQ(r.rmsd_tested_to_reference, 0.0);
    EXPECT_EQ(r.area_rel_error, 0.0);
    EXPECT_EQ(r.volume_rel_error, 0.0);
    EXPECT_EQ(r.ref_vertices, sphere.vertex_count());
    EXPECT_EQ(r.ref_triangles, sphere.triangle_count());
    EXPECT_NEAR(r.area_ref, 4 * M_PI * 9, 4 * M_PI * 9 * 0.01);
}

// Reference: icosphere of radius 3; tested: the same subdivision at radius 3.2. A reference
// vertex (radius 3) lies inside the tested polyhedron, whose faces are between its inscribed
// radius h (3.2 minus the largest chordal sagitta) and 3.2 from the centre: h - 3 <= d <= 0.2.
TEST(CompareMeshes, ConcentricSpheresGiveTheRadiusDifference) {
    const int level = 5;  // 20480 triangles, edges ~0.1 Å
    const Mesh inner = test::icosphere(3.0, level), outer = test::icosphere(3.2, level);
    const double h_outer = inscribed_radius(outer), h_inner = inscribed_radius(inner);
    ASSERT_LT(3.2 - h_outer, 0.002);  // the sagitta at this subdivision
    const double slack = 1e-5;        // float positions
    CompareOptions options;
    options.spacing = 0.1;

    const CompareResult r = compare_meshes(inner, outer, options);
    EXPECT_GE(r.rmsd_weighted, h_outer - 3.0 - slack);
    EXPECT_LE(r.rmsd_weighted, 0.2 + slack);
    EXPECT_NEAR(r.rmsd_weighted, 0.2, 0.002);
    EXPECT_NEAR(r.mean_signed, -r.mean_unsigned, 1e-12);  // every reference vertex inside
    EXPECT_LT(r.mean_signed, 0);
    EXPECT_EQ(r.share_beyond_spacing, 1.0);  // all d ~ 0.2 > 0.1
    // Tested vertices (radius 3.2) against the inner polyhedron: 0.2 <= d <= 3.2 - h_inner.
    EXPECT_GE(r.rmsd_tested_to_reference, 0.2 - slack);
    EXPECT_LE(r.rmsd_tested_to_reference, 3.2 - h_inner + slack);
    EXPECT_LE(r.hausdorff, 3.2 - h_inner + slack);
    // A scaled copy: the area and volume ratios are exact up to float rounding.
    EXPECT_NEAR(r.area_rel_error, (3.2 / 3) * (3.2 / 3) - 1, 1e-5);
    EXPECT_NEAR(r.volume_rel_error, std::pow(3.2 / 3, 3) - 1, 1e-5);

    options.spacing = 0.5;
    const CompareResult swapped = compare_meshes(outer, inner, options);
    EXPECT_GT(swapped.mean_signed, 0);  // reference outside the tested mesh
    EXPECT_NEAR(swapped.mean_signed, swapped.mean_unsigned, 1e-12);
    EXPECT_EQ(swapped.share_beyond_spacing, 0.0);
    EXPECT_GE(swapped.rmsd_weighted, 0.2 - slack);
    EXPECT_LE(swapped.rmsd_weighted, 3.2 - h_inner + slack);
    EXPECT_NEAR(swapped.area_rel_error, (3.0 / 3.2) * (3.0 / 3.2) - 1, 1e-5);
}

// Random triangles (some degenerate) and random points, near and far: the tree's answers equal
// testing every triangle.
TEST(ClosestPoints, TreeEqualsBruteForce) {
    std::mt19937 rng(20240531);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int round = 0; round < 4; ++round) {
        Mesh soup;
        const int triangles = 50 + 150 * round;
        for (int t = 0; t < triangles; ++t) {
            const Vec3 centre = {5 * unit(rng), 5 * unit(rng), 5 * unit(rng)};
            const double size = t % 7 == 0 ? 3.0 : 0.5;
            for (int k = 0; k < 3; ++k) {
                test::add_vertex(soup, centre[0] + size * unit(rng), centre[1] + size * unit(rng),
                                 centre[2] + size * unit(rng));
            }
            const auto first = std::uint32_t(soup.vertex_count() - 3);
            if (t % 11 == 0) {  // collinear: a zero-area triangle
                soup.positions[3 * (first + 2) + 0] = soup.positions[3 * first + 0];
                soup.positions[3 * (first + 2) + 1] = soup.positions[3 * first + 1];
                soup.positions[3 * (first + 2) + 2] = soup.positions[3 * first + 2] + 0.25f;
                soup.positions[3 * (first + 1) + 0] = soup.positions[3 * first + 0];
                soup.positions[3 * (first + 1) + 1] = soup.positions[3 * first + 1];
            }
            soup.indices.insert(soup.indices.end(), {first, first + 1, first + 2});
        }
        const detail::CleanMesh mesh = detail::clean_mesh(soup, -1);
        std::vector<double> points;
        const int count = round == 0 ? 9000 : 500;  // 9000: several chunks, several threads
        for (int i = 0; i < count; ++i) {
            const double scale = i % 5 == 0 ? 20.0 : 6.0;
            for (int k = 0; k < 3; ++k) points.push_back(scale * unit(rng));
        }
        // Points on the mesh: its vertices (ties between triangles sharing them).
        for (std::size_t v = 0; v < 60; ++v) {
            for (int k = 0; k < 3; ++k) points.push_back(mesh.positions[3 * v + std::size_t(k)]);
        }
        const auto brute = detail::closest_points_brute_force(mesh, points);
        for (unsigned threads : {1u, 3u}) {
            const auto fast = detail::closest_points(mesh, points, threads);
            ASSERT_EQ(fast.size(), brute.size());
            for (std::size_t i = 0; i < brute.size(); ++i) {
                EXPECT_NEAR(fast[i].distance, brute[i].distance, 1e-9) << "point " << i;
                EXPECT_EQ(fast[i].triangle, brute[i].triangle) << "point " << i;
            }
        }
        // The distances alone, to points given as floats (a mesh's vertices): those of their
        // values in double.
        const std::vector<float> as_float(points.begin(), points.end());
        const std::vector<double> rounded(as_float.begin(), as_float.end());
        const auto brute_rounded = detail::closest_points_brute_force(mesh, rounded);
        const std::vector<double> distances = detail::closest_distances(mesh, as_float, 2);
        ASSERT_EQ(distances.size(), brute_rounded.size());
        for (std::size_t i = 0; i < brute_rounded.size(); ++i) {
            EXPECT_NEAR(distances[i], brute_rounded[i].distance, 1e-9) << "point " << i;
        }
    }
}

// A regular grid of squares, each split along one diagonal: points at and above its vertices
// and edge midpoints are equally close to several triangles whose centroids are as near too.
// The tree, whichever leaf it starts from and in whichever order it visits them, picks the
// brute force's triangle (the lowest-numbered).
TEST(ClosestPoints, ExactTiesGoToTheBruteForcesTriangle) {
    Mesh grid;
    constexpr std::uint32_t kSide = 40;
    for (std::uint32_t j = 0; j <= kSide; ++j) {
        for (std::uint32_t i = 0; i <= kSide; ++i) test::add_vertex(grid, i, j, 0.0);
    }
    for (std::uint32_t j = 0; j < kSide; ++j) {
        for (std::uint32_t i = 0; i < kSide; ++i) {
            const std::uint32_t a = j * (kSide + 1) + i, b = a + 1, c = a + kSide + 1, d = c + 1;
            grid.indices.insert(grid.indices.end(), {a, b, d, a, d, c});
        }
    }
    const detail::CleanMesh mesh = detail::clean_mesh(grid, -1);
    std::vector<double> points;
    for (std::uint32_t j = 0; j <= 2 * kSide; j += 3) {
        for (std::uint32_t i = 0; i <= 2 * kSide; i += 2) {
            for (const double z : {0.0, 0.5}) points.insert(points.end(), {0.5 * i, 0.5 * j, z});
        }
    }
    const auto brute = detail::closest_points_brute_force(mesh, points);
    for (unsigned threads : {1u, 2u}) {
        const auto fast = detail::closest_points(mesh, points, threads);
        ASSERT_EQ(fast.size(), brute.size());
        std::size_t mismatched = 0;
        for (std::size_t i = 0; i < brute.size(); ++i) {
            EXPECT_EQ(fast[i].distance, brute[i].distance) << "point " << i;
            mismatched += fast[i].triangle != brute[i].triangle;
        }
        EXPECT_EQ(mismatched, 0u) << "of " << brute.size() << " points";
    }
}

// Every metric recomputed here from brute-force distances, on a small bumpy pair.
TEST(CompareMeshes, EqualsABruteForceEvaluation) {
    Mesh reference = test::icosphere(2.0, 3);
    Mesh tested = test::icosphere(2.1, 2);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> bump(-0.15f, 0.15f);
    for (float& x : tested.positions) x += bump(rng);
    test::append(tested, test::icosphere(0.5, 1, {0.3, 0.2, 0.1}));  // a stray inner piece

    CompareOptions options;
    options.spacing = 0.12;
    const CompareResult r = compare_meshes(reference, tested, options);

    const detail::CleanMesh a = detail::clean_mesh(reference, 1e-5);
    const detail::CleanMesh b = detail::clean_mesh(tested, 1e-5);
    auto weights = [](const detail::CleanMesh& m) {
        std::vector<double> sum(m.vertex_count(), 0.0), count(m.vertex_count(), 0.0);
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            Vec3 v[3];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t i = m.indices[3 * t + std::size_t(k)];
                v[k] = {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
            }
            const Vec3 e1 = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
            const Vec3 e2 = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
            const double area =
                0.5 * std::hypot(e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]);
            for (int k = 0; k < 3; ++k) {
                sum[m.indices[3 * t + std::size_t(k)]] += area;
                count[m.indices[3 * t + std::size_t(k)]] += 1;
            }
        }
        for (std::size_t v = 0; v < sum.size(); ++v) sum[v] /= count[v];
        return sum;
    };
    auto as_points = [](const detail::CleanMesh& m) {
        return std::vector<double>(m.positions.begin(), m.positions.end());
    };
    const auto wa = weights(a), wb = weights(b);
    const auto ab = detail::closest_points_brute_force(b, as_points(a));
    const auto ba = detail::closest_points_brute_force(a, as_points(b));
    double w = 0, wd = 0, wd2 = 0, wsd = 0, beyond = 0, max_ab = 0, wb_sum = 0, wbd2 = 0,
           max_ba = 0;
    for (std::size_t v = 0; v < wa.size(); ++v) {
        const double d = ab[v].distance;
        const std::uint32_t* t = &b.indices[3 * std::size_t(ab[v].triangle)];
        Vec3 c[3];
        for (int k = 0; k < 3; ++k)
            c[k] = {b.positions[3 * t[k]], b.positions[3 * t[k] + 1], b.positions[3 * t[k] + 2]};
        const Vec3 e1 = {c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]};
        const Vec3 e2 = {c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]};
        const Vec3 n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
        const double side = (a.positions[3 * v] - ab[v].point[0]) * n[0] +
                            (a.positions[3 * v + 1] - ab[v].point[1]) * n[1] +
                            (a.positions[3 * v + 2] - ab[v].point[2]) * n[2];
        w += wa[v];
        wd += wa[v] * d;
        wd2 += wa[v] * d * d;
        wsd += wa[v] * d * (side > 0 ? 1 : side < 0 ? -1 : 0);
        if (d > options.spacing) beyond += wa[v];
        max_ab = std::max(max_ab, d);
    }
    for (std::size_t v = 0; v < wb.size(); ++v) {
        wb_sum += wb[v];
        wbd2 += wb[v] * ba[v].distance * ba[v].distance;
        max_ba = std::max(max_ba, ba[v].distance);
    }
    EXPECT_NEAR(r.rmsd_weighted, std::sqrt(wd2 / w), 1e-12);
    EXPECT_NEAR(r.mean_unsigned, wd / w, 1e-12);
    EXPECT_NEAR(r.mean_signed, wsd / w, 1e-12);
    EXPECT_NEAR(r.share_beyond_spacing, beyond / w, 1e-12);
    EXPECT_GT(r.share_beyond_spacing, 0.05);  // the bumps make the share non-trivial
    EXPECT_LT(r.share_beyond_spacing, 0.95);
    EXPECT_NEAR(r.max_ref_to_test, max_ab, 1e-12);
    EXPECT_NEAR(r.max_test_to_ref, max_ba, 1e-12);
    EXPECT_NEAR(r.hausdorff, std::max(max_ab, max_ba), 1e-12);
    EXPECT_NEAR(r.rmsd_tested_to_reference, std::sqrt(wbd2 / wb_sum), 1e-12);
}

TEST(CleanMesh, WeldsDuplicatesAndNearDuplicatesOnly) {
    const Mesh sphere = test::icosphere(1.0, 2);
    const Mesh soup = unwelded(sphere);
    const detail::CleanMesh welded = detail::clean_mesh(soup, 1e-5);
    EXPECT_EQ(welded.vertex_count(), sphere.vertex_count());
    EXPECT_EQ(welded.welded, soup.vertex_count() - sphere.vertex_count());
    EXPECT_EQ(welded.triangle_count(), sphere.triangle_count());
    // Exact duplicates only, and none at all.
    EXPECT_EQ(detail::clean_mesh(soup, 0).vertex_count(), sphere.vertex_count());
    EXPECT_EQ(detail::clean_mesh(soup, -1).vertex_count(), soup.vertex_count());

    // 4e-6 apart is welded (and the triangle between them collapses), 4e-5 apart is not.
    Mesh pair;
    test::add_vertex(pair, 0, 0, 0);
    test::add_vertex(pair, 4e-6, 0, 0);
    test::add_vertex(pair, 0, 1, 0);
    test::add_vertex(pair, 1, 1, 0);
    test::add_vertex(pair, 1, 1 + 4e-5, 0);
    test::add_vertex(pair, 9, 9, 9);  // used by no triangle
    pair.indices = {0, 1, 2, 1, 3, 2, 2, 3, 4};
    const detail::CleanMesh cleaned = detail::clean_mesh(pair, 1e-5);
    EXPECT_EQ(cleaned.welded, 1u);
    EXPECT_EQ(cleaned.collapsed, 1u);
    EXPECT_EQ(cleaned.unreferenced, 1u);
    EXPECT_EQ(cleaned.vertex_count(), 4u);
    EXPECT_EQ(cleaned.triangle_count(), 2u);
    // The class keeps its first vertex's position.
    EXPECT_EQ(cleaned.positions[0], 0.0f);
}

TEST(CleanMesh, WeldsAcrossCellFacesAtAnyPosition) {
    // Pairs 6e-6 apart at many offsets, so that some straddle the hash grid's cell faces.
    Mesh m;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> where(-50.0, 50.0);
    for (int i = 0; i < 2000; ++i) {
        const double x = where(rng), y = where(rng), z = where(rng);
        const auto a = test::add_vertex(m, x, y, z);
        const auto b = test::add_vertex(m, x + 3e-6, y - 3e-6, z + 3e-6);
        const auto c = test::add_vertex(m, x + 0.5, y, z);
        m.indices.insert(m.indices.end(), {a, c, b});  // collapses once a and b merge
        m.indices.insert(m.indices.end(), {a, c, test::add_vertex(m, x, y + 0.5, z)});
    }
    const detail::CleanMesh cleaned = detail::clean_mesh(m, 1e-5);
    EXPECT_EQ(cleaned.welded, 2000u);
    EXPECT_EQ(cleaned.collapsed, 2000u);
}

TEST(CompareMeshes, WeldingMakesASoupCompareLikeTheIndexedMesh) {
    const Mesh a = test::icosphere(3.0, 3), b = test::icosphere(3.1, 2);
    expect_same(compare_meshes(a, b, {}), compare_meshes(unwelded(a), unwelded(b), {}), 1e-12);
}

TEST(CompareMeshes, OuterComparesTheLargestPiecesOnly) {
    Mesh with_cavity = test::icosphere(4.0, 3);
    Mesh cavity = test::icosphere(1.0, 2);
    for (std::size_t t = 0; t < cavity.triangle_count(); ++t) test::flip_triangle(cavity, t);
    test::append(with_cavity, cavity);
    const Mesh plain = test::icosphere(4.0, 3);

    CompareOptions options;
    const CompareResult all = compare_meshes(with_cavity, plain, options);
    EXPECT_GT(all.hausdorff, 2.9);  // the cavity is far from the tested surface
    EXPECT_LT(all.volume_ref, all.volume_test);
    options.outer_only = true;
    const CompareResult outer = compare_meshes(with_cavity, plain, options);
    EXPECT_EQ(outer.hausdorff, 0.0);
    EXPECT_EQ(outer.ref_vertices, plain.vertex_count());
    EXPECT_EQ(outer.volume_rel_error, 0.0);
}

TEST(CompareMeshes, RejectsBadOptionsAndEmptyMeshes) {
    const Mesh sphere = test::icosphere(1.0, 1);
    CompareOptions options;
    for (double spacing : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        options.spacing = spacing;
        EXPECT_EQ(code_of([&] { compare_meshes(sphere, sphere, options); }),
                  ErrorCode::InvalidArgument)
            << spacing;
    }
    options.spacing = 0.5;
    EXPECT_EQ(code_of([&] { compare_meshes(Mesh{}, sphere, options); }), ErrorCode::Format);
    EXPECT_EQ(code_of([&] { compare_meshes(sphere, Mesh{}, options); }), ErrorCode::Format);
    Mesh flat;  // triangles, but of zero area
    test::add_vertex(flat, 0, 0, 0);
    test::add_vertex(flat, 1, 0, 0);
    test::add_vertex(flat, 2, 0, 0);
    flat.indices = {0, 1, 2};
    EXPECT_EQ(code_of([&] { compare_meshes(flat, sphere, options); }), ErrorCode::Format);
    Mesh broken = sphere;
    broken.indices.back() = 100000;
    EXPECT_EQ(code_of([&] { compare_meshes(sphere, broken, options); }),
              ErrorCode::InvalidArgument);
    Mesh not_finite = sphere;
    not_finite.positions[4] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(code_of([&] { compare_meshes(not_finite, sphere, options); }), ErrorCode::Format);
}

// ---------------------------------------------------------------------------------------------
// Readers

class CompareFiles : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("fdmsurf_compare_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write_file(const std::string& name, const std::string& content) const {
        std::ofstream((dir_ / name).string(), std::ios::binary) << content;
        return (dir_ / name).string();
    }
    std::string write_gzip(const std::string& name, const std::string& content) const {
        const std::string path = (dir_ / name).string();
        gzFile f = gzopen(path.c_str(), "wb");
        EXPECT_NE(f, nullptr);
        EXPECT_EQ(gzwrite(f, content.data(), unsigned(content.size())), int(content.size()));
        gzclose(f);
        return path;
    }
    fs::path dir_;
};

// A unit square as two triangles, in OFF with the given header lines.
std::string square_off(const std::string& header, bool normals) {
    std::string text = header;
    const char* const corners[] = {"0 0 0", "1 0 0", "1 1 0", "0 1 0"};
    for (const char* c : corners) text += std::string(c) + (normals ? " 0 0 1\n" : "\n");
    return text + "4 0 1 2 3\n";  // one quad: fan-triangulated
}

void expect_unit_square(const Mesh& m) {
    ASSERT_EQ(m.vertex_count(), 4u);
    ASSERT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(m.positions[6], 1.0f);
    EXPECT_EQ(m.positions[7], 1.0f);
}

TEST_F(CompareFiles, ReadsOffVariants) {
    expect_unit_square(read_mesh_any(write_file("a.off", square_off("OFF\n4 1 0\n", false))));
    expect_unit_square(read_mesh_any(write_file("b.off", square_off("OFF 4 1 0\n", false))));
    expect_unit_square(read_mesh_any(
        write_file("c.off", square_off("# written by a test\nNOFF\n# counts\n4 1 0\n\n", true))));
    // NanoShaper's header, under a name without .off: recognised by its first line.
    expect_unit_square(read_mesh_any(write_file("d.mesh", square_off("OFF+N\n4 1 0\n", true))));
    expect_unit_square(read_mesh_any(write_gzip("e.off.gz", square_off("OFF\n4 1 0\n", false))));
}

TEST_F(CompareFiles, RejectsMalformedOff) {
    auto code = [this](const std::string& text) {
        const std::string path = write_file("bad.off", text);
        return code_of([&] { read_mesh_any(path); });
    };
    EXPECT_EQ(code("PLOP\n4 1 0\n"), ErrorCode::Format);
    EXPECT_EQ(code("OFF\n4 1 0\n0 0 0\n1 0 0\n"), ErrorCode::Format);  // truncated
    EXPECT_EQ(code("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 7\n"), ErrorCode::Format);
    EXPECT_EQ(code("OFF\n4 1 0\n0 0 x\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n"), ErrorCode::Format);
    EXPECT_EQ(code("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2\n"), ErrorCode::Format);
}

TEST_F(CompareFiles, ReadsMsmsPairsByEitherName) {
    const std::string vert =
        "# MSMS solvent excluded surface vertices\n#vertex #sphere density probe_r\n"
        "     4      2  1.00  1.50\n"
        "    0.000    0.000    0.000    0.000    0.000    1.000       0      1  2\n"
        "    1.000    0.000    0.000    0.000    0.000    1.000       0      1  2\n"
        "    1.000    1.000    0.000    0.000    0.000    1.000       0      2  2\n"
        "    0.000    1.000    0.000    0.000    0.000    1.000       0      2  2\n";
    const std::string face =
        "# MSMS solvent excluded surface faces\n#faces  #sphere density probe_r\n"
        "     2      2  1.00  1.50\n"
        "     1      2      3  1  1\n"
        "     1      3      4  1  2\n";
    write_file("s.vert", vert);
    const std::string face_path = write_file("s.face", face);
    expect_unit_square(read_mesh_any((dir_ / "s.vert").string()));
    expect_unit_square(read_mesh_any(face_path));
    expect_unit_square(read_mesh_any((dir_ / "s").string()));  // the base name
    write_gzip("z.vert.gz", vert);
    write_gzip("z.face.gz", face);
    expect_unit_square(read_mesh_any((dir_ / "z.face.gz").string()));
    // A missing sibling is an Io error naming it.
    write_file("lone.vert", vert);
    try {
        read_mesh_any((dir_ / "lone.vert").string());
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Io);
        EXPECT_NE(std::string(e.what()).find("lone.face"), std::string::npos) << e.what();
    }
    write_file("bad.vert", vert);
    write_file("bad.face", "     1      2  1.00  1.50\n     1      2      9  1  1\n");
    EXPECT_EQ(code_of([&] { read_mesh_any((dir_ / "bad.vert").string()); }), ErrorCode::Format);
}

TEST_F(CompareFiles, ReadsGzippedPlyAndRejectsBadGzip) {
    const Mesh sphere = test::icosphere(1.0, 2);
    const std::string plain = (dir_ / "s.ply").string();
    write_mesh(sphere, plain);
    std::ifstream in(plain, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const Mesh back = read_mesh_any(write_gzip("s.ply.gz", bytes.str()));
    EXPECT_EQ(back.positions, sphere.positions);
    EXPECT_EQ(back.indices, sphere.indices);
    const std::string gz = write_gzip("t.ply.gz", bytes.str());
    std::string packed;
    {
        std::ifstream g(gz, std::ios::binary);
        std::ostringstream s;
        s << g.rdbuf();
        packed = s.str();
    }
    write_file("cut.ply.gz", packed.substr(0, packed.size() / 2));
    EXPECT_EQ(code_of([&] { read_mesh_any((dir_ / "cut.ply.gz").string()); }), ErrorCode::Format);
    EXPECT_EQ(code_of([&] { read_mesh_any((dir_ / "missing.ply").string()); }), ErrorCode::Io);
    EXPECT_EQ(code_of([&] { read_mesh_any(dir_.string()); }), ErrorCode::Io);
    EXPECT_EQ(code_of([&] { read_mesh_any(write_file("x.stl", "solid x\nendsolid x\n")); }),
              ErrorCode::Format);
}

// The same mesh as PLY, OFF and MSMS gives the same comparison.
TEST_F(CompareFiles, FormatsCompareAlike) {
    const Mesh reference = test::icosphere(2.0, 3);
    Mesh tested = test::icosphere(2.05, 2);
    std::string off = "OFF\n" + std::to_string(tested.vertex_count()) + " " +
                      std::to_string(tested.triangle_count()) + " 0\n";
    std::string vert = "# vert\n" + std::to_string(tested.vertex_count()) + " 0 1.0 1.4\n";
    std::string face = "# face\n" + std::to_string(tested.triangle_count()) + " 0 1.0 1.4\n";
    char line[256];
    for (std::size_t v = 0; v < tested.vertex_count(); ++v) {
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", double(tested.positions[3 * v]),
                      double(tested.positions[3 * v + 1]), double(tested.positions[3 * v + 2]));
        off += line;
        vert += line;
    }
    for (std::size_t t = 0; t < tested.triangle_count(); ++t) {
        const auto* f = &tested.indices[3 * t];
        off += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " +
               std::to_string(f[2]) + "\n";
        face += std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
                std::to_string(f[2] + 1) + " 1 1\n";
    }
    write_file("t.vert", vert);
    write_file("t.face", face);
    const CompareResult direct = compare_meshes(reference, tested, {});
    expect_same(direct, compare_meshes(reference, read_mesh_any(write_file("t.off", off)), {}), 0);
    expect_same(direct, compare_meshes(reference, read_mesh_any((dir_ / "t.face").string()), {}),
                0);
}

// ---------------------------------------------------------------------------------------------
// Agreement with shared/tools/meshstat.py on a real pair: NanoShaper's SES of 1CRN against
// fdmsurf's at 0.5 Å (tests/data).


TEST(CompareMeshes, AgreesWithMeshstatOn1crn) {
    FDMSURF_REQUIRE_MESHSTAT();
    const std::string reference = kDataDir + "/1crn-ses-nanoshaper.ply.gz";
    const std::string tested = kDataDir + "/1crn-fdm-0.5.ply";
    int status = 0;
    const std::string text =
        test::run_meshstat({"compare", reference, tested, "--spacing", "0.5"}, status);
    ASSERT_EQ(status, 0) << text;
    const auto json = fdmsurf_cli_test::parse_json(text);
    ASSERT_TRUE(json.has_value()) << text;
    auto number = [&](const char* key) {
        const auto* v = json->find(key);
        EXPECT_NE(v, nullptr) << key;
        return v != nullptr ? v->number : std::nan("");
    };

    CompareOptions options;
    options.spacing = 0.5;
    const CompareResult r =
        compare_meshes(read_mesh_any(reference), read_mesh_any(tested), options);
    // Same welding, same closest-point arithmetic, same tie-breaking: agreement far below the
    // 1e-4 relative asked for; only summation order differs.
    auto relative = [](double ours, double theirs) {
        return std::fabs(ours - theirs) / std::max(std::fabs(theirs), 1e-300);
    };
    EXPECT_LT(relative(r.rmsd_weighted, number("rmsd")), 1e-9);
    EXPECT_LT(relative(r.mean_unsigned, number("mean_unsigned")), 1e-9);
    EXPECT_LT(relative(r.mean_signed, number("mean_signed")), 1e-6);
    EXPECT_LT(relative(100 * r.share_beyond_spacing, number("pct_area_beyond_spacing")), 1e-9);
    EXPECT_LT(relative(r.area_rel_error, number("area_rel_err")), 1e-9);
    EXPECT_LT(relative(r.volume_rel_error, number("volume_rel_err")), 1e-9);
    EXPECT_LT(relative(r.hausdorff, number("hausdorff")), 1e-12);
    EXPECT_LT(relative(r.rmsd_tested_to_reference, number("rmsd_test_to_ref")), 1e-9);
    EXPECT_EQ(double(r.ref_vertices), number("ref_vertices"));
    EXPECT_EQ(double(r.test_vertices), number("test_vertices"));
}

}  // namespace
}  // namespace fdmsurf
