// The snap's field on the exact SES (src/engine/surface_fields.hpp): the projection through
// SesDistanceField's per-chunk cursor, vertices visited bin by bin, against the same field
// sampled point by point through SesHostField::distance in index order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "engine/surface_fields.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "refine/refine.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::Mesh;
using fdmsurf::detail::Vec3;
using fdmsurf::detail::SesDistanceField;
using fdmsurf::detail::SesHostField;
using fdmsurf::detail::SurfaceField;

// The plain reference: every sample through SesHostField::distance, no view, no cells.
class PointByPoint final : public SurfaceField {
public:
    explicit PointByPoint(const SurfaceField& field) : field_(field) {}
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override {
        return field_.sample(p, value, gradient);
    }
    double iso() const override { return field_.iso(); }
    double outward() const override { return field_.outward(); }

private:
    const SurfaceField& field_;
};

// Vertices near the SES of hemoglobin and crambin (around random atoms, from a probe radius
// outside the balls to 2 Å inside, in random order), each with its normal away from its atom,
// as the snap stage projects marching-cubes vertices: the same positions, normals and counts.
TEST(SurfaceFields, SnapThroughTheCursorMatchesThePointDistance) {
    for (const char* name : {"4hhb.xyzr", "1crn.xyzr"}) {
        const Atoms atoms = fdmsurf::read_structure(fdmsurf::test::data_path(name)).atoms;
        const fdmsurf::SurfaceOptions options{.method = fdmsurf::SesMethod::Edt, .spacing = 0.5f};
        const fdmsurf::detail::GridPlan plan = fdmsurf::detail::plan_grid(atoms, options);
        ASSERT_TRUE(plan.exact_ses);
        const auto features = fdmsurf::detail::build_ses_features(atoms, options.probe);
        const SesHostField ses(features, plan.ses_d_max);
        const SesDistanceField field(ses, plan.iso, plan.ses_d_max);
        Vec3 origin{};
        double cell = 0.0;
        ASSERT_TRUE(field.visit_cells(origin, cell));
        ASSERT_NE(field.local(), nullptr);

        Mesh mesh;
        std::mt19937 rng(4421);
        std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
        std::normal_distribution<double> offset(0.0, 1.0);
        std::uniform_real_distribution<double> depth(-0.3, 1.5);
        for (int n = 0; n < 20000; ++n) {
            const std::size_t i = pick(rng);
            double dir[3] = {offset(rng), offset(rng), offset(rng)};
            const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            const double r = atoms.radius[i] + options.probe * depth(rng);
            for (int k = 0; k < 3; ++k) {
                mesh.positions.push_back(float(atoms.xyz[3 * i + k] + r * dir[k] / len));
                mesh.normals.push_back(float(dir[k] / len));
            }
        }
        Mesh reference = mesh;
        const auto po = fdmsurf::detail::ses_snap_options(plan.info.spacing);
        const auto kept = fdmsurf::detail::project_onto_field(mesh, 0, field, po);
        const auto plain =
            fdmsurf::detail::project_onto_field(reference, 0, PointByPoint(field), po);
        std::printf("  %s: %zu of 20000 projected, %zu off their normals, %zu failed\n", name,
                    plain.projected, plain.off_normal, plain.failed());
        EXPECT_EQ(mesh.positions, reference.positions) << name;
        EXPECT_EQ(mesh.normals, reference.normals) << name;
        EXPECT_EQ(kept.projected, plain.projected);
        EXPECT_EQ(kept.not_converged, plain.not_converged);
        EXPECT_EQ(kept.outside_field, plain.outside_field);
        EXPECT_EQ(kept.off_normal, plain.off_normal);
        EXPECT_GT(plain.projected, 2000u);  // the comparison covers projected vertices
    }
}

}  // namespace
