// One engine, many surfaces of the same grid size, without the validation layer (which hands out
// unique handles and so hid a stale-descriptor bug: drivers reuse a destroyed buffer's handle).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fdmsurf/fdmsurf.hpp"
#include "support/gpu_fixture.hpp"

TEST(EngineReuse, SameSizeSurfacesWithoutValidationAreIdentical) {
    std::string why;
    const std::unique_ptr<fdmsurf::Engine> engine = fdmsurf_test::own_engine({}, why);
    if (!engine) GTEST_SKIP() << why;
    const fdmsurf::Structure s = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/1crn.pdb");
    fdmsurf::SurfaceOptions options;
    options.spacing = 0.8f;
    const fdmsurf::SurfaceResult first = engine->make_surface(s.atoms, options);
    for (int run = 0; run < 3; ++run) {
        const fdmsurf::SurfaceResult again = engine->make_surface(s.atoms, options);
        ASSERT_EQ(again.grid.dims, first.grid.dims);
        ASSERT_EQ(again.mesh.indices, first.mesh.indices) << "run " << run;
        ASSERT_EQ(again.mesh.positions, first.mesh.positions) << "run " << run;
    }
}
