// CPU references of the exact SES field (--method edt): the per-point evaluation the shader
// mirrors, and an independent brute-force evaluation from the atoms alone.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_features.hpp"

namespace fdmsurf::detail {

// d(p): the distance from p to the region outside every ball of radius r + probe, or minus the
// distance to the balls outside them, clamped to [-d_max, d_max] (Å, double precision). The SES
// is d = probe. With `gradient` not null, also d's gradient (unit length; zero where clamped).
// every_face false: the other sphere faces are tried only where a ball ties with the deepest,
// as shaders/ses_distance.comp does (the snap and refine stages): the nearest point of any other
// face is buried or lies on an arc, so the value is the same in exact arithmetic (bit for bit
// where tested).
// Mirrors shaders/ses_distance.comp.
double ses_distance(const SesFeatures& f, const double p[3], double d_max,
                    double* gradient = nullptr, bool every_face = true);

// The same without arcs: every sphere face, every pairwise circle and every point where three
// spheres meet, each kept unless another ball buries it; atoms farther than r + probe + d_max
// are ignored. Cubic in the local atoms: for tests.
double ses_distance_brute(const Atoms& atoms, float probe, const double p[3], double d_max);

// The field at every point of `plan`'s grid, in its layout (plan.pitch floats per row): d
// clamped to [plan.ses_d_min, plan.ses_d_max].
std::vector<float> ses_field_cpu(const SesFeatures& f, const GridPlan& plan);

// The margin (Å) by which a box must clear the lower clamp to be classed outside: far above the
// float rounding of the shaders' distances (a few 1e-5 Å at 300 Å from the origin).
inline constexpr double kSesBoxSlack = 0.002;

// The class (shader::kSesBoxBand or kSesBoxOutside) of each box of the GPU pass (kSesGroupX x
// kSesGroupY x kSesGroupZ * points_z points, x fastest): outside when, at the box's centre c,
// every ball is deeper than min(d_min - r, 0) - kSesBoxSlack below (r: the half-diagonal), by
// all the spheres, not the bins. Mirrors shaders/ses_boxes.comp.
std::vector<std::uint32_t> ses_box_classes_cpu(const SesFeatures& f, const GridPlan& plan,
                                               std::uint32_t points_z);

}  // namespace fdmsurf::detail
