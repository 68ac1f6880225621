// Areas and volumes of snapped vdw and sas meshes of real structures (issue 13) against FreeSASA
// (Lee-Richards, resolution 100, the same atoms and radii) and a Monte-Carlo estimate of the
// union of balls; skipped when freesasa is not installed (a failure under
// FDMSURF_REQUIRE_TOOLS=1).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "support/ball_union.hpp"
#include "support/freesasa_tool.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::MeshStats;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::test::data_path;

class SnapFreesasa : public GpuTest {
protected:
    static std::string scratch() {
        const auto dir = std::filesystem::temp_directory_path() /
                         ("fdmsurf-freesasa-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        return dir.string();
    }
};

struct Case {
    const char* file;
    SurfaceKind kind;
    float spacing;
    double area_bound;    // relative, against FreeSASA
    double volume_bound;  // relative, against Monte Carlo
    double mc_cell;       // Å
};

// The bounds: area within 1% at 0.5 Å and 0.5% at 0.25 Å, volume within 0.5%.
void check(fdmsurf::Engine& engine, const Case& c, const std::string& folder) {
    const Atoms atoms = fdmsurf::read_structure(data_path(c.file)).atoms;
    const double probe = c.kind == SurfaceKind::Sas ? 1.4 : 0.0;
    const double reference = fdmsurf::test::freesasa_total(atoms, probe > 0 ? probe : 1e-4, folder);
    ASSERT_GT(reference, 0.0) << "freesasa failed on " << c.file;
    const double volume =
        fdmsurf::test::union_volume(fdmsurf::test::balls_of(atoms, probe), c.mc_cell);
    const SurfaceOptions options{.surface = c.kind, .spacing = c.spacing, .probe = float(probe)};
    SurfaceOptions plain = options;
    plain.snap = false;
    const fdmsurf::SurfaceResult res = engine.make_surface(atoms, options);
    const fdmsurf::SurfaceResult off = engine.make_surface(atoms, plain);
    EXPECT_TRUE(IsClosedManifold(res.mesh));
    const MeshStats s = fdmsurf::compute_stats(res.mesh), p = fdmsurf::compute_stats(off.mesh);
    const double da = s.area / reference - 1.0, dv = s.volume / volume - 1.0;
    std::printf(
        "  %s %s %.2f Å: area %.1f vs FreeSASA %.1f (%+.2f%%; marching cubes alone "
        "%+.2f%%), volume %.1f vs Monte Carlo %.1f (%+.2f%%), %zu triangles (%zu)\n",
        c.file, fdmsurf::to_string(c.kind), c.spacing, s.area, reference, 100 * da,
        100 * (p.area / reference - 1.0), s.volume, volume, 100 * dv, s.triangles, p.triangles);
    EXPECT_LE(std::abs(da), c.area_bound) << c.file << " " << fdmsurf::to_string(c.kind);
    EXPECT_LE(std::abs(dv), c.volume_bound) << c.file << " " << fdmsurf::to_string(c.kind);
    EXPECT_LT(std::abs(da), std::abs(p.area / reference - 1.0));
}

TEST_F(SnapFreesasa, CrambinAreasMatchFreesasa) {
    FDMSURF_REQUIRE_FREESASA();
    const std::string folder = scratch();
    for (const Case& c : {Case{"1crn.xyzr", SurfaceKind::Sas, 0.5f, 0.01, 0.005, 0.2},
                          Case{"1crn.xyzr", SurfaceKind::Vdw, 0.5f, 0.01, 0.005, 0.15},
                          Case{"1crn.xyzr", SurfaceKind::Sas, 0.25f, 0.005, 0.005, 0.2},
                          Case{"1crn.xyzr", SurfaceKind::Vdw, 0.25f, 0.005, 0.005, 0.15}})
        check(engine(), c, folder);
    std::filesystem::remove_all(folder);
}

TEST_F(SnapFreesasa, HaemoglobinAreasMatchFreesasa) {
    FDMSURF_REQUIRE_FREESASA();
    const std::string folder = scratch();
    for (const Case& c : {Case{"4hhb.xyzr", SurfaceKind::Sas, 0.5f, 0.01, 0.005, 0.35},
                          Case{"4hhb.xyzr", SurfaceKind::Vdw, 0.5f, 0.01, 0.005, 0.25}})
        check(engine(), c, folder);
    std::filesystem::remove_all(folder);
}

}  // namespace
