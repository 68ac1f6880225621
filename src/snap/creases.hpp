// Crease recovery on meshes of a union of balls (the vdw and sas surfaces): marching cubes'
// vertices moved onto the balls, its edges split where they cross the circles on which two
// spheres meet, triangles split at the points where three meet, and chords split until each lies
// within a tolerance of its arc. Related work: Kobbelt, Botsch, Schwanecke & Seidel, "Feature
// sensitive surface extraction from volume data", SIGGRAPH 2001 (extended marching cubes), which
// inserts a feature vertex per cell from sampled normals; here the features are known exactly
// (circles and three-sphere points), so they are computed, not estimated (docs/mesh.md).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// The balls whose union the vdw and sas surfaces bound, binned for point queries, with the
// list of the balls each one meets.
class BallUnion {
public:
    // Ball i: centre atoms.xyz[3i..3i+2], radius sqrt((r_i + radius_add)^2 + pi_iso), the level set
    // pi = pi_iso of the power distance (0 at the default level); a ball whose radius would not be
    // positive is left out.
    BallUnion(const Atoms& atoms, double radius_add, double pi_iso);
    std::size_t size() const { return radius_.size(); }
    const double* centre(std::uint32_t i) const { return &centre_[3 * std::size_t(i)]; }
    double radius(std::uint32_t i) const { return radius_[i]; }
    double max_radius() const { return r_max_; }
    // Calls f(i) for every ball whose centre lies within `reach` of p (and some farther).
    template <class F>
    void for_each_within(const double p[3], double reach, F&& f) const {
        if (radius_.empty()) return;
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const double u0 = (p[a] - reach - origin_[a]) / cell_;
            const double u1 = (p[a] + reach - origin_[a]) / cell_;
            if (!(u1 >= 0.0) || !(u0 < double(dims_[a]))) return;  // also NaN
            lo[a] = std::max<std::int64_t>(0, std::int64_t(u0));
            hi[a] = std::min<std::int64_t>(dims_[a] - 1, std::int64_t(u1));
        }
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
                const std::size_t row = std::size_t((z * dims_[1] + y) * dims_[0]);
                for (std::uint32_t s = start_[row + lo[0]]; s < start_[row + hi[0] + 1]; ++s)
                    f(items_[s]);
            }
    }
    // The balls that meet or touch ball i, i left out.
    const std::uint32_t* neighbours_begin(std::uint32_t i) const { return &nb_[nb_start_[i]]; }
    const std::uint32_t* neighbours_end(std::uint32_t i) const {
        return &nb_[0] + nb_start_[i + 1];
    }
    std::size_t neighbour_count(std::uint32_t i) const { return nb_start_[i + 1] - nb_start_[i]; }

private:
    std::vector<double> centre_;  // x, y, z per ball
    std::vector<double> radius_;
    double r_max_ = 0.0;
    double origin_[3] = {0, 0, 0};
    double cell_ = 1.0;
    std::int64_t dims_[3] = {0, 0, 0};
    std::vector<std::uint32_t> start_;  // per cell (x fastest), into items_; one more than cells
    std::vector<std::uint32_t> items_;
    std::vector<std::size_t> nb_start_;
    std::vector<std::uint32_t> nb_;
};

struct CreaseOptions {
    // Å. An edge whose arc (on its ball, or on its circle for an edge along a crease) lies
    // farther than this from the edge's midpoint is split there; 0: no such splits (vertices on
    // the surface, creases and corners only).
    double chord_tolerance = 0.0;
    double min_edge = 1e-4;  // Å: shorter edges are never split
    int max_rounds = 4;      // rounds of splits and corner insertions
    // No further round starts once the mesh has this many triangles (2^27, about 3 GB of mesh).
    std::size_t max_triangles = std::size_t{1} << 27;
};

struct CreaseStats {
    std::size_t projected = 0;        // input vertices placed on the surface
    std::size_t unresolved = 0;       // input vertices left in place (no exposed point near)
    std::size_t snapped = 0;          // vertices moved onto a crease (instead of a split)
    std::size_t crease_splits = 0;    // edges split on a circle where two spheres meet
    std::size_t chord_splits = 0;     // edges split on their ball or circle (chord tolerance)
    std::size_t other_splits = 0;     // crossing edges split at a nearest surface point
    std::size_t vetoed = 0;           // splits withdrawn: they would have folded a triangle over
    std::size_t corners = 0;          // three-sphere points inserted
    std::size_t crossings_left = 0;   // edges whose ends still share no ball at the end
    std::size_t crease_vertices = 0;  // vertices on two spheres at the end
    std::size_t corner_vertices = 0;  // vertices on three at the end
    int rounds = 0;
    bool stopped_at_size = false;  // max_triangles reached: rounds left out
};

// Moves every vertex of `mesh` (a closed or open triangle mesh near the boundary of `balls`)
// onto that boundary, splits edges and triangles as described at the top of this file, and sets
// every vertex's normal to the outward normal of its sphere (the normalised mean of its spheres'
// normals on a crease or corner). Only edge and triangle splits change the connectivity, so a
// closed, manifold, consistently oriented mesh stays one. Atoms, colours and scalars are
// cleared (computed later for the final mesh). Runs on all threads.
CreaseStats recover_creases(Mesh& mesh, const BallUnion& balls, const CreaseOptions& options);

}  // namespace fdmsurf::detail
