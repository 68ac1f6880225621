// Tests of the GLB, STL and OFF writers and readers (src/io): round trips of a real surface
// (crambin, tests/data/1crn-fdm-0.5.ply) and of analytic meshes, the GLB read back by tinygltf
// itself, the byte layouts, the limits, streams, and meshstat.py as an independent reader.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "cli/json_check.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "io/formats.hpp"
#include "mesh/mesh_shapes.hpp"
#include "support/meshstat_tool.hpp"
#include "support/temp_folder.hpp"
#include "support/test_data.hpp"

namespace fdmsurf {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder per test, removed afterwards.
class FormatFiles : public test::TempFolderTest {
protected:
    FormatFiles() : TempFolderTest("fdmsurf_formats_") {}
};

template <typename F>
Error error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << "no fdmsurf::Error thrown";
    return Error(ErrorCode::Internal, "none");
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// Crambin's surface at 0.5 Å as fdmsurf computed it (positions and normals, closed), read once.
const Mesh& crambin() {
    static const Mesh mesh = read_mesh(test::data_path("1crn-fdm-0.5.ply"));
    return mesh;
}

// The same with every attribute: atoms, colours (every byte value) and two scalars.
Mesh attributed_crambin() {
    Mesh mesh = crambin();
    const std::size_t n = mesh.vertex_count();
    mesh.atoms.resize(n);
    mesh.colors.resize(3 * n);
    mesh.scalars = {{"coulombic", std::vector<float>(n)},
                    {"mean_curvature", std::vector<float>(n)}};
    for (std::size_t v = 0; v < n; ++v) {
        mesh.atoms[v] = std::uint32_t((v * 7) % 327);
        for (std::size_t k = 0; k < 3; ++k)
            mesh.colors[3 * v + k] = std::uint8_t((v + 85 * k) % 256);
        mesh.scalars[0].values[v] = -10.0f + 0.001f * float(v);
        mesh.scalars[1].values[v] = mesh.positions[3 * v] - mesh.positions[3 * v + 2];
    }
    return mesh;
}

// The triangles as position triples, for meshes whose vertices were renumbered (STL welding).
std::vector<std::array<float, 9>> triangle_positions(const Mesh& mesh) {
    std::vector<std::array<float, 9>> out(mesh.triangle_count());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        for (std::size_t k = 0; k < 3; ++k) {
            for (std::size_t c = 0; c < 3; ++c) {
                out[t][3 * k + c] = mesh.positions[3 * std::size_t{mesh.indices[3 * t + k]} + c];
            }
        }
    }
    return out;
}

void expect_same_geometry(const Mesh& expected, const Mesh& got) {
    EXPECT_EQ(got.positions, expected.positions);
    EXPECT_EQ(got.indices, expected.indices);
    const MeshStats a = compute_stats(expected);
    const MeshStats b = compute_stats(got);
    EXPECT_EQ(b.area, a.area);
    EXPECT_EQ(b.volume, a.volume);
    EXPECT_EQ(b.is_closed_manifold(), a.is_closed_manifold());
}

// ---------------------------------------------------------------------------------------------
// Extensions

TEST(MeshFormats, EveryExtensionChoosesItsFormatInAnyCase) {
    EXPECT_EQ(mesh_format_for_path("a.glb"), MeshFormat::Glb);
    EXPECT_EQ(mesh_format_for_path("dir.d/A.GLB"), MeshFormat::Glb);
    EXPECT_EQ(mesh_format_for_path("a.Stl"), MeshFormat::Stl);
    EXPECT_EQ(mesh_format_for_path("a.off"), MeshFormat::Off);
    EXPECT_EQ(mesh_format_for_path("a.ply"), MeshFormat::Ply);
    EXPECT_EQ(mesh_format_for_path("a.obj"), MeshFormat::Obj);
    for (MeshFormat f :
         {MeshFormat::Ply, MeshFormat::Obj, MeshFormat::Glb, MeshFormat::Stl, MeshFormat::Off}) {
        EXPECT_EQ(mesh_format_for_path(std::string("x") + mesh_format_extension(f)), f);
    }
    EXPECT_STREQ(mesh_format_extension(MeshFormat::Auto), "");
}

TEST(MeshFormats, UnknownExtensionListsEverySupportedOne) {
    for (const char* name : {"out.gltf", "out", "out.wrl"}) {
        const Error e = error_of([&] { mesh_format_for_path(name); });
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
        EXPECT_TRUE(contains(e.what(), ".ply, .obj, .glb, .stl or .off")) << e.what();
        EXPECT_TRUE(contains(e.what(), name)) << e.what();
    }
}

// ---------------------------------------------------------------------------------------------
// GLB

TEST_F(FormatFiles, GlbRoundTripsASurfaceWithEveryAttribute) {
    const Mesh mesh = attributed_crambin();
    write_mesh(mesh, path("c.glb"));
    const Mesh back = read_mesh(path("c.glb"));
    expect_same_geometry(mesh, back);
    ASSERT_EQ(back.normals.size(), mesh.normals.size());
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        ASSERT_NEAR(back.normals[i], mesh.normals[i], 1e-6f) << i;  // renormalized
    }
    EXPECT_EQ(back.colors, mesh.colors);
    EXPECT_EQ(back.atoms, mesh.atoms);
    ASSERT_EQ(back.scalars.size(), 2u);
    for (std::size_t s = 0; s < 2; ++s) {
        EXPECT_EQ(back.scalars[s].name, mesh.scalars[s].name);
        EXPECT_EQ(back.scalars[s].values, mesh.scalars[s].values);
    }
    EXPECT_TRUE(compute_stats(back).is_closed_manifold());
}

// tinygltf itself, not our reader: the accessors are what docs/formats.md says.
TEST_F(FormatFiles, GlbAsTinygltfReadsIt) {
    const Mesh mesh = attributed_crambin();
    write_mesh(mesh, path("c.glb"));
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path("c.glb"))) << err;
    EXPECT_EQ(err, "");
    EXPECT_EQ(model.asset.version, "2.0");
    EXPECT_TRUE(model.asset.generator.starts_with("fdmsurf ")) << model.asset.generator;
    ASSERT_EQ(model.meshes.size(), 1u);
    ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
    ASSERT_EQ(model.scenes.size(), 1u);
    EXPECT_EQ(model.scenes[0].nodes, std::vector<int>{0});
    EXPECT_EQ(model.nodes[0].mesh, 0);
    const tinygltf::Primitive& p = model.meshes[0].primitives[0];
    EXPECT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
    const std::size_t n = mesh.vertex_count();

    // The bytes of an accessor (tightly packed, as written).
    auto bytes = [&](int index, int component, int type, std::size_t count) {
        const tinygltf::Accessor& a = model.accessors.at(std::size_t(index));
        EXPECT_EQ(a.componentType, component);
        EXPECT_EQ(a.type, type);
        EXPECT_EQ(a.count, count);
        EXPECT_FALSE(a.normalized);
        const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(a.bufferView));
        EXPECT_EQ(view.byteStride, 0u);
        EXPECT_EQ((view.byteOffset + a.byteOffset) % 4, 0u);
        return model.buffers.at(std::size_t(view.buffer)).data.data() + view.byteOffset +
               a.byteOffset;
    };
    auto floats = [&](const std::string& attribute, int type, std::size_t components) {
        EXPECT_TRUE(p.attributes.count(attribute)) << attribute;
        std::vector<float> out(components * n);
        if (!p.attributes.count(attribute)) return out;
        std::memcpy(out.data(),
                    bytes(p.attributes.at(attribute), TINYGLTF_COMPONENT_TYPE_FLOAT, type, n),
                    4 * out.size());
        return out;
    };

    EXPECT_EQ(floats("POSITION", TINYGLTF_TYPE_VEC3, 3), mesh.positions);
    const tinygltf::Accessor& position =
        model.accessors.at(std::size_t(p.attributes.at("POSITION")));
    ASSERT_EQ(position.minValues.size(), 3u);
    ASSERT_EQ(position.maxValues.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (std::size_t v = 0; v < n; ++v) {
            lo = std::min(lo, mesh.positions[3 * v + k]);
            hi = std::max(hi, mesh.positions[3 * v + k]);
        }
        EXPECT_EQ(position.minValues[k], lo);
        EXPECT_EQ(position.maxValues[k], hi);
    }
    const std::vector<float> normals = floats("NORMAL", TINYGLTF_TYPE_VEC3, 3);
    for (std::size_t v = 0; v < n; ++v) {
        const double length = std::hypot(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        ASSERT_NEAR(length, 1.0, 1e-6) << v;
    }
    // COLOR_0 is linear: sRGB byte 0 and 255 are 0 and 1, 188 is about 0.5.
    const std::vector<float> color = floats("COLOR_0", TINYGLTF_TYPE_VEC3, 3);
    for (std::size_t i = 0; i < color.size(); ++i) {
        const std::uint8_t byte = mesh.colors[i];
        if (byte == 0) {
            ASSERT_EQ(color[i], 0.0f);
        } else if (byte == 255) {
            ASSERT_EQ(color[i], 1.0f);
        } else if (byte == 188) {
            ASSERT_NEAR(color[i], 0.5, 0.003);
        }
    }
    const std::vector<float> atoms = floats("_ATOM", TINYGLTF_TYPE_SCALAR, 1);
    for (std::size_t v = 0; v < n; ++v) ASSERT_EQ(atoms[v], float(mesh.atoms[v])) << v;
    EXPECT_EQ(floats("_COULOMBIC", TINYGLTF_TYPE_SCALAR, 1), mesh.scalars[0].values);
    EXPECT_EQ(floats("_MEAN_CURVATURE", TINYGLTF_TYPE_SCALAR, 1), mesh.scalars[1].values);

    std::vector<std::uint32_t> indices(mesh.indices.size());
    std::memcpy(indices.data(),
                bytes(p.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                      indices.size()),
                4 * indices.size());
    EXPECT_EQ(indices, mesh.indices);
    EXPECT_EQ(
        model.bufferViews.at(std::size_t(model.accessors.at(std::size_t(p.indices)).bufferView))
            .target,
        TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    EXPECT_EQ(model.bufferViews.at(std::size_t(position.bufferView)).target,
              TINYGLTF_TARGET_ARRAY_BUFFER);
}

// glTF's COLOR_0 is linear; every sRGB byte survives the way there and back.
TEST_F(FormatFiles, GlbColoursRoundTripEveryByteThroughLinearFloats) {
    Mesh mesh;
    for (int v = 0; v < 258; ++v) test::add_vertex(mesh, v, v % 7, v % 3);
    for (std::uint32_t t = 0; t + 2 < 258; t += 3)
        mesh.indices.insert(mesh.indices.end(), {t, t + 1, t + 2});
    for (int v = 0; v < 258; ++v) {
        for (int k = 0; k < 3; ++k) mesh.colors.push_back(std::uint8_t((v + 100 * k) % 256));
    }
    write_mesh(mesh, path("c.glb"));
    EXPECT_EQ(read_mesh(path("c.glb")).colors, mesh.colors);
}

TEST_F(FormatFiles, GlbOfAMeshWithoutAttributesHasPositionsAndIndicesOnly) {
    Mesh mesh = test::icosphere(2.0, 1);
    mesh.normals.clear();
    write_mesh(mesh, path("s.glb"));
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path("s.glb"))) << err;
    const auto& attributes = model.meshes.at(0).primitives.at(0).attributes;
    EXPECT_EQ(attributes.size(), 1u);
    EXPECT_TRUE(attributes.count("POSITION"));
    const Mesh back = read_mesh(path("s.glb"));
    expect_same_geometry(mesh, back);
    EXPECT_TRUE(back.normals.empty());
    EXPECT_TRUE(back.colors.empty());
    EXPECT_TRUE(back.atoms.empty());
    EXPECT_TRUE(back.scalars.empty());
}

// glTF requires unit normals: zero ones become their triangles' normal, others renormalized.
TEST_F(FormatFiles, GlbNormalsAreUnitEvenWhereTheMeshHasOthers) {
    Mesh mesh = test::icosphere(1.0, 1);
    for (float& n : mesh.normals) n *= 3.0f;
    for (int k = 0; k < 3; ++k) mesh.normals[k] = 0.0f;         // vertex 0
    mesh.normals[5] = std::numeric_limits<float>::quiet_NaN();  // vertex 1
    write_mesh(mesh, path("s.glb"));
    const Mesh back = read_mesh(path("s.glb"));
    ASSERT_EQ(back.normals.size(), mesh.normals.size());
    for (std::size_t v = 0; v < back.vertex_count(); ++v) {
        const float* n = &back.normals[3 * v];
        EXPECT_NEAR(std::hypot(n[0], n[1], n[2]), 1.0, 1e-6) << v;
        // Outward: along the position on this unit sphere around the origin.
        const float* p = &back.positions[3 * v];
        EXPECT_GT(n[0] * p[0] + n[1] * p[1] + n[2] * p[2], 0.9f) << v;
    }
}

TEST_F(FormatFiles, GlbOfNoTrianglesKeepsTheVerticesAndOfNothingIsEmpty) {
    Mesh points;
    points.positions = {1.0f, 2.0f, 3.0f, -1.0f, 0.5f, 2.0f};
    write_mesh(points, path("p.glb"));
    const Mesh back = read_mesh(path("p.glb"));
    EXPECT_EQ(back.positions, points.positions);
    EXPECT_TRUE(back.indices.empty());
    write_mesh(Mesh{}, path("e.glb"));
    const Mesh none = read_mesh(path("e.glb"));
    EXPECT_EQ(none.vertex_count(), 0u);
    EXPECT_EQ(none.triangle_count(), 0u);
}

TEST_F(FormatFiles, GlbLimitsAreCheckedBeforeAnythingIsCreated) {
    Mesh mesh = test::icosphere(1.0, 1);
    mesh.atoms.assign(mesh.vertex_count(), 16777216u);  // 2^24: still exact as float
    write_mesh(mesh, path("ok.glb"));
    EXPECT_EQ(read_mesh(path("ok.glb")).atoms, mesh.atoms);
    fs::remove(path("ok.glb"));

    auto refused = [&](const Mesh& bad, const std::string& mention) {
        const Error e = error_of([&] { write_mesh(bad, path("bad.glb")); });
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        EXPECT_TRUE(contains(e.what(), mention)) << e.what();
        EXPECT_TRUE(contains(e.what(), "bad.glb")) << e.what();
        EXPECT_TRUE(empty()) << mention;
    };
    Mesh beyond = mesh;
    beyond.atoms[3] = 16777217u;
    refused(beyond, "2^24");
    Mesh nan_scalar = mesh;
    nan_scalar.scalars = {{"coulombic", std::vector<float>(mesh.vertex_count(), 1.0f)}};
    nan_scalar.scalars[0].values[2] = std::numeric_limits<float>::quiet_NaN();
    refused(nan_scalar, "not finite");
    Mesh same_name = mesh;
    same_name.scalars = {{"abc", std::vector<float>(mesh.vertex_count())},
                         {"ABC", std::vector<float>(mesh.vertex_count())}};
    refused(same_name, "_ABC");
    Mesh atom_scalar = mesh;
    atom_scalar.scalars = {{"ATOM", std::vector<float>(mesh.vertex_count())}};
    refused(atom_scalar, "_ATOM");
    Mesh infinite = mesh;
    infinite.positions[4] = std::numeric_limits<float>::infinity();
    refused(infinite, "non-finite coordinate");
    // The same mesh is fine as PLY, which has room for all of it.
    write_mesh(beyond, path("fine.ply"));
}

// A node hierarchy of other tools: transforms applied to positions and normals, and a
// mirroring one turns the winding so that the volume stays positive.
TEST_F(FormatFiles, GlbReaderAppliesNodeTransforms) {
    const Mesh sphere = test::icosphere(1.0, 2);
    write_mesh(sphere, path("s.glb"));
    tinygltf::TinyGLTF gltf;
    tinygltf::Model model;
    std::string err, warn;
    ASSERT_TRUE(gltf.LoadBinaryFromFile(&model, &err, &warn, path("s.glb"))) << err;
    // Parent: translate (10, 0, 0); child: rotate 90° about z, scale (2, 2, -2) (a mirror).
    tinygltf::Node parent;
    parent.translation = {10.0, 0.0, 0.0};
    parent.children = {0};
    tinygltf::Node& child = model.nodes[0];
    const double h = std::sqrt(0.5);
    child.rotation = {0.0, 0.0, h, h};
    child.scale = {2.0, 2.0, -2.0};
    model.nodes.push_back(parent);
    model.scenes[0].nodes = {1};
    std::ostringstream bytes;
    ASSERT_TRUE(gltf.WriteGltfSceneToStream(&model, bytes, false, true));
    const Mesh moved = detail::parse_glb(bytes.str(), "moved.glb");
    ASSERT_EQ(moved.vertex_count(), sphere.vertex_count());
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        const float* p = &sphere.positions[3 * v];
        const float* q = &moved.positions[3 * v];
        // (x, y, z) -> scale (2x, 2y, -2z) -> rotate (-2y, 2x, -2z) -> translate
        ASSERT_NEAR(q[0], 10.0 - 2.0 * p[1], 1e-5) << v;
        ASSERT_NEAR(q[1], 2.0 * p[0], 1e-5) << v;
        ASSERT_NEAR(q[2], -2.0 * p[2], 1e-5) << v;
        // Still the outward normal of a sphere of radius 2 around (10, 0, 0).
        const float* n = &moved.normals[3 * v];
        ASSERT_NEAR(n[0], (q[0] - 10.0) / 2.0, 1e-5) << v;
        ASSERT_NEAR(n[1], q[1] / 2.0, 1e-5) << v;
        ASSERT_NEAR(n[2], q[2] / 2.0, 1e-5) << v;
    }
    const MeshStats stats = compute_stats(moved);
    EXPECT_NEAR(stats.volume, 8.0 * compute_stats(sphere).volume, 1e-4);
    EXPECT_TRUE(stats.is_closed_manifold());
}

TEST_F(FormatFiles, MalformedGlbThrowsFormatNamingTheFile) {
    write_mesh(test::icosphere(1.0, 1), path("s.glb"));
    const std::string good = read_file("s.glb");
    for (const std::string& bad :
         {std::string("glTF"), good.substr(0, good.size() / 2), std::string("glTF\x01\0\0\0", 8)}) {
        write_file("bad.glb", bad);
        const Error e = error_of([&] { read_mesh(path("bad.glb")); });
        EXPECT_EQ(e.code(), ErrorCode::Format);
        EXPECT_TRUE(contains(e.what(), "bad.glb")) << e.what();
    }
    write_file("text.glb", "not a glb at all\n");
    EXPECT_EQ(error_of([&] { read_mesh(path("text.glb")); }).code(), ErrorCode::Format);
}

// ---------------------------------------------------------------------------------------------
// STL

TEST_F(FormatFiles, StlIsBinaryWithAFaceNormalPerTriangle) {
    const Mesh mesh = test::icosphere(1.5, 1, {1.0, 2.0, 3.0});
    write_mesh(mesh, path("s.stl"));
    const std::string bytes = read_file("s.stl");
    ASSERT_EQ(bytes.size(), 84 + 50 * mesh.triangle_count());
    EXPECT_FALSE(bytes.starts_with("solid"));  // readers would take it for ASCII
    EXPECT_TRUE(bytes.starts_with("fdmsurf "));
    EXPECT_EQ(detail::get_le<std::uint32_t>(bytes.data() + 80), mesh.triangle_count());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const char* record = bytes.data() + 84 + 50 * t;
        float f[12];
        for (int k = 0; k < 12; ++k) f[k] = detail::get_le<float>(record + 4 * k);
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(f[3 + 3 * k + c],
                          mesh.positions[3 * std::size_t{mesh.indices[3 * t + k]} + c]);
            }
        }
        // Unit, and outward on this sphere: near the centroid's direction from the centre.
        const double centroid[3] = {(f[3] + f[6] + f[9]) / 3.0 - 1.0,
                                    (f[4] + f[7] + f[10]) / 3.0 - 2.0,
                                    (f[5] + f[8] + f[11]) / 3.0 - 3.0};
        const double length = std::hypot(centroid[0], centroid[1], centroid[2]);
        EXPECT_NEAR(std::hypot(f[0], f[1], f[2]), 1.0, 1e-6);
        EXPECT_GT((f[0] * centroid[0] + f[1] * centroid[1] + f[2] * centroid[2]) / length, 0.999);
        EXPECT_EQ(record[48], 0);
        EXPECT_EQ(record[49], 0);
    }
}

// STL repeats every corner; welding identical positions gives the mesh back, so area, volume
// and closedness are exactly those of the surface written.
TEST_F(FormatFiles, StlRoundTripOfASurfaceWeldsItBackExactly) {
    const Mesh mesh = crambin();
    write_mesh(mesh, path("c.stl"));
    const Mesh back = read_mesh(path("c.stl"));
    EXPECT_EQ(back.vertex_count(), mesh.vertex_count());
    EXPECT_EQ(back.triangle_count(), mesh.triangle_count());
    EXPECT_TRUE(back.normals.empty());
    EXPECT_EQ(triangle_positions(back), triangle_positions(mesh));
    const MeshStats a = compute_stats(mesh);
    const MeshStats b = compute_stats(back);
    EXPECT_EQ(b.area, a.area);
    EXPECT_EQ(b.volume, a.volume);
    EXPECT_EQ(b.pieces, a.pieces);
    EXPECT_EQ(b.euler_characteristic, a.euler_characteristic);
    EXPECT_TRUE(b.is_closed_manifold());
}

TEST_F(FormatFiles, ReadsAsciiStlWithSeveralSolidsAndWeldsCorners) {
    // A tetrahedron, outward, in two solids; -0 and 0 are the same corner.
    const std::string text =
        "solid first part\n"
        "  facet normal 0 0 -1\n    outer loop\n      vertex 0 0 0\n      vertex 0 1 0\n"
        "      vertex 1 0 0\n    endloop\n  endfacet\n"
        "  facet normal 0 -1 0\n    outer loop\n      vertex -0 0 0\n      vertex 1 0 0\n"
        "      vertex 0 0 1\n    endloop\n  endfacet\n"
        "endsolid first part\n"
        "solid\n"
        "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\n"
        "endfacet\n"
        "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 +1e0\nendloop\n"
        "endfacet\n"
        "endsolid\n";
    write_file("t.stl", text);
    const Mesh mesh = read_mesh(path("t.stl"));
    EXPECT_EQ(mesh.vertex_count(), 4u);
    EXPECT_EQ(mesh.triangle_count(), 4u);
    const MeshStats stats = compute_stats(mesh);
    EXPECT_TRUE(stats.is_closed_manifold());
    EXPECT_NEAR(stats.volume, 1.0 / 6.0, 1e-12);
    // Without the extension, by its text.
    write_file("t.mesh", text);
    EXPECT_EQ(read_mesh(path("t.mesh")).triangle_count(), 4u);
}

TEST_F(FormatFiles, MalformedStlThrowsFormatWithTheLine) {
    const std::string facet =
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
        "endfacet\n";
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 zero 0\n", "line 4: coordinate 'zero'"},
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nendloop\n",
         "line 5: expected 'vertex', found 'endloop'"},
        {"solid x\n" + facet, "line 9: expected 'facet' or 'endsolid', found the end"},
        {"solid x\nendsolid x\n", "without a single facet"},
        {"solid x\n" + facet + "endsolid x\ngarbage\n", "expected 'solid' or the end"},
        {std::string(84, ' ').replace(80, 4, std::string("\x02\0\0\0", 4)) + std::string(50, 'x'),
         "not a binary STL of 2 triangles (184 bytes) but 134 bytes"},
        {"tiny", "too short"},
    };
    for (const auto& [content, message] : bad) {
        write_file("bad.stl", content);
        const Error e = error_of([&] { read_mesh(path("bad.stl")); });
        EXPECT_EQ(e.code(), ErrorCode::Format) << e.what();
        EXPECT_TRUE(contains(e.what(), "bad.stl: ")) << e.what();
        EXPECT_TRUE(contains(e.what(), message)) << message << " not in: " << e.what();
    }
}

// ---------------------------------------------------------------------------------------------
// OFF

TEST_F(FormatFiles, OffRoundTripsPositionsExactlyAndColoursAsCoff) {
    Mesh mesh = attributed_crambin();
    write_mesh(mesh, path("c.off"));
    const std::string text = read_file("c.off");
    EXPECT_TRUE(text.starts_with("COFF\n" + std::to_string(mesh.vertex_count()) + " " +
                                 std::to_string(mesh.triangle_count()) + " 0\n"))
        << text.substr(0, 40);
    Mesh back = read_mesh(path("c.off"));
    expect_same_geometry(mesh, back);
    EXPECT_EQ(back.colors, mesh.colors);
    EXPECT_TRUE(back.normals.empty());  // OFF holds positions and faces only
    EXPECT_TRUE(back.atoms.empty());

    mesh.colors.clear();
    write_mesh(mesh, path("plain.off"));
    const std::string plain = read_file("plain.off");
    EXPECT_TRUE(plain.starts_with("OFF\n")) << plain.substr(0, 20);
    const std::string first_vertex = plain.substr(plain.find('\n', 4) + 1);
    EXPECT_EQ(std::count(first_vertex.begin(), first_vertex.begin() + first_vertex.find('\n'), ' '),
              2);
    back = read_mesh(path("plain.off"));
    expect_same_geometry(mesh, back);
    EXPECT_TRUE(back.colors.empty());
    // compare's reader takes the same files.
    expect_same_geometry(mesh, read_mesh_any(path("plain.off")));
}

TEST_F(FormatFiles, ReadsOtherToolsCoffColoursAsBytesOrFloats) {
    write_file("i.off",
               "COFF\n3 1 0\n0 0 0 255 0 10 255\n1 0 0 0 128 0 255\n0 1 0 1 2 3 4\n3 0 1 2\n");
    EXPECT_EQ(read_mesh(path("i.off")).colors,
              (std::vector<std::uint8_t>{255, 0, 10, 0, 128, 0, 1, 2, 3}));
    write_file("f.off", "COFF\n3 1 0\n0 0 0 1.0 0 0.5 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n");
    EXPECT_EQ(read_mesh(path("f.off")).colors,
              (std::vector<std::uint8_t>{255, 0, 128, 0, 255, 0, 0, 0, 255}));
    write_file("n.off",
               "CNOFF\n3 1 0\n0 0 0 0 0 1 9 8 7 255\n1 0 0 0 0 1 9 8 7 255\n"
               "0 1 0 0 0 1 9 8 7 255\n3 0 1 2\n");
    EXPECT_EQ(read_mesh(path("n.off")).colors,
              (std::vector<std::uint8_t>{9, 8, 7, 9, 8, 7, 9, 8, 7}));
    // A vertex without a colour: none at all.
    write_file("part.off", "COFF\n3 1 0\n0 0 0 1 2 3 255\n1 0 0\n0 1 0 1 2 3 255\n3 0 1 2\n");
    EXPECT_TRUE(read_mesh(path("part.off")).colors.empty());
}

// ---------------------------------------------------------------------------------------------
// Every format: files, streams, failures

TEST_F(FormatFiles, StreamBytesEqualFileBytesForEveryFormat) {
    const Mesh mesh = attributed_crambin();
    for (const detail::MeshFormatName& f : detail::kMeshFormats) {
        const std::string name = std::string("c").append(f.extension);
        write_mesh(mesh, path(name));
        std::ostringstream out;
        write_mesh(mesh, out, f.format, "the test stream");
        EXPECT_TRUE(out.str() == read_file(name)) << name;
    }
    std::ostringstream out;
    const Error e = error_of([&] { write_mesh(mesh, out, MeshFormat::Auto, "the test stream"); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_TRUE(contains(e.what(), "needs a format")) << e.what();
    EXPECT_EQ(out.str(), "");
}

// Accepts `limit` bytes, then fails as a closed pipe would.
class FailingBuffer : public std::streambuf {
public:
    explicit FailingBuffer(std::size_t limit) : limit_(limit) {}
    std::size_t written = 0;

protected:
    std::streamsize xsputn(const char*, std::streamsize n) override {
        if (written + std::size_t(n) > limit_) return 0;
        written += std::size_t(n);
        return n;
    }
    int_type overflow(int_type c) override {
        return xsputn(nullptr, 1) == 1 ? traits_type::not_eof(c) : traits_type::eof();
    }

private:
    std::size_t limit_;
};

TEST_F(FormatFiles, FailingStreamThrowsIoNamingItForEveryFormat) {
    const Mesh mesh = attributed_crambin();
    for (const detail::MeshFormatName& f : detail::kMeshFormats) {
        FailingBuffer buffer(100);
        std::ostream out(&buffer);
        const Error e = error_of([&] { write_mesh(mesh, out, f.format, "the pipe"); });
        EXPECT_EQ(e.code(), ErrorCode::Io) << f.name;
        EXPECT_TRUE(contains(e.what(), "cannot write the pipe")) << e.what();
    }
    // A stream that fails already: nothing is attempted.
    std::ostringstream bad;
    bad.setstate(std::ios::badbit);
    EXPECT_EQ(error_of([&] { write_mesh(mesh, bad, MeshFormat::Stl, "bad"); }).code(),
              ErrorCode::Io);
}

TEST_F(FormatFiles, EveryFormatIsWrittenAtomically) {
    const Mesh mesh = crambin();
    for (const detail::MeshFormatName& f : detail::kMeshFormats) {
        const std::string name = std::string("c").append(f.extension);
        write_file(name, "old contents");
        write_mesh(mesh, path(name));
        EXPECT_NE(read_file(name), "old contents");
        // Into a folder that does not exist: Io, nothing created.
        const Error e = error_of([&] { write_mesh(mesh, path("missing/" + name)); });
        EXPECT_EQ(e.code(), ErrorCode::Io) << name;
    }
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(dir_)) files.push_back(entry.path().filename());
    EXPECT_EQ(files.size(), detail::kMeshFormats.size()) << "a temporary file was left";
}

TEST_F(FormatFiles, CompareReadsGlbAndStl) {
    const Mesh mesh = crambin();
    write_mesh(mesh, path("c.glb"));
    write_mesh(mesh, path("c.stl"));
    expect_same_geometry(mesh, read_mesh_any(path("c.glb")));
    const Mesh stl = read_mesh_any(path("c.stl"));
    EXPECT_EQ(triangle_positions(stl), triangle_positions(mesh));
}

// meshstat.py, an independent reader, on the formats it reads (STL, OFF; not GLB).
TEST_F(FormatFiles, MeshstatReadsStlAndOffWithTheSameAreaAndVolume) {
    FDMSURF_REQUIRE_MESHSTAT();
    const Mesh mesh = attributed_crambin();
    const MeshStats ours = compute_stats(mesh);
    for (const char* name : {"c.stl", "c.off"}) {
        write_mesh(mesh, path(name));
        std::string text;
        const auto stats = test::meshstat_stats(path(name), text);
        ASSERT_TRUE(stats.has_value()) << name << ": " << text;
        for (const char* key : {"area", "volume", "vertices", "triangles"}) {
            ASSERT_NE(stats->find(key), nullptr) << key << " in " << text;
        }
        EXPECT_NEAR(stats->find("area")->number, ours.area, 1e-9 * ours.area) << name;
        EXPECT_NEAR(stats->find("volume")->number, ours.volume, 1e-9 * ours.volume) << name;
        EXPECT_EQ(stats->find("vertices")->number, double(mesh.vertex_count())) << name;
        EXPECT_EQ(stats->find("triangles")->number, double(mesh.triangle_count())) << name;
    }
}

}  // namespace
}  // namespace fdmsurf
