// Tests of per-vertex attributes (atoms, colours, scalars): PLY and OBJ round trips, meshstat.py
// on such files, rejection of malformed attributes, extract_patch, and their alignment through
// cavity removal and refinement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/json_check.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/cavities.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_shapes.hpp"
#include "refine/refine.hpp"
#include "support/mesh_checks.hpp"
#include "support/meshstat_tool.hpp"
#include "support/temp_folder.hpp"

namespace fdmsurf {
namespace {

// A fresh, empty folder per test, removed afterwards.
class MeshAttributeFiles : public test::TempFolderTest {
protected:
    MeshAttributeFiles() : TempFolderTest("fdmsurf_attr_") {}
};

template <typename F>
ErrorCode error_code_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.code();
    }
    ADD_FAILURE() << "no fdmsurf::Error thrown";
    return ErrorCode::Internal;
}

// Deterministic attributes derived from the vertex number and position, so that a vertex moved
// without its attributes shows.
void attach_attributes(Mesh& mesh, std::size_t atom_count = 7) {
    const std::size_t n = mesh.vertex_count();
    mesh.atoms.resize(n);
    mesh.colors.resize(3 * n);
    mesh.scalars = {{"mean_curvature", std::vector<float>(n)}, {"x_plus_y", std::vector<float>(n)}};
    for (std::size_t v = 0; v < n; ++v) {
        mesh.atoms[v] = std::uint32_t((v * 5 + 3) % atom_count);
        for (int k = 0; k < 3; ++k) mesh.colors[3 * v + k] = std::uint8_t((v * 37 + 91 * k) % 256);
        mesh.scalars[0].values[v] = -0.5f + 0.01f * float(v);
        mesh.scalars[1].values[v] = mesh.positions[3 * v] + mesh.positions[3 * v + 1];
    }
}

// Every vertex still carries the attributes attach_attributes gave it: the x + y scalar matches
// its position.
void expect_aligned(const Mesh& mesh) {
    ASSERT_EQ(mesh.atoms.size(), mesh.vertex_count());
    ASSERT_EQ(mesh.colors.size(), 3 * mesh.vertex_count());
    ASSERT_EQ(mesh.scalars.size(), 2u);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        ASSERT_EQ(mesh.scalars[1].values[v], mesh.positions[3 * v] + mesh.positions[3 * v + 1])
            << "vertex " << v;
    }
}

Mesh attributed_sphere() {
    Mesh mesh = test::icosphere(2.0, 2, {1.0, -2.0, 3.5});
    attach_attributes(mesh);
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// PLY

TEST_F(MeshAttributeFiles, PlyRoundTripsAtomsColorsAndScalarsExactly) {
    const Mesh mesh = attributed_sphere();
    write_mesh(mesh, path("s.ply"));
    const Mesh back = read_mesh(path("s.ply"));
    EXPECT_EQ(back.positions, mesh.positions);
    EXPECT_EQ(back.normals, mesh.normals);
    EXPECT_EQ(back.indices, mesh.indices);
    EXPECT_EQ(back.atoms, mesh.atoms);
    EXPECT_EQ(back.colors, mesh.colors);
    ASSERT_EQ(back.scalars.size(), 2u);
    for (std::size_t s = 0; s < 2; ++s) {
        EXPECT_EQ(back.scalars[s].name, mesh.scalars[s].name);
        EXPECT_EQ(back.scalars[s].values, mesh.scalars[s].values);
    }
}

TEST_F(MeshAttributeFiles, PlyHeaderListsTheVertexPropertiesInOrder) {
    const Mesh mesh = attributed_sphere();
    write_mesh(mesh, path("s.ply"));
    const std::string bytes = read_file("s.ply");
    const std::size_t body = bytes.find("end_header\n") + 11;
    const std::string header = bytes.substr(0, body);
    EXPECT_NE(header.find("element vertex " + std::to_string(mesh.vertex_count()) +
                          "\nproperty float x\nproperty float y\nproperty float z\n"
                          "property float nx\nproperty float ny\nproperty float nz\n"
                          "property uint atom\n"
                          "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                          "property float mean_curvature\nproperty float x_plus_y\n"
                          "element face "),
              std::string::npos)
        << header;
    // 24 + 4 + 3 + 2 * 4 bytes per vertex, 13 per triangle.
    EXPECT_EQ(bytes.size(), body + 39 * mesh.vertex_count() + 13 * mesh.triangle_count());
}

TEST_F(MeshAttributeFiles, PlyWritesEachAttributeOnlyWhenSet) {
    Mesh mesh = attributed_sphere();
    mesh.normals.clear();
    mesh.colors.clear();
    mesh.scalars.clear();
    write_mesh(mesh, path("atoms.ply"));
    const Mesh back = read_mesh(path("atoms.ply"));
    EXPECT_EQ(back.atoms, mesh.atoms);
    EXPECT_TRUE(back.normals.empty());
    EXPECT_TRUE(back.colors.empty());
    EXPECT_TRUE(back.scalars.empty());
    const std::string text = read_file("atoms.ply");
    EXPECT_EQ(text.find("red"), std::string::npos);
    EXPECT_EQ(text.find("property float nx"), std::string::npos);
}

TEST_F(MeshAttributeFiles, ReadsOtherToolsColorsAndScalarsFromAsciiPly) {
    // MeshLab-like: float colours in [0, 1], a quality, an alpha, a list (skipped), a lone "red"
    // in a second file (not a colour: skipped, since write_mesh reserves the name).
    const std::string file = write_file("tool.ply",
                                        "ply\nformat ascii 1.0\n"
                                        "element vertex 3\n"
                                        "property float x\nproperty float y\nproperty float z\n"
                                        "property float red\nproperty float green\n"
                                        "property float blue\n"
                                        "property double quality\n"
                                        "property list uchar int extra\n"
                                        "property ushort atom\n"
                                        "property uchar quality\n"
                                        "element face 1\n"
                                        "property list uchar int vertex_indices\n"
                                        "end_header\n"
                                        "0 0 0 1 0.5 0 2.5 0 4 9\n"
                                        "1 0 0 0 1 0.2 -1 1 5 3 8\n"
                                        "0 1 0 2 -1 1 0.25 2 7 7 6 1\n"
                                        "3 0 1 2\n");
    const Mesh mesh = read_mesh(file);
    EXPECT_EQ(mesh.colors, (std::vector<std::uint8_t>{255, 128, 0, 0, 255, 51, 255, 0, 255}));
    EXPECT_EQ(mesh.atoms, (std::vector<std::uint32_t>{4, 3, 6}));
    ASSERT_EQ(mesh.scalars.size(), 1u);  // the second "quality" is skipped
    EXPECT_EQ(mesh.scalars[0].name, "quality");
    EXPECT_EQ(mesh.scalars[0].values, (std::vector<float>{2.5f, -1.0f, 0.25f}));
    write_mesh(mesh, path("back.ply"));  // what read_mesh gives, write_mesh takes

    const Mesh lone = read_mesh(write_file("lone.ply",
                                           "ply\nformat ascii 1.0\nelement vertex 1\n"
                                           "property float x\nproperty float y\nproperty float z\n"
                                           "property uchar red\nproperty float nx\n"
                                           "element face 0\n"
                                           "property list uchar int vertex_indices\n"
                                           "end_header\n1 2 3 200 0.5\n"));
    EXPECT_TRUE(lone.colors.empty());
    EXPECT_TRUE(lone.normals.empty());
    EXPECT_TRUE(lone.scalars.empty());
}

TEST_F(MeshAttributeFiles, PlyAtomThatIsNotAnIndexThrowsFormat) {
    const std::string file = write_file("bad.ply",
                                        "ply\nformat ascii 1.0\nelement vertex 1\n"
                                        "property float x\nproperty float y\nproperty float z\n"
                                        "property float atom\n"
                                        "element face 0\n"
                                        "property list uchar int vertex_indices\n"
                                        "end_header\n0 0 0 1.5\n");
    EXPECT_EQ(error_code_of([&] { read_mesh(file); }), ErrorCode::Format);
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST_F(MeshAttributeFiles, ObjRoundTripsColorsAsUnitFloats) {
    const Mesh mesh = attributed_sphere();
    write_mesh(mesh, path("s.obj"));
    const Mesh back = read_mesh(path("s.obj"));
    EXPECT_EQ(back.colors, mesh.colors);
    EXPECT_EQ(back.indices, mesh.indices);
    ASSERT_EQ(back.normals.size(), mesh.normals.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_NEAR(back.positions[i], mesh.positions[i], 1e-5);
        EXPECT_NEAR(back.normals[i], mesh.normals[i], 1e-5);
    }
    // OBJ has no place for atoms and scalars.
    EXPECT_TRUE(back.atoms.empty());
    EXPECT_TRUE(back.scalars.empty());
    // The first vertex line: position then r g b in [0, 1].
    const std::string text = read_file("s.obj");
    const std::size_t v = text.find("\nv ");
    ASSERT_NE(v, std::string::npos);
    std::istringstream line(text.substr(v + 3, text.find('\n', v + 1) - v - 3));
    std::vector<double> numbers;
    for (double x; line >> x;) numbers.push_back(x);
    ASSERT_EQ(numbers.size(), 6u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(numbers[3 + k], mesh.colors[k] / 255.0, 1e-6);
        EXPECT_GE(numbers[3 + k], 0.0);
        EXPECT_LE(numbers[3 + k], 1.0);
    }
    EXPECT_NE(text.find("\nvn "), std::string::npos);
}

TEST_F(MeshAttributeFiles, ObjColorsAreKeptOnlyWhenEveryVertexHasOne) {
    const Mesh some =
        read_mesh(write_file("some.obj", "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nf 1 2 3\n"));
    EXPECT_TRUE(some.colors.empty());
    const Mesh all = read_mesh(write_file("all.obj",
                                          "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 2\n"
                                          "v 2 2 2 1\nf 1 2 3\n"));
    EXPECT_TRUE(all.colors.empty());  // the fourth vertex has a w, not a colour
    const Mesh coloured = read_mesh(write_file("coloured.obj",
                                               "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 2\n"
                                               "f 1 2 3\n"));
    EXPECT_EQ(coloured.colors, (std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255}));
}

// ---------------------------------------------------------------------------------------------
// Malformed attributes

TEST_F(MeshAttributeFiles, MalformedAttributesThrowInvalidArgumentAndLeaveNoFile) {
    std::vector<Mesh> bad;
    Mesh mesh = attributed_sphere();
    mesh.atoms.pop_back();
    bad.push_back(mesh);
    mesh = attributed_sphere();
    mesh.colors.push_back(1);
    bad.push_back(mesh);
    mesh = attributed_sphere();
    mesh.colors.resize(mesh.vertex_count());  // one per vertex instead of three
    bad.push_back(mesh);
    mesh = attributed_sphere();
    mesh.scalars[1].values.push_back(0.0f);
    bad.push_back(mesh);
    mesh = attributed_sphere();
    mesh.scalars[0].values.clear();
    bad.push_back(mesh);
    for (const char* name :
         {"", "two words", "x", "nz", "atom", "red", "blue", "tab\tname", "new\nline", "é"}) {
        mesh = attributed_sphere();
        mesh.scalars[0].name = name;
        bad.push_back(mesh);
    }
    mesh = attributed_sphere();
    mesh.scalars[1].name = mesh.scalars[0].name;  // twice the same property
    bad.push_back(mesh);
    mesh = attributed_sphere();
    mesh.scalars[0].name = std::string(65, 'a');
    bad.push_back(mesh);
    for (std::size_t i = 0; i < bad.size(); ++i) {
        for (const char* file : {"bad.ply", "bad.obj"}) {
            EXPECT_EQ(error_code_of([&] { write_mesh(bad[i], path(file)); }),
                      ErrorCode::InvalidArgument)
                << "case " << i << " " << file;
        }
    }
    EXPECT_TRUE(empty());
}

TEST(MeshAttributes, ScalarNamesAcceptedAreTheDocumentedOnes) {
    for (const char* name :
         {"coulombic", "mean_curvature", "B-factor", "v2.1", "X", "Atom", "nxx", "quality"}) {
        EXPECT_TRUE(detail::valid_scalar_name(name)) << name;
    }
}

// ---------------------------------------------------------------------------------------------
// meshstat.py reads our files with every attribute


TEST_F(MeshAttributeFiles, MeshstatReadsPlyAndObjWithAllAttributes) {
    FDMSURF_REQUIRE_MESHSTAT();
    const Mesh mesh = attributed_sphere();
    const MeshStats ours = compute_stats(mesh);
    for (const char* name : {"s.ply", "s.obj"}) {
        write_mesh(mesh, path(name));
        std::string text;
        const auto stats = test::meshstat_stats(path(name), text);
        ASSERT_TRUE(stats.has_value()) << name << ": " << text;
        const auto* area = stats->find("area");
        const auto* vertices = stats->find("vertices");
        ASSERT_NE(area, nullptr) << text;
        ASSERT_NE(vertices, nullptr) << text;
        // PLY holds the exact floats; OBJ's 6 decimals move the area by far less than 1e-5.
        EXPECT_NEAR(area->number, ours.area, 1e-5 * ours.area) << name;
        EXPECT_EQ(vertices->number, double(mesh.vertex_count())) << name;
    }
}

// ---------------------------------------------------------------------------------------------
// extract_patch

// Two triangles sharing edge 1-2 plus a third on vertices 2, 3, 4:
//   atoms per vertex: 0 1 1 2 2.
Mesh strip() {
    Mesh mesh;
    for (int v = 0; v < 5; ++v) test::add_vertex(mesh, v, v % 2, 0.0);
    mesh.normals.assign(15, 0.0f);
    for (int v = 0; v < 5; ++v) mesh.normals[3 * v + 2] = 1.0f;
    mesh.indices = {0, 1, 2, 1, 3, 2, 2, 3, 4};
    mesh.atoms = {0, 1, 1, 2, 2};
    mesh.colors = {10, 11, 12, 20, 21, 22, 30, 31, 32, 40, 41, 42, 50, 51, 52};
    mesh.scalars = {{"s", {0.0f, 1.0f, 2.0f, 3.0f, 4.0f}}};
    return mesh;
}

TEST(ExtractPatch, KeepsTrianglesWhoseThreeAtomsAreSelectedWithTheirAttributes) {
    const Mesh mesh = strip();
    const Mesh patch = extract_patch(mesh, {0, 1, 1});
    // Triangles 1-3-2 and 2-3-4 (atoms 1 2 1 and 1 2 2); vertices 1 2 3 4 become 0 1 2 3.
    EXPECT_EQ(patch.indices, (std::vector<std::uint32_t>{0, 2, 1, 1, 2, 3}));
    EXPECT_EQ(patch.positions,
              (std::vector<float>(mesh.positions.begin() + 3, mesh.positions.end())));
    EXPECT_EQ(patch.normals, (std::vector<float>(mesh.normals.begin() + 3, mesh.normals.end())));
    EXPECT_EQ(patch.atoms, (std::vector<std::uint32_t>{1, 1, 2, 2}));
    EXPECT_EQ(patch.colors,
              (std::vector<std::uint8_t>(mesh.colors.begin() + 3, mesh.colors.end())));
    ASSERT_EQ(patch.scalars.size(), 1u);
    EXPECT_EQ(patch.scalars[0].name, "s");
    EXPECT_EQ(patch.scalars[0].values, (std::vector<float>{1, 2, 3, 4}));

    // Nothing selected: an empty mesh with the same (empty) attributes.
    const Mesh none = extract_patch(mesh, {0, 0, 0});
    EXPECT_EQ(none.vertex_count(), 0u);
    EXPECT_EQ(none.triangle_count(), 0u);
    ASSERT_EQ(none.scalars.size(), 1u);
    EXPECT_TRUE(none.scalars[0].values.empty());
    // Everything: the mesh itself.
    const Mesh all = extract_patch(mesh, {1, 1, 1});
    EXPECT_EQ(all.positions, mesh.positions);
    EXPECT_EQ(all.indices, mesh.indices);
    EXPECT_EQ(all.colors, mesh.colors);
}

TEST(ExtractPatch, PatchOfASphereIsOpenWithOneBoundaryLoop) {
    // Atom 1 for the vertices with z > 0.5 R: a cap, a disc with one boundary loop.
    Mesh mesh = test::icosphere(10.0, 3);
    mesh.atoms.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        mesh.atoms[v] = mesh.positions[3 * v + 2] > 5.0f ? 1 : 0;
    }
    attach_attributes(mesh);  // also sets atoms: keep ours
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        mesh.atoms[v] = mesh.positions[3 * v + 2] > 5.0f ? 1 : 0;
    }
    const Mesh patch = extract_patch(mesh, {0, 1});
    const MeshStats s = compute_stats(patch);
    EXPECT_GT(s.triangles, 0u);
    EXPECT_EQ(s.pieces, 1u);
    EXPECT_EQ(s.closed_pieces, 0u);
    EXPECT_EQ(s.euler_characteristic, 1);  // a disc
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    // The boundary: the edges of exactly one selected triangle, as counted on the full mesh.
    std::size_t crossing = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* f = &mesh.indices[3 * t];
        const bool in = mesh.atoms[f[0]] && mesh.atoms[f[1]] && mesh.atoms[f[2]];
        if (in) continue;
        // An unselected triangle with two selected vertices has a boundary edge of the patch
        // (when the selected triangle on its other side exists, which holds on this cap).
        const int selected = int(mesh.atoms[f[0]] + mesh.atoms[f[1]] + mesh.atoms[f[2]]);
        if (selected == 2) ++crossing;
    }
    EXPECT_EQ(s.boundary_edges, crossing);
    EXPECT_GT(s.boundary_edges, 0u);
    for (std::uint32_t a : patch.atoms) EXPECT_EQ(a, 1u);
    expect_aligned(patch);
}

TEST(ExtractPatch, ThrowsWithoutAtomsOrWithAnAtomBeyondTheSelection) {
    Mesh mesh = strip();
    EXPECT_EQ(error_code_of([&] { extract_patch(mesh, {1, 1}); }), ErrorCode::InvalidArgument);
    mesh.atoms.clear();
    EXPECT_EQ(error_code_of([&] { extract_patch(mesh, {1, 1, 1}); }), ErrorCode::InvalidArgument);
    // An empty surface (nothing to map) has an empty patch.
    EXPECT_EQ(extract_patch(Mesh{}, {1}).vertex_count(), 0u);
    mesh = strip();
    mesh.colors.pop_back();
    EXPECT_EQ(error_code_of([&] { extract_patch(mesh, {1, 1, 1}); }), ErrorCode::InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// Operations that drop or add vertices

TEST(MeshAttributes, RemoveCavitiesKeepsAttributesAligned) {
    // An outer sphere, a cavity (inward sphere) inside it, and a second outer sphere: the
    // cavity's vertices sit between the others', so removing it shifts the later ones.
    Mesh mesh = test::icosphere(10.0, 2);
    test::append(mesh, test::turned_inside_out(test::icosphere(3.0, 2)));
    test::append(mesh, test::icosphere(2.0, 1, {30.0, 0.0, 0.0}));
    attach_attributes(mesh);
    const std::size_t cavity_vertices = test::icosphere(3.0, 2).vertex_count();
    const Mesh before = mesh;
    EXPECT_EQ(remove_cavities(mesh, 1e9), 1u);
    EXPECT_EQ(mesh.vertex_count(), before.vertex_count() - cavity_vertices);
    expect_aligned(mesh);
    EXPECT_TRUE(IsClosedManifold(mesh));
    // The first sphere's vertices kept their place; the last sphere's moved down.
    const std::size_t first = test::icosphere(10.0, 2).vertex_count();
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const std::size_t old = v < first ? v : v + cavity_vertices;
        EXPECT_EQ(mesh.atoms[v], before.atoms[old]);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.colors[3 * v + k], before.colors[3 * old + k]);
        EXPECT_EQ(mesh.scalars[0].values[v], before.scalars[0].values[old]);
    }
}

TEST(MeshAttributes, RemoveSpecksKeepsAttributesAligned) {
    Mesh mesh = test::icosphere(0.1, 1);  // a speck first
    test::append(mesh, test::icosphere(10.0, 2));
    attach_attributes(mesh);
    EXPECT_EQ(detail::remove_specks(mesh, 0.01), 1u);
    EXPECT_EQ(mesh.vertex_count(), test::icosphere(10.0, 2).vertex_count());
    expect_aligned(mesh);
}

TEST(MeshAttributes, RemoveCavitiesRejectsMisalignedAttributes) {
    Mesh mesh = test::icosphere(10.0, 1);
    attach_attributes(mesh);
    mesh.scalars[0].values.pop_back();
    EXPECT_EQ(error_code_of([&] { remove_cavities(mesh, 1e9); }), ErrorCode::InvalidArgument);
}

TEST(MeshAttributes, RefinementClearsAttributesItCannotKnow) {
    Mesh mesh = test::icosphere(5.0, 1);
    attach_attributes(mesh);
    detail::subdivide_butterfly(mesh);
    EXPECT_TRUE(mesh.atoms.empty());
    EXPECT_TRUE(mesh.colors.empty());
    EXPECT_TRUE(mesh.scalars.empty());
    EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
}

}  // namespace
}  // namespace fdmsurf
