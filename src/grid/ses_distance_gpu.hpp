// The exact SES field on the GPU (--method edt): spheres and arcs uploaded, one dispatch.
#pragma once

#include "grid/grid_plan.hpp"
#include "grid/ses_features.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

class SesDistancePass {
public:
    explicit SesDistancePass(Context& ctx);
    // Records the field of `features` on `plan`'s grid into `field` (plan's layout). Uploads go
    // to `arena`. force_global: every workgroup takes the per-point fallback (tests).
    void record(Commands& cmds, StagingArena& arena, const SesFeatures& features,
                const GridPlan& plan, const Buffer& field, bool force_global = false);

private:
    Context& ctx_;
    ComputePipeline pipeline_;
    Buffer spheres_, sphere_start_, arcs_, arc_start_;
};

}  // namespace fdmsurf::detail
