// Slab stitching: the vertices of a shared plane are identified by (x, y, axis), found by
// replaying the crossing tests of marching_cubes_cpu on host copies of the shared planes.
// stitch_slabs joins finished parts into a new mesh (the reference); stitch_top_plane joins them
// in the mesh they are appended to, which the slab pipeline uses: the copy into fresh pages was
// most of the stitch's time.
#include "isosurface/slab_stitch.hpp"

#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "base/parallel.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {
namespace {

// Keys (y * nx + x) * 3 + axis of the crossed edges owned by the points of plane z (`here`),
// in vertex order; z-edges only when `with_z` and plane z + 1 (`next`) exists.
std::vector<std::uint32_t> plane_keys(const float* here, const float* next, std::uint32_t nx,
                                      std::uint32_t ny, float iso, bool with_z) {
    std::vector<std::uint32_t> keys;
    for (std::uint32_t y = 0; y < ny; ++y)
        for (std::uint32_t x = 0; x < nx; ++x) {
            const std::size_t i = std::size_t(y) * nx + x;
            bool in = here[i] >= iso;
            std::uint32_t base = (y * nx + x) * 3;
            if (x + 1 < nx && (here[i + 1] >= iso) != in) keys.push_back(base);
            if (y + 1 < ny && (here[i + nx] >= iso) != in) keys.push_back(base + 1);
            if (with_z && next != nullptr && (next[i] >= iso) != in) keys.push_back(base + 2);
        }
    return keys;
}

// For each crossed x/y edge of plane z (`here`), in vertex order, its vertex's position among
// the vertices of plane z with its z edges to plane z + 1 (`next`): the order of the next part's
// first vertices, which keep the same points in the same order with the z edges between.
std::vector<std::uint32_t> top_to_bottom(const float* here, const float* next, std::uint32_t nx,
                                         std::uint32_t ny, float iso) {
    std::vector<std::uint32_t> where;
    std::uint32_t bottom = 0;
    for (std::uint32_t y = 0; y < ny; ++y)
        for (std::uint32_t x = 0; x < nx; ++x) {
            const std::size_t i = std::size_t(y) * nx + x;
            const bool in = here[i] >= iso;
            if (x + 1 < nx && (here[i + 1] >= iso) != in) where.push_back(bottom++);
            if (y + 1 < ny && (here[i + nx] >= iso) != in) where.push_back(bottom++);
            if (next != nullptr && (next[i] >= iso) != in) ++bottom;
        }
    return where;
}

}  // namespace

void stitch_top_plane(Mesh& mesh, std::size_t first_vertex, std::size_t first_index,
                      const float* here, const float* next, std::uint32_t nx, std::uint32_t ny,
                      float iso) {
    const std::vector<std::uint32_t> where = top_to_bottom(here, next, nx, ny, iso);
    const std::size_t vertices = mesh.vertex_count();
    if (first_vertex > vertices || vertices - first_vertex < where.size() ||
        first_index > mesh.indices.size())
        throw Error(ErrorCode::Internal, "stitch: slab has fewer vertices than its top plane");
    // The next part's first vertex comes where this part's top plane begins.
    const std::uint32_t kept_end = static_cast<std::uint32_t>(vertices - where.size());
    std::uint32_t* idx = mesh.indices.data();
    constexpr std::size_t block = std::size_t{1} << 18;
    const std::size_t count = mesh.indices.size() - first_index;
    parallel_chunks((count + block - 1) / block, thread_count(), [&](std::size_t b) {
        const std::size_t end = first_index + std::min(count, (b + 1) * block);
        for (std::size_t k = first_index + b * block; k < end; ++k)
            if (idx[k] >= kept_end) idx[k] = kept_end + where[idx[k] - kept_end];
    });
    mesh.positions.resize(3 * std::size_t(kept_end));
    if (!mesh.normals.empty()) mesh.normals.resize(3 * std::size_t(kept_end));
}

Mesh stitch_slabs(std::vector<Mesh>& parts, const SlabPlanes& field, float iso,
                  const std::vector<std::uint32_t>& starts) {
    const auto keys = [&](std::uint32_t z, bool with_z) {
        return plane_keys(field.plane(z), z + 1 < field.nz ? field.plane(z + 1) : nullptr,
                          field.nx, field.ny, iso, with_z);
    };
    const std::size_t n = parts.size();
    if (starts.size() != n + 1) throw Error(ErrorCode::Internal, "stitch_slabs: bad starts");
    // remap[j][k]: global index of part j's vertex k.
    std::vector<std::vector<std::uint32_t>> remap(n);
    std::vector<std::size_t> kept(n);
    std::vector<std::size_t> top_count(n, 0);
    for (std::size_t j = 0; j + 1 < n; ++j)
        top_count[j] = keys(starts[j + 1], false).size();
    std::size_t offset = 0;
    std::vector<std::size_t> offsets(n);
    for (std::size_t j = 0; j < n; ++j) {
        if (parts[j].vertex_count() < top_count[j])
            throw Error(ErrorCode::Internal, "stitch_slabs: slab has fewer vertices than its top plane");
        offsets[j] = offset;
        kept[j] = parts[j].vertex_count() - top_count[j];
        offset += kept[j];
    }
    for (std::size_t j = 0; j < n; ++j) {
        std::vector<std::uint32_t>& r = remap[j];
        r.resize(parts[j].vertex_count());
        for (std::size_t k = 0; k < kept[j]; ++k) r[k] = static_cast<std::uint32_t>(offsets[j] + k);
        if (j + 1 < n) {
            std::uint32_t z = starts[j + 1];
            std::vector<std::uint32_t> top = keys(z, false);
            std::vector<std::uint32_t> bottom = keys(z, true);
            std::unordered_map<std::uint32_t, std::uint32_t> where;
            where.reserve(bottom.size());
            for (std::size_t k = 0; k < bottom.size(); ++k)
                where.emplace(bottom[k], static_cast<std::uint32_t>(offsets[j + 1] + k));
            for (std::size_t k = 0; k < top.size(); ++k) {
                auto it = where.find(top[k]);
                if (it == where.end())
                    throw Error(ErrorCode::Internal, "stitch_slabs: unmatched boundary vertex");
                r[kept[j] + k] = it->second;
            }
        }
    }
    Mesh out;
    out.positions.reserve(offset * 3);
    out.normals.reserve(offset * 3);
    std::size_t tris = 0;
    for (const Mesh& m : parts) tris += m.indices.size();
    out.indices.reserve(tris);
    for (std::size_t j = 0; j < n; ++j) {
        Mesh& m = parts[j];
        out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.begin() + 3 * kept[j]);
        if (!m.normals.empty())
            out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.begin() + 3 * kept[j]);
        for (std::uint32_t i : m.indices) out.indices.push_back(remap[j][i]);
        m = Mesh{};  // release memory as we go
    }
    return out;
}

}  // namespace fdmsurf::detail
