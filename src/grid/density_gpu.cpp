// Density pass dispatch (shaders/density_tiles.comp, then shaders/density.comp).
#include "grid/density_gpu.hpp"

#include <algorithm>
#include <string>

#include "vulkan/shaders.hpp"
#include "base/trace.hpp"
#include "fdmsurf/error.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

namespace {

// The tiles' candidate lists share one pool: a tile takes the words it needs (at 0.5 Å the tiles
// of 4HHB hold 10 on average and at most 78; at 2 Å, up to 267). A tile with more than
// kMaxCapacity, or that finds the pool full, falls back to the (exact, slower) search per point.
// The pool holds at most kPoolBudget bytes; only what the lists use is written (on lavapipe,
// where device memory is host memory, the rest is never touched).
constexpr std::uint64_t kMaxCapacity = 1535;
constexpr std::uint64_t kPoolBudget = 64ull << 20;

static_assert(shader::kDensityGroupX % 4 == 0, "density.comp evaluates quads of 4 points along x");
constexpr std::uint32_t kQuadsPerTile =
    shader::kDensityGroupX / 4 * shader::kDensityGroupY * shader::kDensityGroupZ;
static_assert(kQuadsPerTile % shader::kDensityTileLanes == 0, "quads split evenly over lanes");
static_assert(shader::kDensityPointGroup % shader::kDensityTileLanes == 0,
              "whole tiles per workgroup");

}  // namespace

DensityPass::DensityPass(Context& ctx) : ctx_(ctx) {
    ShaderCode tiles = shader_code(Shader::DensityTiles);
    tiles_pipeline_ = ComputePipeline(ctx, tiles.words, tiles.bytes, 6, sizeof(shader::DensityPush),
                                      "density_tiles");
    ShaderCode code = shader_code(Shader::Density);
    pipeline_ =
        ComputePipeline(ctx, code.words, code.bytes, 6, sizeof(shader::DensityPush), "density");
}

void DensityPass::record(Commands& cmds, StagingArena& arena, const AtomBins& bins,
                         const GridPlan& plan, const Buffer& field) {
    const std::uint32_t group[3] = {shader::kDensityGroupX, shader::kDensityGroupY,
                                    shader::kDensityGroupZ};
    trace("density: recording");
    const std::vector<std::uint32_t> tiles = reached_boxes(bins, plan, group);
    trace("density: reached tiles listed");
    const GridInfo& g = plan.info;
    std::uint32_t capacity =
        static_cast<std::uint32_t>(std::min<std::uint64_t>(kMaxCapacity, capacity_limit_));
    // Per tile a count and a first word, then the pool's top, then the pool (density_common.glsl).
    const std::uint64_t header_words = 2 * std::uint64_t{tiles.size()} + 1;
    const std::uint64_t range_words = ctx_.limits().max_storage_buffer_range / sizeof(std::uint32_t);
    if (header_words > range_words)  // the slabs keep a field, 64 points per tile, in one binding
        throw Error(ErrorCode::DeviceLimit,
                    "density pass: " + std::to_string(tiles.size()) +
                        " tiles' candidate headers exceed maxStorageBufferRange");
    const std::uint64_t pool_words =
        std::min({std::uint64_t{tiles.size()} * capacity, kPoolBudget / sizeof(std::uint32_t),
                  range_words - header_words, pool_limit_});
    // The pool's top may overshoot by what the tiles claim at once after it is full, at most
    // every tile's capacity: that must stay below 2^32 for the top's 32-bit word.
    capacity = static_cast<std::uint32_t>(std::min<std::uint64_t>(
        capacity, (0xffffffffull - pool_words) / std::max<std::size_t>(tiles.size(), 1)));

    atoms_ = upload_buffer(ctx_, cmds, arena, bins.atoms.data(), bins.atoms.size() * sizeof(float),
                           "atoms");
    start_ = upload_buffer(ctx_, cmds, arena, bins.start.data(),
                           bins.start.size() * sizeof(std::uint32_t), "bin_start");
    first_shell_ = upload_buffer(ctx_, cmds, arena, bins.first_shell.data(),
                                 bins.first_shell.size() * sizeof(std::uint32_t), "bin_first_shell");
    trace("density: atoms uploaded");
    // An empty buffer cannot be bound: one word stands in when no box is reached.
    const std::uint32_t none = 0;
    tiles_ = upload_buffer(ctx_, cmds, arena, tiles.empty() ? &none : tiles.data(),
                           std::max<std::size_t>(tiles.size(), 1) * sizeof(std::uint32_t),
                           "density_tiles");
    tile_count_ = tiles.size();
    candidates_ = Buffer(ctx_, (header_words + pool_words) * sizeof(std::uint32_t),
                         MemoryUse::Device, "density_candidates");
    trace("density: tiles uploaded, candidate lists allocated");
    // Boxes no atom reaches are 0; the dispatches below visit only the others. The pool starts
    // empty.
    cmds.fill(field, 0);
    cmds.fill(candidates_, (header_words - 1) * sizeof(std::uint32_t), sizeof(std::uint32_t), 0);
    cmds.barrier_compute();

    shader::DensityPush p{};
    set_grid_push(p, plan, bins.origin, bins.size, bins.dims);
    p.max_shell = bins.max_shell;
    p.inv_sigma2 = 1.0f / (plan.density.sigma * plan.density.sigma);
    p.pi_cut = plan.density.pi_cut;
    p.r2_max = bins.r2_max;
    p.level_t = plan.density.level_t;
    p.boxes_x = (g.dims[0] + group[0] - 1) / group[0];
    p.boxes_y = (g.dims[1] + group[1] - 1) / group[1];
    p.tile_count = static_cast<std::uint32_t>(tiles.size());
    p.capacity = capacity;
    p.pool_words = static_cast<std::uint32_t>(pool_words);
    if (!tiles.empty()) {
        // Workgroups folded into rows of at most maxComputeWorkGroupCount[0].
        std::initializer_list<BufferRange> buffers = {whole(field),  whole(atoms_),
                                                      whole(start_), whole(first_shell_),
                                                      whole(tiles_), whole(candidates_)};
        const auto [tx, ty] = cmds.fold_groups((tiles.size() + shader::kDensityTileGroup - 1) /
                                               shader::kDensityTileGroup);
        p.groups_x = tx;
        cmds.dispatch(tiles_pipeline_, buffers, &p, tx, ty);
        cmds.barrier_compute();

        const std::uint32_t tiles_per_group =
            shader::kDensityPointGroup / shader::kDensityTileLanes;
        const auto [px, py] =
            cmds.fold_groups((tiles.size() + tiles_per_group - 1) / tiles_per_group);
        p.groups_x = px;
        cmds.dispatch(pipeline_, buffers, &p, px, py);
    }
    cmds.mark("density");
    cmds.barrier_compute();
}

std::optional<DensityPass::ListOutcome> DensityPass::list_outcome() const {
    if (!candidates_.host_visible()) return std::nullopt;
    candidates_.invalidate();
    const auto* words = static_cast<const std::uint32_t*>(candidates_.mapped());
    ListOutcome out;
    for (std::size_t t = 0; t < tile_count_; ++t)
        ++(words[2 * t] == shader::kDensityOverflow ? out.overflowed : out.listed);
    return out;
}

}  // namespace fdmsurf::detail
