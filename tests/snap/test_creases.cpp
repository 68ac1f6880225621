// Tests of crease recovery (src/snap/creases.cpp) on the CPU marching cubes of unions of one,
// two and three balls, as the engine meshes vdw and sas: every vertex on the balls' boundary,
// each crease a closed polyline of mesh edges on its circle, each exposed three-sphere point a
// vertex, a closed consistently oriented manifold, and area and volume against closed forms
// (spheres less their exposed caps, Gauss-Bonnet for two caps that overlap) and Monte Carlo.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "snap/creases.hpp"
#include "support/ball_union.hpp"
#include "support/mesh_checks.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::Mesh;
using fdmsurf::detail::BallUnion;
using fdmsurf::detail::CreaseOptions;
using fdmsurf::detail::CreaseStats;
using fdmsurf::detail::recover_creases;
using fdmsurf::test::Ball;
using fdmsurf::test::circle_radius;
using fdmsurf::test::dot3;
using fdmsurf::test::norm3;
using fdmsurf::test::OnSpheres;
using fdmsurf::test::share_sphere;
using fdmsurf::test::spheres_of;
using fdmsurf::test::sub3;
using fdmsurf::test::union_area;
using fdmsurf::test::union_volume;
using V = std::array<double, 3>;

constexpr double kPi = std::numbers::pi;
// Positions are floats: a vertex placed exactly lands within about 1e-6 Å at these coordinates.
constexpr double kOnTolerance = 1e-5;

// Bounds on the relative area and volume errors with the default chord tolerance h / 50, set
// from the measured chord deficit of balls of radius 1.6-1.8 Å (one ball of 1.8 Å: area -0.43%,
// volume -0.85% at 0.5 Å; -0.17%, -0.40% at 0.25 Å; the two- and three-ball cases alike).
double area_bound(double h) { return h > 0.3 ? 0.006 : 0.0025; }
double volume_bound(double h) { return h > 0.3 ? 0.012 : 0.005; }

V sub(const V& a, const V& b) { return sub3(a, b); }
double dot(const V& a, const V& b) { return dot3(a, b); }
double norm(const V& a) { return norm3(a); }
V cross(const V& a, const V& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Atoms atoms_of(const std::vector<Ball>& balls) {
    Atoms a;
    for (const Ball& b : balls) {
        a.xyz.insert(a.xyz.end(), {float(b.c[0]), float(b.c[1]), float(b.c[2])});
        a.radius.push_back(float(b.r));
        a.element.push_back("C");
    }
    return a;
}

// The engine's vdw field, T exp(-pi / sigma^2) with T = 1 and sigma = 3 Å, pi the least power
// distance, meshed at level T by the CPU marching cubes (vertices on the spheres where one ball
// wins along the edge).
Mesh union_mesh(const std::vector<Ball>& balls, double h) {
    V lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (const Ball& b : balls)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.c[a] - b.r - 2 * h);
            hi[a] = std::max(hi[a], b.c[a] + b.r + 2 * h);
        }
    std::uint32_t n[3];
    for (int a = 0; a < 3; ++a) n[a] = std::uint32_t(std::ceil((hi[a] - lo[a]) / h)) + 1;
    std::vector<float> field(std::size_t{n[0]} * n[1] * n[2]);
    for (std::uint32_t z = 0; z < n[2]; ++z)
        for (std::uint32_t y = 0; y < n[1]; ++y)
            for (std::uint32_t x = 0; x < n[0]; ++x) {
                const V p{lo[0] + h * x, lo[1] + h * y, lo[2] + h * z};
                double pi = 1e30;
                for (const Ball& b : balls) {
                    const V d = sub(p, b.c);
                    pi = std::min(pi, dot(d, d) - b.r * b.r);
                }
                field[(std::size_t(z) * n[1] + y) * n[0] + x] = float(std::exp(-pi / 9.0));
            }
    fdmsurf::detail::FieldView view{field.data(), n[0], n[1], n[2], n[0]};
    fdmsurf::detail::McParams p;
    for (int a = 0; a < 3; ++a) p.origin[a] = float(lo[a]);
    p.spacing = float(h);
    p.iso = 1.0f;
    p.z_begin = 0;
    p.z_end = n[2] - 1;
    p.power_sigma2 = 9.0f;
    p.power_t = 1.0f;
    return fdmsurf::detail::marching_cubes_cpu(view, p);
}

V vertex(const Mesh& m, std::size_t v) {
    return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

struct Measured {
    double area, volume;
    double crease_length;  // edges between vertices of both spheres of a circle, per circle
    std::size_t crease_vertices, corner_vertices;
};

// Checks every vertex is on the boundary and every edge's ends share a sphere; measures.
Measured check_union_mesh(const Mesh& mesh, const std::vector<Ball>& balls) {
    EXPECT_TRUE(IsClosedManifold(mesh));
    const fdmsurf::MeshStats stats = fdmsurf::compute_stats(mesh);
    Measured m{stats.area, stats.volume, 0.0, 0, 0};
    std::vector<OnSpheres> on(mesh.vertex_count());
    std::size_t off = 0, buried = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        on[v] = spheres_of(balls, vertex(mesh, v), kOnTolerance);
        off += on[v].on.empty();
        buried += on[v].buried;
        m.crease_vertices += on[v].on.size() == 2;
        m.corner_vertices += on[v].on.size() == 3;
    }
    EXPECT_EQ(off, 0u) << "vertices on no sphere (within " << kOnTolerance << " Å)";
    EXPECT_EQ(buried, 0u) << "vertices inside a ball";
    std::size_t crossing = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
            if (a > b) continue;
            if (!share_sphere(on[a], on[b])) ++crossing;
            if (on[a].on.size() >= 2 && on[b].on.size() >= 2) {
                // Both ends on a circle: an edge along the crease when they share two spheres.
                int shared = 0;
                for (int i : on[a].on)
                    shared += std::find(on[b].on.begin(), on[b].on.end(), i) != on[b].on.end();
                if (shared >= 2) m.crease_length += norm(sub(vertex(mesh, a), vertex(mesh, b)));
            }
        }
    EXPECT_EQ(crossing, 0u) << "edges across a crease (ends on no common sphere)";
    return m;
}

void expect_rel(double got, double want, double tolerance, const char* what) {
    std::printf("    %s %.4f, exact %.4f, %+.3f%%\n", what, got, want, 100.0 * (got / want - 1.0));
    EXPECT_LE(std::abs(got / want - 1.0), tolerance) << what << " " << got << " vs " << want;
}

CreaseStats recover(Mesh& mesh, const std::vector<Ball>& balls, double tolerance) {
    const BallUnion union_(atoms_of(balls), 0.0, 0.0);
    CreaseOptions o;
    o.chord_tolerance = tolerance;
    return recover_creases(mesh, union_, o);
}

// Radii 1.8 and 1.7 Å, 2.4 Å apart along a diagonal (the engine tests' pair).
std::vector<Ball> two_balls() {
    const double u = 2.4 / std::sqrt(3.0);
    return {{{0.1, 0.2, 0.3}, 1.8}, {{0.1 + u, 0.2 + u, 0.3 + u}, 1.7}};
}

// Three balls whose spheres meet pairwise and in two exposed points (a corner above and one
// below the plane of the centres).
std::vector<Ball> three_balls() {
    return {{{0.13, 0.21, -0.17}, 1.7}, {{2.53, 0.31, 0.09}, 1.6}, {{1.21, 2.12, 0.23}, 1.8}};
}

TEST(Creases, OneBallVerticesOnTheSphereAndChordsWithinTolerance) {
    const std::vector<Ball> balls{{{0.3, -0.7, 1.1}, 1.8}};
    for (const double h : {0.5, 0.25}) {
        Mesh mesh = union_mesh(balls, h);
        const double before = fdmsurf::compute_stats(mesh).area;
        const double tol = h / 50.0;
        const CreaseStats s = recover(mesh, balls, tol);
        std::printf("  one ball, h %.2f: %zu triangles, %zu chord splits\n", h,
                    mesh.triangle_count(), s.chord_splits);
        const Measured m = check_union_mesh(mesh, balls);
        EXPECT_EQ(s.crease_splits, 0u);
        EXPECT_EQ(m.crease_vertices, 0u);
        // Every edge within the chord tolerance of its arc: sagitta r - sqrt(r^2 - l^2/4).
        double worst = 0.0;
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k) {
                const double l = norm(sub(vertex(mesh, mesh.indices[3 * t + k]),
                                          vertex(mesh, mesh.indices[3 * t + (k + 1) % 3])));
                worst = std::max(worst, 1.8 - std::sqrt(1.8 * 1.8 - l * l / 4.0));
            }
        EXPECT_LE(worst, tol * (1.0 + 1e-6));
        // The chord deficit of the flat triangles, -1.8% at 0.5 Å unsplit, is under half a
        // percent.
        expect_rel(before, 4.0 * kPi * 1.8 * 1.8, 0.05, "area before");
        EXPECT_GT(m.area, before);
        expect_rel(m.area, 4.0 * kPi * 1.8 * 1.8, area_bound(h), "area");
        expect_rel(m.volume, 4.0 / 3.0 * kPi * std::pow(1.8, 3), volume_bound(h), "volume");
    }
}

TEST(Creases, TwoBallsKeepTheirCreaseAsAPolylineOnTheCircle) {
    const std::vector<Ball> balls = two_balls();
    const double exact = union_area(balls);
    const double circle = 2.0 * kPi * circle_radius(balls[0], balls[1]);
    for (const double h : {0.5, 0.25}) {
        std::printf("  two balls, h %.2f:\n", h);
        Mesh plain = union_mesh(balls, h);
        const double before = fdmsurf::compute_stats(plain).area;
        // Creases only (no chord splits): the crease deficit is gone, the chord one remains.
        Mesh creases_only = plain;
        recover(creases_only, balls, 0.0);
        const Measured c = check_union_mesh(creases_only, balls);
        Mesh mesh = plain;
        const CreaseStats s = recover(mesh, balls, h / 50.0);
        const Measured m = check_union_mesh(mesh, balls);
        EXPECT_GT(s.crease_splits + s.snapped, 0u);
        EXPECT_GT(m.crease_vertices, 10u);
        EXPECT_EQ(m.corner_vertices, 0u);
        EXPECT_EQ(s.crossings_left, 0u);
        // The crease is a closed polyline inscribed in its circle: its length is the
        // circumference less the chords' (relative deficit about (edge / circle radius)^2 / 24).
        expect_rel(m.crease_length, circle, 0.003, "crease length");
        expect_rel(before, exact, 0.06, "area, marching cubes");
        expect_rel(c.area, exact, h > 0.3 ? 0.025 : 0.008, "area, creases only");
        EXPECT_GT(c.area, before);
        expect_rel(m.area, exact, area_bound(h), "area");
        const double r1 = 1.8, r2 = 1.7, d = 2.4;
        const double a = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
        const double h1 = r1 - a, h2 = r2 - (d - a);
        const double volume = 4.0 / 3.0 * kPi * (r1 * r1 * r1 + r2 * r2 * r2) -
                              kPi * h1 * h1 * (3.0 * r1 - h1) / 3.0 -
                              kPi * h2 * h2 * (3.0 * r2 - h2) / 3.0;
        expect_rel(m.volume, volume, volume_bound(h), "volume");
    }
}

TEST(Creases, ThreeBallsGetTheirCornerPoints) {
    const std::vector<Ball> balls = three_balls();
    const double exact = union_area(balls);
    const double volume = union_volume(balls, 0.02);
    // The two points where the three spheres meet (exposed: no fourth ball).
    std::vector<V> corners;
    {
        const V e1 = sub(balls[1].c, balls[0].c), e2 = sub(balls[2].c, balls[0].c);
        const double r0 = balls[0].r * balls[0].r;
        const double b1 = 0.5 * (dot(e1, e1) + r0 - balls[1].r * balls[1].r);
        const double b2 = 0.5 * (dot(e2, e2) + r0 - balls[2].r * balls[2].r);
        const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
        const double det = g11 * g22 - g12 * g12;
        const double al = (b1 * g22 - b2 * g12) / det, be = (b2 * g11 - b1 * g12) / det;
        const V y0{al * e1[0] + be * e2[0], al * e1[1] + be * e2[1], al * e1[2] + be * e2[2]};
        const V n = cross(e1, e2);
        const double t = std::sqrt((r0 - dot(y0, y0)) / dot(n, n));
        for (const double s : {t, -t})
            corners.push_back({balls[0].c[0] + y0[0] + s * n[0], balls[0].c[1] + y0[1] + s * n[1],
                               balls[0].c[2] + y0[2] + s * n[2]});
    }
    for (const double h : {0.5, 0.25}) {
        std::printf("  three balls, h %.2f:\n", h);
        Mesh mesh = union_mesh(balls, h);
        const double before = fdmsurf::compute_stats(mesh).area;
        const CreaseStats s = recover(mesh, balls, h / 50.0);
        const Measured m = check_union_mesh(mesh, balls);
        EXPECT_EQ(s.crossings_left, 0u);
        EXPECT_EQ(m.corner_vertices, 2u);
        for (const V& c : corners) {
            double nearest = 1e9;
            for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
                nearest = std::min(nearest, norm(sub(vertex(mesh, v), c)));
            EXPECT_LE(nearest, kOnTolerance)
                << "no vertex at the corner " << c[0] << ", " << c[1] << ", " << c[2];
        }
        const double circles =
            2.0 * kPi *
            (circle_radius(balls[0], balls[1]) + circle_radius(balls[1], balls[2]) +
             circle_radius(balls[0], balls[2]));
        // Only the exposed arcs are creases: less than the full circles.
        EXPECT_LT(m.crease_length, circles);
        expect_rel(before, exact, 0.06, "area, marching cubes");
        expect_rel(m.area, exact, area_bound(h), "area");
        expect_rel(m.volume, volume, volume_bound(h), "volume (Monte Carlo)");
    }
}

TEST(Creases, ThreeBallsInAChainHaveTwoCreasesAndNoCorner) {
    // 0-1 and 1-2 meet, 0 and 2 do not: the caps on ball 1 are apart, the area is closed-form.
    const std::vector<Ball> balls{
        {{0.11, 0.07, 0.19}, 1.7}, {{2.61, 0.4, -0.2}, 1.55}, {{5.0, 0.9, 0.3}, 1.8}};
    const double exact = union_area(balls);
    Mesh mesh = union_mesh(balls, 0.5);
    recover(mesh, balls, 0.01);
    const Measured m = check_union_mesh(mesh, balls);
    EXPECT_EQ(m.corner_vertices, 0u);
    const double circles =
        2.0 * kPi * (circle_radius(balls[0], balls[1]) + circle_radius(balls[1], balls[2]));
    expect_rel(m.crease_length, circles, 0.003, "crease length");
    expect_rel(m.area, exact, area_bound(0.5), "area");
}

TEST(Creases, ZeroToleranceSplitsNoChord) {
    const std::vector<Ball> balls = two_balls();
    Mesh mesh = union_mesh(balls, 0.5);
    const std::size_t vertices = mesh.vertex_count();
    const CreaseStats s = recover(mesh, balls, 0.0);
    EXPECT_EQ(s.chord_splits, 0u);
    EXPECT_EQ(s.projected, vertices);
    EXPECT_EQ(mesh.vertex_count(), vertices + s.crease_splits + s.other_splits + s.corners);
}

TEST(Creases, NormalsAreTheSpheresOrTheirMeanOnACrease) {
    const std::vector<Ball> balls = two_balls();
    Mesh mesh = union_mesh(balls, 0.5);
    recover(mesh, balls, 0.01);
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const V p = vertex(mesh, v);
        const OnSpheres on = spheres_of(balls, p, kOnTolerance);
        V want{0, 0, 0};
        for (int i : on.on) {
            const V d = sub(p, balls[std::size_t(i)].c);
            for (int a = 0; a < 3; ++a) want[a] += d[a] / norm(d);
        }
        const double len = norm(want);
        for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(mesh.normals[3 * v + a], want[a] / len, 1e-4) << "vertex " << v;
    }
}

TEST(Creases, BallsThatDoNotMeetStayApartAndClosed) {
    // A gap of 0.05 Å, under the spacing: whatever marching cubes makes of it stays a closed
    // manifold, every vertex on a sphere.
    const std::vector<Ball> balls{{{0.13, 0.21, 0.37}, 1.7}, {{3.58, 0.21, 0.37}, 1.7}};
    Mesh mesh = union_mesh(balls, 0.5);
    recover(mesh, balls, 0.01);
    EXPECT_TRUE(IsClosedManifold(mesh));
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        EXPECT_FALSE(spheres_of(balls, vertex(mesh, v), kOnTolerance).on.empty()) << "vertex " << v;
}

TEST(Creases, SizeCapStopsTheRoundsAndLeavesAClosedMesh) {
    const std::vector<Ball> balls = two_balls();
    Mesh mesh = union_mesh(balls, 0.5);
    const BallUnion union_(atoms_of(balls), 0.0, 0.0);
    CreaseOptions o;
    o.chord_tolerance = 0.001;
    o.max_triangles = mesh.triangle_count() + 1;
    const CreaseStats s = recover_creases(mesh, union_, o);
    EXPECT_TRUE(s.stopped_at_size);
    EXPECT_EQ(s.rounds, 1);
    EXPECT_TRUE(IsClosedManifold(mesh));
}

TEST(Creases, EmptyMeshAndNoBallsAreLeftAlone) {
    Mesh empty;
    const BallUnion none(Atoms{}, 0.0, 0.0);
    EXPECT_EQ(recover_creases(empty, none, CreaseOptions{}).projected, 0u);
    Mesh mesh = union_mesh(two_balls(), 0.5);
    const Mesh before = mesh;
    recover_creases(mesh, none, CreaseOptions{});
    EXPECT_EQ(mesh.positions, before.positions);
    EXPECT_EQ(mesh.indices, before.indices);
}

}  // namespace
