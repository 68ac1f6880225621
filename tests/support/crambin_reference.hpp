// Test helper: a GPU suite base with crambin's reference atoms (tests/data/1crn.xyzr) and
// NanoShaper's analytical SES of them, for accuracy tests against the true surface.
#pragma once

#include <string>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "support/gpu_fixture.hpp"

class CrambinReferenceTest : public GpuTest {
protected:
    static const fdmsurf::Atoms& crambin() {
        static const fdmsurf::Atoms atoms =
            fdmsurf::read_structure(std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.xyzr").atoms;
        return atoms;
    }
    static const fdmsurf::Mesh& nanoshaper() {
        static const fdmsurf::Mesh mesh = fdmsurf::read_mesh_any(
            std::string(FDMSURF_TEST_DATA_DIR) + "/1crn-ses-nanoshaper.ply.gz");
        return mesh;
    }
    // `r`'s mesh against the reference (fdmsurf::compare_meshes, spacing in Å).
    static fdmsurf::CompareResult against_reference(const fdmsurf::SurfaceResult& r,
                                                    double spacing) {
        fdmsurf::CompareOptions o;
        o.spacing = spacing;
        return fdmsurf::compare_meshes(nanoshaper(), r.mesh, o);
    }
};
