// Areas of computed surfaces (GPU): the mesh split by sphere patch on analytic balls and on
// crambin against FreeSASA, the ses split by vertex atom, buried areas on one engine.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "fdmsurf/areas.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "support/freesasa_tool.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using namespace fdmsurf;

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

class SurfaceAreas : public GpuTest {};

TEST_F(SurfaceAreas, MeshSplitFollowsTheSpherePatches) {
    // Two balls cutting each other and a third apart: every triangle of the snapped mesh lies
    // on one sphere, so each atom's share of the mesh is its patch, within the chord deficit.
    const Atoms atoms =
        fdmsurf_test::make_atoms({{0, 0, 0, 1.8f}, {2.4f, 0, 0, 1.7f}, {12, 0, 0, 1.5f}});
    for (const SurfaceKind kind : {SurfaceKind::Vdw, SurfaceKind::Sas}) {
        SurfaceOptions options;
        options.surface = kind;
        options.spacing = 0.25f;
        const SurfaceResult r = engine().make_surface(atoms, options);
        const AtomAreas a = surface_atom_areas(atoms, options, &r.mesh);
        ASSERT_TRUE(a.exact);
        const double mesh_area = compute_stats(r.mesh).area;
        EXPECT_NEAR(sum(a.mesh_area), mesh_area, 1e-9 * mesh_area);
        EXPECT_GT(a.mesh_on_patches, 0.999 * mesh_area);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_LT(a.mesh_area[i], a.area[i]) << i;  // flat triangles inside the spheres
            EXPECT_NEAR(a.mesh_area[i], a.area[i], 0.005 * a.area[i]) << to_string(kind) << i;
        }
    }
}

TEST_F(SurfaceAreas, CrambinAgainstFreesasa) {
    // Issue 13 at 0.5 Å: total within 0.5%, per-residue mean absolute difference <= 0.5 Å²,
    // 99th percentile <= 3 Å², for the exact patches and for the mesh's own split.
    FDMSURF_REQUIRE_FREESASA();
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    const auto folder = std::filesystem::temp_directory_path() /
                        ("fdmsurf-surface-areas-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    const std::vector<double> reference = test::freesasa_atom_areas(atoms, 1.4, folder.string());
    std::filesystem::remove_all(folder);
    ASSERT_EQ(reference.size(), atoms.size());
    SurfaceOptions options;
    options.surface = SurfaceKind::Sas;
    const SurfaceResult r = engine().make_surface(atoms, options);
    const AtomAreas a = surface_atom_areas(atoms, options, &r.mesh);
    AtomAreas ref;
    ref.area = reference;
    const std::vector<ResidueArea> theirs = residue_areas(atoms, ref);
    const std::vector<ResidueArea> ours = residue_areas(atoms, a, RelativeTable::Tien2013);
    ASSERT_EQ(ours.size(), theirs.size());
    for (const bool mesh : {false, true}) {
        std::vector<double> d;
        for (std::size_t k = 0; k < ours.size(); ++k)
            d.push_back(std::abs((mesh ? ours[k].mesh_area : ours[k].area) - theirs[k].area));
        std::sort(d.begin(), d.end());
        const double mad = sum(d) / double(d.size());
        const double p99 = d[std::size_t(0.99 * double(d.size() - 1))];
        const double total = mesh ? sum(a.mesh_area) : sum(a.area);
        const double error = total / sum(reference) - 1.0;
        std::printf("  1CRN sas 0.5 Å %s: total %+.3f%%, residues MAD %.3f p99 %.3f Å²\n",
                    mesh ? "mesh" : "exact", 100 * error, mad, p99);
        EXPECT_LT(std::abs(error), 0.005);
        EXPECT_LT(mad, 0.5);
        EXPECT_LT(p99, 3.0);
    }
    // Relative areas: every amino acid has a maximum, and none is far beyond it.
    for (const ResidueArea& res : ours) {
        EXPECT_GT(res.max_area, 0.0) << res.name;
        EXPECT_GE(res.relative, 0.0);
        EXPECT_LT(res.relative, 1.2) << res.name << res.number;
    }
}

TEST_F(SurfaceAreas, SesIsTheMeshSplitByVertexAtom) {
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    SurfaceOptions options;
    options.method = SesMethod::Edt;
    const SurfaceResult r = engine().make_surface(atoms, options);
    const AtomAreas a = surface_atom_areas(atoms, options, &r.mesh);
    EXPECT_FALSE(a.exact);
    EXPECT_EQ(a.area, a.mesh_area);
    EXPECT_EQ(a.area, atom_mesh_areas(r.mesh, atoms.size()));
    EXPECT_NEAR(sum(a.area), compute_stats(r.mesh).area, 1e-9 * sum(a.area));
    EXPECT_THROW(surface_atom_areas(atoms, options, nullptr), Error);
}

TEST_F(SurfaceAreas, BuriedAreasComputeThreeSurfacesOnOneEngine) {
    // 3AL1's chains A and B: the complex surface is of their atoms alone; its exact buried area
    // is the one computed without a device, and the meshes' agrees within 5%.
    const Atoms atoms = read_structure(test::data_path("3al1.pdb")).atoms;
    std::array<std::string, 2> names;
    const std::vector<std::uint8_t> g = match_buried_groups(atoms, "A:B", names);
    SurfaceOptions options;
    options.surface = SurfaceKind::Sas;
    options.spacing = 0.5f;
    const BuriedAreas with = buried_areas(&engine(), atoms, g, names, options);
    const BuriedAreas without = buried_areas(nullptr, atoms, g, names, options);
    ASSERT_EQ(with.complex.size(), std::size_t(std::count(g.begin(), g.end(), 1)) +
                                       std::size_t(std::count(g.begin(), g.end(), 2)));
    EXPECT_TRUE(IsClosedManifold(with.complex_surface.mesh));
    EXPECT_EQ(with.complex_surface.mesh.atoms.size(), with.complex_surface.mesh.vertex_count());
    EXPECT_DOUBLE_EQ(with.buried(), without.buried());
    EXPECT_TRUE(without.alone.mesh_area.empty());
    EXPECT_GT(with.buried(), 100.0);
    EXPECT_NEAR(with.mesh_buried(), with.buried(), 0.05 * with.buried());
    for (int k = 0; k < 2; ++k) {
        EXPECT_GT(with.area_alone[k], with.area_in_complex[k]);
        EXPECT_NEAR(with.mesh_area_alone[k], with.area_alone[k], 0.01 * with.area_alone[k]);
    }
    std::printf("  3AL1 A:B sas 0.5 Å: buried %.1f Å² exact, %.1f Å² from the meshes\n",
                with.buried(), with.mesh_buried());
}

}  // namespace
