// Dispatch of the vertex-property passes: the atoms binned into cells on the host, vertices in
// chunks that fit one storage-buffer binding.
#include "properties/vertex_properties_gpu.hpp"
#include "base/trace.hpp"
#include "properties/vertex_atoms_host.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

#include "base/parallel.hpp"
#include "vulkan/shaders.hpp"
#include "fdmsurf/error.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

namespace {

// Cubic cells over a box, numbered x fastest.
struct CellGrid {
    float origin[3] = {0, 0, 0};
    float size = 0.0f;
    std::uint32_t dims[3] = {1, 1, 1};
    std::size_t count() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
    std::uint32_t cell_of(const float* p) const {
        std::uint32_t k[3];
        for (int a = 0; a < 3; ++a) {
            const float f = std::floor((p[a] - origin[a]) / size);
            k[a] = static_cast<std::uint32_t>(std::clamp(f, 0.0f, float(dims[a] - 1)));
        }
        return (k[2] * dims[1] + k[1]) * dims[0] + k[0];
    }
};

// The box of `count` points of `stride` floats (x, y, z first), grown into lo and hi.
void extend_box(const float* values, std::size_t count, std::size_t stride, float lo[3],
                float hi[3]) {
    for (std::size_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], values[stride * i + a]);
            hi[a] = std::max(hi[a], values[stride * i + a]);
        }
}

// Cells of `size` Å over [lo, hi], wider (x1.5 at a time) while there would be more than
// 2^24: a dense table per cell stays small whatever the box.
CellGrid make_grid(const float lo[3], const float hi[3], float size) {
    CellGrid g;
    g.size = size;
    for (;;) {
        std::uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            g.dims[a] = static_cast<std::uint32_t>(std::floor((hi[a] - lo[a]) / g.size)) + 1;
            n *= g.dims[a];
        }
        if (n <= (1u << 24)) break;
        g.size *= 1.5f;
    }
    for (int a = 0; a < 3; ++a) g.origin[a] = lo[a];
    return g;
}

// A counting sort of n points (`stride` floats each, x, y, z first) by cell: cell c holds
// slots [start[c], start[c + 1]); order[slot] is the point there.
struct CellSort {
    std::vector<std::uint32_t> start, order;
};

CellSort sort_into_cells(const CellGrid& g, const float* values, std::size_t n,
                         std::size_t stride) {
    CellSort s;
    std::vector<std::uint32_t> cell_of(n);
    s.start.assign(g.count() + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        cell_of[i] = g.cell_of(values + stride * i);
        ++s.start[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < g.count(); ++c) s.start[c + 1] += s.start[c];
    s.order.resize(n);
    std::vector<std::uint32_t> fill(s.start.begin(), s.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) s.order[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    return s;
}

// The `stride` floats of each point in `order`.
std::vector<float> gather(const float* values, const std::vector<std::uint32_t>& order,
                          std::size_t stride) {
    std::vector<float> out(order.size() * stride);
    for (std::size_t k = 0; k < order.size(); ++k)
        std::memcpy(&out[k * stride], values + std::size_t(order[k]) * stride,
                    stride * sizeof(float));
    return out;
}

// Atoms sorted into cells over the box of the atoms and the vertices.
struct AtomCells {
    CellGrid grid;
    float r2_max = 0.0f;
    std::vector<float> atoms;          // x, y, z, (r + radius_add)² per atom, by cell
    std::vector<std::uint32_t> index;  // the atom's index in the input
    std::vector<std::uint32_t> start;  // cell c holds [start[c], start[c + 1])
    std::vector<float> cell_r2;        // the largest (r + radius_add)² in each cell (0: empty)
};

// Cells over the box [lo, hi] (which holds every vertex) and the atoms.
AtomCells bin_for_vertices(const Atoms& atoms, const float box_lo[3], const float box_hi[3],
                           float radius_add) {
    AtomCells c;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = box_lo[a];
        hi[a] = box_hi[a];
    }
    extend_box(atoms.xyz.data(), atoms.size(), 3, lo, hi);
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r + radius_add);
    c.r2_max = r_max * r_max;
    // 5 Å cells: a vertex near a surface has its first candidate in its own cell and the rest
    // within 8 to 27 cells. On 1AON (ses, 0.5 Å, vertices sorted by cell) 5 Å cells took
    // 0.41 s, 4 Å 0.49 s, 3 Å 0.56 s, 6 Å 0.42 s, 8 Å 0.53 s.
    c.grid = make_grid(lo, hi, 5.0f);
    CellSort sorted = sort_into_cells(c.grid, atoms.xyz.data(), atoms.size(), 3);
    c.start = std::move(sorted.start);
    c.index = std::move(sorted.order);
    c.atoms.resize(4 * atoms.size());
    c.cell_r2.assign(c.grid.count(), 0.0f);
    for (std::size_t slot = 0; slot < c.index.size(); ++slot) {
        const std::size_t i = c.index[slot];
        const float r = atoms.radius[i] + radius_add;
        std::memcpy(&c.atoms[4 * slot], &atoms.xyz[3 * i], 3 * sizeof(float));
        c.atoms[4 * slot + 3] = r * r;
        float& cell_r2 = c.cell_r2[c.grid.cell_of(&atoms.xyz[3 * i])];
        cell_r2 = std::max(cell_r2, r * r);
    }
    return c;
}

AtomCells bin_for_vertices(const Atoms& atoms, const Mesh& mesh, float radius_add) {
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::max();
        hi[a] = -lo[a];
    }
    extend_box(mesh.positions.data(), mesh.vertex_count(), 3, lo, hi);
    return bin_for_vertices(atoms, lo, hi, radius_add);
}

// The push constants of vertex_atoms.comp for `n` vertices over `cells`.
shader::VertexAtomsPush vertex_atoms_push(const AtomCells& cells, std::size_t n,
                                          std::uint32_t per_atom, std::uint32_t stride,
                                          std::uint32_t groups_x) {
    shader::VertexAtomsPush p{};
    p.bin_origin_x = cells.grid.origin[0];
    p.bin_origin_y = cells.grid.origin[1];
    p.bin_origin_z = cells.grid.origin[2];
    p.bin_size = cells.grid.size;
    p.bin_nx = cells.grid.dims[0];
    p.bin_ny = cells.grid.dims[1];
    p.bin_nz = cells.grid.dims[2];
    p.vertex_count = static_cast<std::uint32_t>(n);
    p.r2_max = cells.r2_max;
    p.attributes = per_atom;
    p.position_stride = stride;
    p.groups_x = groups_x;
    return p;
}

// Vertices per dispatch: every buffer of the chunk within one binding.
std::size_t chunk_vertices(const Context& ctx, std::size_t bytes_per_vertex) {
    const std::uint64_t range = ctx.limits().max_storage_buffer_range;
    return std::max<std::size_t>(1, range / bytes_per_vertex / shader::kVertexGroup) *
           shader::kVertexGroup;
}

void check_fits(const Context& ctx, std::size_t bytes, const char* what) {
    if (bytes > ctx.limits().max_storage_buffer_range)
        throw Error(ErrorCode::DeviceLimit,
                    std::string("vertex properties: the ") + what + " (" +
                        std::to_string(bytes >> 20) +
                        " MiB) exceed this device's maxStorageBufferRange (" +
                        std::to_string(ctx.limits().max_storage_buffer_range >> 20) + " MiB)");
}

// Copies `n` results of `stride` words, in sorted order, to their vertices' places.
void scatter(const Buffer& host, const std::vector<std::uint32_t>& order, std::size_t first,
             std::size_t n, std::uint32_t stride, std::vector<std::uint32_t>& out) {
    host.invalidate();
    const auto* words = static_cast<const std::uint32_t*>(host.mapped());
    if (order.empty()) {  // mesh order
        std::memcpy(&out[first * stride], words, n * stride * sizeof(std::uint32_t));
        return;
    }
    for (std::size_t i = 0; i < n; ++i)
        std::memcpy(&out[std::size_t(order[first + i]) * stride], &words[i * stride],
                    stride * sizeof(std::uint32_t));
}

template <class T>
Buffer upload_vector(Context& ctx, Commands& cmds, StagingArena& arena, const std::vector<T>& v,
                     const char* name) {
    static const T none{};  // a buffer cannot be empty
    return upload_buffer(ctx, cmds, arena, v.empty() ? &none : v.data(),
                         std::max<std::size_t>(v.size(), 1) * sizeof(T), name);
}

}  // namespace

VertexPropertiesPass::VertexPropertiesPass(Context& ctx)
    : ctx_(ctx), sort_vertices_(ctx.info().type == "CPU"), on_host_(ctx.info().type == "CPU") {
    ShaderCode a = shader_code(Shader::VertexAtoms);
    atoms_pipeline_ = ComputePipeline(ctx, a.words, a.bytes, 7, sizeof(shader::VertexAtomsPush),
                                      "vertex_atoms");
    // Made at its first dispatch, like every pipeline, and not by make_pipelines: most surfaces
    // are not coloured by the potential.
    ShaderCode c = shader_code(Shader::Coulombic);
    coulomb_pipeline_ =
        ComputePipeline(ctx, c.words, c.bytes, 5, sizeof(shader::CoulombPush), "coulombic");
}

std::vector<std::uint32_t> VertexPropertiesPass::vertex_atoms(
    Commands& cmds, const Mesh& mesh, const Atoms& atoms, float radius_add,
    const std::vector<std::uint32_t>& attributes, std::uint32_t per_atom) {
    const std::size_t nv = mesh.vertex_count();
    const std::uint32_t stride = 1 + per_atom;
    std::vector<std::uint32_t> out(nv * stride);
    if (nv == 0 || atoms.empty()) return out;
    if (on_host_) {
        host_vertex_atoms(atoms, mesh.positions.data(), nv, radius_add, out.data(), stride);
        trace("vertex atoms: attributes");
        if (per_atom == 0) return out;
        for (std::size_t v = 0; v < nv; ++v) {
            std::uint32_t* w = &out[v * stride];
            // No atom only for a vertex that is not a number: its attributes stay 0.
            if (w[0] >= atoms.size()) continue;
            for (std::uint32_t k = 0; k < per_atom; ++k)
                w[1 + k] = attributes[std::size_t(per_atom) * w[0] + k];
        }
        return out;
    }
    const AtomCells cells = bin_for_vertices(atoms, mesh, radius_add);
    // Vertices in cell order: neighbours in a dispatch then search the same cells, so the
    // lanes of a SIMD group run alike (on 1AON the pass took 0.6 of the time of mesh order).
    // (set_sort_vertices: on CPU devices only; `order` stays empty for mesh order.)
    std::vector<std::uint32_t> order;
    std::vector<float> sorted;
    if (sort_vertices_) {
        order = sort_into_cells(cells.grid, mesh.positions.data(), nv, 3).order;
        sorted = gather(mesh.positions.data(), order, 3);
    }
    const float* positions = order.empty() ? mesh.positions.data() : sorted.data();
    trace("vertex atoms: atoms binned, vertices sorted");
    check_fits(ctx_, cells.atoms.size() * sizeof(float), "binned atoms");
    check_fits(ctx_, attributes.size() * sizeof(std::uint32_t), "atom attributes");
    const std::size_t chunk = chunk_vertices(ctx_, stride * sizeof(std::uint32_t) + 12);

    StagingArena arena;
    cmds.begin();
    Buffer bin_atoms = upload_vector(ctx_, cmds, arena, cells.atoms, "vertex_bin_atoms");
    Buffer bin_index = upload_vector(ctx_, cmds, arena, cells.index, "vertex_bin_index");
    Buffer bin_start = upload_vector(ctx_, cmds, arena, cells.start, "vertex_bin_start");
    Buffer attr = upload_vector(ctx_, cmds, arena, attributes, "atom_attributes");
    Buffer cell_r2 = upload_vector(ctx_, cmds, arena, cells.cell_r2, "vertex_bin_r2");
    std::deque<Buffer> outputs;  // deque: the read-back may be the buffer itself
    std::vector<const Buffer*> hosts;
    for (std::size_t first = 0; first < nv; first += chunk) {
        const std::size_t n = std::min(chunk, nv - first);
        Buffer pos = upload_buffer(ctx_, cmds, arena, positions + 3 * first, 3 * n * sizeof(float),
                                   "vertex_positions");
        outputs.emplace_back(ctx_, n * stride * sizeof(std::uint32_t), MemoryUse::Device,
                             "vertex_atoms");
        cmds.barrier_compute();
        const auto [gx, gy] = cmds.fold_groups((n + shader::kVertexGroup - 1) / shader::kVertexGroup);
        const shader::VertexAtomsPush p = vertex_atoms_push(cells, n, per_atom, 3, gx);
        cmds.dispatch(atoms_pipeline_,
                      {whole(pos), whole(bin_atoms), whole(bin_index), whole(bin_start),
                       whole(attr), whole(outputs.back()), whole(cell_r2)},
                      &p, gx, gy);
        arena.buffers.push_back(std::move(pos));
        hosts.push_back(&readback_buffer(ctx_, cmds, arena, outputs.back(),
                                         n * stride * sizeof(std::uint32_t), "vertex_atoms_readback"));
    }
    cmds.mark("vertex-atoms");
    cmds.barrier_to_host();
    trace("vertex atoms: uploaded, recorded");
    cmds.submit_and_wait();
    trace("vertex atoms: waited for");
    for (std::size_t k = 0, first = 0; k < hosts.size(); ++k, first += chunk)
        scatter(*hosts[k], order, first, std::min(chunk, nv - first), stride, out);
    trace("vertex atoms: scattered");
    return out;
}

Buffer VertexPropertiesPass::device_vertex_atoms(Commands& cmds, const Buffer& vertices,
                                                 std::uint32_t vertex_count, const float lo[3],
                                                 const float hi[3], const Atoms& atoms,
                                                 float radius_add,
                                                 const std::vector<std::uint32_t>& colors) {
    constexpr std::uint32_t kStride = 2;  // atom, colour
    Buffer out(ctx_, std::size_t(vertex_count) * kStride * sizeof(std::uint32_t),
               MemoryUse::Device, "mesh_attributes");
    if (vertex_count == 0 || atoms.empty()) return out;
    const AtomCells cells = bin_for_vertices(atoms, lo, hi, radius_add);
    check_fits(ctx_, cells.atoms.size() * sizeof(float), "binned atoms");
    check_fits(ctx_, colors.size() * sizeof(std::uint32_t), "atom colours");
    // Chunks of whole workgroups whose 24-byte vertices fit one binding; a chunk's offsets
    // (a multiple of 64 vertices: 1,536 and 512 bytes) meet every device's
    // minStorageBufferOffsetAlignment (at most 256).
    const std::size_t chunk = chunk_vertices(ctx_, 6 * sizeof(float));
    StagingArena arena;
    cmds.begin();
    // The mesh's vertices were written by an earlier submission's compute shaders (or by the
    // host): make them visible to this one's.
    cmds.barrier_compute();
    Buffer bin_atoms = upload_vector(ctx_, cmds, arena, cells.atoms, "vertex_bin_atoms");
    Buffer bin_index = upload_vector(ctx_, cmds, arena, cells.index, "vertex_bin_index");
    Buffer bin_start = upload_vector(ctx_, cmds, arena, cells.start, "vertex_bin_start");
    Buffer attr = upload_vector(ctx_, cmds, arena, colors, "atom_colors");
    Buffer cell_r2 = upload_vector(ctx_, cmds, arena, cells.cell_r2, "vertex_bin_r2");
    cmds.barrier_compute();
    for (std::size_t first = 0; first < vertex_count; first += chunk) {
        const std::size_t n = std::min<std::size_t>(chunk, vertex_count - first);
        const auto [gx, gy] = cmds.fold_groups((n + shader::kVertexGroup - 1) / shader::kVertexGroup);
        const shader::VertexAtomsPush p = vertex_atoms_push(cells, n, 1, 6, gx);
        const BufferRange in{vertices.handle(), first * 6 * sizeof(float), n * 6 * sizeof(float)};
        const BufferRange words{out.handle(), first * kStride * sizeof(std::uint32_t),
                                n * kStride * sizeof(std::uint32_t)};
        cmds.dispatch(atoms_pipeline_,
                      {in, whole(bin_atoms), whole(bin_index), whole(bin_start), whole(attr),
                       words, whole(cell_r2)},
                      &p, gx, gy);
    }
    cmds.mark("vertex-atoms");
    cmds.submit_and_wait();
    return out;
}

std::vector<std::uint32_t> VertexPropertiesPass::coulombic(Commands& cmds, const Mesh& mesh,
                                                           const Atoms& atoms,
                                                           const std::vector<float>& charges,
                                                           float offset, bool color) {
    static_assert(kCoulombNearCells <= 3, "coulombic.comp holds (2 * 3 + 1)² rows of near cells");
    const std::size_t nv = mesh.vertex_count();
    const std::uint32_t stride = color ? 2 : 1;
    std::vector<std::uint32_t> out(nv * stride);
    if (nv == 0) return out;
    if (mesh.normals.size() != mesh.positions.size())
        throw Error(ErrorCode::InvalidArgument, "coulombic: the mesh has no normals");
    std::vector<float> sites;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        if (charges[i] == 0.0f) continue;
        sites.insert(sites.end(), {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2],
                                   charges[i]});
    }
    const std::size_t site_count = sites.size() / 4;
    // Evaluation points; cells over them and the sites; both sorted by cell.
    std::vector<float> points(3 * nv);
    for (std::size_t k = 0; k < 3 * nv; ++k)
        points[k] = mesh.positions[k] + offset * mesh.normals[k];
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::max();
        hi[a] = -lo[a];
    }
    extend_box(points.data(), nv, 3, lo, hi);
    extend_box(sites.data(), site_count, 4, lo, hi);
    const CellGrid grid = make_grid(lo, hi, kCoulombCell);
    const CellSort by_site = sort_into_cells(grid, sites.data(), site_count, 4);
    const std::vector<float> sorted_sites = gather(sites.data(), by_site.order, 4);
    const CellSort by_point = sort_into_cells(grid, points.data(), nv, 3);
    const std::vector<std::uint32_t>& order = by_point.order;
    const std::vector<float> sorted = gather(points.data(), order, 3);
    check_fits(ctx_, sorted_sites.size() * sizeof(float), "charge sites");
    check_fits(ctx_, by_site.start.size() * sizeof(std::uint32_t), "site cells");

    // Target cells (x, y, z, first point) in chunks whose points fit one binding.
    const std::size_t chunk_points = chunk_vertices(ctx_, stride * sizeof(std::uint32_t) + 12);
    struct Chunk {
        std::size_t first_point = 0, points = 0;
        std::vector<std::uint32_t> cells;  // + a sentinel with the chunk's point count
    };
    std::vector<Chunk> chunks(1);
    for (std::size_t c = 0; c < grid.count(); ++c) {
        const std::size_t a = by_point.start[c], n = by_point.start[c + 1] - a;
        if (n == 0) continue;
        if (n > chunk_points)
            throw Error(ErrorCode::DeviceLimit,
                        "coulombic: a cell holds more evaluation points than one binding");
        if (chunks.back().points + n > chunk_points) {
            chunks.emplace_back();
            chunks.back().first_point = a;
        }
        Chunk& k = chunks.back();
        k.cells.insert(k.cells.end(),
                       {std::uint32_t(c % grid.dims[0]), std::uint32_t((c / grid.dims[0]) % grid.dims[1]),
                        std::uint32_t(c / (std::size_t(grid.dims[0]) * grid.dims[1])),
                        std::uint32_t(a - k.first_point)});
        k.points += n;
    }

    StagingArena arena;
    cmds.begin();
    Buffer site_buffer = upload_vector(ctx_, cmds, arena, sorted_sites, "charge_sites");
    Buffer start_buffer = upload_vector(ctx_, cmds, arena, by_site.start, "charge_site_cells");
    std::deque<Buffer> outputs;  // deque: the read-back may be the buffer itself
    std::vector<const Buffer*> hosts;
    for (Chunk& k : chunks) {
        const std::uint32_t cell_count = static_cast<std::uint32_t>(k.cells.size() / 4);
        k.cells.insert(k.cells.end(), {0, 0, 0, static_cast<std::uint32_t>(k.points)});
        Buffer pts = upload_buffer(ctx_, cmds, arena, &sorted[3 * k.first_point],
                                   3 * k.points * sizeof(float), "coulomb_points");
        Buffer cells = upload_vector(ctx_, cmds, arena, k.cells, "coulomb_cells");
        outputs.emplace_back(ctx_, k.points * stride * sizeof(std::uint32_t), MemoryUse::Device,
                             "coulombic");
        cmds.barrier_compute();
        shader::CoulombPush p{};
        p.cell_origin_x = grid.origin[0];
        p.cell_origin_y = grid.origin[1];
        p.cell_origin_z = grid.origin[2];
        p.cell_size = grid.size;
        p.cell_count = cell_count;
        p.site_count = static_cast<std::uint32_t>(site_count);
        p.scale = static_cast<float>(kCoulombScale);
        p.color = color ? 1u : 0u;
        p.color_range = kCoulombColorRange;
        p.near_cells = kCoulombNearCells;
        p.cell_nx = grid.dims[0];
        p.cell_ny = grid.dims[1];
        p.cell_nz = grid.dims[2];
        const auto [gx, gy] = cmds.fold_groups(cell_count);
        p.groups_x = gx;
        cmds.dispatch(coulomb_pipeline_,
                      {whole(pts), whole(cells), whole(site_buffer), whole(start_buffer),
                       whole(outputs.back())},
                      &p, gx, gy);
        arena.buffers.push_back(std::move(pts));
        arena.buffers.push_back(std::move(cells));
        hosts.push_back(&readback_buffer(ctx_, cmds, arena, outputs.back(),
                                         k.points * stride * sizeof(std::uint32_t),
                                         "coulombic_readback"));
    }
    cmds.mark("coulombic");
    cmds.barrier_to_host();
    cmds.submit_and_wait();
    for (std::size_t k = 0; k < chunks.size(); ++k)
        scatter(*hosts[k], order, chunks[k].first_point, chunks[k].points, stride, out);
    return out;
}

}  // namespace fdmsurf::detail
