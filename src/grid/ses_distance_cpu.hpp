// CPU references of the exact SES field (--method edt): the per-point evaluation the shader
// mirrors, and an independent brute-force evaluation from the atoms alone.
#pragma once

#include <vector>

#include "fdmsurf/structure.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_features.hpp"

namespace fdmsurf::detail {

// d(p): the distance from p to the region outside every ball of radius r + probe, or minus the
// distance to the balls outside them, clamped to [-d_max, d_max] (Å, double precision). The SES
// is d = probe. With `gradient` not null, also d's gradient (unit length; zero where clamped).
// Mirrors shaders/ses_distance.comp.
double ses_distance(const SesFeatures& f, const double p[3], double d_max,
                    double* gradient = nullptr);

// The same without arcs: every sphere face, every pairwise circle and every point where three
// spheres meet, each kept unless another ball buries it; atoms farther than r + probe + d_max
// are ignored. Cubic in the local atoms: for tests.
double ses_distance_brute(const Atoms& atoms, float probe, const double p[3], double d_max);

// The field at every point of `plan`'s grid, in its layout (plan.pitch floats per row).
std::vector<float> ses_field_cpu(const SesFeatures& f, const GridPlan& plan);

}  // namespace fdmsurf::detail
