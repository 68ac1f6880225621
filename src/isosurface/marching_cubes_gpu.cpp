// Marching-cubes dispatches (shaders/mc_*.comp): sizes come from a counting pass and a prefix
// sum, so no fixed cap can drop triangles.
#include "isosurface/marching_cubes_gpu.hpp"
#include "base/trace.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "base/parallel.hpp"
#include "vulkan/shaders.hpp"
#include "fdmsurf_generated/mc_tables.hpp"
#include "fdmsurf/error.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {
namespace {

void check_binding(const Context& ctx, std::uint64_t bytes, const char* what) {
    std::uint64_t limit = ctx.limits().max_storage_buffer_range;
    if (bytes > limit)
        throw Error(ErrorCode::DeviceLimit,
                    std::string(what) + " needs " + std::to_string(bytes >> 20) +
                        " MiB in one storage buffer, more than the device's maxStorageBufferRange (" +
                        std::to_string(limit >> 20) + " MiB); use a coarser --spacing");
}

}  // namespace

MarchingCubesPass::MarchingCubesPass(Context& ctx) : ctx_(ctx) {
    auto make = [&](Shader s, std::uint32_t bindings, std::uint32_t push, const char* name) {
        ShaderCode code = shader_code(s);
        return ComputePipeline(ctx, code.words, code.bytes, bindings, push, name);
    };
    occupancy_ = make(Shader::McOccupancy, 2, sizeof(shader::McPush), "mc_occupancy");
    count_ = make(Shader::McCount, 4, sizeof(shader::McPush), "mc_count");
    scan_ = make(Shader::McScan, 2, sizeof(shader::ScanPush), "mc_scan");
    vertices_ = make(Shader::McVertices, 5, sizeof(shader::McPush), "mc_vertices");
    triangles_ = make(Shader::McTriangles, 5, sizeof(shader::McPush), "mc_triangles");
}

GpuMesh MarchingCubesPass::run(Commands& cmds, StagingArena& arena, const Buffer& field,
                               std::uint32_t nx, std::uint32_t ny, std::uint32_t nz,
                               std::uint32_t pitch, const McParams& params) {
    if (params.z_end >= nz || params.z_begin > params.z_end || nx < 2 || ny < 2)
        throw Error(ErrorCode::Internal, "marching cubes: bad slab range");
    const std::uint64_t points = std::uint64_t(pitch) * ny * nz;
    if (points >= (1ull << 32))
        throw Error(ErrorCode::DeviceLimit, "marching cubes: more than 2^32 grid points in one part");
    check_binding(ctx_, points * 4, "marching cubes (the field)");
    const std::uint32_t words = (nx + shader::kMcSegment - 1) / shader::kMcSegment;
    const std::uint64_t segments = std::uint64_t(words) * ny * (params.z_end - params.z_begin + 1);
    const std::uint64_t runs = (segments + shader::kMcRun - 1) / shader::kMcRun;
    shader::McPush push{};
    push.origin_x = params.origin[0];
    push.origin_y = params.origin[1];
    push.origin_z = params.origin[2];
    push.spacing = params.spacing;
    push.nx = nx;
    push.ny = ny;
    push.nz = nz;
    push.pitch = pitch;
    push.z_begin = params.z_begin;
    push.z_end = params.z_end;
    push.iso = params.iso;
    push.words = words;
    push.segments = static_cast<std::uint32_t>(segments);
    push.power_sigma2 = params.power_sigma2;
    push.power_t = params.power_t;
    // One invocation per `items` (segments or runs), in flat workgroups folded into a 2D grid.
    auto dispatch = [&](const ComputePipeline& pipeline, std::initializer_list<BufferRange> buffers,
                        std::uint64_t items) {
        const auto [gx, gy] = cmds.fold_groups((items + shader::kMcGroup - 1) / shader::kMcGroup);
        shader::McPush p = push;
        p.groups_x = gx;
        cmds.dispatch(pipeline, buffers, &p, gx, gy);
    };

    if (!tables_) {
        // Same layout as McTables in shaders/mc_common.glsl.
        std::vector<std::int32_t> table;
        for (int c = 0; c < 256; ++c) table.push_back(mc::kTriCount[c]);
        for (int c = 0; c < 256; ++c)
            for (int k = 0; k < 3 * mc::kMaxTriangles; ++k) table.push_back(mc::kTriEdges[c][k]);
        tables_ = upload_buffer(ctx_, cmds, arena, table.data(), table.size() * 4, "mc_tables");
        cmds.barrier_compute();
    }
    Buffer occupancy(ctx_, segments * 4, MemoryUse::Device, "mc_occupancy");
    Buffer local(ctx_, segments * 4, MemoryUse::Device, "mc_local_offsets");
    Buffer run_sums(ctx_, (runs + 1) * 8, MemoryUse::Device, "mc_run_sums");
    Buffer totals(ctx_, 8, MemoryUse::Device, "mc_totals");
    dispatch(occupancy_, {whole(field), whole(occupancy)}, segments);
    cmds.mark("mc-occupancy");
    cmds.barrier_compute();
    dispatch(count_, {whole(occupancy), whole(local), whole(run_sums), whole(tables_)}, runs);
    cmds.mark("mc-count");
    cmds.barrier_compute();
    shader::ScanPush scan{static_cast<std::uint32_t>(runs)};
    cmds.dispatch(scan_, {whole(run_sums), whole(totals)}, &scan, 1);
    cmds.mark("mc-scan");
    cmds.barrier_compute();
    const Buffer& totals_host = readback_buffer(ctx_, cmds, arena, totals, 8, "mc_totals_readback");
    cmds.barrier_to_host();
    trace("marching cubes: recorded");
    cmds.submit_and_wait();
    trace("marching cubes: field, occupancy, count, scan waited for");
    std::vector<StageTime> first = cmds.stage_times();

    totals_host.invalidate();
    std::uint32_t total[2];
    std::memcpy(total, totals_host.mapped(), sizeof(total));
    GpuMesh mesh;
    mesh.vertex_count = total[0];
    mesh.triangle_count = total[1];
    check_binding(ctx_, std::uint64_t(total[0]) * 24, "the vertex buffer");
    check_binding(ctx_, std::uint64_t(total[1]) * 12, "the index buffer");
    mesh.vertices = Buffer(ctx_, std::uint64_t(total[0]) * 24, MemoryUse::Device, "mesh_vertices");
    mesh.indices = Buffer(ctx_, std::uint64_t(total[1]) * 12, MemoryUse::Device, "mesh_indices");

    trace("marching cubes: mesh buffers allocated");
    cmds.begin();
    if (total[0] > 0) {
        dispatch(
            vertices_,
            {whole(field), whole(occupancy), whole(local), whole(run_sums), whole(mesh.vertices)},
            segments);
        cmds.mark("mc-vertices");
        cmds.barrier_compute();
    }
    if (total[1] > 0)
        dispatch(
            triangles_,
            {whole(occupancy), whole(local), whole(run_sums), whole(mesh.indices), whole(tables_)},
            segments);
    cmds.mark("mc-triangles");
    cmds.barrier_compute();
    cmds.submit_and_wait();
    trace("marching cubes: vertices and triangles waited for");
    first.insert(first.end(), cmds.stage_times().begin(), cmds.stage_times().end());
    times_ = std::move(first);
    return mesh;
}

Mesh MarchingCubesPass::read_back(Commands& cmds, const GpuMesh& gpu) {
    Mesh mesh;
    read_back_append(cmds, gpu, mesh);
    return mesh;
}

void MarchingCubesPass::read_back_append(Commands& cmds, const GpuMesh& gpu, Mesh& mesh,
                                         double reserve_scale) {
    const std::size_t v0 = mesh.vertex_count(), i0 = mesh.indices.size();
    StagingArena arena;
    cmds.begin();
    std::size_t vbytes = std::size_t(gpu.vertex_count) * 24, ibytes = std::size_t(gpu.triangle_count) * 12;
    const Buffer& v = readback_buffer(ctx_, cmds, arena, gpu.vertices, vbytes, "vertices_readback");
    const Buffer& i = readback_buffer(ctx_, cmds, arena, gpu.indices, ibytes, "indices_readback");
    cmds.barrier_to_host();
    cmds.mark("read-back");
    trace("read-back: staging allocated, recorded");
    cmds.submit_and_wait();
    trace("read-back: waited for");
    const double t0 = now_ms();
    v.invalidate();
    i.invalidate();
    grow_mesh_for_part(mesh, gpu.vertex_count, ibytes / 4, reserve_scale);
    const std::uint32_t base = std::uint32_t(v0);
    // Split the interleaved vertices and copy the indices on all threads, in blocks.
    const float* src = static_cast<const float*>(v.mapped());
    constexpr std::size_t block = std::size_t{1} << 16;
    const std::size_t vertex_blocks = (gpu.vertex_count + block - 1) / block;
    const std::size_t index_blocks = (ibytes / 4 + block - 1) / block;
    parallel_chunks(vertex_blocks + index_blocks, thread_count(), [&](std::size_t b) {
        if (b < vertex_blocks) {
            for (std::size_t k = b * block; k < std::min<std::size_t>(gpu.vertex_count, (b + 1) * block); ++k) {
                std::memcpy(&mesh.positions[3 * (v0 + k)], src + 6 * k, 12);
                std::memcpy(&mesh.normals[3 * (v0 + k)], src + 6 * k + 3, 12);
            }
        } else {
            const std::size_t first = (b - vertex_blocks) * block;
            const std::size_t count = std::min(block, ibytes / 4 - first);
            const std::uint32_t* from = static_cast<const std::uint32_t*>(i.mapped()) + first;
            std::uint32_t* to = mesh.indices.data() + i0 + first;
            if (base == 0)
                std::memcpy(to, from, count * 4);
            else
                for (std::size_t k = 0; k < count; ++k) to[k] = from[k] + base;
        }
    });
    unpack_ms_ = now_ms() - t0;
}

}  // namespace fdmsurf::detail
