// Tests of mesh refinement (src/refine/refine.cpp): the butterfly weights and what they reproduce,
// the topology of a subdivided mesh, and the projection onto a field's level set.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "mesh/mesh_shapes.hpp"
#include "refine/refine.hpp"
#include "support/mesh_checks.hpp"

namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::Mesh;
using fdmsurf::MeshStats;
using fdmsurf::detail::GridField;
using fdmsurf::detail::GridInterpolation;
using fdmsurf::detail::ProjectOptions;
using fdmsurf::detail::Vec3;

Vec3 vertex(const Mesh& m, std::size_t v) {
    return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

// A regular triangulated patch of the plane: points (i + j / 2, j sqrt(3) / 2) scaled by `edge`,
// i < nx, j < ny, counter-clockwise from +z. Interior vertices have valence 6.
struct Lattice {
    int nx, ny;
    Mesh mesh;
    std::uint32_t at(int i, int j) const { return std::uint32_t(j * nx + i); }
    bool interior(std::uint32_t v) const {
        const int i = int(v) % nx, j = int(v) / nx;
        return i > 0 && j > 0 && i + 1 < nx && j + 1 < ny;
    }
};

Lattice lattice(int nx, int ny, double edge, double x0 = 0.0, double y0 = 0.0) {
    Lattice l{nx, ny, {}};
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            fdmsurf::test::add_vertex(l.mesh, x0 + edge * (i + 0.5 * j),
                                      y0 + edge * j * std::sqrt(3.0) / 2.0, 0.0);
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i)
            l.mesh.indices.insert(l.mesh.indices.end(),
                                  {l.at(i, j), l.at(i + 1, j), l.at(i, j + 1), l.at(i + 1, j),
                                   l.at(i + 1, j + 1), l.at(i, j + 1)});
    return l;
}

// The two old vertices whose edge new vertex v was made on: the corners of the triangles that use
// it. Found from the subdivided mesh: in the central triangle (ab, bc, ca) of each original
// triangle (a, b, c) of `before`, in the order subdivide_butterfly writes them.
std::vector<std::array<std::uint32_t, 2>> edge_ends(const Mesh& before, const Mesh& after) {
    const std::size_t nv = before.vertex_count();
    std::vector<std::array<std::uint32_t, 2>> ends(after.vertex_count() - nv);
    for (std::size_t t = 0; t < before.triangle_count(); ++t) {
        const std::uint32_t* c = &before.indices[3 * t];
        const std::uint32_t* mid = &after.indices[12 * t + 9];  // ab, bc, ca
        for (int k = 0; k < 3; ++k) ends[mid[k] - nv] = {c[k], c[(k + 1) % 3]};
    }
    return ends;
}

TEST(Refine, ExtraordinaryWeightsSumToAQuarterAndReproduceLinearFunctions) {
    // With 3/4 at the centre the weights sum to 1; on a regular planar k-gon around the centre
    // the new vertex is the midpoint of the edge (linear precision).
    for (int k = 3; k <= 16; ++k) {
        SCOPED_TRACE("valence " + std::to_string(k));
        const std::vector<double> w = fdmsurf::detail::extraordinary_weights(k);
        ASSERT_EQ(w.size(), std::size_t(k));
        double sum = 0.0, x = 0.0, y = 0.0;
        for (int j = 0; j < k; ++j) {
            const double a = 2.0 * std::numbers::pi * j / k;
            sum += w[j];
            x += w[j] * std::cos(a);
            y += w[j] * std::sin(a);
        }
        EXPECT_NEAR(sum, 0.25, 1e-14);
        EXPECT_NEAR(x, 0.5, 1e-14);
        EXPECT_NEAR(y, 0.0, 1e-14);
    }
    EXPECT_EQ(fdmsurf::detail::extraordinary_weights(3),
              (std::vector<double>{5.0 / 12.0, -1.0 / 12.0, -1.0 / 12.0}));
    EXPECT_EQ(fdmsurf::detail::extraordinary_weights(4),
              (std::vector<double>{3.0 / 8.0, 0.0, -1.0 / 8.0, 0.0}));
    EXPECT_TRUE(fdmsurf::detail::extraordinary_weights(2).empty());
}

TEST(Refine, PlanarLatticeStaysPlanarWithNewVerticesAtMidpoints) {
    // Every rule (8-point inside, 4-point on the boundary, mirrored wing tips near it) has linear
    // precision, so a plane is reproduced exactly, boundary included, except where the boundary
    // turns a corner of the patch: there the 4-point curve rounds the corner, in the plane.
    const Lattice l = lattice(7, 6, 1.0, -2.0, 1.0);
    Mesh m = l.mesh;
    fdmsurf::detail::subdivide_butterfly(m);
    ASSERT_EQ(m.triangle_count(), 4 * l.mesh.triangle_count());
    const auto ends = edge_ends(l.mesh, m);
    const std::uint32_t corners[4] = {l.at(0, 0), l.at(6, 0), l.at(0, 5), l.at(6, 5)};
    auto at_corner = [&](std::uint32_t v) { return std::count(corners, corners + 4, v) > 0; };
    int exact = 0;
    for (std::size_t e = 0; e < ends.size(); ++e) {
        const Vec3 a = vertex(l.mesh, ends[e][0]), b = vertex(l.mesh, ends[e][1]);
        const Vec3 p = vertex(m, l.mesh.vertex_count() + e);
        EXPECT_EQ(p[2], 0.0f) << "edge " << e;
        if (at_corner(ends[e][0]) || at_corner(ends[e][1])) continue;
        ++exact;
        for (int k = 0; k < 2; ++k) EXPECT_NEAR(p[k], 0.5 * (a[k] + b[k]), 1e-5) << "edge " << e;
    }
    // Two edges meet at each acute corner, three at each obtuse one.
    EXPECT_EQ(exact, int(ends.size()) - 10);
    for (std::size_t v = 0; v < l.mesh.vertex_count(); ++v)
        EXPECT_EQ(vertex(m, v), vertex(l.mesh, v)) << "old vertex " << v << " moved";
}

// Height fields z = f(x, y) over the lattice; the 8-point stencil (w = 1/16) reproduces
// polynomials up to degree 3 on a regular lattice, so a new vertex between two regular interior
// vertices lies exactly on the graph.
double quadratic(double x, double y) { return 0.3 * x * x - 0.2 * x * y + 0.15 * y * y + x - 2.0; }
double cubic(double x, double y) {
    return 0.05 * x * x * x - 0.04 * x * x * y + 0.03 * x * y * y - 0.02 * y * y * y +
           quadratic(x, y);
}

void expect_height_field_reproduced(double (*f)(double, double), const char* what) {
    SCOPED_TRACE(what);
    Lattice l = lattice(8, 8, 0.5, -2.0, -1.5);
    for (std::size_t v = 0; v < l.mesh.vertex_count(); ++v)
        l.mesh.positions[3 * v + 2] =
            float(f(l.mesh.positions[3 * v], l.mesh.positions[3 * v + 1]));
    Mesh m = l.mesh;
    fdmsurf::detail::subdivide_butterfly(m);
    const auto ends = edge_ends(l.mesh, m);
    int regular = 0;
    double worst_other = 0.0;
    for (std::size_t e = 0; e < ends.size(); ++e) {
        const Vec3 p = vertex(m, l.mesh.vertex_count() + e);
        const double err = std::abs(p[2] - f(p[0], p[1]));
        if (l.interior(ends[e][0]) && l.interior(ends[e][1])) {
            ++regular;
            EXPECT_NEAR(p[2], f(p[0], p[1]), 2e-5) << "regular edge " << e;
        } else {
            worst_other = std::max(worst_other, err);
        }
    }
    std::printf("  %s: %d regular edges exact; largest error elsewhere %.2e\n", what, regular,
                worst_other);
    EXPECT_GT(regular, 50);
}

TEST(Refine, QuadraticHeightFieldIsReproducedAtRegularEdges) {
    expect_height_field_reproduced(quadratic, "quadratic");
}

TEST(Refine, CubicHeightFieldIsReproducedAtRegularEdges) {
    expect_height_field_reproduced(cubic, "cubic");
}

TEST(Refine, IcosphereStaysAClosedManifoldWithFourTimesTheTriangles) {
    // Valence 5 (extraordinary) and 6 vertices, two levels.
    Mesh m = fdmsurf::test::icosphere(2.0, 1);
    const MeshStats s0 = fdmsurf::compute_stats(m);
    std::size_t triangles = m.triangle_count();
    for (int level = 1; level <= 2; ++level) {
        const Mesh before = m;
        fdmsurf::detail::subdivide_butterfly(m);
        triangles *= 4;
        EXPECT_EQ(m.triangle_count(), triangles);
        EXPECT_TRUE(IsClosedManifold(m));
        const MeshStats s = fdmsurf::compute_stats(m);
        EXPECT_EQ(s.euler_characteristic, 2);
        EXPECT_EQ(s.pieces, 1u);
        // V' = V + E, and E = 3F / 2 on a closed triangle mesh.
        EXPECT_EQ(m.vertex_count(), before.vertex_count() + 3 * before.triangle_count() / 2);
        ASSERT_EQ(m.normals.size(), 3 * m.vertex_count());
        for (std::size_t v = 0; v < before.vertex_count(); ++v)
            EXPECT_EQ(vertex(m, v), vertex(before, v));
        // The butterfly bulges towards the sphere: area and volume grow towards the sphere's.
        EXPECT_GT(s.area, s0.area);
        EXPECT_LT(s.area, 4.0 * std::numbers::pi * 4.0);
    }
}

TEST(Refine, OpenMeshKeepsItsBoundaryAndOrientation) {
    // A sphere with three triangles cut out: one boundary loop, extraordinary and regular
    // vertices on it. The boundary doubles its edges; no edge becomes non-manifold or flipped.
    Mesh m = fdmsurf::test::icosphere(2.0, 2);
    for (int i = 0; i < 3; ++i) fdmsurf::test::remove_triangle(m, std::size_t(7 * i));
    const MeshStats s0 = fdmsurf::compute_stats(m);
    ASSERT_GT(s0.boundary_edges, 0u);
    fdmsurf::detail::subdivide_butterfly(m);
    const MeshStats s = fdmsurf::compute_stats(m);
    EXPECT_EQ(s.boundary_edges, 2 * s0.boundary_edges);
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    EXPECT_EQ(s.inconsistent_edges, 0u);
    EXPECT_EQ(s.nonmanifold_vertices, 0u);
    EXPECT_EQ(s.degenerate_triangles, 0u);
    EXPECT_EQ(s.euler_characteristic, s0.euler_characteristic);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3 p = vertex(m, v);
        const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        EXPECT_NEAR(r, 2.0, 0.1) << "vertex " << v;
    }
}

TEST(Refine, NonManifoldAndDegenerateInputDoesNotBreakIt) {
    // Three triangles on one edge, and one triangle that repeats a vertex.
    Mesh m;
    for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0.5, 1, 0}, Vec3{0.5, -1, 0},
                          Vec3{0.5, 0, 1}, Vec3{2, 2, 2}})
        fdmsurf::test::add_vertex(m, p[0], p[1], p[2]);
    m.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4, 5, 5, 2};
    fdmsurf::detail::subdivide_butterfly(m);
    EXPECT_EQ(m.triangle_count(), 16u);
    // The shared edge gets one midpoint used by all three triangles' children.
    const Vec3 mid{0.5, 0, 0};
    int found = 0;
    for (std::size_t v = 6; v < m.vertex_count(); ++v)
        if (vertex(m, v) == mid) ++found;
    EXPECT_EQ(found, 1);
    for (float x : m.positions) EXPECT_TRUE(std::isfinite(x));
}

TEST(Refine, MalformedMeshAndBadLevelsAreRejected) {
    Mesh bad;
    bad.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bad.indices = {0, 1, 7};
    EXPECT_THROW(fdmsurf::detail::subdivide_butterfly(bad), Error);
    Mesh empty;
    EXPECT_NO_THROW(fdmsurf::detail::subdivide_butterfly(empty));
    auto code_of = [](auto&& f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what()) + " [" + fdmsurf::to_string(e.code()) + "]";
        }
        return std::string("no error");
    };
    const std::string negative = code_of([] { fdmsurf::detail::check_refine_levels(-1); });
    EXPECT_NE(negative.find("between 0 and 4 levels (got -1)"), std::string::npos) << negative;
    const std::string five = code_of([] { fdmsurf::detail::check_refine_levels(5); });
    EXPECT_NE(five.find("(got 5)"), std::string::npos) << five;
    EXPECT_NO_THROW(fdmsurf::detail::check_refine_size(2, 4'000'000));
    const std::string big = code_of([] { fdmsurf::detail::check_refine_size(3, 4'000'000); });
    std::printf("  %s\n", big.c_str());
    EXPECT_NE(big.find("refine 3 would turn 4.0 M triangles into 256.0 M"), std::string::npos)
        << big;
    EXPECT_NE(big.find("use --refine 2 (64.0 M triangles)"), std::string::npos) << big;
    EXPECT_NE(big.find("[invalid-argument]"), std::string::npos) << big;
}

// ---------------------------------------------------------------------------------------------
// Projection onto a sampled field: a ball of radius R at c, as the pipeline's density would see
// it, rho = exp(-(|p - c|^2 - R^2) / sigma^2) with sigma = 3 Å, inside where rho >= 1.

struct SphereGrid {
    double radius = 3.0, spacing = 0.5;
    Vec3 center{0.13, -0.21, 0.07}, origin{};
    std::uint32_t n = 0;
    std::vector<float> values;
    SphereGrid(double r, double h) : radius(r), spacing(h) {
        n = std::uint32_t(std::ceil(2.0 * (r + 2.5) / h)) + 1;
        for (double& o : origin) o = -(r + 2.5);
        values.resize(std::size_t(n) * n * n);
        for (std::uint32_t k = 0; k < n; ++k)
            for (std::uint32_t j = 0; j < n; ++j)
                for (std::uint32_t i = 0; i < n; ++i) {
                    const double p[3] = {origin[0] + h * i - center[0],
                                         origin[1] + h * j - center[1],
                                         origin[2] + h * k - center[2]};
                    const double d2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
                    values[(std::size_t(k) * n + j) * n + i] = float(std::exp(-(d2 - r * r) / 9.0));
                }
    }
    Mesh marching_cubes() const {
        fdmsurf::detail::McParams p;
        for (int a = 0; a < 3; ++a) p.origin[a] = float(origin[a]);
        p.spacing = float(spacing);
        p.iso = 1.0f;
        p.z_end = n - 1;
        return fdmsurf::detail::marching_cubes_cpu({values.data(), n, n, n, n}, p);
    }
    GridField field(GridInterpolation interpolation) const {
        return GridField(values.data(), {n, n, n}, n, origin, spacing, 1.0, -1.0, interpolation);
    }
    // RMS and largest distance of vertices [first, end) to the sphere.
    std::array<double, 2> distance(const Mesh& m, std::size_t first) const {
        double sum = 0.0, worst = 0.0;
        for (std::size_t v = first; v < m.vertex_count(); ++v) {
            const Vec3 p = vertex(m, v);
            const double d =
                std::abs(std::hypot(p[0] - center[0], p[1] - center[1], p[2] - center[2]) - radius);
            sum += d * d;
            worst = std::max(worst, d);
        }
        return {std::sqrt(sum / double(m.vertex_count() - first)), worst};
    }
};

TEST(Refine, ProjectionPutsNewVerticesOnTheSphereMuchCloserThanButterflyAlone) {
    const SphereGrid grid(3.0, 0.5);
    const Mesh mc = grid.marching_cubes();
    ASSERT_TRUE(IsClosedManifold(mc));
    const auto [mc_rms, mc_max] = grid.distance(mc, 0);
    std::printf("  marching cubes, h 0.5: %zu triangles, vertices to sphere rms %.5f max %.5f Å\n",
                mc.triangle_count(), mc_rms, mc_max);
    const ProjectOptions options = fdmsurf::detail::project_options_for_spacing(grid.spacing);
    for (int levels = 1; levels <= 2; ++levels) {
        Mesh butterfly = mc;
        fdmsurf::detail::refine_mesh(butterfly, levels, nullptr, options);
        const auto [b_rms, b_max] = grid.distance(butterfly, mc.vertex_count());
        const GridField field = grid.field(GridInterpolation::CatmullRom);
        Mesh projected = mc;
        const auto stats = fdmsurf::detail::refine_mesh(projected, levels, &field, options);
        const auto [p_rms, p_max] = grid.distance(projected, mc.vertex_count());
        std::printf(
            "  refine %d: %zu triangles; new vertices to sphere: butterfly rms %.5f max %.5f, "
            "projected rms %.5f max %.5f Å (%zu projected, %zu not)\n",
            levels, projected.triangle_count(), b_rms, b_max, p_rms, p_max,
            stats.projection.projected, stats.projection.failed());
        EXPECT_EQ(projected.triangle_count(), mc.triangle_count() << (2 * levels));
        EXPECT_TRUE(IsClosedManifold(projected));
        EXPECT_EQ(fdmsurf::compute_stats(projected).euler_characteristic, 2);
        EXPECT_EQ(stats.projection.failed(), 0u);
        EXPECT_LT(p_rms, 0.1 * b_rms);
        EXPECT_LT(p_max, 0.2 * b_max);
        // Normals from the field's gradient: the sphere's radial direction.
        double worst_angle = 0.0;
        for (std::size_t v = 0; v < projected.vertex_count(); ++v) {
            const Vec3 p = vertex(projected, v);
            const Vec3 r{p[0] - grid.center[0], p[1] - grid.center[1], p[2] - grid.center[2]};
            const double len = std::hypot(r[0], r[1], r[2]);
            double c = 0.0;
            for (int a = 0; a < 3; ++a) c += r[a] / len * projected.normals[3 * v + a];
            worst_angle = std::max(worst_angle, std::acos(std::min(1.0, c)));
        }
        EXPECT_LT(worst_angle, 0.02) << "radians";
    }
}

// Triangles whose geometric normal points away from the sphere's centre: folds.
std::size_t folded_on_sphere(const Mesh& m, const Vec3& center) {
    std::size_t folded = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const Vec3 a = vertex(m, m.indices[3 * t]), b = vertex(m, m.indices[3 * t + 1]),
                   c = vertex(m, m.indices[3 * t + 2]);
        const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]},
            w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const Vec3 g{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                     u[0] * w[1] - u[1] * w[0]};
        const Vec3 r{a[0] - center[0], a[1] - center[1], a[2] - center[2]};
        if (g[0] * r[0] + g[1] * r[1] + g[2] * r[2] < 0.0) ++folded;
    }
    return folded;
}

TEST(Refine, MarchingCubesSliversFoldTheFullStencilButNotTheNormalOffset) {
    // Marching cubes makes sliver triangles (a vertex near a grid point); the full butterfly
    // point of a short edge lands tangentially farther away than the edge is long and folds the
    // new triangles over. Keeping only the offset along the normal (what refine_mesh does) puts
    // each new vertex over its edge's midpoint, and projection along that normal keeps it there.
    const SphereGrid grid(3.0, 0.5);
    const Mesh mc = grid.marching_cubes();
    ASSERT_EQ(folded_on_sphere(mc, grid.center), 0u);
    Mesh full = mc, normal = mc;
    fdmsurf::detail::subdivide_butterfly(full, fdmsurf::detail::ButterflyOffset::Full);
    fdmsurf::detail::subdivide_butterfly(normal, fdmsurf::detail::ButterflyOffset::Normal);
    const GridField field = grid.field(GridInterpolation::CatmullRom);
    Mesh projected = mc;
    fdmsurf::detail::refine_mesh(projected, 2, &field,
                                 fdmsurf::detail::project_options_for_spacing(grid.spacing));
    const std::size_t f_full = folded_on_sphere(full, grid.center);
    std::printf(
        "  folded triangles of %zu: full stencil %zu, normal offset %zu, refine 2 "
        "projected %zu of %zu\n",
        full.triangle_count(), f_full, folded_on_sphere(normal, grid.center),
        folded_on_sphere(projected, grid.center), projected.triangle_count());
    EXPECT_GT(f_full, 0u);
    EXPECT_EQ(folded_on_sphere(normal, grid.center), 0u);
    EXPECT_EQ(folded_on_sphere(projected, grid.center), 0u);
}

TEST(Refine, CatmullRomBeatsTrilinearInterpolationOfTheField) {
    // The spline's level set is closer to the sphere than the trilinear one's, whose gradient
    // also jumps across cell faces (Newton then stalls more often).
    const SphereGrid grid(3.0, 1.0);
    const Mesh mc = grid.marching_cubes();
    const ProjectOptions options = fdmsurf::detail::project_options_for_spacing(grid.spacing);
    std::array<double, 3> rms{};
    const GridInterpolation kinds[3] = {GridInterpolation::Trilinear,
                                        GridInterpolation::TrilinearGradient,
                                        GridInterpolation::CatmullRom};
    const char* names[3] = {"trilinear", "trilinear value, interpolated central differences",
                            "Catmull-Rom"};
    for (int i = 0; i < 3; ++i) {
        const GridField field = grid.field(kinds[i]);
        Mesh m = mc;
        const auto stats = fdmsurf::detail::refine_mesh(m, 1, &field, options);
        rms[i] = grid.distance(m, mc.vertex_count())[0];
        std::printf("  h 1.0, %s: new vertices to sphere rms %.5f Å, %zu of %zu not projected\n",
                    names[i], rms[i], stats.projection.failed(), stats.new_vertices);
    }
    EXPECT_LT(rms[2], 0.5 * rms[0]);
    EXPECT_LT(rms[2], 0.5 * rms[1]);
}

TEST(Refine, ProjectionKeepsButterflyPositionWhereTheFieldIsUndefined) {
    // A field whose grid does not reach the mesh: nothing moves, and nothing fails.
    const SphereGrid grid(3.0, 0.5);
    const Mesh mc = grid.marching_cubes();
    std::vector<float> far(64, 0.0f);
    const GridField nowhere(far.data(), {4, 4, 4}, 4, Vec3{100, 100, 100}, 0.5, 1.0, -1.0,
                            GridInterpolation::CatmullRom);
    const ProjectOptions options = fdmsurf::detail::project_options_for_spacing(0.5);
    Mesh butterfly = mc, projected = mc;
    fdmsurf::detail::refine_mesh(butterfly, 1, nullptr, options);
    const auto stats = fdmsurf::detail::refine_mesh(projected, 1, &nowhere, options);
    EXPECT_EQ(projected.positions, butterfly.positions);
    EXPECT_EQ(stats.projection.outside_field, stats.new_vertices);
    EXPECT_EQ(stats.projection.projected, 0u);
}

TEST(Refine, PowerDistanceFieldProjectsOntoTheBallsExactly) {
    // The vdw surface of two overlapping balls as the pipeline makes it: marching cubes of the
    // density T exp(-pi / sigma^2) with crossings at the roots of pi, so on the spheres. Refined
    // and projected onto the power distance, every new vertex is on the union's surface too.
    fdmsurf::Atoms atoms;
    atoms.xyz = {0.1f, 0.2f, 0.3f, 1.5f, 1.6f, 1.1f};
    atoms.radius = {1.8f, 1.7f};
    auto power = [&](const Vec3& p) {
        double pi = 1e30;
        for (int i = 0; i < 2; ++i) {
            const double dx = p[0] - atoms.xyz[3 * i], dy = p[1] - atoms.xyz[3 * i + 1],
                         dz = p[2] - atoms.xyz[3 * i + 2];
            pi = std::min(pi,
                          dx * dx + dy * dy + dz * dz - double(atoms.radius[i]) * atoms.radius[i]);
        }
        return pi;
    };
    const double h = 0.5;
    const std::uint32_t n = 20;
    const Vec3 origin{-4.0, -4.0, -4.0};
    std::vector<float> rho(std::size_t(n) * n * n);
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i)
                rho[(std::size_t(k) * n + j) * n + i] = float(std::exp(
                    -power({origin[0] + h * i, origin[1] + h * j, origin[2] + h * k}) / 9.0));
    fdmsurf::detail::McParams p;
    for (int a = 0; a < 3; ++a) p.origin[a] = float(origin[a]);
    p.spacing = float(h);
    p.iso = 1.0f;
    p.z_end = n - 1;
    p.power_sigma2 = 9.0f;
    Mesh m = fdmsurf::detail::marching_cubes_cpu({rho.data(), n, n, n, n}, p);
    ASSERT_TRUE(IsClosedManifold(m));
    const std::size_t old_count = m.vertex_count();

    const fdmsurf::detail::PowerDistanceField field(atoms, 0.0, 0.0);
    double value = 0.0;
    Vec3 g;
    ASSERT_TRUE(field.sample({0.1, 0.2, 2.2}, value, g));
    EXPECT_NEAR(value, 1.9 * 1.9 - 1.8 * 1.8, 1e-5);
    EXPECT_NEAR(g[2], 2.0 * 1.9, 1e-5);
    EXPECT_FALSE(field.sample({50.0, 0.0, 0.0}, value, g)) << "far from every atom";

    Mesh butterfly = m;
    fdmsurf::detail::refine_mesh(butterfly, 1, nullptr,
                                 fdmsurf::detail::project_options_for_spacing(h));
    const auto stats =
        fdmsurf::detail::refine_mesh(m, 1, &field, fdmsurf::detail::project_options_for_spacing(h));
    EXPECT_TRUE(IsClosedManifold(m));
    EXPECT_EQ(stats.projection.failed(), 0u);
    // Distance of a point to the union's surface: | |p - c| - r | for the ball of least power.
    auto off_surface = [&](const Vec3& q) {
        double best = 1e30, d = 0.0;
        for (int i = 0; i < 2; ++i) {
            const double r = std::hypot(q[0] - atoms.xyz[3 * i], q[1] - atoms.xyz[3 * i + 1],
                                        q[2] - atoms.xyz[3 * i + 2]);
            const double pi = r * r - double(atoms.radius[i]) * atoms.radius[i];
            if (pi < best) {
                best = pi;
                d = std::abs(r - atoms.radius[i]);
            }
        }
        return d;
    };
    EXPECT_LT(std::abs(power(vertex(m, 0))), 1e-4) << "marching cubes puts vertices on the balls";
    double worst = 0.0, worst_butterfly = 0.0;
    for (std::size_t v = old_count; v < m.vertex_count(); ++v) {
        worst = std::max(worst, off_surface(vertex(m, v)));
        worst_butterfly = std::max(worst_butterfly, off_surface(vertex(butterfly, v)));
    }
    std::printf(
        "  two balls, h 0.5: new vertices off the surface: butterfly %.4f Å, projected "
        "%.6f Å\n",
        worst_butterfly, worst);
    EXPECT_LT(worst, 1e-5);
}

}  // namespace
