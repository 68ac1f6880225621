// atom_sas_areas: Shrake & Rupley's test points over a cell list of the atoms.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "areas/areas_detail.hpp"
#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf {

namespace {

// `n` points spread evenly over the unit sphere: a golden-section spiral, equal-area bands in z.
std::vector<double> spiral_points(int n) {
    std::vector<double> p(3 * std::size_t(n));
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / n;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = golden * i;
        p[3 * i] = r * std::cos(phi);
        p[3 * i + 1] = r * std::sin(phi);
        p[3 * i + 2] = z;
    }
    return p;
}

}  // namespace

std::vector<double> atom_sas_areas(const Atoms& atoms, float probe, int points) {
    if (!(probe >= 0.0f) || !std::isfinite(probe))
        throw Error(ErrorCode::InvalidArgument,
                    "atom_sas_areas: the probe radius must be >= 0 (got " +
                        std::to_string(probe) + ")");
    if (points < 1)
        throw Error(ErrorCode::InvalidArgument, "atom_sas_areas: at least one point per atom");
    detail::check_area_atoms(atoms, probe, "atom_sas_areas");
    const std::size_t n = atoms.size();
    std::vector<double> area(n, 0.0);
    if (n == 0) return area;
    double rmax = 0.0;
    for (float r : atoms.radius) rmax = std::max(rmax, double(r) + probe);
    // Two atoms interact when their centres are closer than the sum of their expanded radii,
    // at most 2 rmax: neighbours are in the 27 cells around an atom's.
    const detail::CellList cells = detail::make_cell_list(atoms.xyz, 2.0 * rmax);
    const std::vector<double> unit = spiral_points(points);
    const std::size_t chunk = 256;
    detail::parallel_chunks((n + chunk - 1) / chunk, detail::thread_count(), [&](std::size_t c) {
        std::vector<double> near_xyzr;  // x, y, z, R² of the neighbours
        for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
            const double ci[3] = {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
            const double ri = double(atoms.radius[i]) + probe;
            near_xyzr.clear();
            bool swallowed = false;
            cells.for_each_near(ci, [&](std::uint32_t j) {
                if (j == i) return;
                const double rj = double(atoms.radius[j]) + probe;
                double d2 = 0.0;
                for (int q = 0; q < 3; ++q) {
                    const double d = atoms.xyz[3 * j + q] - ci[q];
                    d2 += d * d;
                }
                if (d2 >= (ri + rj) * (ri + rj)) return;
                // Twins (same centre and radius) would each see the other's sphere as its own
                // border: the first keeps the area, the others none.
                if (d2 == 0.0 && rj == ri) {
                    swallowed = swallowed || j < i;
                    return;
                }
                near_xyzr.insert(near_xyzr.end(),
                                 {atoms.xyz[3 * j], atoms.xyz[3 * j + 1], atoms.xyz[3 * j + 2],
                                  rj * rj});
            });
            if (swallowed) continue;  // area 0
            const std::size_t m = near_xyzr.size() / 4;
            std::size_t last = 0;  // the last burying neighbour: often buries the next point
            int exposed = 0;
            for (int p = 0; p < points; ++p) {
                const double x = ci[0] + ri * unit[3 * p], y = ci[1] + ri * unit[3 * p + 1],
                             z = ci[2] + ri * unit[3 * p + 2];
                bool buried = false;
                for (std::size_t t = 0; t < m && !buried; ++t) {
                    const std::size_t j = (last + t) % m;
                    const double* q = &near_xyzr[4 * j];
                    const double dx = x - q[0], dy = y - q[1], dz = z - q[2];
                    if (dx * dx + dy * dy + dz * dz < q[3]) {
                        buried = true;
                        last = j;
                    }
                }
                exposed += buried ? 0 : 1;
            }
            area[i] = 4.0 * std::numbers::pi * ri * ri * exposed / points;
        }
    });
    return area;
}

std::vector<double> atom_mesh_areas(const Mesh& mesh, std::size_t atom_count) {
    std::vector<double> area(atom_count, 0.0);
    if (mesh.triangle_count() == 0) return area;
    if (mesh.atoms.size() != mesh.vertex_count())
        throw Error(ErrorCode::InvalidArgument,
                    "atom_mesh_areas: the mesh has no per-vertex atoms (Mesh::atoms)");
    for (std::uint32_t a : mesh.atoms)
        if (a >= atom_count)
            throw Error(ErrorCode::InvalidArgument,
                        "atom_mesh_areas: vertex atom " + std::to_string(a) + " out of range (" +
                            std::to_string(atom_count) + " atoms)");
    const std::vector<float>& p = mesh.positions;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* v = &mesh.indices[3 * t];
        if (std::size_t(std::max({v[0], v[1], v[2]})) >= mesh.vertex_count())
            throw Error(ErrorCode::InvalidArgument, "atom_mesh_areas: index out of range");
        double e1[3], e2[3];
        for (int q = 0; q < 3; ++q) {
            e1[q] = double(p[3 * v[1] + q]) - p[3 * v[0] + q];
            e2[q] = double(p[3 * v[2] + q]) - p[3 * v[0] + q];
        }
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                     cz = e1[0] * e2[1] - e1[1] * e2[0];
        const double third = std::sqrt(cx * cx + cy * cy + cz * cz) / 6.0;
        for (int k = 0; k < 3; ++k) area[mesh.atoms[v[k]]] += third;
    }
    return area;
}

}  // namespace fdmsurf
