// The exact SES field on the GPU (--method edt): spheres and arcs uploaded, the boxes wholly
// outside the balls found (ses_boxes.comp), the field evaluated in the others (ses_distance.comp).
#pragma once

#include <array>
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

// The boxes of the field pass (its workgroups: kSesGroupX x kSesGroupY x kSesGroupZ * points_z
// points) per axis on `plan`'s grid.
std::array<std::uint32_t, 3> ses_boxes(const GridPlan& plan);

class SesDistancePass {
public:
    explicit SesDistancePass(Context& ctx);
    // Records the field of `features` on `plan`'s grid into `field` (plan's layout). Uploads go
    // to `arena`. force_global: every workgroup takes the per-point fallback (tests); classify
    // false: every box is evaluated, none skipped as wholly beyond a clamp (tests).
    void record(Commands& cmds, StagingArena& arena, const SesFeatures& features,
                const GridPlan& plan, const Buffer& field, bool force_global = false,
                bool classify = true);
    // The boxes' classes of the last record() (ses_boxes(plan) words, x fastest; tests).
    const Buffer& box_classes() const { return box_classes_; }

private:
    Context& ctx_;
    ComputePipeline boxes_pipeline_, pipeline_;
    Buffer spheres_, sphere_start_, arcs_, arc_start_, box_classes_;
};

}  // namespace fdmsurf::detail
