// Dispatch of the vertex-property passes: the atoms binned into cells on the host, vertices in
// chunks that fit one storage-buffer binding.
#include "properties/vertex_properties_gpu.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

#include "core/shaders.hpp"
#include "fdmsurf/error.hpp"
#include "shader_interface.h"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"
#include "vulkan/transfer.hpp"

namespace fdmsurf::detail {

namespace {

// Atoms sorted into cubic cells over the box of the atoms and the vertices.
struct Cells {
    float origin[3] = {0, 0, 0};
    float size = 0.0f;
    std::uint32_t dims[3] = {1, 1, 1};
    float r2_max = 0.0f;
    std::vector<float> atoms;           // x, y, z, (r + radius_add)² per atom, by cell
    std::vector<std::uint32_t> index;   // the atom's index in the input
    std::vector<std::uint32_t> start;   // cell c holds [start[c], start[c + 1])
    std::vector<float> cell_r2;         // the largest (r + radius_add)² in each cell (0: empty)
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

void empty_box(float lo[3], float hi[3]) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::max();
        hi[a] = -lo[a];
    }
}

Cells bin_for_vertices(const Atoms& atoms, const Mesh& mesh, float radius_add) {
    Cells c;
    float lo[3], hi[3];
    empty_box(lo, hi);
    extend_box(atoms.xyz.data(), atoms.size(), 3, lo, hi);
    extend_box(mesh.positions.data(), mesh.vertex_count(), 3, lo, hi);
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r + radius_add);
    c.r2_max = r_max * r_max;
    // 5 Å cells: a vertex near a surface has its first candidate in its own cell and the rest
    // within 8 to 27 cells. On 1AON (ses, 0.5 Å, vertices sorted by cell) 5 Å cells took
    // 0.41 s, 4 Å 0.49 s, 3 Å 0.56 s, 6 Å 0.42 s, 8 Å 0.53 s. At most 2^24 cells (huge boxes
    // get wider cells).
    c.size = 5.0f;
    for (;;) {
        std::uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            c.dims[a] = static_cast<std::uint32_t>(std::floor((hi[a] - lo[a]) / c.size)) + 1;
            n *= c.dims[a];
        }
        if (n <= (1u << 24)) break;
        c.size *= 1.5f;
    }
    for (int a = 0; a < 3; ++a) c.origin[a] = lo[a];
    const std::size_t cells = std::size_t(c.dims[0]) * c.dims[1] * c.dims[2];
    std::vector<std::uint32_t> cell_of(atoms.size());
    c.start.assign(cells + 1, 0);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        std::uint32_t k[3];
        for (int a = 0; a < 3; ++a) {
            const float f = std::floor((atoms.xyz[3 * i + a] - c.origin[a]) / c.size);
            k[a] = static_cast<std::uint32_t>(std::clamp(f, 0.0f, float(c.dims[a] - 1)));
        }
        cell_of[i] = (k[2] * c.dims[1] + k[1]) * c.dims[0] + k[0];
        ++c.start[cell_of[i] + 1];
    }
    for (std::size_t b = 0; b < cells; ++b) c.start[b + 1] += c.start[b];
    c.atoms.resize(4 * atoms.size());
    c.index.resize(atoms.size());
    c.cell_r2.assign(cells, 0.0f);
    std::vector<std::uint32_t> fill(c.start.begin(), c.start.end() - 1);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const std::uint32_t slot = fill[cell_of[i]]++;
        const float r = atoms.radius[i] + radius_add;
        std::memcpy(&c.atoms[4 * slot], &atoms.xyz[3 * i], 3 * sizeof(float));
        c.atoms[4 * slot + 3] = r * r;
        c.index[slot] = static_cast<std::uint32_t>(i);
        c.cell_r2[cell_of[i]] = std::max(c.cell_r2[cell_of[i]], r * r);
    }
    return c;
}

// The vertices ordered by the cell of `cells` that holds them (a counting sort): neighbours in a
// dispatch then search the same cells, so the lanes of a SIMD group run alike (on 1AON the pass
// took half the time of mesh order). order[k] is the k-th vertex; `sorted` its position.
// cell_of_sorted (optional): the cell of each sorted point.
void sort_by_cell(const Cells& c, const float* points, std::size_t n,
                  std::vector<std::uint32_t>& order, std::vector<float>& sorted,
                  std::vector<std::uint32_t>* cell_of_sorted = nullptr) {
    const std::size_t cells = std::size_t(c.dims[0]) * c.dims[1] * c.dims[2];
    std::vector<std::uint32_t> cell_of(n), start(cells + 1, 0);
    for (std::size_t v = 0; v < n; ++v) {
        std::uint32_t k[3];
        for (int a = 0; a < 3; ++a) {
            const float f = std::floor((points[3 * v + a] - c.origin[a]) / c.size);
            k[a] = static_cast<std::uint32_t>(std::clamp(f, 0.0f, float(c.dims[a] - 1)));
        }
        cell_of[v] = (k[2] * c.dims[1] + k[1]) * c.dims[0] + k[0];
        ++start[cell_of[v] + 1];
    }
    for (std::size_t b = 0; b < cells; ++b) start[b + 1] += start[b];
    order.resize(n);
    sorted.resize(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint32_t slot = start[cell_of[v]]++;
        order[slot] = static_cast<std::uint32_t>(v);
        std::memcpy(&sorted[3 * std::size_t(slot)], &points[3 * v], 3 * sizeof(float));
    }
    if (cell_of_sorted) {
        cell_of_sorted->resize(n);
        for (std::size_t k = 0; k < n; ++k) (*cell_of_sorted)[k] = cell_of[order[k]];
    }
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

template <class T>
Buffer upload_vector(Context& ctx, Commands& cmds, StagingArena& arena, const std::vector<T>& v,
                     const char* name) {
    static const T none{};  // a buffer cannot be empty
    return upload_buffer(ctx, cmds, arena, v.empty() ? &none : v.data(),
                         std::max<std::size_t>(v.size(), 1) * sizeof(T), name);
}

}  // namespace

VertexPropertiesPass::VertexPropertiesPass(Context& ctx) : ctx_(ctx) {
    ShaderCode a = shader_code(Shader::VertexAtoms);
    atoms_pipeline_ = ComputePipeline(ctx, a.words, a.bytes, 7, sizeof(shader::VertexAtomsPush),
                                      "vertex_atoms");
    ShaderCode c = shader_code(Shader::Coulombic);
    coulomb_pipeline_ =
        ComputePipeline(ctx, c.words, c.bytes, 4, sizeof(shader::CoulombPush), "coulombic");
}

std::vector<std::uint32_t> VertexPropertiesPass::vertex_atoms(
    Commands& cmds, const Mesh& mesh, const Atoms& atoms, float radius_add,
    const std::vector<std::uint32_t>& attributes, std::uint32_t per_atom) {
    const std::size_t nv = mesh.vertex_count();
    const std::uint32_t stride = 1 + per_atom;
    std::vector<std::uint32_t> out(nv * stride);
    if (nv == 0 || atoms.empty()) return out;
    const Cells cells = bin_for_vertices(atoms, mesh, radius_add);
    check_fits(ctx_, cells.atoms.size() * sizeof(float), "binned atoms");
    check_fits(ctx_, attributes.size() * sizeof(std::uint32_t), "atom attributes");
    const std::size_t chunk = chunk_vertices(ctx_, stride * sizeof(std::uint32_t) + 12);
    std::vector<std::uint32_t> order;
    std::vector<float> sorted;
    sort_by_cell(cells, mesh.positions.data(), nv, order, sorted);

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
        Buffer pos = upload_buffer(ctx_, cmds, arena, &sorted[3 * first], 3 * n * sizeof(float),
                                   "vertex_positions");
        outputs.emplace_back(ctx_, n * stride * sizeof(std::uint32_t), MemoryUse::Device,
                             "vertex_atoms");
        cmds.barrier_compute();
        shader::VertexAtomsPush p{};
        p.bin_origin_x = cells.origin[0];
        p.bin_origin_y = cells.origin[1];
        p.bin_origin_z = cells.origin[2];
        p.bin_size = cells.size;
        p.bin_nx = cells.dims[0];
        p.bin_ny = cells.dims[1];
        p.bin_nz = cells.dims[2];
        p.vertex_count = static_cast<std::uint32_t>(n);
        p.r2_max = cells.r2_max;
        p.attributes = per_atom;
        const auto [gx, gy] = cmds.fold_groups((n + shader::kVertexGroup - 1) / shader::kVertexGroup);
        p.groups_x = gx;
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
    cmds.submit_and_wait();
    for (std::size_t k = 0, first = 0; k < hosts.size(); ++k, first += chunk) {
        const std::size_t n = std::min(chunk, nv - first);
        hosts[k]->invalidate();
        const auto* words = static_cast<const std::uint32_t*>(hosts[k]->mapped());
        for (std::size_t i = 0; i < n; ++i)
            std::memcpy(&out[std::size_t(order[first + i]) * stride], &words[i * stride],
                        stride * sizeof(std::uint32_t));
    }
    return out;
}

std::vector<std::uint32_t> VertexPropertiesPass::coulombic(Commands& cmds, const Mesh& mesh,
                                                           const Atoms& atoms,
                                                           const std::vector<float>& charges,
                                                           float offset, bool color) {
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
    // Evaluation points, and 4 Å cells over them and the sites.
    std::vector<float> points(3 * nv);
    for (std::size_t k = 0; k < 3 * nv; ++k)
        points[k] = mesh.positions[k] + offset * mesh.normals[k];
    Cells grid;
    grid.size = kCoulombCell;
    float lo[3], hi[3];
    empty_box(lo, hi);
    extend_box(points.data(), nv, 3, lo, hi);
    extend_box(sites.data(), sites.size() / 4, 4, lo, hi);
    for (int a = 0; a < 3; ++a) {
        grid.origin[a] = lo[a];
        grid.dims[a] = static_cast<std::uint32_t>(std::floor((hi[a] - lo[a]) / grid.size)) + 1;
    }
    if (double(grid.dims[0]) * grid.dims[1] * grid.dims[2] > double(1u << 26))
        throw Error(ErrorCode::DeviceLimit,
                    "coulombic: the evaluation points span more than 2^26 cells of " +
                        std::to_string(int(kCoulombCell)) + " Å");
    std::vector<std::uint32_t> order;
    std::vector<float> sorted;
    std::vector<std::uint32_t> cell_of_sorted;
    sort_by_cell(grid, points.data(), nv, order, sorted, &cell_of_sorted);
    // Target cells: x, y, z and the first sorted point; a sentinel holds the point count.
    std::vector<std::uint32_t> cells;
    for (std::size_t k = 0; k < nv; ++k) {
        if (k > 0 && cell_of_sorted[k] == cell_of_sorted[k - 1]) continue;
        const std::uint32_t c = cell_of_sorted[k];
        cells.insert(cells.end(), {c % grid.dims[0], (c / grid.dims[0]) % grid.dims[1],
                                   c / (grid.dims[0] * grid.dims[1]),
                                   static_cast<std::uint32_t>(k)});
    }
    const std::uint32_t cell_count = static_cast<std::uint32_t>(cells.size() / 4);
    cells.insert(cells.end(), {0, 0, 0, static_cast<std::uint32_t>(nv)});
    check_fits(ctx_, sites.size() * sizeof(float), "charge sites");
    check_fits(ctx_, sorted.size() * sizeof(float), "evaluation points");
    check_fits(ctx_, out.size() * sizeof(std::uint32_t), "potentials");

    StagingArena arena;
    cmds.begin();
    Buffer site_buffer = upload_vector(ctx_, cmds, arena, sites, "charge_sites");
    Buffer point_buffer = upload_vector(ctx_, cmds, arena, sorted, "coulomb_points");
    Buffer cell_buffer = upload_vector(ctx_, cmds, arena, cells, "coulomb_cells");
    Buffer result(ctx_, out.size() * sizeof(std::uint32_t), MemoryUse::Device, "coulombic");
    cmds.barrier_compute();
    shader::CoulombPush p{};
    p.cell_origin_x = grid.origin[0];
    p.cell_origin_y = grid.origin[1];
    p.cell_origin_z = grid.origin[2];
    p.cell_size = grid.size;
    p.cell_count = cell_count;
    p.site_count = static_cast<std::uint32_t>(sites.size() / 4);
    p.scale = static_cast<float>(kCoulombScale);
    p.color = color ? 1u : 0u;
    p.color_range = kCoulombColorRange;
    p.near_cells = kCoulombNearCells;
    const auto [gx, gy] = cmds.fold_groups(cell_count);
    p.groups_x = gx;
    cmds.dispatch(coulomb_pipeline_,
                  {whole(point_buffer), whole(cell_buffer), whole(site_buffer), whole(result)}, &p,
                  gx, gy);
    const Buffer& host = readback_buffer(ctx_, cmds, arena, result,
                                         out.size() * sizeof(std::uint32_t), "coulombic_readback");
    cmds.mark("coulombic");
    cmds.barrier_to_host();
    cmds.submit_and_wait();
    host.invalidate();
    const auto* words = static_cast<const std::uint32_t*>(host.mapped());
    for (std::size_t k = 0; k < nv; ++k)
        std::memcpy(&out[std::size_t(order[k]) * stride], &words[k * stride],
                    stride * sizeof(std::uint32_t));
    return out;
}

}  // namespace fdmsurf::detail
