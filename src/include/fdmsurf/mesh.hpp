// Triangle meshes: the surface as plain arrays, their statistics, and the writers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fdmsurf {

// positions and normals: 3 floats per vertex (Å; unit normals pointing out of the molecule).
// indices: 3 per triangle, counter-clockwise seen from outside. normals may be empty.
struct Mesh {
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<std::uint32_t> indices;
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

enum class MeshFormat { Auto, Ply, Obj };

// Writes binary little-endian PLY (positions, normals, triangles) or OBJ, chosen by the path's
// extension (.ply, .obj) unless `format` says. Writes to a temporary file in the same folder
// and renames it: on failure no file is left at `path`. Throws Error (Io, InvalidArgument).
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format = MeshFormat::Auto);

// The format write_mesh would use for `path`; throws Error(InvalidArgument) for an unknown
// extension.
MeshFormat mesh_format_for_path(const std::string& path);

// Reads PLY (ASCII or binary) or OBJ written by fdmsurf or another tool; for tests and tools.
Mesh read_mesh(const std::string& path);

}  // namespace fdmsurf
