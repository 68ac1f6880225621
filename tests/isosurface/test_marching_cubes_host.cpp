// Tests of marching cubes on the host (src/isosurface/marching_cubes_host.cpp): the mesh of the
// CPU reference marching_cubes_cpu, bit for bit (the same arithmetic in the same order), on
// crambin's filtered and unfiltered fields, on noise at the 64-point word boundaries, with the
// planes in separate buffers as the slab pipeline holds them, on any thread count.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/density_cpu.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "isosurface/marching_cubes_host.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"
#include "support/test_fields.hpp"

namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::Mesh;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::FieldView;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::marching_cubes_cpu;
using fdmsurf::detail::marching_cubes_host;
using fdmsurf::detail::McParams;
using fdmsurf::detail::PlaneStack;

using Field = fdmsurf::test::TestField;

void expect_identical(const Mesh& host, const Mesh& cpu) {
    EXPECT_EQ(host.vertex_count(), cpu.vertex_count());
    EXPECT_EQ(host.triangle_count(), cpu.triangle_count());
    // Bit for bit: the same float expressions (mc_vertex) in the same order.
    EXPECT_TRUE(host.positions == cpu.positions);
    EXPECT_TRUE(host.normals == cpu.normals);
    EXPECT_TRUE(host.indices == cpu.indices);
}

// Crambin at 0.5 Å: filtered (the field the slab pipeline marches on a CPU device) or not (vdw).
Field crambin(bool filtered) { return fdmsurf::test::structure_field("1crn.pdb", 0.5f, filtered); }

TEST(MarchingCubesHost, FilteredCrambinIsTheReferenceMesh) {
    const Field f = crambin(true);
    std::vector<float> copy;
    const Mesh host = marching_cubes_host(f.stack(copy, f.nz / 2), f.params);
    const Mesh cpu = marching_cubes_cpu(f.view(), f.params);
    expect_identical(host, cpu);
    EXPECT_GT(host.triangle_count(), 10000u);
    EXPECT_TRUE(IsClosedManifold(host));
    // A slab's cells: planes z_begin .. z_end of a buffer with a plane under and above them.
    McParams slab = f.params;
    slab.z_begin = f.nz / 3;
    slab.z_end = 2 * f.nz / 3;
    const Mesh part = marching_cubes_host(f.stack(copy, slab.z_end), slab);
    expect_identical(part, marching_cubes_cpu(f.view(), slab));
    EXPECT_GT(part.triangle_count(), 0u);
}

TEST(MarchingCubesHost, UnfilteredCrambinWithPowerInterpolationIsTheReferenceMesh) {
    const Field f = crambin(false);
    ASSERT_GT(f.params.power_sigma2, 0.0f);
    std::vector<float> copy;
    const Mesh host = marching_cubes_host(f.stack(copy, 1), f.params);
    expect_identical(host, marching_cubes_cpu(f.view(), f.params));
    EXPECT_GT(host.triangle_count(), 10000u);
}

// Noise about the level: nearly every cell crossed, every bit of the words used. Rows on, just
// past and just short of the 64-point words, the shortest rows, and a single row or column.
Field noise(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz, std::uint32_t seed) {
    return fdmsurf::test::noise_field(nx, ny, nz, seed);
}

TEST(MarchingCubesHost, NoiseAtWordBoundariesIsTheReferenceMesh) {
    for (std::uint32_t nx : {64u, 65u, 63u, 128u, 129u, 127u, 200u, 2u, 3u, 1u}) {
        for (std::uint32_t ny : {1u, 2u, 17u}) {
            SCOPED_TRACE("nx " + std::to_string(nx) + ", ny " + std::to_string(ny));
            const Field f = noise(nx, ny, 7, 777u + nx * 31u + ny);
            std::vector<float> copy;
            const Mesh host = marching_cubes_host(f.stack(copy, 3), f.params);
            expect_identical(host, marching_cubes_cpu(f.view(), f.params));
            if (nx > 1 && ny > 1) {
                EXPECT_GT(host.triangle_count(), 0u);
            }
        }
    }
}

TEST(MarchingCubesHost, SameMeshOnAnyThreadCountAndOnOnePlane) {
    const Field f = noise(150, 40, 30, 4242u);
    std::vector<float> copy;
    const PlaneStack s = f.stack(copy, 11);
    const Mesh one = marching_cubes_host(s, f.params, 1);
    expect_identical(marching_cubes_host(s, f.params, 3), one);
    expect_identical(marching_cubes_host(s, f.params, 16), one);
    expect_identical(one, marching_cubes_cpu(f.view(), f.params));
    // A single plane: its x and y edges' vertices, no cells.
    McParams plane = f.params;
    plane.z_begin = plane.z_end = 29;
    const Mesh flat = marching_cubes_host(s, plane);
    expect_identical(flat, marching_cubes_cpu(f.view(), plane));
    EXPECT_GT(flat.vertex_count(), 0u);
    EXPECT_EQ(flat.triangle_count(), 0u);
}

TEST(MarchingCubesHost, RowPitchPaddingIsIgnored) {
    // The layout of a field read back from the device: rows padded for the FFT, garbage there.
    const Field f = noise(77, 13, 9, 99u);
    const std::uint32_t pitch = 80;
    std::vector<float> padded(std::size_t(pitch) * f.ny * f.nz, 1e30f);
    for (std::size_t row = 0; row < std::size_t(f.ny) * f.nz; ++row)
        std::copy_n(&f.values[row * f.nx], f.nx, &padded[row * pitch]);
    PlaneStack s{{}, f.nx, f.ny, f.nz, pitch};
    for (std::uint32_t z = 0; z < f.nz; ++z)
        s.planes.push_back(padded.data() + std::size_t(z) * f.ny * pitch);
    expect_identical(marching_cubes_host(s, f.params), marching_cubes_cpu(f.view(), f.params));
}

TEST(MarchingCubesHost, EmptyFieldGivesAnEmptyMesh) {
    Field f = noise(70, 9, 8, 1u);
    std::fill(f.values.begin(), f.values.end(), 0.25f);
    std::vector<float> copy;
    const Mesh host = marching_cubes_host(f.stack(copy, 4), f.params);
    EXPECT_EQ(host.vertex_count(), 0u);
    EXPECT_EQ(host.triangle_count(), 0u);
}

TEST(MarchingCubesHost, RejectsBadGridsAndRanges) {
    const Field f = noise(9, 8, 7, 5u);
    std::vector<float> copy;
    const PlaneStack good = f.stack(copy, 3);
    auto expect_invalid = [](const PlaneStack& s, const McParams& p, const char* what) {
        try {
            marching_cubes_host(s, p);
            ADD_FAILURE() << "no error for " << what;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << what;
            EXPECT_NE(std::string(e.what()).find("marching cubes"), std::string::npos) << what;
        }
    };
    McParams p = f.params;
    p.z_end = 7;
    expect_invalid(good, p, "z_end past the planes");
    p = f.params;
    p.z_begin = 5;
    p.z_end = 4;
    expect_invalid(good, p, "z_begin after z_end");
    p = f.params;
    p.spacing = 0.0f;
    expect_invalid(good, p, "zero spacing");
    PlaneStack missing = good;
    missing.planes[2] = nullptr;
    expect_invalid(missing, f.params, "a missing plane");
    PlaneStack narrow = good;
    narrow.pitch = good.nx - 1;
    expect_invalid(narrow, f.params, "a pitch smaller than nx");
    PlaneStack short_stack = good;
    short_stack.planes.pop_back();
    expect_invalid(short_stack, f.params, "fewer planes than nz");
    expect_invalid(PlaneStack{}, McParams{}, "an empty grid");
}

// The slab pipeline with marching cubes on the host and on the device: the same mesh, index for
// index, positions and normals to the device's float rounding (tests/isosurface/
// test_marching_cubes_gpu.cpp's tolerances), for the FDM surface, vdw (the power distance's
// interpolation) and the exact SES. Auto runs it on the host exactly when the device is a CPU.
class HostMarchingCubesSlabs : public GpuTest {};

TEST_F(HostMarchingCubesSlabs, CrambinInSlabsGivesTheDevicePassesMesh) {
    using fdmsurf::Engine;
    using fdmsurf::EngineOptions;
    using fdmsurf::StagePlace;
    const fdmsurf::Atoms atoms =
        fdmsurf::read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    SurfaceOptions vdw, edt;
    vdw.surface = SurfaceKind::Vdw;
    vdw.snap = false;
    edt.method = fdmsurf::SesMethod::Edt;
    edt.snap = false;
    // Bindings narrow enough for slabs: the FDM field's overlap needs the wider one.
    const std::pair<SurfaceOptions, std::uint64_t> cases[] = {
        {SurfaceOptions{}, 2u << 20}, {vdw, 1u << 20}, {edt, 1u << 20}};
    for (const auto& [o, range] : cases) {
        SCOPED_TRACE(o.surface == SurfaceKind::Vdw         ? "vdw"
                     : o.method == fdmsurf::SesMethod::Edt ? "edt"
                                                           : "fdm");
        Mesh mesh[2];
        for (int host = 0; host < 2; ++host) {
            Engine e(EngineOptions{.validation = true,
                                   .max_buffer_range = range,
                                   .marching_cubes = host ? StagePlace::Host : StagePlace::Device});
            const fdmsurf::SurfaceResult r = e.make_surface(atoms, o);
            EXPECT_GT(r.grid.slabs, 1u);
            EXPECT_EQ(r.grid.host_marching_cubes, host == 1);
            bool device_passes = false, on_host = false;
            for (const fdmsurf::StageTime& t : r.times) {
                device_passes = device_passes || t.name == "mc-triangles";
                on_host = on_host || t.name == "mc-host";
            }
            EXPECT_EQ(device_passes, host == 0);
            EXPECT_EQ(on_host, host == 1);
            EXPECT_TRUE(e.take_validation_messages().empty());
            mesh[host] = r.mesh;
        }
        ASSERT_EQ(mesh[1].vertex_count(), mesh[0].vertex_count());
        EXPECT_TRUE(mesh[1].indices == mesh[0].indices);
        double position = 0.0, normal = 0.0;
        for (std::size_t i = 0; i < mesh[0].positions.size(); ++i) {
            position =
                std::max(position, double(std::abs(mesh[1].positions[i] - mesh[0].positions[i])));
            normal = std::max(normal, double(std::abs(mesh[1].normals[i] - mesh[0].normals[i])));
        }
        EXPECT_LE(position, 1e-4);
        EXPECT_LE(normal, 1e-3);
        EXPECT_GT(mesh[1].triangle_count(), 10000u);
        EXPECT_TRUE(IsClosedManifold(mesh[1]));
    }
}

TEST_F(HostMarchingCubesSlabs, AutoRunsOnTheHostExactlyOnACpuDevice) {
    const fdmsurf::Atoms atoms =
        fdmsurf::read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    fdmsurf::Engine e(fdmsurf::EngineOptions{.max_buffer_range = 2u << 20});
    const fdmsurf::SurfaceResult r = e.make_surface(atoms, SurfaceOptions{});
    ASSERT_GT(r.grid.slabs, 1u);
    const bool cpu = e.device().type == "CPU";
    EXPECT_EQ(r.grid.host_marching_cubes, cpu) << e.device().type;
    // A grid in one binding too, and the filter with it at 0.5 Å.
    fdmsurf::Engine whole;
    const fdmsurf::SurfaceResult one = whole.make_surface(atoms, SurfaceOptions{});
    EXPECT_EQ(one.grid.slabs, 1u);
    EXPECT_EQ(one.grid.host_marching_cubes, cpu);
    EXPECT_EQ(one.grid.host_filter, cpu);
    EXPECT_EQ(one.grid.host_density, cpu);
    // A mesh left on the device for a renderer keeps the device's passes.
    const fdmsurf::DeviceSurfaceResult kept = whole.make_device_surface(atoms, SurfaceOptions{});
    EXPECT_FALSE(kept.grid.host_marching_cubes);
}

// A grid in one binding: density on the device, read back, the Gaussian filter and marching
// cubes on the host, against VkFFT and the device's passes: the same surface but for float
// rounding at a few crossings (the FFT's circular wrap against the host's zeros beyond the grid,
// where the density is nil anyway), also refined (refinement then reads the host's field). The
// exact SES's field is the same either way (the host's on a CPU device, EngineOptions::ses_distance):
// the same mesh index for index.
TEST_F(HostMarchingCubesSlabs, CrambinInOneBindingGivesTheDevicePathsSurface) {
    using fdmsurf::StagePlace;
    const fdmsurf::Atoms atoms =
        fdmsurf::read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    SurfaceOptions refined;
    refined.refine = 1;
    SurfaceOptions edt;
    edt.method = fdmsurf::SesMethod::Edt;
    edt.snap = false;
    for (const SurfaceOptions& o : {SurfaceOptions{}, refined, edt}) {
        const bool exact = o.method == fdmsurf::SesMethod::Edt;
        SCOPED_TRACE(exact ? "edt" : o.refine ? "refined" : "fdm");
        Mesh mesh[2];
        for (int host = 0; host < 2; ++host) {
            const StagePlace place = host ? StagePlace::Host : StagePlace::Device;
            fdmsurf::Engine e(fdmsurf::EngineOptions{
                .validation = true, .gaussian_filter = place, .marching_cubes = place});
            const fdmsurf::SurfaceResult r = e.make_surface(atoms, o);
            EXPECT_EQ(r.grid.slabs, 1u);
            EXPECT_EQ(r.grid.host_marching_cubes, host == 1);
            EXPECT_EQ(r.grid.host_filter, host == 1 && !exact);
            bool fft = false;
            for (const fdmsurf::StageTime& t : r.times) fft = fft || t.name == "fft-forward";
            EXPECT_EQ(fft, host == 0 && !exact);
            EXPECT_TRUE(e.take_validation_messages().empty());
            mesh[host] = r.mesh;
        }
        EXPECT_TRUE(IsClosedManifold(mesh[1]));
        if (exact) {
            EXPECT_TRUE(mesh[1].indices == mesh[0].indices);
            continue;
        }
        const fdmsurf::MeshStats a = fdmsurf::compute_stats(mesh[0]);
        const fdmsurf::MeshStats b = fdmsurf::compute_stats(mesh[1]);
        EXPECT_NEAR(double(b.triangles), double(a.triangles), 1e-4 * double(a.triangles));
        EXPECT_NEAR(b.area, a.area, 1e-5 * a.area);
        EXPECT_NEAR(b.volume, a.volume, 1e-5 * a.volume);
        EXPECT_LT(fdmsurf::compare_meshes(mesh[0], mesh[1], fdmsurf::CompareOptions{}).hausdorff,
                  0.01);
    }
}

}  // namespace
