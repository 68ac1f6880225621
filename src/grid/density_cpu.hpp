// Plain CPU reference of the density pass: rho = max_i G_i by brute force over all atoms.
#pragma once

#include <vector>

#include "fdmsurf/structure.hpp"
#include "grid/grid_plan.hpp"

namespace fdmsurf::detail {

// rho at grid point (x, y, z) of `plan`, in double precision, over every atom.
double density_at(const Atoms& atoms, const GridPlan& plan, std::uint32_t x, std::uint32_t y,
                  std::uint32_t z);

// The whole field in the layout of the GPU buffer (plan.pitch floats per row; padding 0).
std::vector<float> density_cpu(const Atoms& atoms, const GridPlan& plan);

}  // namespace fdmsurf::detail
