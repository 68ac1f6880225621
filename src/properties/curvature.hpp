// Discrete curvature per vertex of a triangle mesh: mean and Gaussian curvature and the shape
// index (properties: VertexProperty::MeanCurvature, GaussianCurvature, ShapeIndex).
//
// M. Meyer, M. Desbrun, P. Schröder and A. H. Barr, "Discrete differential-geometry operators
// for triangulated 2-manifolds", Visualization and Mathematics III, Springer 2003, 35-57:
// the mean-curvature normal from the cotangent Laplacian and the Gaussian curvature from the
// angle deficit, both over the vertex's mixed Voronoi area. Shape index: J. J. Koenderink and
// A. J. van Doorn, "Surface shape and curvature scales", Image and Vision Computing 10 (1992).
#pragma once

#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// One value per vertex of the mesh.
// mean: H, 1/Å, positive where the surface is convex seen from the side its normals point to (a
// sphere of radius R with outward normals: +1/R). gaussian: K, 1/Å² (sphere: 1/R²).
// shape_index: S = (2/π) atan((k1 + k2) / (k1 - k2)) with k1,2 = H ± sqrt(max(H² - K, 0)),
// in [-1, 1]: +1 convex cap, 0.5 ridge, 0 saddle, -0.5 rut, -1 concave cup; at an umbilic
// (k1 = k2) ±1 by the sign of H, and 0 where H = K = 0 (flat, where S is undefined).
struct VertexCurvature {
    std::vector<float> mean, gaussian, shape_index;
};

// Meyer et al. (2003). Per vertex i, over its triangles:
// - mixed area A: the Voronoi area 1/8 (|PR|² cot Q + |PQ|² cot R) of each non-obtuse triangle
//   PQR at P, and of an obtuse triangle area/2 at the obtuse corner, area/4 at the others (so the
//   areas add up to the mesh's area; vertex_mixed_area);
// - mean-curvature normal Kn = 1/(2A) Σ_j (cot α_ij + cot β_ij)(x_i - x_j) = 2 H n, and
//   H = ±|Kn|/2, + when Kn points the way of the vertex normal;
// - K = (2π - Σ θ) / A, θ the triangles' angles at i.
// The vertex normal is the mesh's (mesh.normals, when one per vertex), else the area-weighted
// sum of the adjacent triangles' normals. On a closed mesh Σ K_i A_i = 2π χ exactly (discrete
// Gauss-Bonnet).
// Boundary vertices (on an edge of one triangle; open meshes, patches) have no full ring, and
// the half ring's estimates are poor on a jagged border (the angle deficit then measures the
// border's turning more than the surface's curvature). So a boundary vertex takes the mean of
// the H and K of its interior neighbours (S from those); one with no interior neighbour keeps
// its half ring's values: H = (Kn · n)/2 (the projection drops the tangential part that the
// missing triangles would have cancelled) and K = (π - Σ θ) / A (the deficit against a half
// disc, 0 on a straight border of a flat patch). Triangles of zero area add their angles but no
// area or cotangent weight; a vertex without area (unused, or only in such triangles) gets
// H = K = S = 0 unless it is on a border. Non-manifold edges are used as they come.
// smoothing_passes (default 0: none): that many passes of an area-weighted mean of H and K over
// each vertex's triangles' vertices (itself included), S from the smoothed H and K; Σ K_i A_i
// is then no longer exact. On marching-cubes meshes the per-vertex estimates are noisy (slivers
// give vertices tiny areas): on a sphere of radius 10 Å at 0.5 Å spacing the RMS of H about
// 1/R is 0.090 1/Å unsmoothed, 0.015 after 1 pass, 0.006 after 3 (tests/properties).
// Throws Error(InvalidArgument) for malformed positions, normals or indices, or
// smoothing_passes < 0.
VertexCurvature vertex_curvature(const Mesh& mesh, int smoothing_passes = 0);

// H, K and S (as above) from a least-squares quadric h = a x² + b xy + c y² + d x + e y fitted,
// in the vertex's tangent frame (its normal), to the mesh neighbours within `radius` Å
// (reached through the mesh: at most 400), Goldfeather & Interrante (2004). Uses positions
// only, so the slivers of marching cubes do not disturb it; needs normals. A vertex with
// fewer than 5 neighbours within reach gets 0.
VertexCurvature fitted_curvature(const Mesh& mesh, float radius);

// The mixed Voronoi area of every vertex (Å², as above); they add up to the mesh's area less
// its zero-area triangles. For integrals of the curvatures: Σ K_i A_i, Σ H_i A_i.
std::vector<double> vertex_mixed_area(const Mesh& mesh);

}  // namespace fdmsurf::detail
