// Small steps that the engine's paths share (engine_steps.cpp): reading a field back, the
// filter's reach in planes, marching cubes' settings for a plan, stage times added up, the
// atoms that reach a range of planes. Internal to src/engine/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

struct EngineImpl;

// The atoms whose Gaussian support reaches global planes [z0, z1) of `plan`.
Atoms atoms_near_planes(const Atoms& atoms, const GridPlan& plan, double z0, double z1);

// Ends the recording (begun by the caller, who recorded the passes that fill `field`) with a
// read-back of `field`, submits, waits and copies the values out.
// `mark` (may be null): a stage mark recorded after the copy.
std::vector<float> read_field(EngineImpl& e, StagingArena& arena, const Buffer& field,
                              std::size_t floats, const char* mark = nullptr);

// Planes that the filter's kernel reaches on each side of a point, enough that what lies beyond
// them is below float rounding: for the Gaussian filter 2^-(f/F)^2, whose kernel is a Gaussian
// of sigma = sqrt(ln 2 / 2) / (pi F), 6 sigma (1D tail 2e-9); for the ideal filter, whose kernel
// decays slowly, two wavelengths 2/F. None without a filter (every point is exact on its own).
std::uint32_t filter_reach_planes(const SurfaceOptions& options, const GridPlan& plan);

// The unfiltered density (vdw, sas) is T exp(-pi/sigma^2): its crossings are found on pi. The
// filtered density and the SES distance are interpolated linearly.
void set_interpolation(McParams& mc, const GridPlan& plan);

// Marching cubes' settings for the whole grid of `plan` in one piece.
McParams whole_grid_mc(const GridPlan& plan);

// Adds `times` into `into`, summing the times of stages already there.
void add_times(std::vector<StageTime>& into, const std::vector<StageTime>& times);

// The host Gaussian filter's taps for `plan`: its sigma in points, over the filter's reach.
std::vector<float> host_gaussian_taps(const SurfaceOptions& options, const GridPlan& plan);

// Bytes of the machine's memory (not positive where sysconf cannot tell).
double physical_memory();

}  // namespace fdmsurf::detail
