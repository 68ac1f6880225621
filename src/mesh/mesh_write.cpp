// Mesh writers: binary little-endian PLY (with atoms, colours and scalars per vertex) and OBJ
// (with vertex colours); the choice of format, handing GLB, STL and OFF to src/formats/, and
// the destination: an atomically renamed file or a stream.
#include <charconv>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "fdmsurf/mesh.hpp"
#include "formats/formats.hpp"
#include "mesh/atomic_file.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {
namespace detail {
namespace {

void write_ply(const Mesh& mesh, ByteSink& file) {
    const bool normals = !mesh.normals.empty();
    const bool atoms = !mesh.atoms.empty();
    const bool colors = !mesh.colors.empty();
    std::string header = "ply\nformat binary_little_endian 1.0\n";
    header += "comment written by fdmsurf " + std::string(version()) + "\n";
    header += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (atoms) header += "property uint atom\n";
    if (colors) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    for (const VertexScalars& scalar : mesh.scalars) {
        header += "property float " + scalar.name + "\n";
    }
    header += "element face " + std::to_string(mesh.triangle_count()) + "\n";
    header += "property list uchar int vertex_indices\nend_header\n";
    file.write(header);

    // One vertex record: 24 bytes of position and normal, 4 of atom, 3 of colour, 4 per scalar.
    std::vector<char> record(24 + 4 + 3 + 4 * mesh.scalars.size());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        char* out = record.data();
        for (int k = 0; k < 3; ++k) out = put_le(out, mesh.positions[3 * v + k]);
        if (normals) {
            for (int k = 0; k < 3; ++k) out = put_le(out, mesh.normals[3 * v + k]);
        }
        if (atoms) out = put_le(out, mesh.atoms[v]);
        if (colors) {
            for (int k = 0; k < 3; ++k) *out++ = char(mesh.colors[3 * v + k]);
        }
        for (const VertexScalars& scalar : mesh.scalars) out = put_le(out, scalar.values[v]);
        file.write(record.data(), std::size_t(out - record.data()));
    }
    char face[13];
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        char* out = face;
        *out++ = 3;
        for (int k = 0; k < 3; ++k) out = put_le(out, std::int32_t(mesh.indices[3 * t + k]));
        file.write(face, std::size_t(out - face));
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

void write_obj(const Mesh& mesh, ByteSink& file) {
    const bool normals = !mesh.normals.empty();
    const bool colors = !mesh.colors.empty();
    file.write("# written by fdmsurf " + std::string(version()) + "\n# " +
               std::to_string(mesh.vertex_count()) + " vertices, " +
               std::to_string(mesh.triangle_count()) + " triangles\n");
    // Fixed notation of a float needs at most 39 integer digits, so 6 numbers fit easily; the
    // margin leaves room for the separators written after a number.
    char line[384];
    char* const end = line + sizeof line - 8;
    auto start = [&](const char* tag) {
        char* out = line;
        for (const char* c = tag; *c; ++c) *out++ = *c;
        return out;
    };
    auto finish = [&](char* out) {
        *out++ = '\n';
        file.write(line, std::size_t(out - line));
    };
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        char* out = start("v");
        for (int k = 0; k < 3; ++k) out = put_fixed(out, end, mesh.positions[3 * v + k]);
        // Vertex colours as the common extension MeshLab and Blender read: v x y z r g b, each
        // channel in [0, 1] (6 decimals: c / 255 reads back to the same byte).
        if (colors) {
            for (int k = 0; k < 3; ++k) out = put_fixed(out, end, mesh.colors[3 * v + k] / 255.0f);
        }
        finish(out);
    }
    if (normals) {
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            char* out = start("vn");
            for (int k = 0; k < 3; ++k) out = put_fixed(out, end, mesh.normals[3 * v + k]);
            finish(out);
        }
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        char* out = start("f");
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
        finish(out);
    }
}

// Every check a format needs, before anything is created or written.
void check_for_writing(const Mesh& mesh, MeshFormat format, const std::string& name) {
    validate_mesh(mesh, "write_mesh", true);
    validate_attributes(mesh, "write_mesh");
    check_format_limits(mesh, format, name);
}

void write_format(const Mesh& mesh, MeshFormat format, ByteSink& sink) {
    switch (format) {
        case MeshFormat::Ply:
            write_ply(mesh, sink);
            return;
        case MeshFormat::Obj:
            write_obj(mesh, sink);
            return;
        case MeshFormat::Glb:
            write_glb(mesh, sink);
            return;
        case MeshFormat::Stl:
            write_stl(mesh, sink);
            return;
        case MeshFormat::Off:
            write_off(mesh, sink);
            return;
        case MeshFormat::Auto:
            break;
    }
    throw Error(ErrorCode::Internal, "write_mesh: no format chosen");
}

}  // namespace
}  // namespace detail

MeshFormat mesh_format_for_path(const std::string& path) {
    const std::string ext = detail::lowercase_extension(path);
    for (const detail::MeshFormatName& f : detail::kMeshFormats) {
        if (ext == f.extension) return f.format;
    }
    throw Error(ErrorCode::InvalidArgument,
                (ext.empty() ? "no extension" : "unknown output format '" + ext + "'") + " for " +
                    path + " (use " + detail::supported_extensions() + ")");
}

const char* mesh_format_extension(MeshFormat format) noexcept {
    for (const detail::MeshFormatName& f : detail::kMeshFormats) {
        if (f.format == format) return f.extension.data();
    }
    return "";
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format) {
    if (format == MeshFormat::Auto) format = mesh_format_for_path(path);
    detail::check_for_writing(mesh, format, path);
    detail::AtomicFile file(path);
    detail::write_format(mesh, format, file);
    file.commit();
}

void write_mesh(const Mesh& mesh, std::ostream& out, MeshFormat format, const std::string& name) {
    if (format == MeshFormat::Auto) {
        throw Error(ErrorCode::InvalidArgument, "write_mesh: writing to " + name +
                                                    " needs a format (" +
                                                    detail::supported_extensions() + "), not Auto");
    }
    detail::check_for_writing(mesh, format, name);
    detail::StreamSink sink(out, name);
    detail::write_format(mesh, format, sink);
    sink.finish();
}

}  // namespace fdmsurf
