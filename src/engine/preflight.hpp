// The engine's checks before a surface's work (preflight.cpp).
#pragma once

#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"

namespace fdmsurf::detail {

// The warnings on `options` for `atoms` on `plan`'s grid, before any work: a spacing too coarse
// for the filter's cut-off to act (fdm), coordinates so far from the origin that single
// precision's step there exceeds 5% of the spacing.
std::vector<std::string> preflight_warnings(const Atoms& atoms, const SurfaceOptions& options,
                                            const GridPlan& plan);

}  // namespace fdmsurf::detail
