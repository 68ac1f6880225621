// Internals of the areas room: exact areas of balls, the mesh split by sphere patches.
#pragma once

#include <cstddef>
#include <vector>

#include "fdmsurf/areas.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// Error(InvalidArgument) naming `function` and the first atom with a coordinate that is not
// finite, a radius that is negative, not finite or (with no probe) 0, or xyz not 3 floats per
// radius.
void check_area_atoms(const Atoms& atoms, float probe, const char* function);

// The exposed area (Å²) of each ball of radius sqrt((r + radius_add)² + pi_iso) in the union of
// all of them (the vdw and sas surfaces at any level); 0 for balls that vanish (r² + pi_iso <= 0).
std::vector<double> exact_ball_areas(const Atoms& atoms, double radius_add, double pi_iso);

// The balls a vdw or sas surface of `options` bounds: radius sqrt((r + radius_add)² + pi_iso).
struct BallParameters {
    double radius_add = 0.0;
    double pi_iso = 0.0;
};
BallParameters ball_parameters(const SurfaceOptions& options);

// The mesh's (flat) area per atom: each triangle whose three vertices lie on one ball (within
// `tolerance`, Å) goes whole to that ball's atom (a triangle along a crease, on two, to the one
// whose normal at its centroid is closest to the triangle's); every other triangle a third to
// each vertex's atom (mesh.atoms). on_patches: the area given by patch.
std::vector<double> mesh_patch_areas(const Mesh& mesh, const Atoms& atoms,
                                     const BallParameters& balls, double tolerance,
                                     double* on_patches);

}  // namespace fdmsurf::detail
