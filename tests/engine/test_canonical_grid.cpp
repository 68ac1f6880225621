// Canonical grid sizes (SurfaceOptions::canonical_grid) and Engine::prepare: a small FDM grid
// rounded up to a cube on its own lattice gives the natural grid's mesh, and prepare builds the
// plans of every canonical size (docs/performance.md, "Cold start").
#include <gtest/gtest.h>

#include <string>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "grid/grid_plan.hpp"
#include "support/gpu_fixture.hpp"

namespace {

class CanonicalGrid : public GpuTest {};

// The added points lie farther from the atoms than the natural grid's padding, where the
// filtered density is far below the level; the natural grid's points keep their density, and
// the filter's result moves only by what its periodic images (one box farther apart) gave.
// Stated tolerance: 1e-3 Å for every vertex, area and volume to 1e-5.
TEST_F(CanonicalGrid, MeshIsTheNaturalGridsMesh) {
    for (const char* name : {"1crn.pdb", "3al1.pdb"}) {
        SCOPED_TRACE(name);
        const fdmsurf::Structure s =
            fdmsurf::read_structure(std::string(FDMSURF_TEST_DATA_DIR "/") + name);
        fdmsurf::SurfaceOptions natural;
        natural.canonical_grid = false;
        const fdmsurf::SurfaceResult a = engine().make_surface(s.atoms, natural);
        const fdmsurf::SurfaceResult b = engine().make_surface(s.atoms, fdmsurf::SurfaceOptions{});
        ASSERT_NE(a.grid.dims, b.grid.dims);
        EXPECT_EQ(b.grid.dims[0], b.grid.dims[1]);
        EXPECT_EQ(b.grid.dims[0], b.grid.dims[2]);
        fdmsurf::CompareOptions co;
        co.spacing = 0.5;
        const fdmsurf::CompareResult r = fdmsurf::compare_meshes(a.mesh, b.mesh, co);
        EXPECT_LT(r.hausdorff, 1e-3);
        EXPECT_LT(std::abs(r.area_rel_error), 1e-5);
        EXPECT_LT(std::abs(r.volume_rel_error), 1e-5);
        EXPECT_EQ(r.ref_triangles, r.test_triangles);
    }
}

TEST_F(CanonicalGrid, PrepareBuildsAPlanForEveryCanonicalSize) {
    const std::vector<fdmsurf::Engine::PreparedPlan> rows = engine().prepare();
    ASSERT_EQ(rows.size(), std::size(fdmsurf::detail::kCanonicalGridSizes));
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::uint32_t c = fdmsurf::detail::kCanonicalGridSizes[i];
        EXPECT_EQ(rows[i].dims, (std::array<std::uint32_t, 3>{c, c, c}));
        EXPECT_GT(rows[i].ms, 0.0);
    }
    // The engine goes on as before: 1CRN on its canonical grid, one of the prepared sizes.
    const fdmsurf::Structure s = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/1crn.pdb");
    const fdmsurf::SurfaceResult r = engine().make_surface(s.atoms);
    EXPECT_EQ(r.grid.dims, (std::array<std::uint32_t, 3>{112, 112, 112}));
    EXPECT_GT(r.mesh.triangle_count(), 20000u);
}

}  // namespace
