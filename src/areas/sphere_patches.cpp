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
#include <numeric>
#include <string>
#include <vector>

#include "areas/areas_detail.hpp"
#include "base/power_cell.hpp"
#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf {
namespace detail {
namespace {

constexpr double kPi = std::numbers::pi;

// A buried cap of the unit sphere: n·u > h, of angular radius θ (cos θ = h, sin θ = s).
struct Cap {
    Vec3 u;
    double h, s;
};

// An orthonormal basis (e1, e2) of the plane of a cap's circle, for azimuths.
struct Basis {
    Vec3 e1, e2;
};

Basis basis_of(const Cap& c) {
    // Any unit vector not along u will do.
    const Vec3 helper = std::abs(c.u[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 e1 = cross(c.u, helper);
    e1 = scale(e1, 1.0 / std::sqrt(dot(e1, e1)));
    return {e1, cross(c.u, e1)};
}

Vec3 on_circle(const Cap& c, const Basis& b, double phi) {
    return add(add(scale(c.u, c.h), scale(b.e1, c.s * std::cos(phi))),
               scale(b.e2, c.s * std::sin(phi)));
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

// One exposed crossing on a circle: a pseudo-angle that orders the points around the circle as
// the azimuth does (no trigonometry), and the point.
struct OnCircle {
    double key;
    Vec3 n;
};

// Two circles that cross, of caps j and k (ranks; j has the lower index), at `plus` and `minus`
// (x± = base ± t u_j × u_k), with the points' pseudo-angles on each circle.
struct Pair {
    Vec3 plus, minus;
    std::uint32_t j, k;
    double j_plus, j_minus, k_plus, k_minus;
};

// Scratch space of one thread, reused from atom to atom. The caps that no other cap holds are
// kept and numbered by rank, from the largest (least h) to the smallest; per rank, the cap's
// index, its centre and height in arrays of their own (the tests read them in runs), and the
// ranks of the caps it meets, in increasing rank.
struct Scratch {
    std::vector<std::uint32_t> order;
    std::vector<std::uint32_t> kept;
    std::vector<double> ux, uy, uz, h, s;
    std::vector<std::vector<std::uint32_t>> overlapping;
    std::vector<std::uint32_t> meets;           // the ranks the cap being ranked meets
    std::vector<Basis> basis;                   // per rank
    std::vector<Pair> pairs;                    // the circles that cross
    std::vector<double> from, to;               // per rank, the intervals other caps hold
    std::vector<std::uint32_t> held;            // per rank, how many; from the cell's
                                                // edges, how many pairs were crossed
    std::vector<std::vector<OnCircle>> around;  // per rank, its exposed crossings
    std::vector<std::uint32_t> rank_of;         // per cap index; `kNone` when held by another
};

constexpr std::uint32_t kNone = ~std::uint32_t(0);

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
//
// `edges`, when given, are the pairs of caps (indices into `caps`) whose planes meet on an edge
// of the ball's power cell that comes into the ball (power_cell.hpp): an exposed crossing of
// two circles is a point of the cell on both planes, so on that edge, and only those pairs are
// crossed, each crossing tested against the caps that meet its circle. Returns -1 when a circle
// is left with an odd number of exposed crossings (rounding of the cell): the caller then calls
// without `edges`, which crosses every pair of circles.
double exposed_solid_angle(const std::vector<Cap>& caps, Scratch& w,
                           const std::vector<std::array<std::uint32_t, 2>>* edges) {
    constexpr double eps = 1e-12;
    const std::size_t m = caps.size();
    // Caps inside other caps (or equal to one) change nothing: drop them. Taken from the
    // largest down, a cap can only lie inside one already kept; about half of a protein atom's
    // caps do, so the pairs of those that remain are far fewer than all pairs. Of the kept ones,
    // those that meet are listed: only they can bury a point of each other's circle.
    w.order.resize(m);
    std::iota(w.order.begin(), w.order.end(), std::uint32_t(0));
    std::sort(w.order.begin(), w.order.end(), [&](std::uint32_t x, std::uint32_t y) {
        return caps[x].h < caps[y].h || (caps[x].h == caps[y].h && x < y);
    });
    w.kept.clear();
    w.ux.clear();
    w.uy.clear();
    w.uz.clear();
    w.h.clear();
    w.s.clear();
    w.rank_of.assign(m, kNone);
    for (const std::uint32_t c : w.order) {
        const Cap& b = caps[c];
        const std::size_t ranked = w.kept.size();
        w.meets.clear();
        bool inside = false;
        for (std::size_t a = 0; a < ranked; ++a) {
            // The same products as dot(u_a, u_b) and the bounds below in either order.
            const double g = w.ux[a] * b.u[0] + w.uy[a] * b.u[1] + w.uz[a] * b.u[2];
            if (g <= w.h[a] * b.h - w.s[a] * b.s) {
                // Apart (angle >= θ_a + θ_b), or, when θ_a + θ_b > π (h_a + h_b < 0), so far
                // round the back that the two cover the sphere (angle >= 2π − θ_a − θ_b).
                if (w.h[a] + b.h < 0.0) return 0.0;
                continue;
            }
            if (g >= w.h[a] * b.h + w.s[a] * b.s - eps) {
                // Inside cap a (angle <= θ_b − θ_a), or equal to it: it goes.
                inside = true;
                break;
            }
            w.meets.push_back(std::uint32_t(a));
        }
        if (inside) continue;
        w.rank_of[c] = std::uint32_t(ranked);
        w.kept.push_back(c);
        w.ux.push_back(b.u[0]);
        w.uy.push_back(b.u[1]);
        w.uz.push_back(b.u[2]);
        w.h.push_back(b.h);
        w.s.push_back(b.s);
        if (w.overlapping.size() <= ranked) w.overlapping.resize(ranked + 1);
        w.overlapping[ranked].assign(w.meets.begin(), w.meets.end());
        for (const std::uint32_t a : w.meets) w.overlapping[a].push_back(std::uint32_t(ranked));
    }
    const std::size_t n = w.kept.size();
    if (w.around.size() < n) w.around.resize(n);
    w.basis.resize(n);
    // Circle r's intervals are from[r n + l], to[r n + l] for l < held[r]: at most n − 1.
    w.from.resize(n * n);
    w.to.resize(n * n);
    w.held.assign(n, 0);
    for (std::size_t r = 0; r < n; ++r) {
        w.around[r].clear();
        w.basis[r] = basis_of(caps[w.kept[r]]);
    }
    auto key = [&](const Vec3& x, std::size_t r) {
        return pseudo_angle(dot(x, w.basis[r].e1), dot(x, w.basis[r].e2));
    };
    // The crossing points of the circles that cross, each pair taken in the order of the caps'
    // indices (which fixes the arithmetic's rounding). Going counter-clockwise about u_j, the
    // circle of cap j enters cap k at the crossing x₋ and leaves it at x₊ (the derivative of
    // x·u_k along the circle is −x·(u_j × u_k)); the circle of cap k enters cap j at x₊. So each
    // pair puts an interval of azimuths (as pseudo-angles) on both circles.
    w.pairs.clear();
    // A point of circle j inside another cap (that cap meets cap j: it is in j's list); ranks.
    // The cap that buried the last point is tried first: neighbouring points share it.
    std::uint32_t last = 0;
    auto buried_by = [&](const Vec3& p, std::size_t j) {
        if (last != j &&
            p[0] * w.ux[last] + p[1] * w.uy[last] + p[2] * w.uz[last] > w.h[last] + eps)
            return true;
        for (const std::uint32_t k : w.overlapping[j])
            if (p[0] * w.ux[k] + p[1] * w.uy[k] + p[2] * w.uz[k] > w.h[k] + eps) {
                last = k;
                return true;
            }
        return false;
    };
    // The crossing points of the circles of ranks ra and rb, x± = base ± t u_j × u_k, with j
    // the one of the lower cap index (which fixes the arithmetic's rounding); false when they
    // do not cross (or touch, within rounding).
    auto crossing = [&](std::uint32_t ra, std::uint32_t rb, std::uint32_t& j, std::uint32_t& k,
                        Vec3& plus, Vec3& minus) {
        const bool swap = w.kept[rb] < w.kept[ra];
        j = swap ? rb : ra;
        k = swap ? ra : rb;
        const Cap& a = caps[w.kept[j]];
        const Cap& b = caps[w.kept[k]];
        const double g = dot(a.u, b.u);
        const double w2 = 1.0 - g * g;
        if (w2 < 1e-14) return false;
        const double p = (a.h - b.h * g) / w2, q = (b.h - a.h * g) / w2;
        const double rest = 1.0 - (p * p + q * q + 2.0 * p * q * g);
        if (rest <= 0.0) return false;
        const double t = std::sqrt(rest / w2);
        const Vec3 base = add(scale(a.u, p), scale(b.u, q)), c = cross(a.u, b.u);
        plus = add(base, scale(c, t));
        minus = add(base, scale(c, -t));
        return true;
    };
    for (std::size_t e = 0; edges && e < edges->size(); ++e) {
        const std::uint32_t ra = w.rank_of[(*edges)[e][0]], rb = w.rank_of[(*edges)[e][1]];
        // A plane of the cell's that the ranking dropped (equal to a larger cap, as twin
        // neighbours give) may carry part of an edge, and with it crossings: cross every pair.
        if (ra == kNone || rb == kNone) return -1.0;
        std::uint32_t j, k;
        Vec3 plus, minus;
        if (!crossing(ra, rb, j, k, plus, minus)) continue;
        ++w.held[j];
        ++w.held[k];
        for (const Vec3& x : {plus, minus}) {
            if (buried_by(x, j)) continue;
            w.around[j].push_back({key(x, j), x});
            w.around[k].push_back({key(x, k), x});
        }
    }
    for (std::size_t r = 0; edges && r < n; ++r)
        if (w.around[r].size() % 2 == 1) return -1.0;
    for (std::size_t ra = 0; ra < n && !edges; ++ra) {
        for (const std::uint32_t rb : w.overlapping[ra]) {
            if (rb <= ra) continue;
            Pair pair;
            if (!crossing(std::uint32_t(ra), rb, pair.j, pair.k, pair.plus, pair.minus)) continue;
            const std::uint32_t j = pair.j, k = pair.k;
            pair.j_plus = key(pair.plus, j);
            pair.j_minus = key(pair.minus, j);
            pair.k_plus = key(pair.plus, k);
            pair.k_minus = key(pair.minus, k);
            w.from[j * n + w.held[j]] = pair.j_minus;
            w.to[j * n + w.held[j]++] = pair.j_plus;
            w.from[k * n + w.held[k]] = pair.k_plus;
            w.to[k * n + w.held[k]++] = pair.k_minus;
            w.pairs.push_back(pair);
        }
    }
    // A crossing of circle j lies inside a third cap exactly when its azimuth lies strictly
    // inside that cap's interval on circle j (a cap that holds the point meets circle j; one
    // that holds all of circle j holds cap j or covers the sphere with it, and is gone). Its
    // own pair's interval ends there, so it never holds it. A buried crossing is only counted:
    // both arcs at it lie inside the cap that buries it (neither crosses that cap's circle
    // before the next crossing), so only exposed crossings can end an exposed arc.
    auto exposed_on = [&](double e, std::size_t j) {
        const double* from = w.from.data() + j * n;
        const double* to = w.to.data() + j * n;
        // f < e < t, or for an interval across the key's 0, f < e or e < t; in runs of four
        // without a branch.
        auto holds = [&](std::size_t l) -> std::int64_t {
            const double f = from[l], t = to[l];
            const std::int64_t lo = f < e, hi = e<t, across = f> t;
            return (lo & hi) | (across & (lo | hi));
        };
        const std::size_t count = w.held[j];
        std::size_t l = 0;
        for (; l + 4 <= count; l += 4)
            if (holds(l) | holds(l + 1) | holds(l + 2) | holds(l + 3)) return false;
        for (; l < count; ++l)
            if (holds(l)) return false;
        return true;
    };
    for (const Pair& pair : w.pairs) {
        if (exposed_on(pair.j_plus, pair.j)) {
            w.around[pair.j].push_back({pair.j_plus, pair.plus});
            w.around[pair.k].push_back({pair.k_plus, pair.plus});
        }
        if (exposed_on(pair.j_minus, pair.j)) {
            w.around[pair.j].push_back({pair.j_minus, pair.minus});
            w.around[pair.k].push_back({pair.k_minus, pair.minus});
        }
    }
    // The pole: N, the antipode of the centre S of the largest cap; S is buried and every arc
    // stays at least that cap's angular radius away from it.
    const Vec3 pole = scale(caps[w.kept[0]].u, -1.0);

    // One exposed arc of circle c from `from` to `to` (counter-clockwise about u, spanning
    // `dphi`), integrated from `to` back to `from`: the cap on the right.
    auto arc = [&](const Cap& c, std::size_t r, const Vec3& from, const Vec3& to, double dphi) {
        // The great circle through the ends cuts into the cap for θ <= π/2 (the arc bounds less
        // than the chord's triangle) and into the exposed side otherwise.
        auto segment = [&](double step) {
            return c.h >= 0.0 ? -circular_segment(c.h, step) : circular_segment(-c.h, step);
        };
        if (dphi <= 0.5 * kPi) return solid_angle(pole, to, from) + segment(dphi);
        const Basis& b = w.basis[r];
        const int pieces = int(std::ceil(dphi / (0.5 * kPi)));
        const double step = dphi / pieces;
        const double phi0 = std::atan2(dot(from, b.e2), dot(from, b.e1));
        double sum = 0.0;
        Vec3 a = to;
        for (int s = 1; s <= pieces; ++s) {
            const Vec3 e = s == pieces ? from : on_circle(c, b, phi0 + dphi - s * step);
            sum += solid_angle(pole, a, e) + segment(step);
            a = e;
        }
        return sum;
    };
    // The arcs, summed in the caps' index order.
    double total = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
        const std::size_t j = w.rank_of[i];
        if (j == kNone) continue;
        const Cap& c = caps[i];
        std::vector<OnCircle>& around = w.around[j];
        if (w.held[j] == 0) {
            // No crossing: the whole circle is boundary unless another cap buries it.
            const Vec3 p = on_circle(c, w.basis[j], 0.0);
            if (!buried_by(p, j)) total += arc(c, j, p, p, 2.0 * kPi);
            continue;
        }
        // One exposed crossing or none: every arc touches a buried one.
        if (around.size() < 2) continue;
        std::sort(around.begin(), around.end(),
                  [](const OnCircle& x, const OnCircle& y) { return x.key < y.key; });
        const std::size_t count = around.size();
        for (std::size_t t = 0; t < count; ++t) {
            const Vec3& p = around[t].n;
            const Vec3& q = around[(t + 1) % count].n;
            // In the circle's plane: the ends' directions from its centre, the angle between.
            const Vec3 pa = add(p, scale(c.u, -c.h)), pb = add(q, scale(c.u, -c.h));
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
            if (buried_by(mid, j)) continue;
            total += arc(c, j, p, q, dphi);
        }
    }
    // Rounding can leave a hair below 0 or above 4π.
    return std::clamp(total, 0.0, 4.0 * kPi);
}

// A thread's scratch space for cell_exposed_solid_angle below.
struct Workspace {
    Scratch scratch;
    PowerCell cell;
    std::vector<CellPlane> planes;
    std::vector<std::uint32_t> order, keep;
    std::vector<Cap> shaping;
    std::vector<std::uint32_t> shaping_index;           // per cap, its place in `shaping`
    std::vector<std::array<std::uint32_t, 2>> edges;  // the cell's edges in the ball, in `shaping`
};

// The exposed solid angle of a unit sphere less the union of `caps` (none empty), from only the
// caps whose planes are faces of the ball's power cell that meet the ball (power_cell.hpp):
// about a third of a protein atom's, and none when the cell says the ball is buried.
double cell_exposed_solid_angle(const std::vector<Cap>& caps, Workspace& w) {
    w.planes.resize(caps.size());
    for (std::size_t c = 0; c < caps.size(); ++c) w.planes[c] = {caps[c].u, caps[c].h};
    order_largest_first(w.planes, w.order);
    switch (w.cell.filter(w.planes, w.order, w.keep)) {
    case CellVerdict::Buried:
        return 0.0;
    case CellVerdict::Filtered: {
        w.shaping.clear();
        w.shaping_index.assign(caps.size(), kNone);
        for (const std::uint32_t c : w.keep) {
            w.shaping_index[c] = std::uint32_t(w.shaping.size());
            w.shaping.push_back(caps[c]);
        }
        // A plane kept for touching the cell was never clipped, so its edges are missing.
        if (!w.cell.touched()) {
            w.edges.clear();
            // Both planes of an edge in the ball are kept.
            for (const auto& [a, b] : w.cell.edges_in_ball())
                w.edges.push_back({w.shaping_index[a], w.shaping_index[b]});
            const double omega = exposed_solid_angle(w.shaping, w.scratch, &w.edges);
            if (omega >= 0.0) return omega;
        }
        return exposed_solid_angle(w.shaping, w.scratch, nullptr);
    }
    case CellVerdict::Unknown:
        break;
    }
    return exposed_solid_angle(caps, w.scratch, nullptr);
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
    // The centres and radii in the cell list's order, so that the balls near a centre are a few
    // runs of memory whose distance tests vectorise.
    std::vector<double> bx(n), by(n), bz(n), br(n);
    for (std::size_t s = 0; s < n; ++s) {
        const std::uint32_t j = cells.items[s];
        bx[s] = atoms.xyz[3 * j];
        by[s] = atoms.xyz[3 * j + 1];
        bz[s] = atoms.xyz[3 * j + 2];
        br[s] = radius[j];
    }
    const std::size_t chunk = 128;
    parallel_chunks((n + chunk - 1) / chunk, thread_count(), [&](std::size_t c) {
        std::vector<Cap> caps;
        Workspace work;
        std::vector<std::uint32_t> near;
        for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
            const double ri = radius[i];
            if (ri == 0.0) continue;
            const double ci[3] = {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
            // The balls that meet this one (and itself), in the cell list's order.
            std::size_t meeting = 0;
            cells.for_each_run_near(ci, [&](std::uint32_t first, std::uint32_t end) {
                if (near.size() < meeting + (end - first)) near.resize(meeting + (end - first));
                for (std::uint32_t s = first; s < end; ++s) {
                    const double ex = bx[s] - ci[0], ey = by[s] - ci[1], ez = bz[s] - ci[2];
                    const double reach = ri + br[s];
                    near[meeting] = s;
                    meeting += ex * ex + ey * ey + ez * ez < reach * reach;
                }
            });
            caps.clear();
            bool buried = false;
            for (std::size_t m = 0; m < meeting && !buried; ++m) {
                const std::uint32_t j = cells.items[near[m]];
                if (j == i || radius[j] == 0.0) continue;
                const double cj[3] = {atoms.xyz[3 * j], atoms.xyz[3 * j + 1], atoms.xyz[3 * j + 2]};
                const double rj = radius[j];
                const Vec3 e{cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
                const double d2 = dot(e, e);
                if (d2 == 0.0) {
                    // Twins: the first keeps the area (as atom_sas_areas); a larger ball at the
                    // same centre buries this one, a smaller one nothing.
                    if (rj > ri || (rj == ri && j < i)) buried = true;
                    continue;
                }
                const double d = std::sqrt(d2);
                const double h = (d2 + ri * ri - rj * rj) / (2.0 * d * ri);
                if (h <= -1.0) {
                    buried = true;  // inside ball j
                    continue;
                }
                if (h >= 1.0) continue;  // ball j inside this one
                Cap cap;
                cap.u = scale(e, 1.0 / d);
                cap.h = h;
                cap.s = std::sqrt(std::max(0.0, 1.0 - h * h));
                caps.push_back(cap);
            }
            double omega = 4.0 * kPi;
            if (buried)
                omega = 0.0;
            else if (!caps.empty())
                omega = cell_exposed_solid_angle(caps, work);
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
