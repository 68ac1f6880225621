// Triangle meshes: the surface as plain arrays, their statistics, and the writers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace fdmsurf {

// One named float per vertex ("coulombic", "mean_curvature", ...).
struct VertexScalars {
    std::string name;
    std::vector<float> values;
};

// positions and normals: 3 floats per vertex (Å; unit normals pointing out of the molecule).
// indices: 3 per triangle, counter-clockwise seen from outside. normals may be empty.
// atoms: per vertex, the index into the input's Atoms of the atom the vertex belongs to (least
// power distance; docs/properties.md); empty when not known (a mesh read from a file without
// it). colors: r, g, b per vertex (sRGB, 0-255); empty when uncoloured. scalars: each with one
// value per vertex. Every operation that drops or reorders vertices carries all of them along.
struct Mesh {
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint32_t> atoms;
    std::vector<std::uint8_t> colors;
    std::vector<VertexScalars> scalars;
    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

struct MeshStats {
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    double area = 0.0;    // Å²
    double volume = 0.0;  // Å³, signed (divergence theorem): cavities count negative
    std::size_t pieces = 0;             // connected components (by shared vertices)
    std::size_t closed_pieces = 0;      // pieces without boundary or non-manifold edges
    std::size_t boundary_edges = 0;     // edges used by one triangle
    std::size_t nonmanifold_edges = 0;  // edges used by more than two triangles
    std::size_t nonmanifold_vertices = 0;  // vertices whose triangles form more than one fan
    std::size_t inconsistent_edges = 0;    // edges whose two triangles disagree on orientation
    std::size_t degenerate_triangles = 0;  // a vertex index repeated
    long euler_characteristic = 0;         // V - E + F
    // Closed, manifold, consistently oriented, positive volume.
    bool is_closed_manifold() const;
};

MeshStats compute_stats(const Mesh& mesh);

// Per-piece statistics (same definitions as MeshStats), largest area first.
std::vector<MeshStats> piece_stats(const Mesh& mesh);

// Removes cavities: connected pieces whose signed volume is negative (inward-facing shells)
// and whose enclosed volume is below `max_volume` (Å³; infinity removes every cavity). Vertex
// and triangle order of the rest is kept. Returns the number of pieces removed.
std::size_t remove_cavities(Mesh& mesh, double max_volume);

// The open patch of `mesh` on the selected atoms: the triangles whose three vertices belong to
// atoms with a non-zero `selected` entry (mesh.atoms indexes it), with their vertices (order
// kept) and every per-vertex attribute. Throws Error(InvalidArgument) when mesh.atoms is empty.
Mesh extract_patch(const Mesh& mesh, const std::vector<std::uint8_t>& selected);

// Auto: from the path's extension. Formats and their contents: docs/mesh.md, docs/formats.md.
enum class MeshFormat { Auto, Ply, Obj, Glb, Stl, Off };

// Writes binary little-endian PLY (positions, normals, `uint atom` when mesh.atoms is set,
// `uchar red green blue` when coloured, one float property per scalar, triangles), OBJ
// (v x y z [r g b], vn, f v//vn), GLB (glTF 2.0 binary: POSITION, NORMAL, COLOR_0, _ATOM and
// one _NAME per scalar, UNSIGNED_INT indices), binary STL (a normal per face, no shared
// vertices, no attributes) or OFF (COFF when coloured), chosen by the path's extension (.ply,
// .obj, .glb, .stl, .off, any case) unless `format` says. Writes to a temporary file in the
// same folder and renames it: on failure no file is left at `path`. Throws Error (Io,
// InvalidArgument: an unknown extension, a malformed mesh, or one the format cannot hold, e.g.
// GLB with an atom index above 2^24 or a non-finite scalar), checked before anything is created.
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format = MeshFormat::Auto);

// The same bytes to a stream (std::cout for a pipe); `format` must not be Auto, `name`
// ("standard output") names the stream in messages. Everything is checked before the first
// byte; a stream that fails while being written throws Error(Io, "cannot write <name>: ...")
// (an fdmsurf::Error the stream itself throws passes unchanged), and what was written before
// stays written. The stream is flushed, not closed.
void write_mesh(const Mesh& mesh, std::ostream& out, MeshFormat format, const std::string& name);

// The format write_mesh would use for `path`; throws Error(InvalidArgument), listing every
// supported extension, for any other.
MeshFormat mesh_format_for_path(const std::string& path);

// ".ply", ".obj", ".glb", ".stl" or ".off"; "" for Auto.
const char* mesh_format_extension(MeshFormat format) noexcept;

// Reads PLY (ASCII or binary), OBJ, GLB, STL (binary or ASCII; identical corners welded into
// shared vertices) or OFF written by fdmsurf or another tool; for tests and tools.
Mesh read_mesh(const std::string& path);

}  // namespace fdmsurf
