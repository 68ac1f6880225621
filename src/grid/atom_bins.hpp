// Atoms sorted into a coarse grid of bins, so the density pass visits only nearby atoms.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "grid/grid_plan.hpp"

namespace fdmsurf::detail {

struct AtomBins {
    float origin[3] = {0, 0, 0};
    float size = 0.0f;  // bin edge, Å
    std::uint32_t dims[3] = {0, 0, 0};
    std::uint32_t max_shell = 0;  // shells beyond this hold only atoms with pi > pi_cut
    float r2_max = 0.0f;
    std::vector<float> atoms;          // x, y, z, r² per atom, grouped by bin
    std::vector<std::uint32_t> start;  // bin b holds atoms[start[b] .. start[b+1])
    // Chebyshev distance (in bins) from each bin to the nearest non-empty bin, capped at
    // max_shell + 1: the density pass starts its shell search there.
    std::vector<std::uint32_t> first_shell;
    std::size_t bin_count() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
};

// Bins covering the grid of `plan`; radii get plan.density.radius_add. `first_shell`: also the
// distances to non-empty bins (the device pass's fallback search reads them; the host's pass
// does not: first_shell is then left empty).
AtomBins bin_atoms(const Atoms& atoms, const GridPlan& plan, bool first_shell = true);

// The grid cut into boxes of group[0] x group[1] x group[2] points (the density pass's tiles),
// numbered x fastest: the boxes that the Gaussian support (pi <= pi_cut) of some atom of `bins`
// reaches, ascending. Elsewhere the density is 0 at every point. Conservative: a listed box may
// still be 0 throughout, an unlisted one never holds a point with pi <= pi_cut.
std::vector<std::uint32_t> reached_boxes(const AtomBins& bins, const GridPlan& plan,
                                         const std::uint32_t group[3]);

}  // namespace fdmsurf::detail
