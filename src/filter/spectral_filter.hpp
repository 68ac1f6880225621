// The spectral low-pass of the density: VkFFT R2C forward, mask pass, VkFFT C2R inverse.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "filter/plan_cache.hpp"
#include "grid/grid_plan.hpp"
#include "vulkan/pipeline.hpp"

namespace fdmsurf::detail {

class Buffer;
class Commands;
class Context;
struct FftPlan;

// Owns VkFFT plans, one per grid size, reused across surfaces.
class SpectralFilter {
public:
    explicit SpectralFilter(Context& ctx);
    // Makes the pass's pipelines now (they are made at first use otherwise).
    void make_pipelines() const { mask_.make(); }
    ~SpectralFilter();
    SpectralFilter(const SpectralFilter&) = delete;
    SpectralFilter& operator=(const SpectralFilter&) = delete;

    // Records forward FFT, mask and inverse FFT of `field` (in place, R2C layout with
    // plan.pitch floats per row) into `cmds`, with barriers between them.
    void record(Commands& cmds, const Buffer& field, const GridPlan& plan, FilterShape shape);

    // Builds the plan of `dims` (R2C layout) ahead of its first use, on a field buffer of its
    // own. A plan already in memory is left as it is.
    struct PlanStatus {
        bool from_cache = false;  // the plan cache had its SPIR-V
        bool stored = false;      // built, and written to the plan cache
    };
    PlanStatus prepare(const std::array<std::uint32_t, 3>& dims);

private:
    FftPlan& plan_for(const std::array<std::uint32_t, 3>& dims, const Buffer& field);
    Context& ctx_;
    ComputePipeline mask_;
    VkCommandPool pool_ = VK_NULL_HANDLE;  // VkFFT's own, for its initial uploads
    VkFence fence_ = VK_NULL_HANDLE;
    PlanCache cache_;
    std::map<std::array<std::uint32_t, 3>, std::unique_ptr<FftPlan>> plans_;
    std::vector<std::array<std::uint32_t, 3>> plan_order_;  // oldest first
};

// Process-wide glslang initialisation for VkFFT's run-time shader compilation.
void glslang_acquire();
void glslang_release();

}  // namespace fdmsurf::detail
