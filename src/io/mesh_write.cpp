// Mesh writers: binary little-endian PLY (with atoms, colours and scalars per vertex) and OBJ
// (with vertex colours); the choice of format, handing GLB, STL and OFF to their writers beside it, and
// the destination: an atomically renamed file or a stream.
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <future>
#include <ostream>
#include <string>
#include <vector>

#include "base/parallel.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "fdmsurf/mesh.hpp"
#include "io/formats.hpp"
#include "io/atomic_file.hpp"
#include "mesh/mesh_attributes.hpp"
#include "io/mesh_io.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {
namespace detail {
namespace {

// Serialises items [0, count), `block` items per task, and writes the bytes to `file` in item
// order: rounds of one block per thread, each round written on a thread of its own while the
// next is serialised by the other threads (two rounds' bytes in memory, whatever the mesh).
// serialise(first, last, out) appends the bytes of items [first, last).
template <class Serialise>
void write_in_blocks(ByteSink& file, std::size_t count, std::size_t block, Serialise&& serialise) {
    const unsigned threads = thread_count();
    // One thread of the machine's is the writer's: no more threads busy than cores.
    const unsigned serialisers = std::max(1u, threads - 1);
    std::vector<std::string> bytes[2] = {std::vector<std::string>(threads),
                                         std::vector<std::string>(threads)};
    std::future<void> writing;
    int side = 0;
    for (std::size_t first = 0; first < count; first += block * threads, side ^= 1) {
        const std::size_t blocks = std::min<std::size_t>(threads, (count - first + block - 1) / block);
        std::vector<std::string>& round = bytes[side];
        parallel_chunks(blocks, serialisers, [&](std::size_t k) {
            const std::size_t lo = first + k * block, hi = std::min(count, lo + block);
            round[k].clear();
            serialise(lo, hi, round[k]);
        });
        if (writing.valid()) writing.get();  // the round before, in order
        writing = std::async(std::launch::async, [&file, &round, blocks] {
            for (std::size_t k = 0; k < blocks; ++k) file.write(round[k]);
        });
    }
    if (writing.valid()) writing.get();
}

// Items per serialisation task: 65,536 vertices (about 2 MB of PLY) or triangles.
constexpr std::size_t kWriteBlock = std::size_t{1} << 16;

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

    // One vertex record: 12 bytes of position, 12 of normal, 4 of atom, 3 of colour, 4 per
    // scalar.
    const std::size_t record =
        12 + (normals ? 12 : 0) + (atoms ? 4 : 0) + (colors ? 3 : 0) + 4 * mesh.scalars.size();
    write_in_blocks(file, mesh.vertex_count(), kWriteBlock,
                    [&](std::size_t first, std::size_t last, std::string& bytes) {
        bytes.resize((last - first) * record);
        char* out = bytes.data();
        for (std::size_t v = first; v < last; ++v) {
            for (int k = 0; k < 3; ++k) out = put_le(out, mesh.positions[3 * v + k]);
            if (normals) {
                for (int k = 0; k < 3; ++k) out = put_le(out, mesh.normals[3 * v + k]);
            }
            if (atoms) out = put_le(out, mesh.atoms[v]);
            if (colors) {
                for (int k = 0; k < 3; ++k) *out++ = char(mesh.colors[3 * v + k]);
            }
            for (const VertexScalars& scalar : mesh.scalars) out = put_le(out, scalar.values[v]);
        }
    });
    write_in_blocks(file, mesh.triangle_count(), kWriteBlock,
                    [&](std::size_t first, std::size_t last, std::string& bytes) {
        bytes.resize((last - first) * 13);
        char* out = bytes.data();
        for (std::size_t t = first; t < last; ++t) {
            *out++ = 3;
            for (int k = 0; k < 3; ++k) out = put_le(out, std::int32_t(mesh.indices[3 * t + k]));
        }
    });
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
    // Fixed notation of a float needs at most 39 integer digits plus 7 for the sign, point and
    // decimals, so a line of 6 numbers stays under kLine; the margin leaves room for the
    // separators written after a number.
    constexpr std::size_t kLine = 384;
    // Lines of items [first, last) appended to `bytes`, each formatted by put_line(out, end, i)
    // into a line buffer of the worst case's size and appended at its real length (a typical
    // line is 30-70 bytes: the block is reserved for 64 per line).
    auto lines = [](std::size_t first, std::size_t last, std::string& bytes, auto&& put_line) {
        bytes.reserve((last - first) * 64);
        char line[kLine];
        for (std::size_t i = first; i < last; ++i) {
            char* out = put_line(line, line + kLine - 8, i);
            *out++ = '\n';
            bytes.append(line, std::size_t(out - line));
        }
    };
    auto tag = [](char* out, const char* t) {
        for (const char* c = t; *c; ++c) *out++ = *c;
        return out;
    };
    write_in_blocks(file, mesh.vertex_count(), kWriteBlock,
                    [&](std::size_t first, std::size_t last, std::string& bytes) {
        lines(first, last, bytes, [&](char* out, char* end, std::size_t v) {
            out = tag(out, "v");
            for (int k = 0; k < 3; ++k) out = put_fixed(out, end, mesh.positions[3 * v + k]);
            // Vertex colours as the common extension MeshLab and Blender read: v x y z r g b,
            // each channel in [0, 1] (6 decimals: c / 255 reads back to the same byte).
            if (colors) {
                for (int k = 0; k < 3; ++k)
                    out = put_fixed(out, end, mesh.colors[3 * v + k] / 255.0f);
            }
            return out;
        });
    });
    if (normals) {
        write_in_blocks(file, mesh.vertex_count(), kWriteBlock,
                        [&](std::size_t first, std::size_t last, std::string& bytes) {
            lines(first, last, bytes, [&](char* out, char* end, std::size_t v) {
                out = tag(out, "vn");
                for (int k = 0; k < 3; ++k) out = put_fixed(out, end, mesh.normals[3 * v + k]);
                return out;
            });
        });
    }
    write_in_blocks(file, mesh.triangle_count(), kWriteBlock,
                    [&](std::size_t first, std::size_t last, std::string& bytes) {
        lines(first, last, bytes, [&](char* out, char* end, std::size_t t) {
            out = tag(out, "f");
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t i = std::uint64_t{mesh.indices[3 * t + k]} + 1;  // 1-based
                *out++ = ' ';
                out = put_index(out, end, i);
                if (normals) {
                    *out++ = '/';
                    *out++ = '/';
                    out = put_index(out, end, i);
                }
            }
            return out;
        });
    });
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
