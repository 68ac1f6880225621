// Cavity removal (cavities.cpp): the pieces of a mesh that enclose a void, and the tests that
// decide which of them to drop.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "base/cell_list.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "mesh/mesh_stats_detail.hpp"

namespace fdmsurf::detail {

// A connected piece of a mesh: its signed volume (Å³; < 0 for a cavity, an inward-facing
// shell) and its triangles.
struct MeshPiece {
    double volume = 0.0;
    std::vector<std::array<std::array<double, 3>, 3>> triangles;
};

// Removes the pieces whose signed volume passes `candidate` and for which `remove` is true
// (triangles are gathered for candidates only), keeping the order of the other vertices and
// triangles; returns how many were removed. `concurrent`: `remove` is safe to call from several
// threads at once, and is (on all of the machine's threads); otherwise it is called in piece
// order on the calling thread. `analysis`: the pieces of `mesh` and their statistics
// (analyse_mesh), read for the volumes and brought up to date (keep_pieces); nullptr: found here.
std::size_t remove_pieces_if(Mesh& mesh, const std::function<bool(double)>& candidate,
                             const std::function<bool(const MeshPiece&)>& remove,
                             bool concurrent = false, MeshAnalysis* analysis = nullptr);
// The same for cavities (pieces of negative volume).
std::size_t remove_cavities_if(Mesh& mesh, const std::function<bool(const MeshPiece&)>& remove,
                               bool concurrent = false, MeshAnalysis* analysis = nullptr);
// remove_cavities with an analysis of the mesh, as above.
std::size_t remove_cavities_below(Mesh& mesh, double max_volume, MeshAnalysis* analysis);

// Removes pieces, inward or outward, enclosing less than `max_volume` Å³: specks smaller than a
// grid cell, where the exact SES touches itself at a point (no probe-sized feature is that small).
std::size_t remove_specks(Mesh& mesh, double max_volume, MeshAnalysis* analysis = nullptr);

// The inside test of the clearance search: does a ray from p along a fixed generic direction
// cross the closed piece `tris` an odd number of times? The plain form tests every triangle.
bool inside_piece(const std::array<double, 3>& p,
                  const std::vector<std::array<std::array<double, 3>, 3>>& tris);

// The same test on triangles binned by their projection across the ray: only the triangles of
// four bins are tested, with the same verdict as inside_piece. Holds a pointer to `tris`.
class RayBins {
public:
    explicit RayBins(const std::vector<std::array<std::array<double, 3>, 3>>& tris);
    bool inside(const std::array<double, 3>& p) const;

private:
    double project(const std::array<double, 3>& p, int axis) const;
    std::int64_t bin(double x, int axis) const;
    const std::vector<std::array<std::array<double, 3>, 3>>* tris_;
    std::array<std::array<double, 3>, 2> axis_{};
    double origin_[2] = {0, 0};
    double cell_ = 1.0;
    double pad_ = 0.0;
    std::int64_t dims_[2] = {1, 1};
    std::vector<std::uint32_t> start_, items_;
};

// The atoms in cubic cells of about 8 Å, built once for all voids: the atoms near a void are
// those of the few cells its box overlaps, not a scan of all of them (a million atoms times
// thousands of voids).
struct AtomCells {
    explicit AtomCells(const Atoms& atoms);
    CellList cells;       // over the atoms' centres
    float r_max = 0.0f;   // the largest radius
};

// The largest clearance min_i (|p - c_i| - r_i) from the atoms' van der Waals spheres over the
// points p enclosed by the cavity's triangles: the radius of the largest ball that fits in the
// void (-infinity when no sample point, `step` Å apart, lies inside; infinity without atoms
// near). Grid samples (at most about 20,000: the step grows for large voids), then a pattern
// search to 1e-3 Å from the best four. With a finite `cap` the answer is min(clearance, cap),
// found sooner: only atoms that can bring it under the cap are visited, and the search ends
// at the first point that reaches it.
// `index`, when given, must be of `atoms`: the near atoms are then found from its cells, the
// samples are taken best first from tiles of the grid that bound their clearance (only those
// that can be among the best four are measured, only those taken are tested for inside), the
// pattern search reads only the atoms near its point, and large voids' triangles are binned
// (RayBins). The answer is the same, to the bit, with or without it.
double cavity_clearance(const std::vector<std::array<std::array<double, 3>, 3>>& triangles,
                        const Atoms& atoms, double step = 0.3,
                        double cap = std::numeric_limits<double>::infinity(),
                        const AtomCells* index = nullptr);

// Removes the cavities in which no ball of radius `probe` fits between the atoms: voids that
// are not part of the SES, whatever their volume (the FDM method's default). Voids of less than
// half a probe ball's volume are removed without the search.
std::size_t remove_cavities_without_probe(Mesh& mesh, const Atoms& atoms, double probe,
                                          MeshAnalysis* analysis = nullptr, double step = 0.3);

}  // namespace fdmsurf::detail
