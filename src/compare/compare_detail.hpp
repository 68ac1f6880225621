// Internals of compare_meshes, exposed for the tests: welding, pieces, exact closest points.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "base/vec3.hpp"
#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// A mesh after clean_mesh: no triangle repeats a vertex, every vertex is used by a triangle.
// Positions stay float, as in Mesh (welding picks positions, it computes none); every
// computation on them is in double.
struct CleanMesh {
    std::vector<float> positions;        // 3 per vertex, Å
    std::vector<std::uint32_t> indices;  // 3 per triangle
    std::size_t welded = 0;              // vertices merged into another
    std::size_t collapsed = 0;           // triangles dropped because welding repeated a vertex
    std::size_t unreferenced = 0;        // vertices dropped because no triangle used them
    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

// meshstat.py's clean_mesh: vertices within `tolerance` (Å) are merged transitively (0: exact
// duplicates only; < 0: none), each class keeping the position of its lowest-index vertex;
// then collapsed triangles and unused vertices are dropped, keeping the order of the rest.
// Throws Error(InvalidArgument) for malformed arrays, Error(Format) for non-finite positions.
CleanMesh clean_mesh(const Mesh& mesh, double tolerance);

// The piece (triangles joined through shared vertices) of largest area, unused vertices dropped.
CleanMesh largest_piece(const CleanMesh& mesh);

// Mean area of the triangles around each vertex (Giard & Macq's weight), Å².
std::vector<double> vertex_weights(const CleanMesh& mesh);

double mesh_area(const CleanMesh& mesh);
double mesh_volume(const CleanMesh& mesh);

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5);
// a degenerate triangle is treated as its three edges.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct ClosestPoint {
    double distance = 0;         // Å
    Vec3 point{};                // the closest point of the mesh
    std::uint32_t triangle = 0;  // the triangle holding it (CleanMesh order)
};

// Exact closest points of `mesh` to each of `points` (3 doubles each), through a bounding-volume
// hierarchy. Among triangles at the same distance the one with the nearest centroid wins (the
// order meshstat's KD-tree over centroids gives), then the lowest-numbered. `threads` 0: all
// hardware threads.
std::vector<ClosestPoint> closest_points(const CleanMesh& mesh, const std::vector<double>& points,
                                         unsigned threads = 0);
// The distances alone (Å), to points given as floats (a mesh's positions): a fifth of the
// memory written.
std::vector<double> closest_distances(const CleanMesh& mesh, const std::vector<float>& points,
                                      unsigned threads = 0);

// The same by testing every triangle: O(points x triangles), for the tests.
std::vector<ClosestPoint> closest_points_brute_force(const CleanMesh& mesh,
                                                     const std::vector<double>& points);

}  // namespace fdmsurf::detail
