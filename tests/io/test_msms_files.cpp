// MSMS's files: the SES part of each vertex on two- and three-ball surfaces, the components,
// the exact layout of .vert/.face/.area lines, and reading them back (fdmsurf compare's reader).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fdmsurf/fdmsurf.hpp"
#include "mesh/mesh_shapes.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_atoms.hpp"

using namespace fdmsurf;
using fdmsurf_test::make_atoms;
namespace fs = std::filesystem;

namespace {

class MsmsParts : public GpuTest {};

std::vector<std::size_t> count_parts(const std::vector<SesPart>& parts) {
    std::vector<std::size_t> n(4, 0);
    for (SesPart p : parts) ++n[std::size_t(p)];
    return n;
}

SurfaceResult exact_ses(Engine& engine, const Atoms& atoms) {
    SurfaceOptions o;
    o.method = SesMethod::Edt;
    o.spacing = 0.25f;
    o.probe = 1.4f;
    return engine.make_surface(atoms, o);
}

std::vector<std::string> lines_of(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::vector<std::string> fields(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> f;
    for (std::string w; in >> w;) f.push_back(w);
    return f;
}

}  // namespace

TEST_F(MsmsParts, TwoBallsHaveContactAndToricPartsOnly) {
    // Two balls 3.5 Å apart: each keeps a spherical cap; the probe rolling round both sweeps a
    // torus. No probe position touches three atoms: nothing re-entrant.
    const Atoms atoms = make_atoms({{0, 0, 0, 1.5f}, {3.5f, 0, 0, 1.5f}});
    const SurfaceResult r = exact_ses(engine(), atoms);
    const std::vector<SesPart> parts = ses_vertex_parts(r.mesh, atoms, 1.4f, 0.025f);
    const std::vector<std::size_t> n = count_parts(parts);
    EXPECT_GT(n[1], n[2]);  // the caps are larger than the band
    EXPECT_GT(n[2], 0u);
    EXPECT_EQ(n[3], 0u);
    // Contact vertices lie on their atom's sphere; toric ones between the atoms (|x| < 1.75 +
    // the band's half-width, which is under 1.5 Å here).
    for (std::size_t v = 0; v < parts.size(); ++v) {
        const float x = r.mesh.positions[3 * v];
        if (parts[v] == SesPart::Toric) {
            EXPECT_NEAR(x, 1.75f, 1.5f) << v;
        }
    }
}

TEST_F(MsmsParts, ThreeBallsInATriangleHaveReentrantPatches) {
    // Three balls at the corners of a triangle of side 3.6 Å: a probe sits in the dimple on
    // each side, touching all three: two re-entrant patches.
    const Atoms atoms = make_atoms({{0, 0, 0, 1.6f}, {3.6f, 0, 0, 1.6f}, {1.8f, 3.118f, 0, 1.6f}});
    const SurfaceResult r = exact_ses(engine(), atoms);
    const std::vector<SesPart> parts = ses_vertex_parts(r.mesh, atoms, 1.4f, 0.025f);
    const std::vector<std::size_t> n = count_parts(parts);
    EXPECT_GT(n[1], 0u);
    EXPECT_GT(n[2], 0u);
    ASSERT_GT(n[3], 0u);
    for (std::size_t v = 0; v < parts.size(); ++v) {
        if (parts[v] != SesPart::Reentrant) continue;
        // Over the triangle's centre (1.8, 1.04), above or below its plane.
        EXPECT_NEAR(r.mesh.positions[3 * v], 1.8f, 1.0f);
        EXPECT_NEAR(r.mesh.positions[3 * v + 1], 1.04f, 1.0f);
    }
    EXPECT_THROW(ses_vertex_parts(r.mesh, atoms, 0.0f, 0.1f), Error);
    Mesh bare = r.mesh;
    bare.atoms.clear();
    EXPECT_THROW(ses_vertex_parts(bare, atoms, 1.4f, 0.1f), Error);
}

TEST(MsmsComponents, OuterPiecesFirstThenCavitiesLargestFirst) {
    using fdmsurf::test::icosphere;
    Mesh mesh = icosphere(10.0, 2);
    fdmsurf::test::append(mesh, fdmsurf::test::turned_inside_out(icosphere(2.0, 2, {3, 0, 0})));
    fdmsurf::test::append(mesh, fdmsurf::test::turned_inside_out(icosphere(3.0, 2, {-4, 0, 0})));
    fdmsurf::test::append(mesh, icosphere(1.0, 1, {30, 0, 0}));  // a second outer piece
    mesh.atoms.assign(mesh.vertex_count(), 7);
    const std::vector<Mesh> c = msms_components(mesh);
    ASSERT_EQ(c.size(), 3u);
    EXPECT_EQ(compute_stats(c[0]).pieces, 2u);
    EXPECT_GT(compute_stats(c[0]).volume, 0.0);
    EXPECT_LT(compute_stats(c[1]).volume, compute_stats(c[2]).volume);  // larger cavity first
    EXPECT_NEAR(compute_stats(c[1]).volume, -4.0 / 3 * 3.14159 * 27, 15.0);
    std::size_t triangles = 0;
    for (const Mesh& m : c) {
        triangles += m.triangle_count();
        EXPECT_EQ(m.atoms, std::vector<std::uint32_t>(m.vertex_count(), 7));
    }
    EXPECT_EQ(triangles, mesh.triangle_count());
}

TEST(MsmsFiles, LayoutAsMsmsWritesIt) {
    const fs::path dir = fs::temp_directory_path() / "fdmsurf-msms-layout";
    fs::remove_all(dir);
    fs::create_directories(dir);
    Mesh mesh;
    mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    mesh.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    mesh.indices = {0, 1, 2};
    mesh.atoms = {1, 0, 1};
    Atoms atoms = make_atoms({{0, 0, 0, 1.5f}, {1, 1, 1, 1.7f}});
    atoms.meta.resize(2);
    atoms.meta[0].xyzrn_name = "A_1_x_THR_N_Blue";
    atoms.meta[1].xyzrn_name = "A_1_x_THR_CA_Green";
    MsmsFileOptions o;
    o.source = "two.xyzrn";
    o.density = 3.0f;
    const std::string base = (dir / "s").string();
    write_msms_surface(mesh, atoms, {SesPart::Contact, SesPart::Toric, SesPart::Toric}, base, o);
    write_msms_areas(atoms, {1.25, 2.5}, {10.0, 20.125}, base + ".area", o);

    const std::vector<std::string> vert = lines_of(base + ".vert");
    ASSERT_EQ(vert.size(), 6u);
    EXPECT_EQ(vert[0].rfind("# MSMS solvent excluded surface vertices for two.xyzrn", 0), 0u);
    EXPECT_EQ(fields(vert[2]), (std::vector<std::string>{"3", "2", "3.00", "1.50"}));
    EXPECT_EQ(fields(vert[3]),
              (std::vector<std::string>{"0.000", "0.000", "0.000", "0.000", "0.000", "1.000", "0",
                                        "2", "1", "A_1_x_THR_CA_Green"}));
    EXPECT_EQ(fields(vert[4])[7], "1");
    EXPECT_EQ(fields(vert[4])[9], "A_1_x_THR_N_Blue");
    const std::vector<std::string> face = lines_of(base + ".face");
    ASSERT_EQ(face.size(), 4u);
    EXPECT_EQ(fields(face[2])[0], "1");
    EXPECT_EQ(fields(face[3]), (std::vector<std::string>{"1", "2", "3", "2", "0"}));
    const std::vector<std::string> area = lines_of(base + ".area");
    ASSERT_EQ(area.size(), 3u);
    EXPECT_EQ(fields(area[1]), (std::vector<std::string>{"1", "1.250", "10.000",
                                                         "A_1_x_THR_N_Blue"}));
    EXPECT_EQ(fields(area[2])[3], "A_1_x_THR_CA_Green");

    // fdmsurf compare's reader takes the positions, normals and atoms back.
    const Mesh back = read_mesh_any(base + ".vert");
    EXPECT_EQ(back.positions, mesh.positions);
    EXPECT_EQ(back.normals, mesh.normals);
    EXPECT_EQ(back.atoms, mesh.atoms);
    EXPECT_EQ(back.indices, mesh.indices);

    // Without headers; bad arguments refused before anything is written.
    o.header = false;
    write_msms_surface(mesh, atoms, {SesPart::Contact, SesPart::Toric, SesPart::Toric},
                       base + "-bare", o);
    EXPECT_EQ(lines_of(base + "-bare.vert").size(), 3u);
    EXPECT_THROW(write_msms_surface(mesh, atoms, {SesPart::Contact}, base + "-x", o), Error);
    EXPECT_THROW(write_msms_areas(atoms, {1.0}, {1.0, 2.0}, base + "-x.area", o), Error);
    EXPECT_FALSE(fs::exists(base + "-x.vert"));
    EXPECT_FALSE(fs::exists(base + "-x.area"));
    fs::remove_all(dir);
}
