// Cavity removal (cavities.cpp): the pieces of a mesh that enclose a void, and the tests that
// decide which of them to drop.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// A closed inward-facing piece: the void it encloses (Å³, > 0) and its triangles.
struct CavityPiece {
    double volume = 0.0;
    std::vector<std::array<std::array<double, 3>, 3>> triangles;
};

// Removes the cavities (pieces of negative signed volume) for which `remove` is true, keeping
// the order of the other vertices and triangles; returns how many were removed.
std::size_t remove_cavities_if(Mesh& mesh, const std::function<bool(const CavityPiece&)>& remove);

// The largest clearance min_i (|p - c_i| - r_i) from the atoms' van der Waals spheres over the
// points p enclosed by the cavity's triangles: the radius of the largest ball that fits in the
// void (-infinity when no sample point, `step` Å apart, lies inside). Grid samples, then a
// pattern search to 1e-3 Å from the best four.
double cavity_clearance(const std::vector<std::array<std::array<double, 3>, 3>>& triangles,
                        const Atoms& atoms, double step = 0.3);

// Removes the cavities in which no ball of radius `probe` fits between the atoms: voids that
// are not part of the SES, whatever their volume (the FDM method's default).
std::size_t remove_cavities_without_probe(Mesh& mesh, const Atoms& atoms, double probe,
                                          double step = 0.3);

}  // namespace fdmsurf::detail
