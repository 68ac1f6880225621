// Tests of vertex_curvature (Meyer et al. 2003) on analytic meshes: sphere, torus, height fields,
// a flat patch, and the discrete Gauss-Bonnet theorem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "mesh/mesh_shapes.hpp"
#include "properties/curvature.hpp"

namespace fdmsurf {
namespace {

using detail::vertex_curvature;
using detail::vertex_mixed_area;
constexpr double kPi = std::numbers::pi;

struct Summary {
    double mean = 0.0, min = 1e300, max = -1e300;
};

Summary summarise(const std::vector<float>& values) {
    Summary s;
    for (float v : values) {
        s.mean += v;
        s.min = std::min(s.min, double(v));
        s.max = std::max(s.max, double(v));
    }
    s.mean /= double(values.size());
    return s;
}

double total_gaussian_curvature(const Mesh& mesh) {
    const auto c = vertex_curvature(mesh);
    const auto area = vertex_mixed_area(mesh);
    double total = 0.0;
    for (std::size_t v = 0; v < area.size(); ++v) total += double(c.gaussian[v]) * area[v];
    return total;
}

// A square grid of n x n cells of side h in the plane, centred on the origin, lifted to
// z = f(x, y); quads split along alternating diagonals; counter-clockwise from +z. The centre
// vertex is number n / 2 * (n + 1) + n / 2 (n even).
template <typename F>
Mesh height_field(int n, double h, F f) {
    Mesh mesh;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const double x = (i - n / 2) * h, y = (j - n / 2) * h;
            test::add_vertex(mesh, x, y, f(x, y));
        }
    }
    auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            if ((i + j) % 2 == 0) {
                mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1),
                                                         at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                mesh.indices.insert(mesh.indices.end(),
                                    {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j),
                                     at(i + 1, j + 1), at(i, j + 1)});
            }
        }
    }
    return mesh;
}

TEST(VertexCurvature, SphereOfRadius10HasHalfTenthMeanAndHundredthGaussian) {
    // Icosphere of 2,562 vertices (edges about 0.6-0.8 Å), exact sphere normals.
    const Mesh mesh = test::icosphere(10.0, 4);
    const auto c = vertex_curvature(mesh);
    ASSERT_EQ(c.mean.size(), mesh.vertex_count());
    const Summary h = summarise(c.mean), k = summarise(c.gaussian), s = summarise(c.shape_index);
    std::printf(
        "sphere R=10: H mean %.6f [%.6f, %.6f]; K mean %.7f [%.7f, %.7f]; "
        "S mean %.4f min %.4f\n",
        h.mean, h.min, h.max, k.mean, k.min, k.max, s.mean, s.min);
    EXPECT_NEAR(h.mean, 0.1, 0.001);  // 1% on the mean over vertices
    EXPECT_NEAR(h.min, 0.1, 0.003);   // 3% at every vertex
    EXPECT_NEAR(h.max, 0.1, 0.003);
    EXPECT_NEAR(k.mean, 0.01, 0.0002);  // 2%
    EXPECT_NEAR(k.min, 0.01, 0.0006);   // 6% at every vertex
    EXPECT_NEAR(k.max, 0.01, 0.0006);
    EXPECT_GT(s.min, 0.85);
    EXPECT_GT(s.mean, 0.95);
    EXPECT_LE(s.max, 1.0);

    // Without normals: the triangles' normals give the same signs and values.
    Mesh bare = mesh;
    bare.normals.clear();
    const auto b = vertex_curvature(bare);
    EXPECT_EQ(b.mean, c.mean);
    EXPECT_EQ(b.gaussian, c.gaussian);
}

TEST(VertexCurvature, MarchingCubesSphereOfRadius10) {
    // What the pipeline gives the estimator: a marching-cubes mesh (slivers, valences 3-12) of
    // the sphere |p| = 10 at 0.5 Å spacing, from its signed distance, with the gradient normals.
    const std::uint32_t n = 48;
    const double h = 0.5, centre = 0.5 * (n - 1) * h + 0.013;  // off the grid's symmetry
    std::vector<float> field(std::size_t(n) * n * n);
    for (std::uint32_t z = 0; z < n; ++z)
        for (std::uint32_t y = 0; y < n; ++y)
            for (std::uint32_t x = 0; x < n; ++x) {
                field[(std::size_t(z) * n + y) * n + x] =
                    float(10.0 - std::hypot(x * h - centre, y * h - centre, z * h - centre));
            }
    detail::McParams p;
    p.spacing = float(h);
    p.z_end = n - 1;
    const Mesh mesh = detail::marching_cubes_cpu({field.data(), n, n, n, n}, p);
    ASSERT_TRUE(compute_stats(mesh).is_closed_manifold());
    const auto c = vertex_curvature(mesh);
    const auto area = vertex_mixed_area(mesh);
    double total_area = 0.0, h_area = 0.0, k_area = 0.0, h_rms = 0.0;
    for (std::size_t v = 0; v < area.size(); ++v) {
        total_area += area[v];
        h_area += c.mean[v] * area[v];
        k_area += c.gaussian[v] * area[v];
        h_rms += (c.mean[v] - 0.1) * (c.mean[v] - 0.1) * area[v];
    }
    h_rms = std::sqrt(h_rms / total_area);
    const Summary hs = summarise(c.mean), ks = summarise(c.gaussian), ss = summarise(c.shape_index);
    std::size_t convex = 0;
    for (float s : c.shape_index) convex += s > 0.5f;
    std::printf(
        "marching-cubes sphere R=10, h=0.5, %zu vertices: H mean over vertices %.5f, "
        "area-weighted %.5f, rms about 0.1 %.4f; K mean %.6f, area-weighted %.6f; "
        "S mean %.3f, %.1f%% above 0.5\n",
        mesh.vertex_count(), hs.mean, h_area / total_area, h_rms, ks.mean, k_area / total_area,
        ss.mean, 100.0 * double(convex) / double(mesh.vertex_count()));
    std::vector<float> sorted = c.mean;
    std::sort(sorted.begin(), sorted.end());
    auto pct = [&](double q) { return sorted[std::size_t(q * double(sorted.size() - 1))]; };
    std::size_t within10 = 0, within25 = 0;
    for (float v : c.mean) {
        within10 += std::abs(v - 0.1f) < 0.01f;
        within25 += std::abs(v - 0.1f) < 0.025f;
    }
    std::printf(
        "  H percentiles 1/10/50/90/99: %.4f %.4f %.4f %.4f %.4f; within 10%%: %.1f%%, "
        "25%%: %.1f%%\n",
        pct(0.01), pct(0.1), pct(0.5), pct(0.9), pct(0.99),
        100.0 * double(within10) / double(sorted.size()),
        100.0 * double(within25) / double(sorted.size()));
    // The integrals are right; single vertices scatter (the median is right, the 10-90%
    // range is ±35%), so the test bounds the integrals, the median and the shape's sign.
    EXPECT_NEAR(h_area / total_area, 0.1, 0.0005);
    EXPECT_NEAR(k_area, 4 * kPi, 1e-3);  // Gauss-Bonnet: Σ K A = 4π
    EXPECT_NEAR(pct(0.5), 0.1, 0.003);
    EXPECT_GT(double(convex), 0.99 * double(mesh.vertex_count()));

    // Opt-in smoothing: area-weighted means over each vertex's triangles.
    double rms[4] = {};
    for (int passes : {1, 3}) {
        const auto smooth = vertex_curvature(mesh, passes);
        double sum = 0.0, k_sum = 0.0;
        for (std::size_t v = 0; v < area.size(); ++v) {
            sum += (smooth.mean[v] - 0.1) * (smooth.mean[v] - 0.1);
            k_sum += (smooth.gaussian[v] - 0.01) * (smooth.gaussian[v] - 0.01);
        }
        rms[passes] = std::sqrt(sum / double(area.size()));
        std::printf(
            "  %d smoothing pass(es): H rms about 0.1 %.4f, K rms about 0.01 %.5f, S min %.3f\n",
            passes, rms[passes], std::sqrt(k_sum / double(area.size())),
            summarise(smooth.shape_index).min);
    }
    EXPECT_LT(rms[1], 0.02);
    EXPECT_LT(rms[3], 0.008);
}

TEST(VertexCurvature, InsideOutSphereIsAConcaveCup) {
    const Mesh mesh = test::turned_inside_out(test::icosphere(10.0, 4));
    const auto c = vertex_curvature(mesh);
    const Summary h = summarise(c.mean), k = summarise(c.gaussian), s = summarise(c.shape_index);
    EXPECT_NEAR(h.mean, -0.1, 0.001);
    EXPECT_NEAR(k.mean, 0.01, 0.0002);  // K does not depend on the orientation
    EXPECT_LT(s.max, -0.85);
    EXPECT_LT(s.mean, -0.95);
}

TEST(VertexCurvature, TorusMatchesTheEquatorsCurvatures) {
    const double big_r = 10.0, r = 3.0;
    const int nu = 240, nv = 72;  // edges 0.26-0.34 Å along the tube, 0.18-0.34 Å around it
    const Mesh mesh = test::torus(big_r, r, nu, nv);
    const auto c = vertex_curvature(mesh);
    // Vertex (i, j) is number i nv + j, at tube angle 2 pi j / nv: j = 0 outer equator,
    // j = nv / 2 inner equator. Every vertex of an equator has the same neighbourhood.
    auto at = [&](int i, int j) { return std::size_t(i * nv + j); };
    const double k_outer = 1.0 / (r * (big_r + r)), k_inner = -1.0 / (r * (big_r - r));
    const double h_outer = (big_r + 2 * r) / (2 * r * (big_r + r));
    const double h_inner = (big_r - 2 * r) / (2 * r * (big_r - r));
    auto shape = [](double k1, double k2) { return 2 / kPi * std::atan((k1 + k2) / (k1 - k2)); };
    const double s_outer = shape(1 / r, 1 / (big_r + r)), s_inner = shape(1 / r, -1 / (big_r - r));
    double worst[6] = {};
    for (int i = 0; i < nu; ++i) {
        const std::size_t o = at(i, 0), n = at(i, nv / 2);
        const double errors[6] = {c.gaussian[o] / k_outer - 1, c.gaussian[n] / k_inner - 1,
                                  c.mean[o] / h_outer - 1,     c.mean[n] / h_inner - 1,
                                  c.shape_index[o] - s_outer,  c.shape_index[n] - s_inner};
        for (int e = 0; e < 6; ++e) worst[e] = std::max(worst[e], std::abs(errors[e]));
    }
    std::printf(
        "torus R=10 r=3: relative error K outer %.2e inner %.2e, H outer %.2e inner "
        "%.2e; S error outer %.2e inner %.2e\n",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
    EXPECT_LT(worst[0], 0.01);
    EXPECT_LT(worst[1], 0.01);
    EXPECT_LT(worst[2], 0.01);
    EXPECT_LT(worst[3], 0.01);
    EXPECT_LT(worst[4], 0.01);
    EXPECT_LT(worst[5], 0.01);
}

TEST(VertexCurvature, GaussBonnetHoldsOnClosedMeshes) {
    // Σ K_i A_i = Σ (2π - Σθ) = 2π (V - E + F) exactly, whatever the mesh's quality.
    EXPECT_NEAR(total_gaussian_curvature(test::icosphere(10.0, 3)), 4 * kPi, 1e-4);
    EXPECT_NEAR(total_gaussian_curvature(test::icosphere(0.7, 1, {5, 5, 5})), 4 * kPi, 1e-4);
    EXPECT_NEAR(total_gaussian_curvature(test::torus(10.0, 3.0, 60, 20)), 0.0, 1e-4);
    EXPECT_NEAR(total_gaussian_curvature(test::torus(4.0, 3.5, 17, 9)), 0.0, 1e-4);
    Mesh two = test::icosphere(3.0, 2);
    test::append(two, test::turned_inside_out(test::icosphere(1.0, 1)));
    EXPECT_NEAR(total_gaussian_curvature(two), 8 * kPi, 1e-4);
    // Two cones joined at their apex: a pinched vertex, still χ = 3 (V - E + F).
    Mesh cones;
    cones.positions = {0.0f, 0.0f, 0.0f};
    const std::uint32_t apex = 0;
    test::add_cone(cones, apex, 2.0, 1.0, 12);
    test::add_cone(cones, apex, -2.0, 1.0, 12);
    EXPECT_NEAR(total_gaussian_curvature(cones), 2 * kPi * 3, 1e-4);
}

TEST(VertexCurvature, MixedAreasAddUpToTheArea) {
    for (const Mesh& mesh : {test::icosphere(10.0, 3), test::torus(4.0, 3.5, 17, 9)}) {
        double sum = 0.0;
        for (double a : vertex_mixed_area(mesh)) sum += a;
        EXPECT_NEAR(sum, compute_stats(mesh).area, 1e-9 * sum);
    }
}

TEST(VertexCurvature, HeightFieldsGiveCapCupSaddleAtTheCentre) {
    // z = ±a (x² + y²) seen from +z: a cup (k1 = k2 = 2a, concave: S = -1) and a cap; z = a (x²
    // - y²): a saddle (H = 0, K = -4a², S = 0). Small cells: the estimates are of second order.
    const int n = 20;
    const double h = 0.05, a = 0.5;
    const std::uint32_t centre = n / 2 * (n + 1) + n / 2;
    const Mesh cup = height_field(n, h, [a](double x, double y) { return a * (x * x + y * y); });
    const Mesh cap = height_field(n, h, [a](double x, double y) { return -a * (x * x + y * y); });
    const Mesh saddle = height_field(n, h, [a](double x, double y) { return a * (x * x - y * y); });
    const auto c_cup = vertex_curvature(cup), c_cap = vertex_curvature(cap),
               c_saddle = vertex_curvature(saddle);
    std::printf(
        "height fields at the centre: cup H %.5f K %.5f S %.5f; cap H %.5f S %.5f; "
        "saddle H %.5f K %.5f S %.5f\n",
        c_cup.mean[centre], c_cup.gaussian[centre], c_cup.shape_index[centre], c_cap.mean[centre],
        c_cap.shape_index[centre], c_saddle.mean[centre], c_saddle.gaussian[centre],
        c_saddle.shape_index[centre]);
    EXPECT_NEAR(c_cup.mean[centre], -2 * a, 0.01);
    EXPECT_NEAR(c_cup.gaussian[centre], 4 * a * a, 0.02);
    EXPECT_NEAR(c_cup.shape_index[centre], -1.0, 0.05);
    EXPECT_NEAR(c_cap.mean[centre], 2 * a, 0.01);
    EXPECT_NEAR(c_cap.shape_index[centre], 1.0, 0.05);
    EXPECT_NEAR(c_saddle.mean[centre], 0.0, 0.01);
    EXPECT_NEAR(c_saddle.gaussian[centre], -4 * a * a, 0.02);
    EXPECT_NEAR(c_saddle.shape_index[centre], 0.0, 0.01);
}

TEST(VertexCurvature, FlatPatchIsZeroEverywhere) {
    // Border vertices, corners included, take their interior neighbours' zeros.
    const Mesh plane = height_field(8, 0.5, [](double, double) { return 0.0; });
    const auto c = vertex_curvature(plane);
    for (std::size_t v = 0; v < plane.vertex_count(); ++v) {
        EXPECT_NEAR(c.mean[v], 0.0, 1e-6) << v;
        EXPECT_NEAR(c.gaussian[v], 0.0, 1e-5) << v;
        EXPECT_NEAR(c.shape_index[v], 0.0, 1e-6) << v;
    }
}

TEST(VertexCurvature, BorderWithoutInteriorNeighboursKeepsItsHalfRingValues) {
    // One triangle: three border vertices, no interior one. Flat: H = 0; each corner's deficit
    // against a half disc is π - θ over a third of the (equilateral) triangle's area.
    Mesh mesh;
    mesh.positions = {0, 0, 0, 2, 0, 0, 1, float(std::sqrt(3.0)), 0};
    mesh.indices = {0, 1, 2};
    const auto c = vertex_curvature(mesh);
    const double area = std::sqrt(3.0);
    for (int v = 0; v < 3; ++v) {
        EXPECT_NEAR(c.mean[v], 0.0, 1e-6);
        EXPECT_NEAR(c.gaussian[v], (kPi - kPi / 3) / (area / 3), 1e-4);
    }
}

TEST(VertexCurvature, OpenCapKeepsTheSignAndScaleOnItsBorder) {
    // The cap z > 0 of a sphere of radius 10 (a jagged border): interior vertices as on the
    // sphere; border vertices take their interior neighbours' values, whatever the normals.
    // (Their half ring's own estimates would be off by 80% for H with the triangles' normals
    // and by a factor of 800 for K, which the border's zigzag dominates.)
    const Mesh sphere = test::icosphere(10.0, 4);
    Mesh cap;
    cap.positions = sphere.positions;
    cap.normals = sphere.normals;
    for (std::size_t t = 0; t < sphere.triangle_count(); ++t) {
        const std::uint32_t* f = &sphere.indices[3 * t];
        if (sphere.positions[3 * f[0] + 2] > 0 && sphere.positions[3 * f[1] + 2] > 0 &&
            sphere.positions[3 * f[2] + 2] > 0) {
            cap.indices.insert(cap.indices.end(), f, f + 3);
        }
    }
    Mesh bare_cap = cap;
    bare_cap.normals.clear();
    const auto full = vertex_curvature(sphere);
    std::vector<char> used(cap.vertex_count(), 0);
    for (std::uint32_t i : cap.indices) used[i] = 1;
    for (const Mesh* mesh : {&cap, &bare_cap}) {
        const auto c = vertex_curvature(*mesh);
        double worst_border = 0.0, worst_k = 0.0;
        std::size_t border = 0;
        for (std::size_t v = 0; v < cap.vertex_count(); ++v) {
            if (!used[v]) {
                // Unused vertices get zeros.
                EXPECT_EQ(c.mean[v], 0.0f);
                EXPECT_EQ(c.gaussian[v], 0.0f);
                EXPECT_EQ(c.shape_index[v], 0.0f);
                continue;
            }
            if (c.gaussian[v] != full.gaussian[v]) {  // a border vertex
                worst_border = std::max(worst_border, std::abs(c.mean[v] / 0.1 - 1));
                worst_k = std::max(worst_k, std::abs(c.gaussian[v] / 0.01 - 1));
                EXPECT_GT(c.mean[v], 0.0f);
                ++border;
            }
        }
        std::printf(
            "open cap, %s normals: %zu border vertices, H within %.3f%% of 1/R, K within "
            "%.3f%% of 1/R^2\n",
            mesh == &cap ? "exact" : "triangle", border, 100 * worst_border, 100 * worst_k);
        EXPECT_GT(border, 40u);
        EXPECT_LT(worst_border, 0.01);
        EXPECT_LT(worst_k, 0.02);
    }
}

TEST(VertexCurvature, MalformedMeshOrNegativeSmoothingThrowsInvalidArgument) {
    Mesh mesh = test::icosphere(1.0, 1);
    auto code = [](const Mesh& m, int passes) {
        try {
            vertex_curvature(m, passes);
        } catch (const Error& e) {
            return e.code();
        }
        ADD_FAILURE() << "no error";
        return ErrorCode::Internal;
    };
    EXPECT_EQ(code(mesh, -1), ErrorCode::InvalidArgument);
    mesh.indices.push_back(0);
    EXPECT_EQ(code(mesh, 0), ErrorCode::InvalidArgument);
    mesh = test::icosphere(1.0, 1);
    mesh.normals.pop_back();
    EXPECT_EQ(code(mesh, 0), ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace fdmsurf
