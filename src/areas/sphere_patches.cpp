// Exact areas of the sphere patches of a union of balls (the vdw and sas surfaces): on each
// sphere, the part that no other ball buries, by the Gauss-Bonnet theorem on its boundary arcs.
//
// Each neighbour j buries a cap of sphere i, {n : n·u_j > h_j} on the unit sphere. The exposed
// region is the sphere less the union of the caps; its boundary is made of arcs of the caps'
// circles between the points where two circles cross (where three spheres meet). Its area is
// the integral, along those arcs oriented with the exposed region on their left, of a 1-form
// whose exterior derivative is the area form and whose only singularity is a point S inside a
// buried cap (the centre of the largest cap), so no Euler characteristic is needed: each arc,
// cut into pieces of at most a quarter turn, gives the signed solid angle of the geodesic
// triangle (N, P, Q), N the antipode of S (Van Oosterom & Strackee 1983), plus the signed area
// between the chord PQ's great circle and the small-circle arc (a circular segment). The same
// decomposition as the analytical SASA of Connolly (J. Appl. Cryst. 16, 548, 1983) and Richmond
// (J. Mol. Biol. 178, 63, 1984), without their per-component bookkeeping.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "areas/areas_detail.hpp"
#include "core/parallel.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/creases.hpp"

namespace fdmsurf {
namespace detail {
namespace {

constexpr double kPi = std::numbers::pi;

struct Vec {
    double x, y, z;
};
inline Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec cross(Vec a, Vec b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A buried cap of the unit sphere: n·u > h, of angular radius θ (cos θ = h, sin θ = s), with an
// orthonormal basis (e1, e2) of the plane of its circle for azimuths.
struct Cap {
    Vec u, e1, e2;
    double h, s;
};

Vec on_circle(const Cap& c, double phi) {
    return c.h * c.u + (c.s * std::cos(phi)) * c.e1 + (c.s * std::sin(phi)) * c.e2;
}

// Signed solid angle of the geodesic triangle (a, b, c), unit vectors; positive when they turn
// counter-clockwise seen from outside.
double solid_angle(Vec a, Vec b, Vec c) {
    return 2.0 * std::atan2(dot(a, cross(b, c)), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

// Area between a small-circle arc of angular radius θ <= π/2 spanning the azimuth `dphi`
// (<= π/2) and the great-circle arc between its ends: the cap's sector less the isosceles
// geodesic triangle from the cap's centre.
double circular_segment(double cos_t, double dphi) {
    const double t = (1.0 - cos_t) / (1.0 + cos_t);  // tan²(θ/2)
    const double triangle = 2.0 * std::atan2(t * std::sin(dphi), 1.0 + t * std::cos(dphi));
    return dphi * (1.0 - cos_t) - triangle;
}

// The exposed solid angle (steradians) of a unit sphere less the union of `caps` (none empty).
double exposed_solid_angle(std::vector<Cap>& caps, std::vector<std::uint8_t>& dropped,
                           std::vector<std::vector<double>>& azimuths) {
    constexpr double eps = 1e-12;
    const std::size_t m = caps.size();
    dropped.assign(m, 0);
    // Caps inside other caps (or equal to one) change nothing: drop them.
    for (std::size_t j = 0; j < m; ++j) {
        if (dropped[j]) continue;
        for (std::size_t k = 0; k < m; ++k) {
            if (k == j || dropped[k]) continue;
            const Cap& a = caps[j];
            const Cap& b = caps[k];
            // j inside k: angle(u_j, u_k) + θ_j <= θ_k, i.e. θ_j <= θ_k and
            // u_j·u_k >= cos(θ_k − θ_j).
            if (a.h >= b.h - eps && dot(a.u, b.u) >= a.h * b.h + a.s * b.s - eps &&
                (a.h > b.h + eps || j > k || dot(a.u, b.u) < 1.0 - eps)) {
                dropped[j] = 1;
                break;
            }
        }
    }
    // Crossing points, as azimuths on both circles.
    if (azimuths.size() < m) azimuths.resize(m);
    for (std::size_t j = 0; j < m; ++j) azimuths[j].clear();
    for (std::size_t j = 0; j < m; ++j) {
        if (dropped[j]) continue;
        for (std::size_t k = j + 1; k < m; ++k) {
            if (dropped[k]) continue;
            const Cap& a = caps[j];
            const Cap& b = caps[k];
            const double g = dot(a.u, b.u);
            // The circles cross when |θ_j − θ_k| < angle < θ_j + θ_k.
            if (g <= a.h * b.h - a.s * b.s || g >= a.h * b.h + a.s * b.s) continue;
            const double w2 = 1.0 - g * g;
            if (w2 < 1e-14) continue;
            const double p = (a.h - b.h * g) / w2, q = (b.h - a.h * g) / w2;
            const double rest = 1.0 - (p * p + q * q + 2.0 * p * q * g);
            if (rest <= 0.0) continue;  // tangent (within rounding)
            const double t = std::sqrt(rest / w2);
            const Vec base = p * a.u + q * b.u, w = cross(a.u, b.u);
            for (const double sign : {1.0, -1.0}) {
                const Vec n = base + (sign * t) * w;
                azimuths[j].push_back(std::atan2(dot(n, a.e2), dot(n, a.e1)));
                azimuths[k].push_back(std::atan2(dot(n, b.e2), dot(n, b.e1)));
            }
        }
    }
    // The pole: N, the antipode of the centre S of the largest cap; S is buried and every arc
    // stays at least that cap's angular radius away from it.
    std::size_t largest = 0;
    for (std::size_t j = 1; j < m; ++j)
        if (!dropped[j] && (dropped[largest] || caps[j].h < caps[largest].h)) largest = j;
    const Vec pole = -1.0 * caps[largest].u;

    auto buried_by_other = [&](const Vec& n, std::size_t j) {
        for (std::size_t k = 0; k < m; ++k)
            if (k != j && !dropped[k] && dot(n, caps[k].u) > caps[k].h + eps) return true;
        return false;
    };
    // One exposed arc of circle j, from azimuth `hi` down to `lo` (the cap on the right).
    auto arc = [&](std::size_t j, double lo, double hi) {
        const Cap& c = caps[j];
        const int pieces = std::max(1, int(std::ceil((hi - lo) / (0.5 * kPi))));
        const double step = (hi - lo) / pieces;
        // The great circle through the ends cuts into the cap for θ <= π/2 (the arc bounds less
        // than the chord's triangle) and into the exposed side otherwise.
        const double segment =
            c.h >= 0.0 ? -circular_segment(c.h, step) : circular_segment(-c.h, step);
        double sum = 0.0;
        Vec from = on_circle(c, hi);
        for (int s = 1; s <= pieces; ++s) {
            const Vec to = on_circle(c, hi - s * step);
            sum += solid_angle(pole, from, to) + segment;
            from = to;
        }
        return sum;
    };
    double total = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        if (dropped[j]) continue;
        std::vector<double>& a = azimuths[j];
        if (a.empty()) {
            // No crossing: the whole circle is boundary unless another cap buries it.
            if (!buried_by_other(on_circle(caps[j], 0.0), j)) total += arc(j, 0.0, 2.0 * kPi);
            continue;
        }
        std::sort(a.begin(), a.end());
        for (std::size_t t = 0; t < a.size(); ++t) {
            const double lo = a[t];
            const double hi = t + 1 < a.size() ? a[t + 1] : a[0] + 2.0 * kPi;
            if (hi - lo < 1e-15) continue;
            if (!buried_by_other(on_circle(caps[j], 0.5 * (lo + hi)), j)) total += arc(j, lo, hi);
        }
    }
    // Rounding can leave a hair below 0 or above 4π.
    return std::clamp(total, 0.0, 4.0 * kPi);
}

}  // namespace

std::vector<double> exact_ball_areas(const Atoms& atoms, double radius_add, double pi_iso) {
    const std::size_t n = atoms.size();
    std::vector<double> area(n, 0.0);
    if (n == 0) return area;
    // BallUnion leaves out balls whose radius would not be positive: map its balls to atoms.
    std::vector<std::uint32_t> atom_of;
    atom_of.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double r = double(atoms.radius[i]) + radius_add;
        if (r * r + pi_iso > 0.0) atom_of.push_back(std::uint32_t(i));
    }
    const BallUnion balls(atoms, radius_add, pi_iso);
    const std::size_t nb = balls.size();
    const std::size_t chunk = 128;
    parallel_chunks((nb + chunk - 1) / chunk, thread_count(), [&](std::size_t c) {
        std::vector<Cap> caps;
        std::vector<std::uint8_t> dropped;
        std::vector<std::vector<double>> azimuths;
        for (std::size_t i = c * chunk; i < std::min(nb, (c + 1) * chunk); ++i) {
            const double* ci = balls.centre(std::uint32_t(i));
            const double ri = balls.radius(std::uint32_t(i));
            caps.clear();
            bool buried = false;
            for (const std::uint32_t* it = balls.neighbours_begin(std::uint32_t(i));
                 it != balls.neighbours_end(std::uint32_t(i)) && !buried; ++it) {
                const std::uint32_t j = *it;
                const double* cj = balls.centre(j);
                const double rj = balls.radius(j);
                const Vec e{cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
                const double d = std::sqrt(dot(e, e));
                if (d >= ri + rj) continue;
                if (d == 0.0) {
                    // Twins: the first keeps the area (as atom_sas_areas); a larger ball at the
                    // same centre buries this one, a smaller one nothing.
                    if (rj > ri || (rj == ri && j < i)) buried = true;
                    continue;
                }
                const double h = (d * d + ri * ri - rj * rj) / (2.0 * d * ri);
                if (h <= -1.0) {
                    buried = true;  // inside ball j
                    continue;
                }
                if (h >= 1.0) continue;  // ball j inside this one
                Cap cap;
                cap.u = (1.0 / d) * e;
                cap.h = h;
                cap.s = std::sqrt(std::max(0.0, 1.0 - h * h));
                // Any unit vector not along u for the azimuth basis.
                const Vec helper = std::abs(cap.u.x) < 0.6 ? Vec{1, 0, 0} : Vec{0, 1, 0};
                Vec e1 = cross(cap.u, helper);
                e1 = (1.0 / std::sqrt(dot(e1, e1))) * e1;
                cap.e1 = e1;
                cap.e2 = cross(cap.u, e1);
                caps.push_back(cap);
            }
            double omega = 4.0 * kPi;
            if (buried)
                omega = 0.0;
            else if (!caps.empty())
                omega = exposed_solid_angle(caps, dropped, azimuths);
            area[atom_of[i]] = omega * ri * ri;
        }
    });
    return area;
}

}  // namespace detail

std::vector<double> atom_exact_areas(const Atoms& atoms, float probe) {
    if (!(probe >= 0.0f) || !std::isfinite(probe))
        throw Error(ErrorCode::InvalidArgument,
                    "atom_exact_areas: the probe radius must be >= 0 (got " +
                        std::to_string(probe) + ")");
    return detail::exact_ball_areas(atoms, probe, 0.0);
}

}  // namespace fdmsurf
