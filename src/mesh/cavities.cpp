// Removing cavities: closed pieces with negative signed volume (inward-facing shells inside
// another piece), either all of them or those too small to hold the solvent probe.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {

std::size_t remove_cavities(Mesh& mesh, double max_volume) {
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    if (nt == 0) return 0;
    detail::DisjointSets sets(nv);
    for (std::size_t t = 0; t < nt; ++t) {
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 1]);
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 2]);
    }
    // Signed volume per piece (divergence theorem), keyed by root vertex.
    std::vector<double> volume(nv, 0.0);
    const float* p = mesh.positions.data();
    for (std::size_t t = 0; t < nt; ++t) {
        const float* a = p + 3 * mesh.indices[3 * t];
        const float* b = p + 3 * mesh.indices[3 * t + 1];
        const float* c = p + 3 * mesh.indices[3 * t + 2];
        double det = double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
                     double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
                     double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0]);
        volume[sets.find(mesh.indices[3 * t])] += det / 6.0;
    }
    std::vector<char> drop(nv, 0);
    std::size_t removed = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (sets.find(static_cast<std::uint32_t>(v)) != v) continue;
        if (volume[v] < 0.0 && -volume[v] < max_volume) {
            drop[v] = 1;
            ++removed;
        }
    }
    if (removed == 0) return 0;
    std::vector<std::uint32_t> remap(nv, UINT32_MAX);
    std::size_t kept = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (drop[sets.find(static_cast<std::uint32_t>(v))]) continue;
        remap[v] = static_cast<std::uint32_t>(kept);
        for (int k = 0; k < 3; ++k) {
            mesh.positions[3 * kept + k] = mesh.positions[3 * v + k];
            if (!mesh.normals.empty()) mesh.normals[3 * kept + k] = mesh.normals[3 * v + k];
        }
        ++kept;
    }
    mesh.positions.resize(3 * kept);
    if (!mesh.normals.empty()) mesh.normals.resize(3 * kept);
    std::size_t out = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        if (drop[sets.find(mesh.indices[3 * t])]) continue;
        for (int k = 0; k < 3; ++k) mesh.indices[3 * out + k] = remap[mesh.indices[3 * t + k]];
        ++out;
    }
    mesh.indices.resize(3 * out);
    return removed;
}

}  // namespace fdmsurf
