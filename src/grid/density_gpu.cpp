// Density pass dispatch (shaders/density.comp).
#include "grid/density_gpu.hpp"

#include "core/shaders.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

DensityPass::DensityPass(Context& ctx) : ctx_(ctx) {
    ShaderCode code = shader_code(Shader::Density);
    pipeline_ = ComputePipeline(ctx, code.words, code.bytes, 5, sizeof(shader::DensityPush), "density");
}

void DensityPass::record(Commands& cmds, StagingArena& arena, const AtomBins& bins,
                         const GridPlan& plan, const Buffer& field) {
    atoms_ = upload_buffer(ctx_, cmds, arena, bins.atoms.data(), bins.atoms.size() * sizeof(float),
                           "atoms");
    start_ = upload_buffer(ctx_, cmds, arena, bins.start.data(),
                           bins.start.size() * sizeof(std::uint32_t), "bin_start");
    first_shell_ = upload_buffer(ctx_, cmds, arena, bins.first_shell.data(),
                                 bins.first_shell.size() * sizeof(std::uint32_t), "bin_first_shell");
    const std::uint32_t group[3] = {shader::kDensityGroupX, shader::kDensityGroupY,
                                    shader::kDensityGroupZ};
    std::vector<std::uint8_t> reached = reached_groups(bins, plan, group);
    std::vector<std::uint32_t> words(reached.begin(), reached.end());
    reached_ = upload_buffer(ctx_, cmds, arena, words.data(), words.size() * sizeof(std::uint32_t),
                             "density_groups");
    cmds.barrier_compute();
    const GridInfo& g = plan.info;
    shader::DensityPush p{};
    p.origin_x = g.origin[0];
    p.origin_y = g.origin[1];
    p.origin_z = g.origin[2];
    p.spacing = g.spacing;
    p.nx = g.dims[0];
    p.ny = g.dims[1];
    p.nz = g.dims[2];
    p.pitch = plan.pitch;
    p.bin_origin_x = bins.origin[0];
    p.bin_origin_y = bins.origin[1];
    p.bin_origin_z = bins.origin[2];
    p.bin_size = bins.size;
    p.bin_nx = bins.dims[0];
    p.bin_ny = bins.dims[1];
    p.bin_nz = bins.dims[2];
    p.max_shell = bins.max_shell;
    p.inv_sigma2 = 1.0f / (plan.density.sigma * plan.density.sigma);
    p.pi_cut = plan.density.pi_cut;
    p.r2_max = bins.r2_max;
    p.level_t = plan.density.level_t;
    auto groups = [](std::uint32_t n, std::uint32_t g) { return (n + g - 1) / g; };
    cmds.dispatch(pipeline_, {whole(field), whole(atoms_), whole(start_), whole(first_shell_), whole(reached_)}, &p,
                  groups(g.dims[0], shader::kDensityGroupX), groups(g.dims[1], shader::kDensityGroupY),
                  groups(g.dims[2], shader::kDensityGroupZ));
    cmds.mark("density");
    cmds.barrier_compute();
}

}  // namespace fdmsurf::detail
