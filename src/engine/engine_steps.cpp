// Small steps that the engine's paths share (engine_steps.hpp).
#include "engine/engine_steps.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "engine/engine_impl.hpp"
#include "filter/spatial_gaussian.hpp"

namespace fdmsurf::detail {

Atoms atoms_near_planes(const Atoms& atoms, const GridPlan& plan, double z0, double z1) {
    const double h = plan.info.spacing, oz = plan.info.origin[2];
    Atoms out;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        double r = atoms.radius[i] + plan.density.radius_add;
        double reach = std::sqrt(r * r + plan.density.pi_cut) + h;
        double z = atoms.xyz[3 * i + 2];
        if (z + reach < oz + z0 * h || z - reach > oz + (z1 - 1) * h) continue;
        out.xyz.insert(out.xyz.end(), atoms.xyz.begin() + 3 * i, atoms.xyz.begin() + 3 * i + 3);
        out.radius.push_back(atoms.radius[i]);
    }
    return out;
}

std::vector<float> read_field(EngineImpl& e, StagingArena& arena, const Buffer& field,
                              std::size_t floats, const char* mark) {
    const std::size_t bytes = floats * sizeof(float);
    const Buffer& host =
        readback_buffer(e.context, e.commands, arena, field, bytes, "field_readback");
    if (mark) e.commands.mark(mark);
    e.commands.barrier_to_host();
    e.commands.submit_and_wait();
    host.invalidate();
    std::vector<float> out(floats);
    std::memcpy(out.data(), host.mapped(), bytes);
    return out;
}

std::uint32_t filter_reach_planes(const SurfaceOptions& options, const GridPlan& plan) {
    if (!plan.filtered) return 0;
    const double reach =
        options.filter == FilterShape::Gaussian
            ? 6.0 * std::sqrt(std::log(2.0) / 2.0) / (std::numbers::pi * plan.info.cutoff)
            : 2.0 / plan.info.cutoff;
    return static_cast<std::uint32_t>(std::ceil(reach / plan.info.spacing));
}

void set_interpolation(McParams& mc, const GridPlan& plan) {
    if (plan.filtered || plan.exact_ses) return;
    mc.power_sigma2 = plan.density.sigma * plan.density.sigma;
    mc.power_t = plan.density.level_t;
}

McParams whole_grid_mc(const GridPlan& plan) {
    McParams mc;
    for (int a = 0; a < 3; ++a) mc.origin[a] = plan.info.origin[a];
    mc.spacing = plan.info.spacing;
    mc.iso = plan.iso;
    mc.z_begin = 0;
    mc.z_end = plan.info.dims[2] - 1;
    set_interpolation(mc, plan);
    return mc;
}

void add_times(std::vector<StageTime>& into, const std::vector<StageTime>& times) {
    for (const StageTime& t : times) {
        auto it = std::find_if(into.begin(), into.end(),
                               [&](const StageTime& u) { return u.name == t.name; });
        if (it == into.end())
            into.push_back(t);
        else
            it->ms += t.ms;
    }
}

std::vector<float> host_gaussian_taps(const SurfaceOptions& options, const GridPlan& plan) {
    return gaussian_taps(gaussian_sigma_points(plan.info.cutoff, plan.info.spacing),
                         filter_reach_planes(options, plan));
}

double physical_memory() {
    return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
}

bool EngineImpl::gaussian_on_host(const SurfaceOptions& options, const GridPlan& plan) const {
    if (!plan.filtered || plan.exact_ses || options.filter != FilterShape::Gaussian) return false;
    return on_host(gaussian_filter);
}

bool EngineImpl::density_on_host(const SurfaceOptions& options, const GridPlan& plan) const {
    if (plan.exact_ses || !on_host(density_place)) return false;
    return !plan.filtered || gaussian_on_host(options, plan);
}

}  // namespace fdmsurf::detail
