// The density pass on the host's threads (EngineOptions::density): for CPU devices (lavapipe),
// whose compute passes share the host's cores and cost several times the host's own loops.
// The same field as the device's pass (shaders/density.comp): per box of grid points, the atoms
// that can be the least power somewhere in it, the same float power expression, and
// rho = T exp(-pi / sigma^2) where pi <= pi_cut; the only difference is the exponential's
// rounding (the host's expf against the device's). density_cpu is the plain reference.
#pragma once

#include <cstdint>

#include "grid/atom_bins.hpp"
#include "grid/grid_plan.hpp"

namespace fdmsurf::detail {

// The density of `bins` (bin_atoms of the same plan) on the points of `plan`, into `field`:
// nx floats of x per row, rows `pitch` >= nx floats apart, ny rows per plane, nz planes; every
// point is written (0 where no atom's Gaussian reaches; row padding untouched), on `threads`
// threads (0: all).
void density_host(const AtomBins& bins, const GridPlan& plan, float* field, std::uint32_t pitch,
                  unsigned threads = 0);

}  // namespace fdmsurf::detail
