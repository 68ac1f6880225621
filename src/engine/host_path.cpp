// The one-piece path with marching cubes on the host (EngineOptions::marching_cubes; not for a
// mesh left on the device): the field comes back (or was computed on the host: the exact SES,
// and the density where density_on_host says so), the Gaussian filter runs on the host too where
// gaussian_on_host says so (the host's field then holds the filtered values, which refinement
// reads there), and the host stages follow.
#include <cstring>
#include <vector>

#include "base/trace.hpp"
#include "engine/engine_impl.hpp"
#include "engine/engine_steps.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/density_host.hpp"
#include "isosurface/marching_cubes_host.hpp"

namespace fdmsurf::detail {

SurfaceResult EngineImpl::run_on_host(const Atoms& atoms, const SurfaceOptions& options,
                                      const GridPlan& plan, FieldSources& src,
                                      SurfaceResult result) {
    const auto& d = plan.info.dims;
    StagingArena arena;
    Buffer field;
    const bool host_density = density_on_host(options, plan);
    if (!src.host_ses && !host_density) {
        field = Buffer(context, static_cast<VkDeviceSize>(plan.field_floats() * sizeof(float)),
                       MemoryUse::Device, "field");
        trace("engine: field allocated");
    }
    const McParams mc = whole_grid_mc(plan);
    const bool host_gaussian = gaussian_on_host(options, plan);
    std::vector<float> values;
    const float* data = src.host_values.get();
    if (host_density) {
        field = Buffer();
        const double t_density = now_ms();
        values.resize(plan.field_floats());
        density_host(src.bins, plan, values.data(), plan.pitch);
        add_times(result.times, {{"density-host", now_ms() - t_density, false}});
        data = values.data();
    } else if (!src.host_ses) {
        commands.begin();
        if (host_gaussian)
            density.record(commands, arena, src.bins, plan, field);
        else
            record_field(arena, plan, &src.bins, &src.features, options.filter, field);
        values = read_field(*this, arena, field, plan.field_floats(), "read-field");
        add_times(result.times, commands.stage_times());
        data = values.data();
    }
    std::uint32_t pitch = plan.pitch;
    if (host_gaussian) {
        // Nothing reads the device's (unfiltered) field again: its memory goes before the
        // filter's.
        field = Buffer();
        arena.clear();
        const double t_filter = now_ms();
        std::vector<float> filtered(plan.points()), scratch;
        gaussian_filter_planes(values.data(), d[0], d[1], d[2], plan.pitch,
                               host_gaussian_taps(options, plan), 0, d[2], filtered.data(),
                               scratch);
        values = std::move(filtered);
        data = values.data();
        pitch = d[0];
        add_times(result.times, {{"filter-host", now_ms() - t_filter, false}});
    }
    const double t_mc = now_ms();
    PlaneStack planes{{}, d[0], d[1], d[2], pitch};
    for (std::uint32_t z = 0; z < d[2]; ++z)
        planes.planes.push_back(data + std::size_t(z) * d[1] * pitch);
    result.mesh = marching_cubes_host(planes, mc);
    src.host_values.reset();  // the exact SES's refinement and snap evaluate d itself
    add_times(result.times, {{"mc-host", now_ms() - t_mc, false}});
    result.grid.host_filter = host_gaussian;
    result.grid.host_density = host_density;
    result.grid.host_marching_cubes = true;
    report(plan.exact_ses ? "ses-distance, marching cubes" : "density, filter, marching cubes");
    const FieldView view{values.data(), d[0], d[1], d[2], pitch};
    // Refinement reads the field where it is: the host's (filtered or computed there), or the
    // device's.
    const bool on_host_field = host_gaussian || host_density;
    host_stages(result, atoms, options, plan, src.ses.get(),
                on_host_field || src.host_ses ? nullptr : &field, on_host_field ? &view : nullptr);
    return result;
}

}  // namespace fdmsurf::detail
