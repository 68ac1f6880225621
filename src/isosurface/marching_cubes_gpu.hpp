// Marching cubes on the GPU: occupancy bits, count, scan, then emit vertices and triangles into
// exact-size buffers.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/surface.hpp"

#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

struct GpuMesh {
    Buffer vertices;  // 6 floats per vertex: position (Å), outward unit normal
    Buffer indices;   // 3 uint32 per triangle
    std::uint32_t vertex_count = 0;
    std::uint32_t triangle_count = 0;
};

class MarchingCubesPass {
public:
    explicit MarchingCubesPass(Context& ctx);
    // Makes the pass's pipelines now (they are made at first use otherwise).
    void make_pipelines() const { occupancy_.make(), count_.make(), scan_.make(), vertices_.make(), triangles_.make(); }
    // Records the counting passes into `cmds` (already begun, after the field's producer) and
    // submits; then records and submits the emission. `field` has `pitch` floats per row and
    // nz planes; the result stays on the device.
    GpuMesh run(Commands& cmds, StagingArena& arena, const Buffer& field, std::uint32_t nx,
                std::uint32_t ny, std::uint32_t nz, std::uint32_t pitch, const McParams& params);
    // Copies a GpuMesh to the host.
    Mesh read_back(Commands& cmds, const GpuMesh& mesh);
    // The same appended to `out`, as marching_cubes_host_append appends.
    void read_back_append(Commands& cmds, const GpuMesh& mesh, Mesh& out,
                          double reserve_scale = 1.0);
    // Host time of the last read_back() or read_back_append() spent unpacking the buffers into
    // a Mesh, ms.
    double unpack_ms() const { return unpack_ms_; }
    // Stage times of the submissions of the last run().
    const std::vector<StageTime>& stage_times() const { return times_; }

private:
    Context& ctx_;
    std::vector<StageTime> times_;
    double unpack_ms_ = 0.0;
    ComputePipeline occupancy_, count_, scan_, vertices_, triangles_;
    Buffer tables_;  // triangle counts and edges per cube case (uploaded on first use)
};

}  // namespace fdmsurf::detail
