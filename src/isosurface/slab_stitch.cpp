// Slab stitching: the vertices of a shared plane are identified by (x, y, axis), found by
// replaying the crossing tests of marching_cubes_cpu on host copies of the shared planes.
#include "isosurface/slab_stitch.hpp"

#include <cstring>
#include <unordered_map>

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

}  // namespace

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
