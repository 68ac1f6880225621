// Exposed SAS arcs: every pair of intersecting inflated balls gives a circle; each neighbour ball
// buries an angular interval of it; what no ball buries is exposed (ALGORITHM.md §7, closing).
#include "grid/ses_features.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "base/parallel.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// A unit vector perpendicular to the unit vector u.
Vec3 perpendicular(const Vec3& u) {
    Vec3 t = std::abs(u[0]) < 0.6 ? Vec3{1, 0, 0}
                                  : (std::abs(u[1]) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    Vec3 p = cross(u, t);
    return scale(p, 1.0 / std::sqrt(dot(p, p)));
}

// A pseudo-angle of the direction (x, y) in [0, 4): increasing with its angle from +x like the
// angle itself (the "diamond angle"), without trigonometry; antipodal directions differ by 2.
double pseudo_angle(double x, double y) {
    if (y >= 0.0) return x >= 0.0 ? y / (x + y) : 1.0 - x / (y - x);
    return x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}

// The angle in [0, 2 pi) of the direction whose pseudo-angle is p (in [0, 4)).
double angle_of_pseudo(double p) {
    double x, y;
    if (p < 1.0)
        x = 1.0 - p, y = p;
    else if (p < 2.0)
        x = 1.0 - p, y = 2.0 - p;
    else if (p < 3.0)
        x = p - 3.0, y = 2.0 - p;
    else
        x = p - 3.0, y = p - 4.0;
    const double a = std::atan2(y, x);
    return a < 0.0 ? a + kTwoPi : a;
}

// A conservative record of the part of a circle's turn of pseudo-angles [0, 4) that buried
// intervals cover: 256 bins, each set when one interval holds it whole (strictly, ends
// included). Every bin set means no point of the circle is exposed, which exposed_parts would
// find from the same intervals; a gap smaller than a bin leaves bins unset and exposed_parts
// decides. Most circles buried by several balls are found so before their last ball.
struct CoverBins {
    static constexpr int kBins = 256;
    static constexpr double kPerUnit = kBins / 4.0;
    std::uint64_t words[4] = {0, 0, 0, 0};
    void set(int first, int last) {  // bins first..last, 0 <= first <= last < kBins
        for (int w = first >> 6; w <= last >> 6; ++w) {
            const int lo = std::max(first, w * 64) - w * 64, hi = std::min(last, w * 64 + 63) - w * 64;
            const std::uint64_t upper = hi == 63 ? ~std::uint64_t(0) : (std::uint64_t(1) << (hi + 1)) - 1;
            words[w] |= upper & (~std::uint64_t(0) << lo);
        }
    }
    // The open interval (from, from + len) of pseudo-angles (from in [0, 4), len in (0, 4]);
    // returns whether every bin is now set.
    bool add(double from, double len) {
        if (len >= 4.0) {
            for (auto& w : words) w = ~std::uint64_t(0);
            return true;
        }
        // Bins b with from < b / kPerUnit and (b + 1) / kPerUnit < from + len, unwrapped.
        const int first = static_cast<int>(std::floor(from * kPerUnit)) + 1;
        const int last = static_cast<int>(std::ceil((from + len) * kPerUnit)) - 2;
        if (last < first) return false;
        if (last < kBins) {
            set(first, last);
        } else if (first >= kBins) {
            set(first - kBins, last - kBins);
        } else {
            set(first, kBins - 1);
            set(0, last - kBins);
        }
        return (words[0] & words[1] & words[2] & words[3]) == ~std::uint64_t(0);
    }
};

// Exposed parts of the turn [0, 4) of pseudo-angles once the intervals [start, start + length)
// (start in [0, 4), length in (0, 4]) are removed, as (start, length), into `out`; `cuts` and
// `gaps` are scratch (reused from circle to circle).
using Interval = std::pair<double, double>;
void exposed_parts(const std::vector<Interval>& buried, std::vector<Interval>& cuts,
                   std::vector<Interval>& gaps, std::vector<Interval>& out) {
    constexpr double kTurn = 4.0;
    out.clear();
    if (buried.empty()) {
        out.push_back({0.0, kTurn});
        return;
    }
    cuts.clear();  // [a, b] within [0, 4]
    for (auto [s, len] : buried) {
        if (s + len <= kTurn) {
            cuts.push_back({s, s + len});
        } else {
            cuts.push_back({s, kTurn});
            cuts.push_back({0.0, s + len - kTurn});
        }
    }
    std::sort(cuts.begin(), cuts.end());
    gaps.clear();  // [a, b]
    double cursor = 0.0;
    for (auto [a, b] : cuts) {
        if (a > cursor) gaps.push_back({cursor, a});
        cursor = std::max(cursor, b);
    }
    if (cursor < kTurn) gaps.push_back({cursor, kTurn});
    // A gap that runs through angle 0 is one arc.
    if (gaps.size() >= 2 && gaps.front().first == 0.0 && gaps.back().second == kTurn) {
        gaps.back().second = kTurn + gaps.front().second;
        gaps.erase(gaps.begin());
    }
    for (auto [a, b] : gaps)
        if (b - a > 1e-9) out.push_back({a, b - a});
}

// The steps of build_ses_features, in order: read_balls, without_duplicates (when two balls
// coincide, the build starts again without the copies), bin_spheres, find_neighbours,
// neighbours_by_sphere, cut_circles, bin_arcs.
struct FeatureBuilder {
    // Atoms per task of the neighbour and circle passes.
    static constexpr std::size_t kChunk = 256;

    const Atoms& atoms;
    const float probe;
    const std::size_t n;
    const std::size_t chunk_count;
    SesFeatures f;
    std::vector<Vec3> c;    // centres, by atom
    std::vector<double> R;  // inflated radii r + probe, by atom
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};  // centres' bounds
    // The balls by bin: bin b holds atoms order[start[b]] .. order[start[b + 1] - 1].
    std::vector<std::uint32_t> start, order;
    std::vector<std::uint32_t> nb_start, nb;  // the intersecting balls of each atom (rows by atom)

    FeatureBuilder(const Atoms& atoms_in, float probe_in)
        : atoms(atoms_in),
          probe(probe_in),
          n(atoms_in.size()),
          chunk_count((n + kChunk - 1) / kChunk),
          c(n),
          R(n) {}

    // Checks each atom's radius and coordinates; the centres, inflated radii and bounds.
    void read_balls() {
        for (std::size_t i = 0; i < n; ++i) {
            const float r = atoms.radius[i];
            if (!(r > 0.0f) || !std::isfinite(r))
                throw Error(ErrorCode::InvalidArgument,
                            "atom " + std::to_string(i + 1) + " has radius " + std::to_string(r));
            for (int a = 0; a < 3; ++a)
                if (!std::isfinite(atoms.xyz[3 * i + a]))
                    throw Error(ErrorCode::InvalidArgument,
                                "atom " + std::to_string(i + 1) + " has a non-finite coordinate");
            c[i] = {atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
            R[i] = double(r) + probe;
            f.r_max = std::max(f.r_max, static_cast<float>(R[i]));
            const double p[3] = {c[i][0], c[i][1], c[i][2]};
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
        }
    }

    // Coincident balls (the same centre and radius: duplicated atoms) are one ball. Kept twice,
    // each would bury the other's face wherever rounding puts the projection a hair inside it,
    // and no circle joins them: d would jump there. The first of each is kept. Balls are the
    // same when their stored float spheres are (centre and float(r + probe), as the shaders read
    // them), so that two radii that round to one inflated radius are one ball there too.
    // Whether there were any; if so, `unique` holds the atoms without them.
    bool without_duplicates(Atoms& unique) const {
        std::vector<std::uint32_t> by_ball(n);
        for (std::size_t i = 0; i < n; ++i) by_ball[i] = static_cast<std::uint32_t>(i);
        auto key = [&](std::uint32_t i) {
            return std::array<float, 4>{atoms.xyz[3 * i], atoms.xyz[3 * i + 1],
                                        atoms.xyz[3 * i + 2], static_cast<float>(R[i])};
        };
        std::sort(by_ball.begin(), by_ball.end(), [&](std::uint32_t a, std::uint32_t b) {
            const auto ka = key(a), kb = key(b);
            return ka != kb ? ka < kb : a < b;
        });
        std::vector<std::uint8_t> duplicate(n, 0);
        bool any = false;
        for (std::size_t k = 1; k < n; ++k) {
            if (key(by_ball[k]) == key(by_ball[k - 1])) duplicate[by_ball[k]] = 1, any = true;
        }
        if (!any) return false;
        for (std::size_t i = 0; i < n; ++i) {
            if (duplicate[i]) continue;
            unique.xyz.insert(unique.xyz.end(), &atoms.xyz[3 * i], &atoms.xyz[3 * i] + 3);
            unique.radius.push_back(atoms.radius[i]);
        }
        return true;
    }

    // The bin holding p (clamped to the bins), and its cell.
    std::size_t bin_index(const Vec3& p, int (&cell)[3]) const {
        const double q[3] = {p[0], p[1], p[2]};
        for (int a = 0; a < 3; ++a) {
            const double t = std::floor((q[a] - f.origin[a]) / f.bin_size);
            cell[a] = static_cast<int>(std::clamp(t, 0.0, double(f.dims[a] - 1)));
        }
        return (std::size_t(cell[2]) * f.dims[1] + cell[1]) * f.dims[0] + cell[0];
    }

    // Bins of edge r_max: two balls intersect only within two bins of each other. The balls
    // by bin (start, order) and the features' spheres in that order.
    void bin_spheres() {
        f.bin_size = f.r_max;
        for (int a = 0; a < 3; ++a) {
            f.origin[a] = static_cast<float>(lo[a]);
            f.dims[a] = static_cast<std::uint32_t>(std::floor((hi[a] - lo[a]) / f.bin_size)) + 1;
        }
        std::vector<std::size_t> bin_of(n);
        start.assign(f.bin_count() + 1, 0);
        for (std::size_t i = 0; i < n; ++i) {
            int cell[3];
            bin_of[i] = bin_index(c[i], cell);
            ++start[bin_of[i] + 1];
        }
        for (std::size_t b = 0; b < f.bin_count(); ++b) start[b + 1] += start[b];
        order.resize(n);
        {
            std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
            for (std::size_t i = 0; i < n; ++i)
                order[fill[bin_of[i]]++] = static_cast<std::uint32_t>(i);
        }
        f.sphere_start = start;
        f.spheres.resize(4 * n);
        for (std::size_t s = 0; s < n; ++s) {
            const std::uint32_t i = order[s];
            f.spheres[4 * s + 0] = atoms.xyz[3 * i + 0];
            f.spheres[4 * s + 1] = atoms.xyz[3 * i + 1];
            f.spheres[4 * s + 2] = atoms.xyz[3 * i + 2];
            f.spheres[4 * s + 3] = static_cast<float>(R[i]);
        }
    }

    // The balls that intersect those of chunk `chunk`'s atoms, appended to `out` (ascending bin
    // order), and each atom's count into nb_start[i + 1].
    void neighbours_of_chunk(std::size_t chunk, std::vector<std::uint32_t>& out) {
        for (std::size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
            const std::size_t before = out.size();
            int cell[3];
            bin_index(c[i], cell);
            for (int z = std::max(cell[2] - 2, 0); z <= std::min(cell[2] + 2, int(f.dims[2]) - 1);
                 ++z)
                for (int y = std::max(cell[1] - 2, 0);
                     y <= std::min(cell[1] + 2, int(f.dims[1]) - 1); ++y)
                    for (int x = std::max(cell[0] - 2, 0);
                         x <= std::min(cell[0] + 2, int(f.dims[0]) - 1); ++x) {
                        const std::size_t b = (std::size_t(z) * f.dims[1] + y) * f.dims[0] + x;
                        for (std::uint32_t s = start[b]; s < start[b + 1]; ++s) {
                            const std::uint32_t j = order[s];
                            if (j == i) continue;
                            const Vec3 d = sub(c[j], c[i]);
                            const double reach = R[i] + R[j];
                            if (dot(d, d) < reach * reach) out.push_back(j);
                        }
                    }
            nb_start[i + 1] = static_cast<std::uint32_t>(out.size() - before);
        }
    }

    // Neighbours: balls that intersect (compressed rows, ascending bin order), chunks of atoms
    // on all threads, joined in atom order.
    void find_neighbours() {
        nb_start.assign(n + 1, 0);
        std::vector<std::vector<std::uint32_t>> lists(chunk_count);
        parallel_chunks(chunk_count, thread_count(),
                        [&](std::size_t chunk) { neighbours_of_chunk(chunk, lists[chunk]); });
        for (std::size_t i = 0; i < n; ++i) nb_start[i + 1] += nb_start[i];
        nb.reserve(nb_start[n]);
        for (const auto& list : lists) nb.insert(nb.end(), list.begin(), list.end());
    }

    // The same lists by sphere index, for the host's burial tests.
    void neighbours_by_sphere() {
        std::vector<std::uint32_t> sphere_of(n);
        for (std::size_t s = 0; s < n; ++s) sphere_of[order[s]] = static_cast<std::uint32_t>(s);
        f.neighbour_start.assign(n + 1, 0);
        for (std::size_t s = 0; s < n; ++s)
            f.neighbour_start[s + 1] =
                f.neighbour_start[s] + (nb_start[order[s] + 1] - nb_start[order[s]]);
        f.neighbours.resize(nb.size());
        for (std::size_t s = 0; s < n; ++s) {
            std::uint32_t* out = f.neighbours.data() + f.neighbour_start[s];  // may be empty
            for (std::uint32_t q = nb_start[order[s]]; q < nb_start[order[s] + 1]; ++q)
                *out++ = sphere_of[nb[q]];
        }
    }

    // The circle where balls i and j meet: centre m, radius rho, plane spanned by e1 and e2.
    struct Circle {
        Vec3 m, e1, e2;
        double rho, rho2;
    };

    // Whether the neighbours of i other than j bury the circle whole; else the buried intervals
    // of pseudo-angle into `buried`. The ball that buried the last circle of i whole often buries
    // the next (`last_burier`): tried first (half of the circles are buried by one ball).
    bool buried_whole(const Circle& circle, std::size_t i, std::uint32_t j,
                      std::uint32_t& last_burier, std::vector<Interval>& buried) const {
        const Vec3& m = circle.m;
        const Vec3& e1 = circle.e1;
        const Vec3& e2 = circle.e2;
        const double rho = circle.rho, rho2 = circle.rho2;
        buried.clear();
        // What ball k does to the circle: with w = m - c_k,
        // |P(theta) - c_k|^2 = |w|^2 + rho^2 + 2 rho (A cos theta + B sin theta) < R_k^2.
        struct Cut {
            double A, B, M, E;
            bool misses, covers;  // no point inside ball k; every point inside it
        };
        auto cut_by = [&](std::uint32_t k) {
            const Vec3 w = sub(m, c[k]);
            Cut cut{dot(w, e1), dot(w, e2), 0.0, R[k] * R[k] - dot(w, w) - rho2, false, false};
            cut.M = std::sqrt(cut.A * cut.A + cut.B * cut.B);
            cut.misses = cut.E <= -2.0 * rho * cut.M;
            cut.covers = !cut.misses && cut.E >= 2.0 * rho * cut.M;
            return cut;
        };
        bool all_buried = last_burier != std::numeric_limits<std::uint32_t>::max() &&
                          last_burier != j && cut_by(last_burier).covers;
        CoverBins cover;
        for (std::uint32_t t = nb_start[i]; t < nb_start[i + 1] && !all_buried; ++t) {
            const std::uint32_t k = nb[t];
            if (k == j) continue;
            const Cut cut = cut_by(k);
            if (cut.misses) continue;
            if (cut.covers) {
                all_buried = true;
                last_burier = k;
                break;
            }
            const double A = cut.A, B = cut.B, M = cut.M, E = cut.E;
            // Buried where cos(theta - phi) < t, phi the angle of (A, B): from phi + open
            // to phi - open + 2 pi, open = acos t. The ends as directions (rotations of
            // (A, B) / M by +-open), ordered by their pseudo-angles: no trigonometry
            // for the circles that end up buried (nine in ten).
            const double t_cos = std::clamp(E / (2.0 * rho * M), -1.0, 1.0);
            const double sin_open = std::sqrt(std::max(0.0, 1.0 - t_cos * t_cos));
            const double ca = A / M, sa = B / M;
            const double from =
                pseudo_angle(ca * t_cos - sa * sin_open, sa * t_cos + ca * sin_open);
            const double to = pseudo_angle(ca * t_cos + sa * sin_open, sa * t_cos - ca * sin_open);
            double len = to - from;
            if (len < 0.0) len += 4.0;
            // At least half a turn (t >= 0) is at least 2 in pseudo-angle, less is less
            // than 2. Past that, rounding has swapped the ends of an all but full or
            // all but empty interval (a length near 0 or 4), or of a half turn (t near
            // 0: the ends antipodal, a length a hair off 2).
            if (t_cos >= 0.0 && len < 2.0) len = len < 1.0 ? 4.0 : 2.0;
            if (t_cos < 0.0 && len > 2.0) {
                if (len > 3.0) continue;
                len = 2.0;
            }
            if (len > 0.0) {
                buried.push_back({from, len});
                // Covered whole by the intervals so far: buried, no more balls to try.
                if (cover.add(from, len)) {
                    all_buried = true;
                    break;
                }
            }
        }
        return all_buried;
    }

    // The exposed parts (pseudo-angles) of the circle as arcs, into `out`.
    static void add_arcs(const Circle& circle, const std::vector<Interval>& parts,
                         std::vector<SesArc>& out) {
        const Vec3& m = circle.m;
        const Vec3& e1 = circle.e1;
        const Vec3& e2 = circle.e2;
        for (auto [from_p, len_p] : parts) {
            // Back to angles, the exposed arcs only.
            double from = 0.0, len = kTwoPi;
            if (len_p < 4.0) {
                from = angle_of_pseudo(from_p);
                const double end_p = from_p + len_p;
                len = angle_of_pseudo(end_p >= 4.0 ? end_p - 4.0 : end_p) - from;
                if (len_p >= 2.0 ? len < kTwoPi * 0.25 : len < 0.0) len += kTwoPi;
                if (!(len > 1e-9)) continue;
            }
            SesArc arc{};
            arc.m[0] = float(m[0]), arc.m[1] = float(m[1]), arc.m[2] = float(m[2]);
            arc.rho = float(circle.rho);
            arc.e1[0] = float(e1[0]), arc.e1[1] = float(e1[1]), arc.e1[2] = float(e1[2]);
            arc.e2[0] = float(e2[0]), arc.e2[1] = float(e2[1]), arc.e2[2] = float(e2[2]);
            arc.start = float(from);
            arc.length = float(len);
            out.push_back(arc);
        }
    }

    struct ChunkArcs {
        std::vector<SesArc> arcs;
        std::size_t circles = 0, buried_circles = 0;
    };

    // The circles of the pairs i < j of chunk `chunk`'s atoms i, cut by the other neighbours of
    // i: their exposed arcs into `out`.
    void arcs_of_chunk(std::size_t chunk, ChunkArcs& out) const {
        std::vector<Interval> buried, cuts, gaps, parts;
        for (std::size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
            std::uint32_t last_burier = std::numeric_limits<std::uint32_t>::max();
            for (std::uint32_t q = nb_start[i]; q < nb_start[i + 1]; ++q) {
                const std::uint32_t j = nb[q];
                if (j <= i) continue;
                const Vec3 dij = sub(c[j], c[i]);
                const double d = std::sqrt(dot(dij, dij));
                if (d <= std::abs(R[i] - R[j]) || d == 0.0) continue;  // one ball inside the other
                const Vec3 u = scale(dij, 1.0 / d);
                const double a = (d * d + R[i] * R[i] - R[j] * R[j]) / (2.0 * d);
                const double rho2 = R[i] * R[i] - a * a;
                if (rho2 <= 0.0) continue;
                const double rho = std::sqrt(rho2);
                const Vec3 m = add(c[i], scale(u, a));
                const Vec3 e1 = perpendicular(u);
                const Vec3 e2 = cross(u, e1);
                const Circle circle{m, e1, e2, rho, rho2};
                ++out.circles;
                if (buried_whole(circle, i, j, last_burier, buried))
                    parts.clear();
                else
                    exposed_parts(buried, cuts, gaps, parts);
                if (parts.empty()) ++out.buried_circles;
                add_arcs(circle, parts, out.arcs);
            }
        }
    }

    // Circles of the pairs i < j, cut by the other neighbours of i: chunks of atoms on all
    // threads, each with its own arcs, joined in atom order (the result does not depend on the
    // thread count).
    std::vector<SesArc> cut_circles() {
        std::vector<ChunkArcs> chunks(chunk_count);
        parallel_chunks(chunks.size(), thread_count(),
                        [&](std::size_t chunk) { arcs_of_chunk(chunk, chunks[chunk]); });
        std::vector<SesArc> arcs;
        for (const ChunkArcs& chunk : chunks) {
            arcs.insert(arcs.end(), chunk.arcs.begin(), chunk.arcs.end());
            f.circles += chunk.circles;
            f.buried_circles += chunk.buried_circles;
        }
        for (const SesArc& arc : arcs) f.rho_max = std::max(f.rho_max, arc.rho);
        return arcs;
    }

    // Arcs by the bin of their circle's centre (on the segment between two centres: in range).
    void bin_arcs(const std::vector<SesArc>& arcs) {
        std::vector<std::size_t> arc_bin(arcs.size());
        f.arc_start.assign(f.bin_count() + 1, 0);
        for (std::size_t k = 0; k < arcs.size(); ++k) {
            int cell[3];
            arc_bin[k] = bin_index(Vec3{arcs[k].m[0], arcs[k].m[1], arcs[k].m[2]}, cell);
            ++f.arc_start[arc_bin[k] + 1];
        }
        for (std::size_t b = 0; b < f.bin_count(); ++b) f.arc_start[b + 1] += f.arc_start[b];
        f.arcs.resize(arcs.size());
        std::vector<std::uint32_t> fill(f.arc_start.begin(), f.arc_start.end() - 1);
        for (std::size_t k = 0; k < arcs.size(); ++k) f.arcs[fill[arc_bin[k]]++] = arcs[k];
    }
};

}  // namespace

double arc_distance(const SesArc& arc, const double p[3], double* nearest, double bound) {
    const Vec3 m{arc.m[0], arc.m[1], arc.m[2]};
    const Vec3 e1{arc.e1[0], arc.e1[1], arc.e1[2]};
    const Vec3 e2{arc.e2[0], arc.e2[1], arc.e2[2]};
    const Vec3 v = sub(Vec3{p[0], p[1], p[2]}, m);
    const double height = dot(v, cross(e1, e2));
    if (std::abs(height) >= bound) return bound;
    const double a = dot(v, e1), b = dot(v, e2);
    const double r = std::sqrt(a * a + b * b);
    if (std::abs(r - arc.rho) >= bound) return bound;
    double rel = r > 0.0 ? std::atan2(b, a) - arc.start : 0.0;
    rel -= kTwoPi * std::floor(rel / kTwoPi);
    // Off the arc, the nearer end (in angle) is the nearer point.
    double delta = 0.0;
    if (rel > arc.length) delta = std::min(rel - arc.length, kTwoPi - rel);
    if (nearest != nullptr) {
        const double theta =
            rel <= arc.length
                ? arc.start + rel
                : (rel - arc.length < kTwoPi - rel ? arc.start + arc.length : arc.start);
        const Vec3 q =
            add(m, scale(add(scale(e1, std::cos(theta)), scale(e2, std::sin(theta))), arc.rho));
        nearest[0] = q[0], nearest[1] = q[1], nearest[2] = q[2];
    }
    const double s = std::sin(0.5 * delta);
    const double rr = r - arc.rho;
    return std::sqrt(height * height + rr * rr + 4.0 * r * arc.rho * s * s);
}

SesFeatures build_ses_features(const Atoms& atoms, float probe) {
    if (atoms.empty()) throw Error(ErrorCode::EmptySelection, "no atoms to build a surface from");
    if (atoms.xyz.size() != 3 * atoms.size())
        throw Error(ErrorCode::InvalidArgument, "atoms: xyz must hold 3 floats per radius");
    if (!(probe > 0.0f) || !std::isfinite(probe))
        throw Error(ErrorCode::InvalidArgument,
                    "the exact SES needs a probe radius > 0 Å (probe 0 is the vdw surface)");
    FeatureBuilder b(atoms, probe);
    b.read_balls();
    Atoms unique;
    if (b.without_duplicates(unique)) return build_ses_features(unique, probe);
    b.bin_spheres();
    b.find_neighbours();
    b.neighbours_by_sphere();
    b.bin_arcs(b.cut_circles());
    return std::move(b.f);
}

}  // namespace fdmsurf::detail
