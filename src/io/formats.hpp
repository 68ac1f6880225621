// Internals of the mesh formats beyond PLY and OBJ (GLB, STL, OFF): the byte sinks every writer
// writes to, the table of formats by extension, their limits, writers and readers.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// Where a writer's bytes go: a file renamed into place (AtomicFile) or a std::ostream
// (StreamSink). write() throws Error(Io) naming the destination on any failure.
class ByteSink {
public:
    virtual ~ByteSink() = default;
    virtual void write(const void* data, std::size_t size) = 0;
    void write(std::string_view text) { write(text.data(), text.size()); }
};

// Bytes to a std::ostream through a chunk buffer, so that the writers' many small records cost
// one stream call per chunk. A failed stream write throws Error(Io, "cannot write <name>: ...")
// at once (an exception the stream itself throws, an fdmsurf::Error from the CLI's standard
// output, passes unchanged); finish() writes what is left and flushes. Not copyable.
class StreamSink final : public ByteSink {
public:
    StreamSink(std::ostream& out, std::string name);
    StreamSink(const StreamSink&) = delete;
    StreamSink& operator=(const StreamSink&) = delete;

    using ByteSink::write;
    void write(const void* data, std::size_t size) override;
    void finish();

private:
    void drain();
    [[noreturn]] void fail(const std::string& reason) const;

    std::ostream& out_;
    std::string name_;
    std::vector<char> chunk_;
    std::size_t used_ = 0;
};

// Stores the little-endian bytes of a 4-byte value at `out` and returns the end; a plain copy
// on little-endian hosts.
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

// The 4-byte value whose little-endian bytes start at `in`.
template <typename T>
T get_le(const char* in) {
    static_assert(sizeof(T) == 4);
    std::uint32_t bits;
    std::memcpy(&bits, in, 4);
    if constexpr (std::endian::native == std::endian::big) {
        bits = (bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) | (bits << 24);
    }
    return std::bit_cast<T>(bits);
}

struct MeshFormatName {
    MeshFormat format;
    std::string_view extension;  // lower case, with its dot
    std::string_view name;       // as --output-format spells it
};

inline constexpr std::array<MeshFormatName, 5> kMeshFormats{{
    {MeshFormat::Ply, ".ply", "ply"},
    {MeshFormat::Obj, ".obj", "obj"},
    {MeshFormat::Glb, ".glb", "glb"},
    {MeshFormat::Stl, ".stl", "stl"},
    {MeshFormat::Off, ".off", "off"},
}};

// ".ply, .obj, .glb, .stl or .off": for messages.
std::string supported_extensions();

// The GLB attribute of a scalar: "_" and its name in upper case ("_MEAN_CURVATURE").
std::string glb_attribute_name(std::string_view scalar_name);

// Format-specific limits, checked before a byte is written: PLY's int32 indices; for GLB finite
// positions and scalars (JSON has no NaN, glTF allows none), atom indices exact as float
// (at most 2^24), attribute names unique once upper-cased, and a file under 4 GiB. Throws
// Error(InvalidArgument) naming `name`. The mesh has been validated (validate_mesh and
// validate_attributes).
void check_format_limits(const Mesh& mesh, MeshFormat format, const std::string& name);

// Writers; the mesh has been validated and checked.
// OFF: "OFF" (or "COFF" with colours), counts, x y z [r g b 255] per vertex, "3 a b c" faces.
void write_off(const Mesh& mesh, ByteSink& sink);
// Binary STL: 80-byte header, uint32 count, per triangle its normal, 3 corners and uint16 0.
void write_stl(const Mesh& mesh, ByteSink& sink);
// glTF 2.0 binary through tinygltf (docs/formats.md lists the attributes).
void write_glb(const Mesh& mesh, ByteSink& sink);

// Readers of a whole file's bytes (`path` for messages); throw Error(Format).
// STL: binary (by its size: 84 + 50 × the count) or ASCII; corners with identical positions
// welded into one vertex, no normals.
Mesh parse_stl(std::string_view data, const std::string& path);
// GLB: every triangle primitive of the default scene (node transforms applied), or of every
// mesh when there is no scene; NORMAL, COLOR_0, _ATOM and _NAME scalars when every primitive
// has them.
Mesh parse_glb(std::string_view data, const std::string& path);

// A glTF binary by its magic ("glTF").
bool is_glb(std::string_view data);
// A binary STL by its size (84 + 50 × the count in bytes 80-83).
bool is_binary_stl(std::string_view data);
// An ASCII STL: "solid" and, later, "facet".
bool is_ascii_stl(std::string_view data);

}  // namespace fdmsurf::detail
