// Tests of GPU marching cubes (src/isosurface/marching_cubes_gpu.cpp, shaders/mc_*.comp) against
// the CPU reference marching_cubes_cpu, which fixes the order and values of its output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Mesh;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::FieldView;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::marching_cubes_cpu;
using fdmsurf::detail::McParams;
using fdmsurf::detail::plan_grid;

using fdmsurf::test::data_path;

// Tolerances: both sides evaluate the same float expressions in the same order, but the GPU
// compiler may contract a * b + c into an fma and its sqrt / division may differ by an ulp.
constexpr double kPositionTol = 1e-4;  // Å
constexpr double kNormalTol = 1e-3;    // per component of a unit normal

struct Diff {
    double position = 0.0;  // max |gpu - cpu| over coordinates, Å
    double normal = 0.0;    // max over normal components
};

// Same counts, same index buffer, positions and normals within tolerance.
Diff expect_same_mesh(const Mesh& gpu, const Mesh& cpu) {
    Diff diff;
    EXPECT_EQ(gpu.vertex_count(), cpu.vertex_count());
    EXPECT_EQ(gpu.triangle_count(), cpu.triangle_count());
    EXPECT_EQ(gpu.normals.size(), gpu.positions.size());
    EXPECT_EQ(cpu.normals.size(), cpu.positions.size());
    if (gpu.positions.size() != cpu.positions.size() || gpu.indices.size() != cpu.indices.size() ||
        gpu.normals.size() != cpu.normals.size())
        return diff;
    std::size_t first_index = cpu.indices.size();
    for (std::size_t i = 0; i < cpu.indices.size() && first_index == cpu.indices.size(); ++i)
        if (gpu.indices[i] != cpu.indices[i]) first_index = i;
    EXPECT_EQ(first_index, cpu.indices.size())
        << "index buffers differ first at index " << first_index << " (triangle " << first_index / 3
        << ")";
    for (std::size_t i = 0; i < cpu.positions.size(); ++i) {
        diff.position =
            std::max(diff.position, double(std::abs(gpu.positions[i] - cpu.positions[i])));
        diff.normal = std::max(diff.normal, double(std::abs(gpu.normals[i] - cpu.normals[i])));
    }
    // NaN-proof: a NaN coordinate makes the comparison false.
    EXPECT_TRUE(diff.position <= kPositionTol) << "max position difference " << diff.position;
    EXPECT_TRUE(diff.normal <= kNormalTol) << "max normal difference " << diff.normal;
    std::printf("  %zu vertices, %zu triangles: max position diff %.3g A, max normal diff %.3g\n",
                cpu.vertex_count(), cpu.triangle_count(), diff.position, diff.normal);
    return diff;
}

// A host field with its view and the McParams of its whole range.
struct Field {
    std::vector<float> values;
    std::uint32_t nx = 0, ny = 0, nz = 0, pitch = 0;
    McParams params;
    FieldView view() const { return FieldView{values.data(), nx, ny, nz, pitch}; }
};

// The analytic field of one ball: T exp(-(|p - c|² - r²) / σ²), T = 1 on the sphere of radius r.
// Odd sizes and a pitch beyond nx whose padding holds garbage that must never be read.
Field sphere_field() {
    Field f;
    f.nx = 37;
    f.ny = 41;
    f.nz = 33;
    f.pitch = 40;
    f.params.spacing = 0.4f;
    f.params.origin[0] = -7.2f;
    f.params.origin[1] = -8.0f;
    f.params.origin[2] = -6.4f;
    f.params.iso = 1.0f;
    f.params.z_begin = 0;
    f.params.z_end = f.nz - 1;
    const double c[3] = {0.13, -0.21, 0.07}, r = 4.5, sigma2 = 9.0;
    f.values.assign(std::size_t(f.pitch) * f.ny * f.nz, 1e30f);
    for (std::uint32_t z = 0; z < f.nz; ++z)
        for (std::uint32_t y = 0; y < f.ny; ++y)
            for (std::uint32_t x = 0; x < f.nx; ++x) {
                const double p[3] = {f.params.origin[0] + f.params.spacing * x,
                                     f.params.origin[1] + f.params.spacing * y,
                                     f.params.origin[2] + f.params.spacing * z};
                double d2 = 0.0;
                for (int a = 0; a < 3; ++a) d2 += (p[a] - c[a]) * (p[a] - c[a]);
                f.values[(std::size_t(z) * f.ny + y) * f.pitch + x] =
                    float(std::exp(-(d2 - r * r) / sigma2));
            }
    return f;
}

class MarchingCubesGpu : public GpuTest {
protected:
    // The filtered crambin field at 0.5 Å, computed once for the suite.
    static const Field& crambin() {
        static const Field field = [] {
            const fdmsurf::Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
            const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = 0.5f});
            Field f;
            f.values = impl().compute_field(atoms, plan, true);
            f.nx = plan.info.dims[0];
            f.ny = plan.info.dims[1];
            f.nz = plan.info.dims[2];
            f.pitch = plan.pitch;
            for (int a = 0; a < 3; ++a) f.params.origin[a] = plan.info.origin[a];
            f.params.spacing = plan.info.spacing;
            f.params.iso = plan.iso;
            f.params.z_begin = 0;
            f.params.z_end = f.nz - 1;
            return f;
        }();
        return field;
    }

    Mesh compare(const Field& f, const McParams& p) {
        const Mesh gpu = impl().run_marching_cubes(f.view(), p);
        const Mesh cpu = marching_cubes_cpu(f.view(), p);
        expect_same_mesh(gpu, cpu);
        return gpu;
    }
};

TEST_F(MarchingCubesGpu, MatchesCpuOnSphereField) {
    const Field f = sphere_field();
    const Mesh gpu = compare(f, f.params);
    EXPECT_GT(gpu.triangle_count(), 1000u);
    EXPECT_TRUE(IsClosedManifold(gpu));
    const fdmsurf::MeshStats s = fdmsurf::compute_stats(gpu);
    EXPECT_EQ(s.pieces, 1u);
    // A loose sanity check of the geometry (r = 4.5 Å at h = 0.4 Å).
    EXPECT_NEAR(s.area, 4.0 * std::numbers::pi * 4.5 * 4.5,
                0.02 * 4.0 * std::numbers::pi * 4.5 * 4.5);
}

TEST_F(MarchingCubesGpu, MatchesCpuOnSphereSlabs) {
    const Field f = sphere_field();
    // Two slabs that meet at plane 15 (through the sphere), and a slab touching neither border.
    for (auto [b, e] : {std::pair<std::uint32_t, std::uint32_t>{0, 15}, {15, f.nz - 1}, {9, 23}}) {
        SCOPED_TRACE("z " + std::to_string(b) + ".." + std::to_string(e));
        McParams p = f.params;
        p.z_begin = b;
        p.z_end = e;
        const Mesh gpu = compare(f, p);
        EXPECT_GT(gpu.triangle_count(), 0u);
    }
}

TEST_F(MarchingCubesGpu, MatchesCpuOnSinglePlaneSlab) {
    // z_begin == z_end: no cells, only the vertices on the plane's x and y edges.
    const Field f = sphere_field();
    McParams p = f.params;
    p.z_begin = p.z_end = 16;
    const Mesh gpu = compare(f, p);
    EXPECT_EQ(gpu.triangle_count(), 0u);
}

TEST_F(MarchingCubesGpu, MatchesCpuOnFilteredCrambin) {
    const Field& f = crambin();
    const Mesh gpu = compare(f, f.params);
    EXPECT_GT(gpu.triangle_count(), 10000u);
    EXPECT_TRUE(IsClosedManifold(gpu));
}

TEST_F(MarchingCubesGpu, MatchesCpuOnFilteredCrambinSlab) {
    const Field& f = crambin();
    McParams p = f.params;
    p.z_begin = f.nz / 3;
    p.z_end = 2 * f.nz / 3;
    const Mesh gpu = compare(f, p);
    EXPECT_GT(gpu.triangle_count(), 0u);
}

TEST_F(MarchingCubesGpu, EmptyFieldGivesEmptyMesh) {
    Field f;
    f.nx = 9;
    f.ny = 8;
    f.nz = 7;
    f.pitch = 9;
    f.values.assign(std::size_t(f.pitch) * f.ny * f.nz, 0.0f);
    f.params.iso = 1.0f;
    f.params.z_end = f.nz - 1;
    const Mesh gpu = compare(f, f.params);
    EXPECT_EQ(gpu.vertex_count(), 0u);
    EXPECT_EQ(gpu.triangle_count(), 0u);
}

// Noise around the iso-level: nearly every cell is crossed, so segments (32-point words of a
// row) carry close to their maximum of vertices and triangles and every run (kMcRun segments)
// its largest local offsets. Row lengths on, just past and just short of a word boundary, and
// the shortest rows (2 and 3 points: one cell or two).
TEST_F(MarchingCubesGpu, MatchesCpuOnNoiseAtWordBoundaries) {
    for (std::uint32_t nx : {64u, 33u, 95u, 32u, 31u, 2u, 3u}) {
        SCOPED_TRACE("nx " + std::to_string(nx));
        Field f;
        f.nx = nx;
        f.ny = 23;
        f.nz = 9;
        f.pitch = nx + 3;
        f.params.spacing = 0.5f;
        f.params.iso = 0.5f;
        f.params.z_begin = 0;
        f.params.z_end = f.nz - 1;
        f.values.assign(std::size_t(f.pitch) * f.ny * f.nz, 1e30f);
        std::uint32_t state = 12345u + nx;
        for (std::uint32_t z = 0; z < f.nz; ++z)
            for (std::uint32_t y = 0; y < f.ny; ++y)
                for (std::uint32_t x = 0; x < f.nx; ++x) {
                    state = state * 1664525u + 1013904223u;
                    f.values[(std::size_t(z) * f.ny + y) * f.pitch + x] =
                        float(state >> 8) / float(1u << 24);
                }
        const Mesh gpu = compare(f, f.params);
        // About 3 triangles per cell on average (3.2 measured at nx = 64).
        const std::size_t cells = std::size_t(f.nx - 1) * (f.ny - 1) * (f.nz - 1);
        EXPECT_GT(gpu.triangle_count(), 2 * cells);
    }
}

}  // namespace
