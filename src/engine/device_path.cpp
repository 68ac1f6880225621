// The one-piece path with marching cubes on the device: the field recorded (or uploaded: the
// exact SES computed on the host), marched there, and the mesh read back for the host stages,
// or left on the device (Engine::make_device_surface) when no host stage changes it.
#include "base/trace.hpp"
#include "engine/engine_impl.hpp"
#include "engine/engine_steps.hpp"

namespace fdmsurf::detail {

SurfaceResult EngineImpl::run_on_device(const Atoms& atoms, const SurfaceOptions& options,
                                        const GridPlan& plan, FieldSources& src, GpuMesh* on_device,
                                        SurfaceResult result) {
    const auto& d = plan.info.dims;
    StagingArena arena;
    Buffer field(context, static_cast<VkDeviceSize>(plan.field_floats() * sizeof(float)),
                 MemoryUse::Device, "field");
    trace("engine: field allocated");
    const McParams mc = whole_grid_mc(plan);
    commands.begin();
    if (src.host_ses) {
        write_pieces(context, commands, arena, field,
                     {{src.host_values.get(), plan.field_floats() * sizeof(float)}}, "field");
        commands.barrier_compute();
        commands.mark("upload-field");
    } else {
        record_field(arena, plan, &src.bins, &src.features, options.filter, field);
    }
    trace("engine: field recorded (staging, FFT plan)");
    GpuMesh gpu = marching_cubes.run(commands, arena, field, d[0], d[1], d[2], plan.pitch, mc);
    src.host_values.reset();  // uploaded and marched
    trace("engine: field and marching cubes done");
    add_times(result.times, marching_cubes.stage_times());
    if (on_device && options.refine == 0 && !snaps(options, plan)) {
        *on_device = std::move(gpu);
        return result;
    }
    result.mesh = marching_cubes.read_back(commands, gpu);
    trace("engine: mesh read back");
    add_times(result.times, commands.stage_times());
    add_times(result.times, {{"unpack-mesh", marching_cubes.unpack_ms(), false}});
    report(plan.exact_ses ? "ses-distance, marching cubes" : "density, filter, marching cubes");
    host_stages(result, atoms, options, plan, src.ses.get(), &field, nullptr);
    if (on_device) *on_device = upload_mesh(result.mesh);
    return result;
}

}  // namespace fdmsurf::detail
