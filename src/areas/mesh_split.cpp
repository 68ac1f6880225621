// A vdw or sas mesh's area shared out to atoms by the sphere patch each triangle lies on (the
// snap stage puts every vertex on its balls, the creases' vertices on two, docs/mesh.md), with
// the atom of each vertex as the fallback for triangles on no single sphere.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "areas/areas_detail.hpp"
#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {

std::vector<double> mesh_patch_areas(const Mesh& mesh, const Atoms& atoms,
                                     const BallParameters& params, double tolerance,
                                     double* on_patches) {
    const std::size_t n = atoms.size();
    if (on_patches) *on_patches = 0.0;
    std::vector<double> area(n, 0.0);
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    if (nt == 0) return area;
    if (mesh.atoms.size() != nv)
        throw Error(ErrorCode::InvalidArgument,
                    "mesh_patch_areas: the mesh has no per-vertex atoms (Mesh::atoms)");
    for (std::uint32_t a : mesh.atoms)
        if (a >= n)
            throw Error(ErrorCode::InvalidArgument, "mesh_patch_areas: vertex atom " +
                                                        std::to_string(a) + " out of range (" +
                                                        std::to_string(n) + " atoms)");
    for (std::uint32_t v : mesh.indices)
        if (v >= nv)
            throw Error(ErrorCode::InvalidArgument, "mesh_patch_areas: index out of range");

    // Ball radii, 0 for balls that vanish.
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    std::vector<double> radius(n, 0.0);
    double r_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double r = double(atoms.radius[i]) + params.radius_add;
        if (r * r + params.pi_iso > 0.0) radius[i] = std::sqrt(r * r + params.pi_iso);
        r_max = std::max(r_max, radius[i]);
    }
    if (r_max == 0.0) return area;
    // Cells of r_max: the balls a point can lie on are in the 27 cells around it.
    const CellList cells = make_cell_list(atoms.xyz, r_max + tolerance);

    // Whether point p lies on ball k (squared distances against (R ± tolerance)²).
    auto on_ball = [&](const double* p, std::uint32_t k) {
        if (radius[k] == 0.0) return false;
        const double dx = p[0] - atoms.xyz[3 * std::size_t(k)],
                     dy = p[1] - atoms.xyz[3 * std::size_t(k) + 1],
                     dz = p[2] - atoms.xyz[3 * std::size_t(k) + 2];
        const double d2 = dx * dx + dy * dy + dz * dz;
        const double lo = std::max(0.0, radius[k] - tolerance), hi = radius[k] + tolerance;
        return d2 >= lo * lo && d2 <= hi * hi;
    };

    const unsigned threads = thread_count();
    std::vector<std::vector<double>> partial(threads, std::vector<double>(n, 0.0));
    std::vector<double> patch_sum(threads, 0.0);
    const std::size_t block = (nt + threads - 1) / threads;
    parallel_chunks(threads, threads, [&](std::size_t w) {
        std::vector<double>& acc = partial[w];
        double patches = 0.0;
        for (std::size_t t = w * block; t < std::min(nt, (w + 1) * block); ++t) {
            const std::uint32_t* v = &mesh.indices[3 * t];
            double p[3][3];
            for (int k = 0; k < 3; ++k)
                for (int q = 0; q < 3; ++q) p[k][q] = mesh.positions[3 * std::size_t(v[k]) + q];
            const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
            const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
            const double nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2],
                         nz = e1[0] * e2[1] - e1[1] * e2[0];
            const double a = 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
            // The balls that all three vertices lie on: first among the vertices' own atoms (a
            // point of the surface has power distance 0 to its atom's ball, so its atom is one
            // of its balls; inside a patch all three are that patch's), else among every ball
            // near the first vertex (a triangle whose corners are all on creases).
            const std::array<std::uint32_t, 3> candidates{mesh.atoms[v[0]], mesh.atoms[v[1]],
                                                          mesh.atoms[v[2]]};
            auto fits = [&](std::uint32_t b) {
                return on_ball(p[0], b) && on_ball(p[1], b) && on_ball(p[2], b);
            };
            std::uint32_t best = kNone;
            double best_align = -2.0;
            auto consider = [&](std::uint32_t b) {
                if (b == best || !fits(b)) return;
                // Along a crease (on two balls): the ball whose outward normal at the centroid
                // is closest to the triangle's.
                const double c[3] = {atoms.xyz[3 * std::size_t(b)],
                                     atoms.xyz[3 * std::size_t(b) + 1],
                                     atoms.xyz[3 * std::size_t(b) + 2]};
                const double g[3] = {(p[0][0] + p[1][0] + p[2][0]) / 3.0 - c[0],
                                     (p[0][1] + p[1][1] + p[2][1]) / 3.0 - c[1],
                                     (p[0][2] + p[1][2] + p[2][2]) / 3.0 - c[2]};
                const double gl = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
                const double align = gl > 0.0 && a > 0.0
                                         ? (g[0] * nx + g[1] * ny + g[2] * nz) / (gl * 2.0 * a)
                                         : -1.0;
                if (best == kNone || align > best_align) {
                    best = b;
                    best_align = align;
                }
            };
            for (const std::uint32_t b : candidates) consider(b);
            if (best == kNone)
                cells.for_each_near(p[0], [&](std::uint32_t b) {
                    if (b != candidates[0] && b != candidates[1] && b != candidates[2]) consider(b);
                });
            if (best != kNone) {
                acc[best] += a;
                patches += a;
            } else {
                for (int k = 0; k < 3; ++k) acc[mesh.atoms[v[k]]] += a / 3.0;
            }
        }
        patch_sum[w] = patches;
    });
    for (unsigned w = 0; w < threads; ++w) {
        for (std::size_t i = 0; i < n; ++i) area[i] += partial[w][i];
        if (on_patches) *on_patches += patch_sum[w];
    }
    return area;
}

}  // namespace fdmsurf::detail
