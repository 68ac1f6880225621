// Exact SES field dispatch (shaders/ses_distance.comp).
#include "grid/ses_distance_gpu.hpp"

#include "core/shaders.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

std::uint32_t ses_points_z(float spacing) { return spacing <= 0.5f ? shader::kSesPointsZ : 1u; }

SesDistancePass::SesDistancePass(Context& ctx) : ctx_(ctx) {}

void SesDistancePass::record(Commands& cmds, StagingArena& arena, const SesFeatures& f,
                             const GridPlan& plan, const Buffer& field, bool force_global) {
    // Made at first use: an engine that only computes FDM surfaces never needs it (35 ms on
    // lavapipe, warm).
    if (pipeline_.handle() == VK_NULL_HANDLE) {
        ShaderCode code = shader_code(Shader::SesDistance);
        pipeline_ = ComputePipeline(ctx_, code.words, code.bytes, 5,
                                    sizeof(shader::SesDistancePush), "ses_distance");
    }
    spheres_ = upload_buffer(ctx_, cmds, arena, f.spheres.data(), f.spheres.size() * sizeof(float),
                             "ses_spheres");
    sphere_start_ =
        upload_buffer(ctx_, cmds, arena, f.sphere_start.data(),
                      f.sphere_start.size() * sizeof(std::uint32_t), "ses_sphere_start");
    // A buffer cannot be empty: without arcs one unused entry stands in (every bin range is empty).
    const SesArc none{};
    arcs_ = upload_buffer(ctx_, cmds, arena, f.arcs.empty() ? &none : f.arcs.data(),
                          std::max<std::size_t>(f.arcs.size(), 1) * sizeof(SesArc), "ses_arcs");
    arc_start_ = upload_buffer(ctx_, cmds, arena, f.arc_start.data(),
                               f.arc_start.size() * sizeof(std::uint32_t), "ses_arc_start");
    cmds.barrier_compute();
    const GridInfo& g = plan.info;
    shader::SesDistancePush p{};
    set_grid_push(p, plan, f.origin, f.bin_size, f.dims);
    p.force_global = force_global ? 1u : 0u;
    p.r_max = f.r_max;
    p.rho_max = f.rho_max;
    p.d_max = plan.ses_d_max;
    p.points_z = ses_points_z(g.spacing);
    auto groups = [](std::uint32_t n, std::uint32_t size) { return (n + size - 1) / size; };
    cmds.dispatch(
        pipeline_,
        {whole(field), whole(spheres_), whole(sphere_start_), whole(arcs_), whole(arc_start_)}, &p,
        groups(g.dims[0], shader::kSesGroupX), groups(g.dims[1], shader::kSesGroupY),
        groups(g.dims[2], shader::kSesGroupZ * p.points_z));
    cmds.mark("ses-distance");
    cmds.barrier_compute();
}

}  // namespace fdmsurf::detail
