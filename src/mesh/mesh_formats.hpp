// Internals of the mesh formats beyond PLY and OBJ (GLB, STL, OFF) and of the choice of a reader.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// Bytes to a std::ostream through a chunk buffer, so that the writers' many small records cost
// one stream call per chunk. Every failed stream write throws Error(Io, "cannot write <name>:
// ...") at once; finish() writes what is left and flushes the stream. Not copyable.
class StreamSink {
public:
    StreamSink(std::ostream& out, std::string name);
    StreamSink(const StreamSink&) = delete;
    StreamSink& operator=(const StreamSink&) = delete;

    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }
    void finish();
    [[noreturn]] void fail() const;

private:
    void drain();

    std::ostream& out_;
    std::string name_;
    std::vector<char> chunk_;
};

// Format-specific limits, checked before anything is written: PLY's int32 indices, STL's uint32
// triangle count, GLB's 4 GiB, finite positions and atoms exact as float. Throw
// Error(InvalidArgument) naming `name`.
void check_format_limits(const Mesh& mesh, MeshFormat format, const std::string& name);

// Writers; the mesh has been validated. `name` is for messages (the path or "output stream").
void write_off(const Mesh& mesh, StreamSink& sink);
void write_stl(const Mesh& mesh, StreamSink& sink);
void write_glb(const Mesh& mesh, std::ostream& out, const std::string& name);

// Parsers of a whole file's bytes (`path` for messages); throw Error(Format).
Mesh parse_stl(std::string_view data, const std::string& path);
Mesh parse_glb(std::string_view data, const std::string& path);

// True when `data` is a binary STL by its size (84 + 50 × the count in bytes 80-83).
bool is_binary_stl(std::string_view data);

// Picks the parser for a file's bytes: PLY and GLB by their magic, then OBJ, STL, OFF and GLB
// by `extension` (lower case, with its dot), else OFF by its first word and STL by its size or
// its "solid ... facet" text. Throws Error(Format) for anything else.
Mesh parse_mesh_data(std::string_view data, const std::string& path, const std::string& extension);

}  // namespace fdmsurf::detail
