// Mesh refinement (ALGORITHM.md §5): modified butterfly subdivision, then the new vertices moved
// onto the level set of the field the mesh was extracted from.
//
// Subdivision: D. Zorin, P. Schröder and W. Sweldens, "Interpolating subdivision for meshes with
// arbitrary topology", SIGGRAPH 1996 (the butterfly of N. Dyn, D. Levin and J. A. Gregory, ACM
// ToG 1990, with w = 1/16, plus stencils for extraordinary vertices). Giard & Macq (2010) name it
// as the refinement step of the FDM method.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "base/vec3.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// Refinement levels accepted (SurfaceOptions::refine): each level multiplies the triangles by 4.
inline constexpr int kMaxRefineLevels = 4;
// The most triangles a refined mesh may have: 2^26 (67.1 M), 1.6 GB of positions, normals and
// indices, about 2.5 GB while the last level is built (the previous level and its edge table).
inline constexpr std::size_t kMaxRefinedTriangles = std::size_t{1} << 26;

// Throws Error(InvalidArgument) unless 0 <= levels <= kMaxRefineLevels.
void check_refine_levels(int levels);
// Throws Error(InvalidArgument), naming the counts, when `levels` levels of refinement would
// take a mesh of `triangles` triangles beyond kMaxRefinedTriangles.
void check_refine_size(int levels, std::size_t triangles);

// The weights s_0 .. s_{k-1} of the ring neighbours e_j of an extraordinary vertex v of valence
// k (e_0 the other end of the edge, then around v in order), the new vertex being
// 3/4 v + sum_j s_j e_j (Zorin et al. 1996): k = 3: 5/12, -1/12, -1/12; k = 4: 3/8, 0, -1/8, 0;
// k >= 5: (1/4 + cos(2 pi j / k) + 1/2 cos(4 pi j / k)) / k. Empty for k < 3.
std::vector<double> extraordinary_weights(int valence);

// One level of modified butterfly subdivision, in place: every triangle (a, b, c) becomes four,
// (a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca), with one new vertex per undirected edge
// shared by every triangle that uses it (vertex old_count + edge number). Old vertices keep their
// index and position (interpolating), orientation is kept, and a closed manifold stays one.
// Edge rules, for an edge (a, b):
// - both ends regular (a closed fan of 6 triangles): the 8-point stencil, a and b 1/2, the two
//   opposite vertices 1/8, the four wing tips -1/16;
// - one end extraordinary (closed fan, valence != 6): that end's stencil (extraordinary_weights);
//   both extraordinary: the average of the two;
// - boundary edges (one triangle): the 4-point scheme along the boundary, -1/16, 9/16, 9/16,
//   -1/16;
// - interior edges whose ends have open fans (a boundary vertex) and no closed extraordinary
//   end: the 8-point stencil, a missing wing tip replaced by its mirror image (b + c - a across
//   the edge bc of triangle abc), which keeps planes planar; the same mirror replaces a missing
//   neighbour in the 4-point scheme;
// - edges of more than two triangles, of two triangles that disagree on orientation, or of a
//   degenerate triangle: the midpoint.
// With ButterflyOffset::Full (the scheme as published) new normals, when the mesh has normals,
// get the same weights, normalised. With ButterflyOffset::Normal the new vertex keeps only the
// stencil's offset from the edge's midpoint along the edge's normal (the mean of its ends'
// normals, or of its triangles' normals without vertex normals), so it lies over the midpoint,
// and gets that normal: on marching-cubes meshes, whose sliver triangles make the stencil's
// tangential offset longer than short edges, the full stencil folds over about 4% of the new
// triangles (docs/mesh.md). Throws Error(InvalidArgument) for malformed arrays or when the
// refined mesh would have more than 2^32 - 1 vertices.
enum class ButterflyOffset { Full, Normal };
void subdivide_butterfly(Mesh& mesh, ButterflyOffset offset = ButterflyOffset::Full);

// A scalar field whose level set is the surface: what the projection sees of the density grid,
// the atoms' power distance, or any other field (an exact SES distance, say).
class SurfaceField {
public:
    virtual ~SurfaceField() = default;
    // Value and gradient (per Å) at p (Å). False where the field is not known there (outside its
    // grid, far from every atom); value and gradient are then unspecified.
    virtual bool sample(const Vec3& p, double& value, Vec3& gradient) const = 0;
    // The level of the surface.
    virtual double iso() const = 0;
    // +1 when the field grows outwards (a distance), -1 when it grows inwards (a density).
    virtual double outward() const = 0;
    // A view for one thread's run of nearby points that may keep what it found from sample to
    // sample, with the same values; null: sample this field itself.
    virtual std::unique_ptr<SurfaceField> local() const { return nullptr; }
    // The cells (edge `cell` from `origin`, Å) whose points such a view serves from what it
    // kept: the projection visits its vertices cell by cell. False: no such cells.
    virtual bool visit_cells(Vec3& origin, double& cell) const {
        (void)origin, (void)cell;
        return false;
    }
};

// How a GridField interpolates between grid points.
enum class GridInterpolation {
    Trilinear,          // value and its own gradient (discontinuous across cell faces)
    TrilinearGradient,  // trilinear value, gradient = trilinear of central differences
    CatmullRom,         // tricubic Catmull-Rom spline through the samples: C1, exact gradient
};

// A field sampled on a regular grid, point (i, j, k) at origin + spacing (i, j, k), value
// data[(k ny + j) pitch + i]. Not owned. Defined where the interpolation stencil lies inside the
// grid (one point in from the border for TrilinearGradient and CatmullRom).
class GridField final : public SurfaceField {
public:
    GridField(const float* data, std::array<std::uint32_t, 3> dims, std::uint32_t pitch,
              Vec3 origin, double spacing, double iso, double outward,
              GridInterpolation interpolation);
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override;
    double iso() const override { return iso_; }
    double outward() const override { return outward_; }

private:
    float at(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return data_[(std::size_t(k) * dims_[1] + std::size_t(j)) * pitch_ + std::size_t(i)];
    }
    const float* data_;
    std::array<std::uint32_t, 3> dims_;
    std::uint32_t pitch_;
    Vec3 origin_;
    double spacing_, iso_, outward_;
    GridInterpolation interpolation_;
};

// The power distance pi(p) = min_i (|p - c_i|^2 - (r_i + radius_add)^2) of the atoms, Å²; its
// level set pi = iso is the surface of the union of balls that marching cubes finds for vdw and
// sas (iso = -sigma^2 ln(level / T), 0 at the default level). Exact, with atoms binned on a
// uniform grid; undefined (false) farther than about 2 Å outside every ball.
class PowerDistanceField final : public SurfaceField {
public:
    PowerDistanceField(const Atoms& atoms, double radius_add, double iso);
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override;
    double iso() const override { return iso_; }
    double outward() const override { return 1.0; }

private:
    std::vector<double> atoms_;         // x, y, z, r^2 per atom, grouped by cell
    std::vector<std::uint32_t> start_;  // cell c holds atoms [start_[c], start_[c + 1])
    Vec3 origin_{};
    std::array<std::int64_t, 3> cells_{};
    double cell_ = 1.0, bound_ = 0.0, iso_ = 0.0;
};

// Newton projection onto the level set: x <- x - (f(x) - iso) grad f / |grad f|^2.
struct ProjectOptions {
    double max_step = 0.25;     // Å per step (h / 2)
    double max_distance = 0.5;  // Å from the start in all (h)
    int iterations = 8;
    double tolerance = 5e-4;  // Å: converged when |f - iso| / |grad f| is below it (h / 1000)
    // Search along each vertex's normal first (the line through the butterfly point along the
    // edge's normal), so that the vertex stays over its edge's midpoint; the gradient is
    // followed where that line meets the level set at a grazing angle or not within reach.
    bool along_normals = true;
    // Also set each projected vertex's normal to outward() grad f / |grad f| at the last point
    // where the field was evaluated (within `tolerance` of the final one), which saves
    // normals_from_field its evaluation per vertex.
    bool set_normals = false;
};

ProjectOptions project_options_for_spacing(double spacing);

struct ProjectStats {
    std::size_t projected = 0;      // moved onto the level set
    std::size_t not_converged = 0;  // no convergence within the steps or the distance
    std::size_t outside_field = 0;  // the field is undefined there, or has no gradient
    std::size_t off_normal = 0;     // projected along the gradient, not the normal (counted
                                    // also in projected or the failures)
    std::size_t failed() const { return not_converged + outside_field; }
};

// Projects vertices [first, vertex_count) of `mesh` onto the level set of `field` by Newton
// steps (each at most max_step, in all at most max_distance from the start); a vertex that does
// not converge, or meets a point where the field is undefined, stays where it is.
ProjectStats project_onto_field(Mesh& mesh, std::size_t first, const SurfaceField& field,
                                const ProjectOptions& options);

// Sets the normals of vertices [first, last) to outward() grad f / |grad f| at the vertex, where
// the field is defined with a gradient; elsewhere the normal is kept (a mesh without normals
// first gets, for every vertex, the normalised sum of the adjacent triangles' normals).
void normals_from_field(Mesh& mesh, const SurfaceField& field, std::size_t first = 0,
                        std::size_t last = std::size_t(-1));

struct RefineStats {
    int levels = 0;
    std::size_t new_vertices = 0;  // over all levels
    ProjectStats projection;       // over all levels (empty without a field)
};

// `levels` levels of subdivide_butterfly (ButterflyOffset::Normal), each followed, when `field`
// is not null, by project_onto_field and normals_from_field of that level's new vertices; at the
// end the original vertices get their normals from the field too.
// Throws as check_refine_size and subdivide_butterfly.
RefineStats refine_mesh(Mesh& mesh, int levels, const SurfaceField* field,
                        const ProjectOptions& options);

}  // namespace fdmsurf::detail
