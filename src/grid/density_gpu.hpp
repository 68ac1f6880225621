// The density pass on the GPU: the host bins the atoms and lists the boxes of grid points (tiles)
// that some atom reaches; one dispatch finds each tile's candidate atoms (lists in a pool shared
// by all tiles), a second the density.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

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
    // Makes the pass's pipelines now (they are made at first use otherwise).
    void make_pipelines() const { tiles_pipeline_.make(), pipeline_.make(); }
    // Records the density of `bins` into `field` (plan's layout). Uploads go to `arena`.
    void record(Commands& cmds, StagingArena& arena, const AtomBins& bins, const GridPlan& plan,
                const Buffer& field);
    // Caps the candidate atoms stored per tile; tiles with more take the per-point search
    // (tests: a small cap exercises that fallback everywhere).
    void set_capacity_limit(std::uint32_t limit) { capacity_limit_ = limit; }
    // Caps the candidates' pool, shared by all tiles, at `words` atom indices; the tiles that
    // find it full take the per-point search (tests: lists and fallbacks in one dispatch).
    void set_pool_limit(std::uint64_t words) { pool_limit_ = words; }
    // Test hook, once the recorded pass has run: the tiles that got a candidate list and those
    // that overflowed; nullopt when the candidates' buffer is not host-visible.
    struct ListOutcome {
        std::uint64_t listed = 0, overflowed = 0;
    };
    std::optional<ListOutcome> list_outcome() const;

private:
    Context& ctx_;
    ComputePipeline tiles_pipeline_, pipeline_;
    Buffer atoms_, start_, first_shell_, tiles_, candidates_;
    std::uint32_t capacity_limit_ = 0xffffffffu;
    std::uint64_t pool_limit_ = ~std::uint64_t{0};
    std::size_t tile_count_ = 0;
};

}  // namespace fdmsurf::detail
