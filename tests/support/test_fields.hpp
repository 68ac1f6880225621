// Fields for the marching-cubes tests (tests/isosurface): a structure's density from the CPU
// reference, filtered by the host Gaussian as the slab pipeline marches it on a CPU device (or
// left unfiltered, vdw), and noise about the level.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/density_cpu.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "isosurface/marching_cubes_host.hpp"
#include "support/test_data.hpp"

namespace fdmsurf::test {

// A field of nx x ny x nz points, x fastest, no padding, with the parameters of its whole range.
struct TestField {
    std::vector<float> values;
    std::uint32_t nx = 0, ny = 0, nz = 0;
    detail::McParams params;

    const float* plane(std::uint32_t z) const { return values.data() + std::size_t(z) * nx * ny; }
    detail::FieldView view() const { return detail::FieldView{values.data(), nx, ny, nz, nx}; }
    detail::PlaneStack stack() const {
        detail::PlaneStack s{{}, nx, ny, nz, nx};
        for (std::uint32_t z = 0; z < nz; ++z) s.planes.push_back(plane(z));
        return s;
    }
    // Planes [0, split) and [split, nz) from two separate copies, as the slab pipeline's pending
    // core and the next core's first planes are.
    detail::PlaneStack stack(std::vector<float>& copy, std::uint32_t split) const {
        copy.assign(values.begin() + std::ptrdiff_t(std::size_t(split) * nx * ny), values.end());
        detail::PlaneStack s{{}, nx, ny, nz, nx};
        for (std::uint32_t z = 0; z < nz; ++z)
            s.planes.push_back(z < split ? plane(z) : copy.data() + std::size_t(z - split) * nx * ny);
        return s;
    }
};

// The density of a structure from tests/data at `spacing` (the CPU reference's): filtered by the
// host Gaussian (the SES field the slab pipeline marches on a CPU device), or unfiltered (vdw,
// with the power distance's interpolation along edges).
inline TestField structure_field(const std::string& file, float spacing, bool filtered = true) {
    const Atoms atoms = read_structure(data_path(file)).atoms;
    SurfaceOptions o{.spacing = spacing};
    if (!filtered) o.surface = SurfaceKind::Vdw;
    const detail::GridPlan plan = detail::plan_grid(atoms, o);
    TestField f;
    f.nx = plan.info.dims[0];
    f.ny = plan.info.dims[1];
    f.nz = plan.info.dims[2];
    const std::vector<float> density = detail::density_cpu(atoms, plan);
    f.values.resize(std::size_t(f.nx) * f.ny * f.nz);
    if (filtered) {
        const double sigma = detail::gaussian_sigma_points(plan.info.cutoff, spacing);
        const std::vector<float> taps =
            detail::gaussian_taps(sigma, std::uint32_t(std::ceil(6 * sigma)));
        std::vector<float> scratch;
        detail::gaussian_filter_planes(density.data(), f.nx, f.ny, f.nz, plan.pitch, taps, 0, f.nz,
                                       f.values.data(), scratch);
    } else {
        for (std::size_t row = 0; row < std::size_t(f.ny) * f.nz; ++row)
            std::copy_n(&density[row * plan.pitch], f.nx, &f.values[row * f.nx]);
        f.params.power_sigma2 = plan.density.sigma * plan.density.sigma;
        f.params.power_t = plan.density.level_t;
    }
    for (int a = 0; a < 3; ++a) f.params.origin[a] = plan.info.origin[a];
    f.params.spacing = plan.info.spacing;
    f.params.iso = plan.iso;
    f.params.z_end = f.nz - 1;
    return f;
}

// Noise about the level 0.5: nearly every cell crossed, and some values exactly at the level
// (the clamp keeps their vertices apart).
inline TestField noise_field(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz,
                             std::uint32_t seed) {
    TestField f;
    f.nx = nx;
    f.ny = ny;
    f.nz = nz;
    f.params.spacing = 0.5f;
    f.params.origin[0] = -3.0f;
    f.params.iso = 0.5f;
    f.params.z_end = nz - 1;
    std::uint32_t state = seed;
    f.values.resize(std::size_t(nx) * ny * nz);
    for (float& v : f.values) {
        state = state * 1664525u + 1013904223u;
        v = float(state >> 8) / float(1u << 24);
        if ((state >> 4) % 23 == 0) v = 0.5f;
    }
    return f;
}

}  // namespace fdmsurf::test
