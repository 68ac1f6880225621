// fitted_curvature (quadric fit, Goldfeather & Interrante 2004), the estimator behind the
// curvature properties: analytic torus, and marching-cubes spheres from the engine, where the
// cotangent estimator (vertex_curvature) is thrown off by slivers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fdmsurf/fdmsurf.hpp"
#include "mesh/mesh_shapes.hpp"
#include "properties/curvature.hpp"
#include "support/gpu_fixture.hpp"

using namespace fdmsurf;
using namespace fdmsurf::detail;

namespace {

double median(std::vector<float> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

}  // namespace

TEST(FittedCurvature, TorusEquators) {
    const double big_r = 10.0, r = 3.0;
    const int nu = 240, nv = 72;
    Mesh mesh = test::torus(big_r, r, nu, nv);
    mesh.normals.clear();
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
            mesh.normals.insert(mesh.normals.end(),
                                {float(std::cos(v) * std::cos(u)), float(std::cos(v) * std::sin(u)),
                                 float(std::sin(v))});
        }
    const VertexCurvature c = fitted_curvature(mesh, 1.0f);
    const double k_outer = 1.0 / (r * (big_r + r)), k_inner = -1.0 / (r * (big_r - r));
    const double h_outer = (big_r + 2 * r) / (2 * r * (big_r + r));
    const double h_inner = (big_r - 2 * r) / (2 * r * (big_r - r));
    double worst = 0.0;
    for (int i = 0; i < nu; ++i) {
        const std::size_t o = std::size_t(i) * nv, n = std::size_t(i) * nv + nv / 2;
        worst = std::max({worst, std::abs(c.gaussian[o] / k_outer - 1),
                          std::abs(c.gaussian[n] / k_inner - 1), std::abs(c.mean[o] / h_outer - 1),
                          std::abs(c.mean[n] / h_inner - 1)});
    }
    std::printf("fitted curvature, torus R=10 r=3: worst relative error on the equators %.2e\n",
                worst);
    // The fit over a 1 Å disc is biased by O((1 Å / 3 Å)²) terms the quadric cannot hold:
    // measured 2.6% at worst (H at the inner equator).
    EXPECT_LT(worst, 0.03);
}

class FittedCurvatureGpu : public GpuTest {};

TEST_F(FittedCurvatureGpu, MarchingCubesSpheresThroughTheProperties) {
    for (float radius : {3.0f, 5.0f}) {
        Atoms atoms;
        atoms.xyz = {1.0f, 2.0f, 3.0f};
        atoms.radius = {radius};
        SurfaceOptions o;
        o.surface = SurfaceKind::Vdw;
        // Marching cubes' own vertices (snap off): the bounds below are the fit's on that vertex
        // layout; the snapped mesh (chord splits, the default since issue 13) is checked after.
        o.snap = false;
        o.properties.scalars = {VertexProperty::MeanCurvature, VertexProperty::GaussianCurvature,
                                VertexProperty::ShapeIndex};
        const Mesh m = engine().make_surface(atoms, o).mesh;
        ASSERT_EQ(m.scalars.size(), 3u);
        const double h = median(m.scalars[0].values), k = median(m.scalars[1].values);
        std::size_t cap = 0, worst_h = 0;
        for (std::size_t v = 0; v < m.vertex_count(); ++v) {
            cap += m.scalars[2].values[v] > 0.99f;
            worst_h += std::abs(m.scalars[0].values[v] * radius - 1.0) > 0.05;
        }
        std::printf(
            "marching-cubes sphere r=%.0f: median H %.5f (1/r %.5f), K %.5f (%.5f), "
            "%zu of %zu vertices with |H r - 1| > 5%%\n",
            radius, h, 1.0 / radius, k, 1.0 / (radius * radius), worst_h, m.vertex_count());
        EXPECT_NEAR(h * radius, 1.0, 0.02);
        EXPECT_NEAR(k * radius * radius, 1.0, 0.04);
        EXPECT_EQ(worst_h, 0u);
        EXPECT_EQ(cap, m.vertex_count());
        // The cotangent estimator on the same mesh: right on average, far off at slivers.
        const VertexCurvature meyer = vertex_curvature(m);
        double spread = 0.0;
        for (float value : meyer.mean) spread = std::max(spread, std::abs(value * radius - 1.0));
        EXPECT_GT(spread, 0.05);
        // Snapped: the chord splits' vertices are placed unevenly (bisected edges next to whole
        // ones), which biases the local fit a little: measured H r 1.021 and K r² 1.042 at
        // r = 3, 1.007 and 1.014 at r = 5.
        o.snap = true;
        const Mesh s = engine().make_surface(atoms, o).mesh;
        const double hs = median(s.scalars[0].values), ks = median(s.scalars[1].values);
        std::printf("  snapped: median H r %.4f, K r^2 %.4f\n", hs * radius, ks * radius * radius);
        EXPECT_NEAR(hs * radius, 1.0, 0.03);
        EXPECT_NEAR(ks * radius * radius, 1.0, 0.06);
    }
}
