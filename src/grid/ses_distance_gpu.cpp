// Exact SES field dispatch: the boxes wholly outside (shaders/ses_boxes.comp), then the field
// (shaders/ses_distance.comp).
#include "grid/ses_distance_gpu.hpp"

#include "vulkan/shaders.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

std::uint32_t ses_points_z(float spacing) { return spacing <= 0.5f ? shader::kSesPointsZ : 1u; }

std::array<std::uint32_t, 3> ses_boxes(const GridPlan& plan) {
    const auto& d = plan.info.dims;
    const std::uint32_t span[3] = {shader::kSesGroupX, shader::kSesGroupY,
                                   shader::kSesGroupZ * ses_points_z(plan.info.spacing)};
    return {(d[0] + span[0] - 1) / span[0], (d[1] + span[1] - 1) / span[1],
            (d[2] + span[2] - 1) / span[2]};
}

// The pipelines are made at their first dispatch (ComputePipeline): an engine that only computes
// FDM surfaces, or the exact SES's field on the host, never compiles them (35 ms on lavapipe,
// warm).
SesDistancePass::SesDistancePass(Context& ctx) : ctx_(ctx) {
    ShaderCode code = shader_code(Shader::SesBoxes);
    boxes_pipeline_ = ComputePipeline(ctx, code.words, code.bytes, 3, sizeof(shader::SesBoxesPush),
                                      "ses_boxes");
    code = shader_code(Shader::SesDistance);
    pipeline_ = ComputePipeline(ctx, code.words, code.bytes, 6, sizeof(shader::SesDistancePush),
                                "ses_distance");
}

void SesDistancePass::record(Commands& cmds, StagingArena& arena, const SesFeatures& f,
                             const GridPlan& plan, const Buffer& field, bool force_global,
                             bool classify) {
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
    const GridInfo& g = plan.info;
    const std::array<std::uint32_t, 3> boxes = ses_boxes(plan);
    const std::uint64_t box_count = std::uint64_t(boxes[0]) * boxes[1] * boxes[2];
    // One word per box (a 686^3 grid at 0.5 Å: 1.3 M boxes, 5 MB), kept from run to run.
    const VkDeviceSize box_bytes = box_count * sizeof(std::uint32_t);
    if (box_classes_.size() < box_bytes)
        box_classes_ = Buffer(ctx_, box_bytes, MemoryUse::Device, "ses_box_classes");
    if (classify) {
        cmds.barrier_compute();
        shader::SesBoxesPush b{};
        set_grid_push(b, plan, f.origin, f.bin_size, f.dims);
        b.points_z = ses_points_z(g.spacing);
        b.r_max = f.r_max;
        b.d_min = plan.ses_d_min;
        b.boxes_x = boxes[0];
        b.boxes_y = boxes[1];
        b.boxes_z = boxes[2];
        b.slack = static_cast<float>(kSesBoxSlack);
        const auto [gx, gy] =
            cmds.fold_groups((box_count + shader::kSesBoxGroup - 1) / shader::kSesBoxGroup);
        cmds.dispatch(boxes_pipeline_,
                      {whole(box_classes_), whole(spheres_), whole(sphere_start_)}, &b, gx, gy);
        cmds.mark("ses-boxes");
    } else {
        // Every box evaluated (tests).
        cmds.fill(box_classes_, shader::kSesBoxBand);
    }
    cmds.barrier_compute();
    shader::SesDistancePush p{};
    set_grid_push(p, plan, f.origin, f.bin_size, f.dims);
    p.force_global = force_global ? 1u : 0u;
    p.r_max = f.r_max;
    p.rho_max = f.rho_max;
    p.d_min = plan.ses_d_min;
    p.d_max = plan.ses_d_max;
    p.points_z = ses_points_z(g.spacing);
    cmds.dispatch(pipeline_,
                  {whole(field), whole(spheres_), whole(sphere_start_), whole(arcs_),
                   whole(arc_start_), whole(box_classes_)},
                  &p, boxes[0], boxes[1], boxes[2]);
    cmds.mark("ses-distance");
    cmds.barrier_compute();
}

}  // namespace fdmsurf::detail
