// The exposed pieces of the solvent-accessible surface that the exact SES distance is made of:
// the inflated atom balls and the exposed arcs of their pairwise intersection circles.
//
// The SES is the level set d(x) = r_s of d(x) = dist(x, E), E the region outside every ball of
// radius r_i + r_s (where a probe centre may go): the morphological closing of ALGORITHM.md §7.
// The nearest point of E's boundary to x lies on a sphere face (the radial projection of x,
// when no other ball buries it), on an exposed arc of a circle where two spheres meet (the
// nearest point of the circle, or an arc end, i.e. a point where three spheres meet). Those
// arcs are found here once, on the host; the distance itself is evaluated per grid point by
// shaders/ses_distance.comp (CPU reference: ses_distance_cpu.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// An exposed arc: the circle of centre m, radius rho, in the plane spanned by the unit vectors
// e1, e2 (e1 x e2 is the circle's axis); the arc is theta in [start, start + length] (radians,
// start in [0, 2 pi), 0 < length <= 2 pi) of m + rho (cos theta e1 + sin theta e2).
// 12 floats: three vec4 in the shader, (m, rho), (e1, start), (e2, length).
struct SesArc {
    float m[3];
    float rho;
    float e1[3];
    float start;
    float e2[3];
    float length;
};
static_assert(sizeof(SesArc) == 12 * sizeof(float));

// Spheres and arcs sorted into cubic bins (counting sort), for the gather of each workgroup.
// Bins are numbered z-major ((z * dims[1] + y) * dims[0] + x), so each plane of bins' spheres
// (arcs) are one run of sphere_start (arc_start): SesHostField reads them by planes.
struct SesFeatures {
    float r_max = 0.0f;    // largest inflated radius r + probe, Å
    float rho_max = 0.0f;  // largest arc circle radius, Å (0 without arcs)
    float origin[3] = {0, 0, 0};
    float bin_size = 0.0f;  // Å
    std::uint32_t dims[3] = {1, 1, 1};
    std::vector<float> spheres;               // x, y, z, R = r + probe per atom, grouped by bin
    std::vector<std::uint32_t> sphere_start;  // bin b: spheres [start[b], start[b+1])
    std::vector<SesArc> arcs;                 // grouped by the bin of the circle centre
    std::vector<std::uint32_t> arc_start;
    // Sphere s's neighbours (the balls that intersect it, by sphere index, as above):
    // neighbours[neighbour_start[s], neighbour_start[s+1]). For the host's burial tests.
    std::vector<std::uint32_t> neighbour_start;
    std::vector<std::uint32_t> neighbours;
    std::size_t circles = 0;         // pairs of intersecting spheres (neither inside the other)
    std::size_t buried_circles = 0;  // of which no point is exposed
    std::size_t bin_count() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
    std::size_t sphere_count() const { return spheres.size() / 4; }
};

// Exposed arcs of the balls of radius r_i + probe (probe > 0) and the binned spheres.
// Throws Error(InvalidArgument) for an empty set, a radius <= 0 or a non-finite value.
// The circles (i, j), j > i, of an atom with `cell_from` such neighbours or more are cut only by
// the balls its power cell keeps (base/power_cell.hpp), and none when the cell finds its sphere
// buried; those of an atom with fewer by all its other neighbours. The default is about where
// the cell (some 30 clips) costs what it saves (1AON, 30 November 2026); 0 builds every cell.
constexpr std::size_t kSesCellFrom = 18;
SesFeatures build_ses_features(const Atoms& atoms, float probe,
                               std::size_t cell_from = kSesCellFrom);

// The same features with every circle of ball i cut by all of i's other neighbours: the plain
// reference of build_ses_features (the same features, bit for bit;
// tests/grid/test_ses_features_cell.cpp).
SesFeatures build_ses_features_plain(const Atoms& atoms, float probe);

// The distance from p to the exposed arc `a` (double precision; the shader mirrors it), and,
// with `nearest` not null, the arc's point at that distance. When the arc is certainly not
// nearer than `bound` (by the distance to its plane or to its circle's cylinder), returns
// `bound` at once and leaves `nearest` alone.
double arc_distance(const SesArc& a, const double p[3], double* nearest = nullptr,
                    double bound = std::numeric_limits<double>::infinity());

}  // namespace fdmsurf::detail
