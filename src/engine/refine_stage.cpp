// The refine stage (ALGORITHM.md §5): the field marching cubes ran on, seen from the host, and
// the mesh refined onto it there (modified butterfly and projection, src/refine/refine.cpp).
#include <cmath>
#include <cstdio>
#include <memory>

#include "engine/engine_impl.hpp"
#include "engine/surface_fields.hpp"
#include "refine/refine.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

void EngineImpl::refine(SurfaceResult& result, const Atoms& atoms, const SurfaceOptions& options,
                        const GridPlan& plan, const SesHostField* ses,
                        const Buffer* device_field, const FieldView* host_field) {
    if (options.refine <= 0) return;
    const double t0 = now_ms();
    check_refine_size(options.refine, result.mesh.triangle_count());
    StagingArena arena;  // holds the field's read-back copy on devices without mappable memory
    std::unique_ptr<SurfaceField> field;
    if (plan.exact_ses) {
        // edt: the exact distance itself, evaluated where each vertex goes (no interpolation),
        // clamped like the grid's (plan.ses_d_max, two spacings beyond the level with
        // refinement: ses_band_steps): the projection moves a vertex at most one spacing.
        field = std::make_unique<SesDistanceField>(*ses, plan.iso, plan.ses_d_max);
    } else if (!plan.filtered) {
        // vdw and sas: the density T exp(-pi / sigma^2) is a function of the power distance pi,
        // whose level set is the union of balls itself: project onto that, exactly, rather than
        // onto an interpolation of the sampled exponential (which rounds the creases off).
        const double sigma2 = double(plan.density.sigma) * plan.density.sigma;
        const double pi_iso = -sigma2 * std::log(double(plan.iso) / plan.density.level_t);
        field = std::make_unique<PowerDistanceField>(atoms, plan.density.radius_add, pi_iso);
    } else {
        // ses: the filtered density, read where it lies (host-visible memory is not copied).
        FieldView view;
        if (host_field != nullptr) {
            view = *host_field;
        } else {
            const std::size_t bytes = plan.field_floats() * sizeof(float);
            commands.begin();
            const Buffer& host =
                readback_buffer(context, commands, arena, *device_field, bytes, "field_readback");
            commands.barrier_to_host();
            commands.submit_and_wait();
            host.invalidate();
            const auto& d = plan.info.dims;
            view =
                FieldView{static_cast<const float*>(host.mapped()), d[0], d[1], d[2], plan.pitch};
        }
        const auto& o = plan.info.origin;
        field = std::make_unique<GridField>(view.data, std::array{view.nx, view.ny, view.nz},
                                            view.pitch, Vec3{o[0], o[1], o[2]}, plan.info.spacing,
                                            plan.iso, -1.0, GridInterpolation::CatmullRom);
    }
    const RefineStats stats = refine_mesh(result.mesh, options.refine, field.get(),
                                          project_options_for_spacing(plan.info.spacing));
    result.times.push_back({"refine", now_ms() - t0, false});
    // A few unprojected vertices (kept at their butterfly position) are harmless; many mean the
    // field is not what the mesh came from.
    const std::size_t failed = stats.projection.failed();
    if (failed > 0 && double(failed) > 1e-3 * double(stats.new_vertices)) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "refine: %zu of %zu new vertices (%.2f%%) could not be projected onto the "
                      "surface and keep their butterfly position",
                      failed, stats.new_vertices,
                      100.0 * double(failed) / double(stats.new_vertices));
        result.warnings.emplace_back(buf);
    }
}

}  // namespace fdmsurf::detail
