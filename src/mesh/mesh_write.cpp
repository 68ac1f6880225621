// Mesh writers: binary little-endian PLY and OBJ, through an atomically renamed file.
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/atomic_file.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {
namespace detail {
namespace {

// Appends the little-endian bytes of a 4-byte value; a no-op copy on little-endian hosts.
template <typename T>
char* put_le(char* out, T value) {
    static_assert(sizeof(T) == 4);
    auto bits = std::bit_cast<std::uint32_t>(value);
    if constexpr (std::endian::native == std::endian::big) {
        bits = (bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) | (bits << 24);
    }
    std::memcpy(out, &bits, 4);
    return out + 4;
}

void write_ply(const Mesh& mesh, AtomicFile& file) {
    const bool normals = !mesh.normals.empty();
    std::string header = "ply\nformat binary_little_endian 1.0\n";
    header += "comment written by fdmsurf " + std::string(version()) + "\n";
    header += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    header += "element face " + std::to_string(mesh.triangle_count()) + "\n";
    header += "property list uchar int vertex_indices\nend_header\n";
    file.write(header);

    char record[24];
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        char* out = record;
        for (int k = 0; k < 3; ++k) out = put_le(out, mesh.positions[3 * v + k]);
        if (normals) {
            for (int k = 0; k < 3; ++k) out = put_le(out, mesh.normals[3 * v + k]);
        }
        file.write(record, std::size_t(out - record));
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        char* out = record;
        *out++ = 3;
        for (int k = 0; k < 3; ++k) out = put_le(out, std::int32_t(mesh.indices[3 * t + k]));
        file.write(record, std::size_t(out - record));
    }
}

// Six decimals: 1e-6 Å, far below any grid spacing, and exact enough for unit normals.
char* put_fixed(char* out, char* end, float value) {
    *out++ = ' ';
    return std::to_chars(out, end, value, std::chars_format::fixed, 6).ptr;
}

char* put_index(char* out, char* end, std::uint64_t value) {
    return std::to_chars(out, end, value).ptr;
}

void write_obj(const Mesh& mesh, AtomicFile& file) {
    const bool normals = !mesh.normals.empty();
    file.write("# written by fdmsurf " + std::string(version()) + "\n# " +
               std::to_string(mesh.vertex_count()) + " vertices, " +
               std::to_string(mesh.triangle_count()) + " triangles\n");
    // Fixed notation of a float needs at most 39 integer digits, so 3 numbers fit easily; the
    // margin leaves room for the separators written after a number.
    char line[256];
    char* const end = line + sizeof line - 8;
    auto put_vector = [&](const char* tag, const std::vector<float>& values, std::size_t v) {
        char* out = line;
        for (const char* c = tag; *c; ++c) *out++ = *c;
        for (int k = 0; k < 3; ++k) out = put_fixed(out, end, values[3 * v + k]);
        *out++ = '\n';
        file.write(line, std::size_t(out - line));
    };
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) put_vector("v", mesh.positions, v);
    if (normals) {
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) put_vector("vn", mesh.normals, v);
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        char* out = line;
        *out++ = 'f';
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t i = std::uint64_t{mesh.indices[3 * t + k]} + 1;  // OBJ is 1-based
            *out++ = ' ';
            out = put_index(out, end, i);
            if (normals) {
                *out++ = '/';
                *out++ = '/';
                out = put_index(out, end, i);
            }
        }
        *out++ = '\n';
        file.write(line, std::size_t(out - line));
    }
}

}  // namespace
}  // namespace detail

MeshFormat mesh_format_for_path(const std::string& path) {
    const std::string ext = detail::lowercase_extension(path);
    if (ext == ".ply") return MeshFormat::Ply;
    if (ext == ".obj") return MeshFormat::Obj;
    throw Error(ErrorCode::InvalidArgument,
                "unknown output format '" + ext + "' for " + path + " (use .ply or .obj)");
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format) {
    detail::validate_mesh(mesh, "write_mesh", true);
    if (format == MeshFormat::Auto) format = mesh_format_for_path(path);
    // PLY indices are signed 32-bit ints.
    if (format == MeshFormat::Ply &&
        mesh.vertex_count() > std::size_t(std::numeric_limits<std::int32_t>::max())) {
        throw Error(ErrorCode::InvalidArgument, "write_mesh: too many vertices for PLY: " + path);
    }
    detail::AtomicFile file(path);
    if (format == MeshFormat::Ply) {
        detail::write_ply(mesh, file);
    } else {
        detail::write_obj(mesh, file);
    }
    file.commit();
}

}  // namespace fdmsurf
