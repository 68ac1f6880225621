// Tests of write_mesh and read_mesh: round trips, other tools' files, atomic writes, bad input.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "base/parallel.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_shapes.hpp"
#include "support/mesh_checks.hpp"
#include "support/temp_folder.hpp"
#include "io/atomic_file.hpp"

namespace fdmsurf {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder per test, removed afterwards.
class MeshFiles : public test::TempFolderTest {
protected:
    MeshFiles() : TempFolderTest("fdmsurf_mesh_") {}

    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir_)) {
            names.push_back(entry.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        return names;
    }
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

template <typename F>
std::string error_message_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "no fdmsurf::Error thrown";
    return "";
}

// Appends a value in the given byte order, for hand-made binary PLY files.
template <typename T>
void put(std::string& out, T value, bool big_endian = false) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (big_endian != (std::endian::native == std::endian::big)) {
        std::reverse(bytes, bytes + sizeof(T));
    }
    out.append(bytes, sizeof(T));
}

Mesh small_sphere() { return test::icosphere(1.5, 2, {10.25, -3.5, 7.0}); }

TEST(MeshFormat, ExtensionChoosesTheFormatInAnyCase) {
    EXPECT_EQ(mesh_format_for_path("out.ply"), MeshFormat::Ply);
    EXPECT_EQ(mesh_format_for_path("dir.d/OUT.PLY"), MeshFormat::Ply);
    EXPECT_EQ(mesh_format_for_path("a.b.Obj"), MeshFormat::Obj);
}

TEST(MeshFormat, UnknownExtensionThrowsInvalidArgument) {
    for (const char* name : {"out.vrml", "out", "ply", "dir.ply/out"}) {
        EXPECT_EQ(error_code_of([&] { mesh_format_for_path(name); }), ErrorCode::InvalidArgument)
            << name;
    }
    EXPECT_NE(error_message_of([] {
                  mesh_format_for_path("x.wrl");
              }).find("use .ply, .obj, .glb, .stl or .off"),
              std::string::npos);
}

TEST_F(MeshFiles, PlyRoundTripIsExact) {
    const Mesh mesh = small_sphere();
    write_mesh(mesh, path("sphere.ply"));
    const Mesh back = read_mesh(path("sphere.ply"));
    EXPECT_EQ(back.positions, mesh.positions);
    EXPECT_EQ(back.normals, mesh.normals);
    EXPECT_EQ(back.indices, mesh.indices);
    EXPECT_TRUE(IsClosedManifold(back));
    EXPECT_EQ(listing(), std::vector<std::string>{"sphere.ply"});
}

TEST_F(MeshFiles, PlyWithoutNormalsRoundTrips) {
    Mesh mesh = small_sphere();
    mesh.normals.clear();
    write_mesh(mesh, path("sphere.PLY"));
    const Mesh back = read_mesh(path("sphere.PLY"));
    EXPECT_EQ(back.positions, mesh.positions);
    EXPECT_TRUE(back.normals.empty());
    EXPECT_EQ(back.indices, mesh.indices);
}

TEST_F(MeshFiles, PlyIsBinaryLittleEndianWithTheDocumentedHeader) {
    const Mesh mesh = small_sphere();
    write_mesh(mesh, path("sphere.ply"));
    const std::string bytes = read_file("sphere.ply");
    const std::size_t body = bytes.find("end_header\n") + 11;
    const std::string header = bytes.substr(0, body);
    EXPECT_TRUE(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    EXPECT_NE(header.find("element vertex " + std::to_string(mesh.vertex_count()) +
                          "\nproperty float x\nproperty float y\nproperty float z\n"
                          "property float nx\nproperty float ny\nproperty float nz\n"
                          "element face " +
                          std::to_string(mesh.triangle_count()) +
                          "\nproperty list uchar int vertex_indices\n"),
              std::string::npos);
    EXPECT_EQ(bytes.size(), body + 24 * mesh.vertex_count() + 13 * mesh.triangle_count());
    float x = 0;
    std::memcpy(&x, bytes.data() + body, 4);
    if constexpr (std::endian::native == std::endian::little) {
        EXPECT_EQ(x, mesh.positions[0]);
    }
}

TEST_F(MeshFiles, ObjRoundTripIsWithinAMicroAngstrom) {
    const Mesh mesh = small_sphere();
    write_mesh(mesh, path("sphere.obj"));
    const Mesh back = read_mesh(path("sphere.obj"));
    ASSERT_EQ(back.positions.size(), mesh.positions.size());
    ASSERT_EQ(back.normals.size(), mesh.normals.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_NEAR(back.positions[i], mesh.positions[i], 1e-5);
        EXPECT_NEAR(back.normals[i], mesh.normals[i], 1e-5);
    }
    EXPECT_EQ(back.indices, mesh.indices);
    const std::string text = read_file("sphere.obj");
    const std::uint32_t a = mesh.indices[0] + 1, b = mesh.indices[1] + 1, c = mesh.indices[2] + 1;
    const std::string first_face = "f " + std::to_string(a) + "//" + std::to_string(a) + " " +
                                   std::to_string(b) + "//" + std::to_string(b) + " " +
                                   std::to_string(c) + "//" + std::to_string(c) + "\n";
    EXPECT_NE(text.find(first_face), std::string::npos);
}

// The writers serialise blocks of 65,536 vertices or triangles on all threads, one block per
// thread per round; a mesh of more than one round on this machine (whatever its thread count)
// must read back in order: every vertex at its own index, every triangle its own.
Mesh strip_of_rounds() {
    const std::size_t threads = detail::thread_count();
    const std::size_t n = (std::size_t{1} << 16) * (threads + 1) + 777;
    Mesh mesh;
    mesh.positions.resize(3 * n);
    mesh.normals.resize(3 * n);
    mesh.atoms.resize(n);
    mesh.colors.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        // Distinct positions (a helix of pitch 0.01 A per vertex) and colours per vertex.
        const double a = 0.05 * double(i);
        mesh.positions[3 * i + 0] = float(20.0 * std::cos(a));
        mesh.positions[3 * i + 1] = float(20.0 * std::sin(a));
        mesh.positions[3 * i + 2] = float(0.01 * double(i % 100000));
        mesh.normals[3 * i + 0] = float(std::cos(a));
        mesh.normals[3 * i + 1] = float(std::sin(a));
        mesh.atoms[i] = std::uint32_t(i % 4099);
        for (int k = 0; k < 3; ++k) mesh.colors[3 * i + k] = std::uint8_t((i >> (4 * k)) & 255);
    }
    for (std::size_t i = 0; i + 2 < n; ++i) {
        const bool odd = i % 2;
        mesh.indices.insert(mesh.indices.end(),
                            {std::uint32_t(i), std::uint32_t(i + (odd ? 2 : 1)),
                             std::uint32_t(i + (odd ? 1 : 2))});
    }
    return mesh;
}

TEST_F(MeshFiles, WritersKeepTheOrderAcrossBlocksAndRounds) {
    const Mesh mesh = strip_of_rounds();
    ASSERT_GT(mesh.triangle_count(), (std::size_t{1} << 16) * detail::thread_count());
    write_mesh(mesh, path("strip.ply"));
    const Mesh ply = read_mesh(path("strip.ply"));
    EXPECT_EQ(ply.positions, mesh.positions);
    EXPECT_EQ(ply.normals, mesh.normals);
    EXPECT_EQ(ply.atoms, mesh.atoms);
    EXPECT_EQ(ply.colors, mesh.colors);
    EXPECT_EQ(ply.indices, mesh.indices);

    write_mesh(mesh, path("strip.obj"));
    const Mesh obj = read_mesh(path("strip.obj"));
    ASSERT_EQ(obj.positions.size(), mesh.positions.size());
    ASSERT_EQ(obj.normals.size(), mesh.normals.size());
    std::size_t far = 0;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        far += std::abs(obj.positions[i] - mesh.positions[i]) > 1e-5f ||
               std::abs(obj.normals[i] - mesh.normals[i]) > 1e-5f;
    }
    EXPECT_EQ(far, 0u) << "coordinates out of place in the OBJ";
    EXPECT_EQ(obj.colors, mesh.colors);
    EXPECT_EQ(obj.indices, mesh.indices);
}

TEST_F(MeshFiles, ObjWithoutNormalsWritesPlainFaces) {
    Mesh mesh = small_sphere();
    mesh.normals.clear();
    write_mesh(mesh, path("sphere.obj"));
    const std::string text = read_file("sphere.obj");
    EXPECT_EQ(text.find("vn "), std::string::npos);
    EXPECT_EQ(text.find("//"), std::string::npos);
    const Mesh back = read_mesh(path("sphere.obj"));
    EXPECT_TRUE(back.normals.empty());
    EXPECT_EQ(back.indices, mesh.indices);
}

TEST_F(MeshFiles, ExplicitFormatOverridesTheExtension) {
    write_mesh(small_sphere(), path("sphere.dat"), MeshFormat::Ply);
    EXPECT_TRUE(read_file("sphere.dat").starts_with("ply\n"));
}

TEST_F(MeshFiles, EmptyMeshRoundTrips) {
    write_mesh(Mesh{}, path("empty.ply"));
    write_mesh(Mesh{}, path("empty.obj"));
    EXPECT_EQ(read_mesh(path("empty.ply")).vertex_count(), 0u);
    EXPECT_EQ(read_mesh(path("empty.obj")).triangle_count(), 0u);
}

TEST_F(MeshFiles, WritingReplacesAnExistingFileAndLeavesNoTemporary) {
    write_file("sphere.ply", "old contents");
    write_mesh(small_sphere(), path("sphere.ply"));
    EXPECT_EQ(read_mesh(path("sphere.ply")).indices, small_sphere().indices);
    EXPECT_EQ(listing(), std::vector<std::string>{"sphere.ply"});
}

TEST_F(MeshFiles, NonexistentFolderThrowsIoAndLeavesNoFile) {
    const std::string target = path("missing/sphere.ply");
    const std::string message = error_message_of([&] { write_mesh(small_sphere(), target); });
    EXPECT_NE(message.find("cannot write " + target), std::string::npos) << message;
    EXPECT_EQ(error_code_of([&] { write_mesh(small_sphere(), target); }), ErrorCode::Io);
    EXPECT_FALSE(fs::exists(target));
    EXPECT_TRUE(listing().empty());
}

TEST_F(MeshFiles, PathThatIsAFolderThrowsIoAndLeavesNoTemporary) {
    fs::create_directory(path("taken.obj"));
    EXPECT_EQ(error_code_of([&] { write_mesh(small_sphere(), path("taken.obj")); }), ErrorCode::Io);
    EXPECT_TRUE(fs::is_directory(path("taken.obj")));
    EXPECT_TRUE(fs::is_empty(path("taken.obj")));
    EXPECT_EQ(listing(), std::vector<std::string>{"taken.obj"});
}

TEST_F(MeshFiles, ASymbolicLinkIsFollowedAndStays) {
    write_file("target.ply", "old contents");
    fs::create_symlink("target.ply", path("link.ply"));
    write_mesh(small_sphere(), path("link.ply"));
    EXPECT_TRUE(fs::is_symlink(path("link.ply")));
    EXPECT_EQ(read_mesh(path("target.ply")).indices, small_sphere().indices);
    // A link to a file not there yet: the file is made where it points.
    fs::create_symlink("new.ply", path("dangling.ply"));
    write_mesh(small_sphere(), path("dangling.ply"));
    EXPECT_TRUE(fs::is_symlink(path("dangling.ply")));
    EXPECT_TRUE(fs::is_regular_file(path("new.ply")));
    EXPECT_EQ(listing(),
              (std::vector<std::string>{"dangling.ply", "link.ply", "new.ply", "target.ply"}));
}

TEST_F(MeshFiles, ASymbolicLinkLoopIsAnErrorAndReplacesNothing) {
    fs::create_symlink("b.ply", path("a.ply"));
    fs::create_symlink("a.ply", path("b.ply"));
    const std::string message = error_message_of([&] { write_mesh(small_sphere(), path("a.ply")); });
    EXPECT_NE(message.find("symbolic links"), std::string::npos) << message;
    EXPECT_TRUE(fs::is_symlink(path("a.ply")));
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.ply", "b.ply"}));
}

TEST_F(MeshFiles, AReplacedFileKeepsItsPermissions) {
    write_file("private.ply", "old contents");
    fs::permissions(path("private.ply"), fs::perms::owner_read | fs::perms::owner_write);
    write_mesh(small_sphere(), path("private.ply"));
    EXPECT_EQ(fs::status(path("private.ply")).permissions(),
              fs::perms::owner_read | fs::perms::owner_write);
    EXPECT_EQ(read_mesh(path("private.ply")).indices, small_sphere().indices);
}

TEST_F(MeshFiles, ANamedPipeIsWrittenThroughNotReplaced) {
    const std::string fifo = path("pipe.off");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] {
        std::ifstream in(fifo, std::ios::binary);
        received.assign(std::istreambuf_iterator<char>(in), {});
    });
    write_mesh(small_sphere(), fifo);
    reader.join();
    EXPECT_EQ(fs::status(fifo).type(), fs::file_type::fifo);
    EXPECT_EQ(received.rfind("OFF", 0), 0u) << received.substr(0, 40);
    EXPECT_EQ(listing(), std::vector<std::string>{"pipe.off"});
}

TEST_F(MeshFiles, ACommitGroupRenamesItsFilesTogetherOrNone) {
    {
        detail::CommitGroup group;
        write_mesh(small_sphere(), path("a.ply"));
        write_mesh(small_sphere(), path("b.ply"));
        EXPECT_FALSE(fs::exists(path("a.ply")));  // not before the group's commit
        group.commit();
    }
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.ply", "b.ply"}));
    // A folder appears at the second path after its file was written: neither is renamed,
    // no temporary file is left.
    fs::remove(path("a.ply"));
    fs::remove(path("b.ply"));
    {
        detail::CommitGroup group;
        write_mesh(small_sphere(), path("a.ply"));
        write_mesh(small_sphere(), path("b.ply"));
        fs::create_directory(path("b.ply"));
        EXPECT_EQ(error_code_of([&] { group.commit(); }), ErrorCode::Io);
    }
    EXPECT_EQ(listing(), std::vector<std::string>{"b.ply"});
    // A rename that fails after others puts back the file they replaced and removes the file
    // they made; no temporary or kept file is left.
    fs::remove(path("b.ply"));
    {
        std::ofstream(path("a.ply")) << "old";
        detail::CommitGroup group;
        write_mesh(small_sphere(), path("a.ply"));
        write_mesh(small_sphere(), path("c.ply"));
        write_mesh(small_sphere(), path("b.ply"));
        std::string stale;
        for (const std::string& name : listing()) {
            // b's temporary file goes: its rename fails.
            if (name.starts_with("b.ply.tmp.")) fs::remove(path(name));
            // A stale file holds the first name a's kept link would take: another is taken.
            if (name.starts_with("a.ply.tmp.")) stale = "a.ply.old." + name.substr(10);
        }
        ASSERT_FALSE(stale.empty());
        std::ofstream(path(stale)) << "stale";
        try {
            group.commit();
            ADD_FAILURE() << "the commit did not throw";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::Io);
            EXPECT_NE(std::string(e.what()).find("b.ply: No such file or directory"),
                      std::string::npos)
                << e.what();
        }
        EXPECT_EQ(listing(), (std::vector<std::string>{"a.ply", stale}));
        std::ifstream in(path("a.ply"));
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "old");
        EXPECT_EQ(fs::file_size(path(stale)), 5u);  // untouched
        fs::remove(path(stale));
    }
    EXPECT_EQ(listing(), std::vector<std::string>{"a.ply"});
    // Without a failure, the kept files go too.
    {
        detail::CommitGroup group;
        write_mesh(small_sphere(), path("a.ply"));
        write_mesh(small_sphere(), path("c.ply"));
        group.commit();
    }
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.ply", "c.ply"}));
    EXPECT_GT(fs::file_size(path("a.ply")), 3u);
    // Left without commit (an exception on the way): nothing.
    fs::remove(path("a.ply"));
    fs::remove(path("c.ply"));
    {
        detail::CommitGroup group;
        write_mesh(small_sphere(), path("c.ply"));
    }
    EXPECT_TRUE(listing().empty());
    // Nested: the inner commit hands its files to the outer group; after the outer commit,
    // files are renamed as without a group.
    {
        detail::CommitGroup outer;
        {
            detail::CommitGroup inner;
            write_mesh(small_sphere(), path("d.ply"));
            inner.commit();
        }
        EXPECT_FALSE(fs::exists(path("d.ply")));  // still under its temporary name
        outer.commit();
        EXPECT_EQ(listing(), std::vector<std::string>{"d.ply"});
        write_mesh(small_sphere(), path("e.ply"));
        EXPECT_EQ(listing(), (std::vector<std::string>{"d.ply", "e.ply"}));
    }
    EXPECT_EQ(listing(), (std::vector<std::string>{"d.ply", "e.ply"}));
}

TEST_F(MeshFiles, UnknownExtensionThrowsInvalidArgumentAndCreatesNothing) {
    EXPECT_EQ(error_code_of([&] { write_mesh(small_sphere(), path("sphere.wrl")); }),
              ErrorCode::InvalidArgument);
    EXPECT_TRUE(listing().empty());
}

TEST_F(MeshFiles, InvalidMeshThrowsInvalidArgumentAndCreatesNothing) {
    Mesh mesh = small_sphere();
    mesh.indices.push_back(0);  // not a multiple of 3
    EXPECT_EQ(error_code_of([&] { write_mesh(mesh, path("bad.ply")); }),
              ErrorCode::InvalidArgument);
    mesh = small_sphere();
    mesh.normals.pop_back();
    EXPECT_EQ(error_code_of([&] { write_mesh(mesh, path("bad.ply")); }),
              ErrorCode::InvalidArgument);
    EXPECT_TRUE(listing().empty());
}

TEST_F(MeshFiles, ReadsAsciiPlySkippingOtherPropertiesAndSplittingQuads) {
    const std::string file = write_file("quad.ply",
                                        "ply\r\n"
                                        "format ascii 1.0\r\n"
                                        "comment made by hand\r\n"
                                        "element vertex 5\r\n"
                                        "property double confidence\r\n"
                                        "property float x\r\n"
                                        "property float y\r\n"
                                        "property float z\r\n"
                                        "property uchar red\r\n"
                                        "property list uchar int extra\r\n"
                                        "element face 2\r\n"
                                        "property uchar flags\r\n"
                                        "property list uchar int vertex_indices\r\n"
                                        "element edge 1\r\n"
                                        "property int vertex1\r\n"
                                        "property int vertex2\r\n"
                                        "end_header\r\n"
                                        "0.5 0 0 0 255 0\r\n"
                                        "0.5 1 0 0 255 2 7 8\r\n"
                                        "0.5 1 1 0 255 0\r\n"
                                        "0.5 0 1 0 255 1 9\r\n"
                                        "0.5 +0.5 0.5 1.5e0 255 0\r\n"
                                        "3 4 0 1 2 3\r\n"
                                        "0 3 0 1 4\r\n"
                                        "0 1\r\n");
    const Mesh mesh = read_mesh(file);
    EXPECT_EQ(mesh.positions,
              (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 1.5f}));
    EXPECT_TRUE(mesh.normals.empty());
    EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 1, 4}));
}

TEST_F(MeshFiles, ReadsBinaryPlyInEitherByteOrderWithOtherTypes) {
    for (const bool big : {false, true}) {
        std::string bytes = std::string("ply\nformat ") +
                            (big ? "binary_big_endian" : "binary_little_endian") +
                            " 1.0\n"
                            "element vertex 4\n"
                            "property double x\nproperty double y\nproperty double z\n"
                            "property short tag\n"
                            "property float nx\nproperty float ny\nproperty float nz\n"
                            "element face 1\n"
                            "property list int uint vertex_index\n"
                            "end_header\n";
        const double xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
        for (const auto& p : xyz) {
            for (double c : p) put(bytes, c, big);
            put(bytes, std::int16_t(-7), big);
            for (float n : {0.0f, 0.0f, 1.0f}) put(bytes, n, big);
        }
        put(bytes, std::int32_t(4), big);
        for (std::uint32_t i : {0u, 1u, 2u, 3u}) put(bytes, i, big);
        const Mesh mesh = read_mesh(write_file("square.ply", bytes));
        EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0}));
        EXPECT_EQ(mesh.normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}));
        EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    }
}

TEST_F(MeshFiles, ReadsObjCornerFormsNegativeIndicesAndPolygons) {
    const std::string file = write_file("shapes.obj",
                                        "# made by hand\n"
                                        "mtllib none.mtl\n"
                                        "o square\n"
                                        "v 0 0 0\n"
                                        "v 1 0 0 1.0\n"
                                        "v 1 1 0\n"
                                        "v 0 1 0\n"
                                        "vt 0 0\n"
                                        "vn 0 0 1\n"
                                        "s off\n"
                                        "f 1 2 3\n"
                                        "f 1/1 3/1 4/1\r\n"
                                        "f 1//1 2//1 3//1\n"
                                        "f -4/1/1 -3/1/1 -2/1/1 -1/1/1\n"
                                        "l 1 2\n");
    const Mesh mesh = read_mesh(file);
    EXPECT_EQ(mesh.vertex_count(), 4u);
    EXPECT_EQ(mesh.indices,
              (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 1, 2, 0, 2, 3}));
    EXPECT_TRUE(mesh.normals.empty());  // some corners have no vn: normals are dropped
}

TEST_F(MeshFiles, ReadsObjNormalsWhenEachVertexHasOne) {
    const std::string file = write_file("tri.obj",
                                        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                        "vn 0 0 1\nvn 0 0 1\n"
                                        "f 1//1 2//2 3//1\n");
    EXPECT_EQ(read_mesh(file).normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}));
}

TEST_F(MeshFiles, MissingFileThrowsIo) {
    EXPECT_EQ(error_code_of([&] { read_mesh(path("absent.ply")); }), ErrorCode::Io);
    EXPECT_NE(error_message_of([&] { read_mesh(path("absent.ply")); }).find("absent.ply"),
              std::string::npos);
}

TEST_F(MeshFiles, TruncatedBinaryPlyThrowsFormatNamingTheFile) {
    write_mesh(small_sphere(), path("sphere.ply"));
    const std::string bytes = read_file("sphere.ply");
    const std::string file = write_file("cut.ply", bytes.substr(0, bytes.size() - 5));
    EXPECT_EQ(error_code_of([&] { read_mesh(file); }), ErrorCode::Format);
    EXPECT_NE(error_message_of([&] { read_mesh(file); }).find("cut.ply"), std::string::npos);
}

TEST_F(MeshFiles, MalformedPlyThrowsFormat) {
    const std::string vertex3 =
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
    const std::vector<std::string> bad = {
        "ply\nformat ascii 1.0\n" + vertex3,  // no end_header
        "ply\nformat ascii 2.0\n" + vertex3 + "end_header\n0 0 0 1 0 0 0 1 0\n",
        "ply\n" + vertex3 + "end_header\n0 0 0 1 0 0 0 1 0\n",  // no format
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n0 0 0\n",
        "ply\nformat ascii 1.0\nbogus line\n" + vertex3 + "end_header\n",
        "ply\nformat ascii 1.0\n" + vertex3 + face + "end_header\n0 0 0 1 0 0 0 1 x\n3 0 1 2\n",
        "ply\nformat ascii 1.0\n" + vertex3 + face + "end_header\n0 0 0 1 0 0 0 1 0\n3 0 1 3\n",
        "ply\nformat ascii 1.0\n" + vertex3 + face + "end_header\n0 0 0 1 0 0 0 1 0\n3 0 -1 2\n",
        "ply\nformat ascii 1.0\n" + vertex3 + face + "end_header\n0 0 0 1 0 0 0 1 0\n2 0 1\n",
        "ply\nformat ascii 1.0\n" + vertex3 + face + "end_header\n0 0 0 1 0 0 0 1 0\n",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
        "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000\n"
        "property float x\nproperty float y\nproperty float z\nend_header\n0123456789",
    };
    for (std::size_t i = 0; i < bad.size(); ++i) {
        const std::string file = write_file("bad" + std::to_string(i) + ".ply", bad[i]);
        EXPECT_EQ(error_code_of([&] { read_mesh(file); }), ErrorCode::Format) << bad[i];
    }
}

TEST_F(MeshFiles, MalformedObjThrowsFormatWithTheLine) {
    const std::vector<std::string> bad = {
        "v 0 0\n",                             // too few coordinates
        "v 0 0 zero\n",                        // not a number
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",  // too few corners
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",  // no vn defined
    };
    for (std::size_t i = 0; i < bad.size(); ++i) {
        const std::string file = write_file("bad" + std::to_string(i) + ".obj", bad[i]);
        EXPECT_EQ(error_code_of([&] { read_mesh(file); }), ErrorCode::Format) << bad[i];
    }
    const std::string file = write_file("line.obj", "# ok\nv 0 0 0\nv 0 0 zero\n");
    EXPECT_NE(error_message_of([&] { read_mesh(file); }).find("line.obj: line 3"),
              std::string::npos);
}

TEST_F(MeshFiles, UnrecognisedFileThrowsFormat) {
    const std::string file = write_file("mesh.stl", "solid nothing\nendsolid\n");
    EXPECT_EQ(error_code_of([&] { read_mesh(file); }), ErrorCode::Format);
}

}  // namespace
}  // namespace fdmsurf
