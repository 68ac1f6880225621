// The exact SES field on the GPU (--method edt): spheres and arcs uploaded, one dispatch.
#pragma once

#include <cstdint>

#include "grid/grid_plan.hpp"
#include "grid/ses_features.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

// Points per invocation along z (1 to shader::kSesPointsZ) at grid spacing h (Å): one gather per
// box and one read of each sphere serve them all, but the candidates are those of a longer box.
// 4 up to 0.5 Å (4HHB's pass 10-20% faster than with 1), 1 above (at 1 Å a box of 4 x 2 layers
// overflows its shared lists in the core and the pass took 2-3 times as long).
std::uint32_t ses_points_z(float spacing);

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
