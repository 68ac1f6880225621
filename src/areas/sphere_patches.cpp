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
#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf {
namespace detail {
namespace {

constexpr double kPi = std::numbers::pi;

// A buried cap of the unit sphere: n·u > h, of angular radius θ (cos θ = h, sin θ = s), with an
// orthonormal basis (e1, e2) of the plane of its circle for azimuths.
struct Cap {
    Vec3 u, e1, e2;
    double h, s;
};

Vec3 on_circle(const Cap& c, double phi) {
    return add(add(scale(c.u, c.h), scale(c.e1, c.s * std::cos(phi))),
               scale(c.e2, c.s * std::sin(phi)));
}

// Signed solid angle of the geodesic triangle (a, b, c), unit vectors; positive when they turn
// counter-clockwise seen from outside.
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
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

// An exposed crossing point of two circles.
struct Crossing {
    Vec3 n;
};

// One crossing on a circle: the point, the other circle, and a pseudo-angle that orders the
// points around the circle as the azimuth does (no trigonometry).
struct OnCircle {
    double key;
    std::uint32_t crossing;
    std::uint32_t other;
};

// Scratch space of one thread, reused from atom to atom.
struct Scratch {
    std::vector<std::uint8_t> dropped;
    std::vector<std::vector<std::uint32_t>> overlapping;  // per cap, the caps it meets
    std::vector<std::vector<OnCircle>> around;            // per cap, its crossings
    std::vector<Crossing> crossings;
    std::vector<std::uint8_t> crossed;  // per cap: its circle crosses another
};

double pseudo_angle(double x, double y) {
    const double t = x / (std::abs(x) + std::abs(y));
    return y >= 0.0 ? 1.0 - t : 3.0 + t;  // in [0, 4), increasing with atan2(y, x) mod 2π
}

// The exposed solid angle (steradians) of a unit sphere less the union of `caps` (none empty).
//
// An arc of a circle between two consecutive crossings crosses no other circle, so it lies
// inside some other cap all along or outside all of them; when a crossing at its end lies
// inside a third cap the arc does too. So exposed arcs run between exposed crossings, and an
// arc between two consecutive exposed crossings is exposed when its midpoint is.
double exposed_solid_angle(const std::vector<Cap>& caps, Scratch& w) {
    constexpr double eps = 1e-12;
    const std::size_t m = caps.size();
    w.dropped.assign(m, 0);
    if (w.overlapping.size() < m) w.overlapping.resize(m);
    if (w.around.size() < m) w.around.resize(m);
    for (std::size_t j = 0; j < m; ++j) {
        w.overlapping[j].clear();
        w.around[j].clear();
    }
    w.crossings.clear();
    // Caps inside other caps (or equal to one) change nothing: drop them. The others that
    // meet are listed: only they can bury a point of each other's circle.
    for (std::size_t j = 0; j < m; ++j) {
        const Cap& a = caps[j];
        for (std::size_t k = j + 1; k < m; ++k) {
            const Cap& b = caps[k];
            const double g = dot(a.u, b.u);
            if (g <= a.h * b.h - a.s * b.s) continue;  // apart: angle >= θ_j + θ_k
            if (g >= a.h * b.h + a.s * b.s - eps) {
                // One inside the other: angle <= |θ_j − θ_k|; the smaller goes (of equal ones
                // the later).
                w.dropped[a.h > b.h + eps ? j : k] = 1;
                continue;
            }
            w.overlapping[j].push_back(std::uint32_t(k));
            w.overlapping[k].push_back(std::uint32_t(j));
        }
    }
    // A point of circle j inside another cap (that cap meets cap j: it is in j's list). The cap
    // that buried the last point is tried first: neighbouring points share it.
    std::uint32_t last = 0;
    auto buried_by = [&](const Vec3& n, std::size_t j, std::size_t skip) {
        if (last != skip && last < m && !w.dropped[last] &&
            dot(n, caps[last].u) > caps[last].h + eps)
            return true;
        for (const std::uint32_t k : w.overlapping[j])
            if (k != skip && !w.dropped[k] && dot(n, caps[k].u) > caps[k].h + eps) {
                last = k;
                return true;
            }
        return false;
    };
    // Crossing points of the circles that cross. A buried one is only counted: both arcs at
    // it lie inside the cap that buries it (neither crosses that cap's circle before the next
    // crossing), so only exposed crossings can end an exposed arc.
    w.crossed.assign(m, 0);
    for (std::size_t j = 0; j < m; ++j) {
        if (w.dropped[j]) continue;
        const Cap& a = caps[j];
        for (const std::uint32_t k : w.overlapping[j]) {
            if (k <= j || w.dropped[k]) continue;
            const Cap& b = caps[k];
            const double g = dot(a.u, b.u);
            const double w2 = 1.0 - g * g;
            if (w2 < 1e-14) continue;
            const double p = (a.h - b.h * g) / w2, q = (b.h - a.h * g) / w2;
            const double rest = 1.0 - (p * p + q * q + 2.0 * p * q * g);
            if (rest <= 0.0) continue;  // tangent (within rounding)
            const double t = std::sqrt(rest / w2);
            const Vec3 base = add(scale(a.u, p), scale(b.u, q)), c = cross(a.u, b.u);
            w.crossed[j] = w.crossed[k] = 1;
            for (const double sign : {1.0, -1.0}) {
                const Vec3 n = add(base, scale(c, sign * t));
                if (buried_by(n, j, k)) continue;
                const std::uint32_t id = std::uint32_t(w.crossings.size());
                w.crossings.push_back({n});
                w.around[j].push_back({pseudo_angle(dot(n, a.e1), dot(n, a.e2)), id, k});
                w.around[k].push_back(
                    {pseudo_angle(dot(n, b.e1), dot(n, b.e2)), id, std::uint32_t(j)});
            }
        }
    }
    // The pole: N, the antipode of the centre S of the largest cap; S is buried and every arc
    // stays at least that cap's angular radius away from it.
    std::size_t largest = m;
    for (std::size_t j = 0; j < m; ++j)
        if (!w.dropped[j] && (largest == m || caps[j].h < caps[largest].h)) largest = j;
    const Vec3 pole = scale(caps[largest].u, -1.0);

    // One exposed arc of circle j from `from` to `to` (counter-clockwise about u_j, spanning
    // `dphi`), integrated from `to` back to `from`: the cap on the right.
    auto arc = [&](const Cap& c, const Vec3& from, const Vec3& to, double dphi) {
        // The great circle through the ends cuts into the cap for θ <= π/2 (the arc bounds less
        // than the chord's triangle) and into the exposed side otherwise.
        auto segment = [&](double step) {
            return c.h >= 0.0 ? -circular_segment(c.h, step) : circular_segment(-c.h, step);
        };
        if (dphi <= 0.5 * kPi) return solid_angle(pole, to, from) + segment(dphi);
        const int pieces = int(std::ceil(dphi / (0.5 * kPi)));
        const double step = dphi / pieces;
        const double phi0 = std::atan2(dot(from, c.e2), dot(from, c.e1));
        double sum = 0.0;
        Vec3 a = to;
        for (int s = 1; s <= pieces; ++s) {
            const Vec3 b = s == pieces ? from : on_circle(c, phi0 + dphi - s * step);
            sum += solid_angle(pole, a, b) + segment(step);
            a = b;
        }
        return sum;
    };
    double total = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        if (w.dropped[j]) continue;
        const Cap& c = caps[j];
        std::vector<OnCircle>& around = w.around[j];
        if (!w.crossed[j]) {
            // No crossing: the whole circle is boundary unless another cap buries it.
            const Vec3 p = on_circle(c, 0.0);
            if (!buried_by(p, j, m)) total += arc(c, p, p, 2.0 * kPi);
            continue;
        }
        // One exposed crossing or none: every arc touches a buried one.
        if (around.size() < 2) continue;
        std::sort(around.begin(), around.end(),
                  [](const OnCircle& x, const OnCircle& y) { return x.key < y.key; });
        const std::size_t count = around.size();
        for (std::size_t t = 0; t < count; ++t) {
            const OnCircle& from = around[t];
            const OnCircle& to = around[(t + 1) % count];
            const Crossing& p = w.crossings[from.crossing];
            const Crossing& q = w.crossings[to.crossing];
            // In the circle's plane: the ends' directions from its centre, the angle between.
            const Vec3 pa = add(p.n, scale(c.u, -c.h)), pb = add(q.n, scale(c.u, -c.h));
            const double cosine = dot(pa, pb), sine = dot(cross(pa, pb), c.u);
            double dphi = std::atan2(sine, cosine);
            if (dphi < 0.0) dphi += 2.0 * kPi;
            if (dphi < 1e-12) continue;  // three circles through one point
            // The midpoint outside every other cap? (Buried crossings between the ends would
            // make the whole arc buried, and then its midpoint too.)
            Vec3 mid_dir = add(pa, pb);
            double len = std::sqrt(dot(mid_dir, mid_dir));
            if (dphi > kPi) mid_dir = scale(mid_dir, -1.0);
            if (len < 1e-9 * c.s) {  // ends opposite each other: the perpendicular
                mid_dir = cross(c.u, pa);
                len = std::sqrt(dot(mid_dir, mid_dir));
            }
            const Vec3 mid = add(scale(c.u, c.h), scale(mid_dir, c.s / len));
            if (buried_by(mid, j, m)) continue;
            total += arc(c, p.n, q.n, dphi);
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
    // Ball radii; 0 for balls that vanish (r² + π_iso <= 0).
    std::vector<double> radius(n, 0.0);
    double r_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double r = double(atoms.radius[i]) + radius_add;
        if (r * r + pi_iso > 0.0) radius[i] = std::sqrt(r * r + pi_iso);
        r_max = std::max(r_max, radius[i]);
    }
    if (r_max == 0.0) return area;
    // Two balls meet when their centres are closer than the sum of the radii, at most 2 r_max:
    // the neighbours are in the 27 cells around a centre's.
    const CellList cells = make_cell_list(atoms.xyz, 2.0 * r_max);
    const std::size_t chunk = 128;
    parallel_chunks((n + chunk - 1) / chunk, thread_count(), [&](std::size_t c) {
        std::vector<Cap> caps;
        Scratch scratch;
        for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
            const double ri = radius[i];
            if (ri == 0.0) continue;
            const double ci[3] = {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
            caps.clear();
            bool buried = false;
            cells.for_each_near(ci, [&](std::uint32_t j) {
                if (j == i || buried || radius[j] == 0.0) return;
                const double cj[3] = {atoms.xyz[3 * j], atoms.xyz[3 * j + 1], atoms.xyz[3 * j + 2]};
                const double rj = radius[j];
                const Vec3 e{cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
                const double d2 = dot(e, e);
                if (d2 >= (ri + rj) * (ri + rj)) return;
                if (d2 == 0.0) {
                    // Twins: the first keeps the area (as atom_sas_areas); a larger ball at the
                    // same centre buries this one, a smaller one nothing.
                    if (rj > ri || (rj == ri && j < i)) buried = true;
                    return;
                }
                const double d = std::sqrt(d2);
                const double h = (d2 + ri * ri - rj * rj) / (2.0 * d * ri);
                if (h <= -1.0) {
                    buried = true;  // inside ball j
                    return;
                }
                if (h >= 1.0) return;  // ball j inside this one
                Cap cap;
                cap.u = scale(e, 1.0 / d);
                cap.h = h;
                cap.s = std::sqrt(std::max(0.0, 1.0 - h * h));
                // Any unit vector not along u for the azimuth basis.
                const Vec3 helper = std::abs(cap.u[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
                Vec3 e1 = cross(cap.u, helper);
                e1 = scale(e1, 1.0 / std::sqrt(dot(e1, e1)));
                cap.e1 = e1;
                cap.e2 = cross(cap.u, e1);
                caps.push_back(cap);
            });
            double omega = 4.0 * kPi;
            if (buried)
                omega = 0.0;
            else if (!caps.empty())
                omega = exposed_solid_angle(caps, scratch);
            area[i] = omega * ri * ri;
        }
    });
    return area;
}

}  // namespace detail

std::vector<double> atom_exact_areas(const Atoms& atoms, float probe) {
    if (!(probe >= 0.0f) || !std::isfinite(probe))
        throw Error(
            ErrorCode::InvalidArgument,
            "atom_exact_areas: the probe radius must be >= 0 (got " + std::to_string(probe) + ")");
    detail::check_area_atoms(atoms, probe, "atom_exact_areas");
    return detail::exact_ball_areas(atoms, probe, 0.0);
}

namespace detail {

void check_area_atoms(const Atoms& atoms, float probe, const char* function) {
    const std::string who = std::string(function) + ": ";
    if (atoms.xyz.size() != 3 * atoms.radius.size())
        throw Error(ErrorCode::InvalidArgument, who + "xyz must hold 3 floats per radius");
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const float r = atoms.radius[i];
        // As plan_grid: a radius of 0 is a ball of the probe's radius in the sas.
        if (!(r >= 0.0f && r + probe > 0.0f) || !std::isfinite(r))
            throw Error(ErrorCode::InvalidArgument,
                        who + "atom " + std::to_string(i + 1) + " has radius " + std::to_string(r));
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(atoms.xyz[3 * i + a]))
                throw Error(ErrorCode::InvalidArgument,
                            who + "atom " + std::to_string(i + 1) + " has a non-finite coordinate");
    }
}

}  // namespace detail

}  // namespace fdmsurf
