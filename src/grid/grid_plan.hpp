// Where the density grid sits and how big it is: padding, FFT-friendly sizes, density parameters.
#pragma once

#include <array>
#include <string>

#include <cstdint>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf::detail {

// The density of ALGORITHM.md §2: rho(p) = T exp(-pi(p) / sigma^2), pi the power distance,
// taken as 0 where pi > pi_cut (G below density_cut * T).
struct DensityParams {
    float sigma = 3.0f;
    float level_t = 1.0f;     // T
    float pi_cut = 0.0f;      // sigma^2 ln(1 / density_cut)
    float radius_add = 0.0f;  // added to every radius (the probe, for sas)
};

struct GridPlan {
    GridInfo info;
    std::uint32_t pitch = 0;  // floats per x row in the field buffer: 2 (nx/2 + 1)
    bool filtered = false;    // ses: FFT low-pass
    DensityParams density;
    float iso = 1.0f;  // iso-level of the field, absolute
    // --method edt: the field is the exact SES distance (ses_distance.comp), clamped to
    // [ses_d_min, ses_d_max] = [probe - b h, probe + b h] (b = ses_band_steps), iso = probe; not
    // filtered, linear interpolation.
    bool exact_ses = false;
    float ses_d_min = 0.0f;
    float ses_d_max = 0.0f;
    std::size_t points() const { return std::size_t(info.dims[0]) * info.dims[1] * info.dims[2]; }
    std::size_t field_floats() const { return std::size_t(pitch) * info.dims[1] * info.dims[2]; }
};

// Sets the members that the density and SES distance shaders' push constants share
// (shaders/shader_interface.h): the grid's origin, spacing, points and pitch, and the atom bins'
// origin, edge (Å) and counts.
template <class Push>
void set_grid_push(Push& p, const GridPlan& plan, const float (&bin_origin)[3], float bin_size,
                   const std::uint32_t (&bin_dims)[3]) {
    const GridInfo& g = plan.info;
    p.origin_x = g.origin[0];
    p.origin_y = g.origin[1];
    p.origin_z = g.origin[2];
    p.spacing = g.spacing;
    p.nx = g.dims[0];
    p.ny = g.dims[1];
    p.nz = g.dims[2];
    p.pitch = plan.pitch;
    p.bin_origin_x = bin_origin[0];
    p.bin_origin_y = bin_origin[1];
    p.bin_origin_z = bin_origin[2];
    p.bin_size = bin_size;
    p.bin_nx = bin_dims[0];
    p.bin_ny = bin_dims[1];
    p.bin_nz = bin_dims[2];
}

// Smallest n' >= n whose prime factors are 2, 3, 5 and 7 only (and even if `even`).
std::uint32_t fft_friendly_size(std::uint32_t n, bool even);

// The size of the contiguous (R2C) axis for at least n points: fft_friendly_size(n, true), moved
// up to a size at which VkFFT's R2C transform is fast, from 240 to 512 points.
std::uint32_t r2c_axis_size(std::uint32_t n);

// The cube edges to which small FFT grids of the Gaussian filter are rounded up
// (SurfaceOptions::canonical_grid): a
// first run on a fresh machine spends its time compiling the FFT kernels of its grid size (on
// lavapipe 2-3 s; VkFFT writes the sizes into its kernels), so small structures share a few
// sizes whose plans `fdmsurf prepare` (Engine::prepare) builds once, at set-up.
inline constexpr std::uint32_t kCanonicalGridSizes[] = {64, 80, 96, 112, 128, 144, 160};

// The canonical cube edge for an FFT grid of `dims` points: the smallest of
// kCanonicalGridSizes that holds every axis, unless the cube would have more than 2.5 times the
// points and more than 96^3 (an elongated structure); 0 when none applies.
std::uint32_t canonical_grid_size(const std::array<std::uint32_t, 3>& dims);

// The exact SES's field is exact within b = ses_band_steps(options) spacings of the level r_s
// and clamped beyond. Marching cubes' crossings read only points within one spacing of it (a
// crossed edge's ends, d being 1-Lipschitz), its central-difference normals their neighbours,
// within two. Where the snap follows without refinement, those normals only aim each vertex's
// first Newton line and are then replaced by -grad d (a vertex the snap cannot project, under
// 0.1% or a warning, keeps its own, from clamped neighbours): b = 1 (the snap takes as many
// steps, the meshes stay as close to NanoShaper's, and the field of the 12-copy shell costs a
// quarter less: docs/performance.md). Else (the normals are the mesh's, or refinement moves
// vertices up to a spacing) b = 2.
float ses_band_steps(const SurfaceOptions& options);

// Validates `options` (throws Error(InvalidArgument)) and places the grid around the atoms.
GridPlan plan_grid(const Atoms& atoms, const SurfaceOptions& options);

// For an error about a grid too large: when some atoms lie apart from the rest, across empty
// space of more than 30 Å along an axis (a misplaced atom at 9999 Å, say), a sentence naming the
// smaller groups' atoms (at most five) and how many there are; "" otherwise. O(N log N).
std::string isolated_atoms_note(const Atoms& atoms);

}  // namespace fdmsurf::detail
