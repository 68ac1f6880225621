// The density pass on the GPU: the host bins the atoms and lists the boxes of grid points (tiles)
// that some atom reaches; one dispatch finds each tile's candidate atoms, a second the density.
#pragma once

#include "grid/atom_bins.hpp"
#include "grid/grid_plan.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

class DensityPass {
public:
    explicit DensityPass(Context& ctx);
    // Records the density of `bins` into `field` (plan's layout). Uploads go to `arena`.
    void record(Commands& cmds, StagingArena& arena, const AtomBins& bins, const GridPlan& plan,
                const Buffer& field);

private:
    Context& ctx_;
    ComputePipeline tiles_pipeline_, pipeline_;
    Buffer atoms_, start_, first_shell_, tiles_, candidates_;
};

}  // namespace fdmsurf::detail
