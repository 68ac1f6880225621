// Exposed SAS arcs: every pair of intersecting inflated balls gives a circle; each neighbour ball
// buries an angular interval of it; what no ball buries is exposed (ALGORITHM.md §7, closing).
#include "grid/ses_features.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <utility>

#include "base/cpu_features.hpp"
#include "base/fresh_pages.hpp"
#include "base/parallel.hpp"
#include "base/power_cell.hpp"
#include "base/trace.hpp"
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

// The cut loops are FDMSURF_AVX2_CLONES: four doubles a vector where the CPU has AVX2; so is
// arcs_of_chunk, which calls them (VEX code, no fused multiply-add).

// What balls 0..k-1 (centres x, y, z, squared inflated radii R2) do to the circle of centre m,
// radius^2 rho2 in the plane of e1, e2: with w = m - c, the circle's points are inside a ball
// where 2 rho M cos(theta - phi) < E, A = w.e1, B = w.e2, M = |(A, B)|, E = R^2 - |w|^2 - rho2
// (phi the angle of (A, B)). One vectorised loop.
FDMSURF_AVX2_CLONES
void circle_cuts(std::size_t k, const double* __restrict x, const double* __restrict y,
                 const double* __restrict z, const double* __restrict R2, const Vec3& m,
                 const Vec3& e1, const Vec3& e2, double rho2, double* __restrict A,
                 double* __restrict B, double* __restrict E, double* __restrict M) {
    const double m0 = m[0], m1 = m[1], m2 = m[2];
    const double a0 = e1[0], a1 = e1[1], a2 = e1[2];
    const double b0 = e2[0], b1 = e2[1], b2 = e2[2];
    for (std::size_t p = 0; p < k; ++p) {
        const double wx = m0 - x[p], wy = m1 - y[p], wz = m2 - z[p];
        const double a = wx * a0 + wy * a1 + wz * a2;
        const double b = wx * b0 + wy * b1 + wz * b2;
        A[p] = a;
        B[p] = b;
        E[p] = R2[p] - (wx * wx + wy * wy + wz * wz) - rho2;
        M[p] = std::sqrt(a * a + b * b);
    }
}

// A pseudo-angle of the direction (x, y) in [0, 4): increasing with its angle from +x like the
// angle itself (the "diamond angle"), without trigonometry; antipodal directions differ by 2.
// By quadrant y / (x + y), 1 - x / (y - x), 2 - y / (-x - y), 3 + x / (x - y): each
// denominator is |x| + |y|, and offset -0, 1, 2, 3 plus q or -q the same sum (-0 + q is q).
// Selects, so that it vectorises.
inline double pseudo_angle(double x, double y) {
    const bool up = y >= 0.0, right = x >= 0.0, swap = up != right;
    const double q = (swap ? x : y) / (std::abs(x) + std::abs(y));
    const double offset = up ? (swap ? 1.0 : -0.0) : (swap ? 3.0 : 2.0);
    return offset + (right ? q : -q);
}

// The intervals of pseudo-angle [from, from + len) that balls 0..k-1 (their A, B, M and
// t = E / (2 rho M), cutting the circle of radius rho: neither missing nor covering it) bury;
// len 0: none. One vectorised loop, selects for branches.
FDMSURF_AVX2_CLONES
void buried_intervals(std::size_t k, const double* __restrict A, const double* __restrict B,
                      const double* __restrict M, const double* __restrict T,
                      double* __restrict from, double* __restrict len) {
    for (std::size_t p = 0; p < k; ++p) {
        // Buried where cos(theta - phi) < t: from phi + open to phi - open + 2 pi, open = acos t.
        // The ends as directions (rotations of (A, B) / M by +-open), ordered by their
        // pseudo-angles: no trigonometry for the circles that end up buried (nine in ten).
        // std::clamp and std::max as selects on values (the same results), which vectorise.
        const double t_lo = T[p] < -1.0 ? -1.0 : T[p];
        const double t_cos = 1.0 < t_lo ? 1.0 : t_lo;
        const double s2 = 1.0 - t_cos * t_cos;
        const double sin_open = std::sqrt(0.0 < s2 ? s2 : 0.0);
        const double ca = A[p] / M[p], sa = B[p] / M[p];
        const double f = pseudo_angle(ca * t_cos - sa * sin_open, sa * t_cos + ca * sin_open);
        const double to = pseudo_angle(ca * t_cos + sa * sin_open, sa * t_cos - ca * sin_open);
        double l = to - f;
        l = l < 0.0 ? l + 4.0 : l;
        // At least half a turn (t >= 0) is at least 2 in pseudo-angle, less is less than 2. Past
        // that, rounding has swapped the ends of an all but full or all but empty interval (a
        // length near 0 or 4), or of a half turn (t near 0: the ends antipodal, a length a hair
        // off 2); an all but empty one is dropped.
        const double long_fix = l < 1.0 ? 4.0 : 2.0, short_fix = l > 3.0 ? 0.0 : 2.0;
        l = t_cos >= 0.0 ? (l < 2.0 ? long_fix : l) : (l > 2.0 ? short_fix : l);
        from[p] = f;
        len[p] = l;
    }
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
// intervals cover: 64 bins, each set when one interval holds it whole (strictly, ends
// included). Every bin set means no point of the circle is exposed, which exposed_parts would
// find from the same intervals; a gap smaller than a bin leaves bins unset and exposed_parts
// decides. Most circles buried by several balls are found so before their last ball.
struct CoverBins {
    static constexpr int kBins = 64;
    static constexpr double kPerUnit = kBins / 4.0;
    std::uint64_t bins = 0;
    // Bits first..last, 0 <= first <= last < 64.
    static std::uint64_t bits(int first, int last) {
        return (~std::uint64_t(0) >> (63 - last)) & (~std::uint64_t(0) << first);
    }
    // The open interval (from, from + len) of pseudo-angles (from in [0, 4], len in (0, 4]);
    // returns whether every bin is now set.
    bool add(double from, double len) {
        if (len >= 4.0) {
            bins = ~std::uint64_t(0);
            return true;
        }
        // Bins b with from < b / kPerUnit and (b + 1) / kPerUnit < from + len, unwrapped: first
        // in [1, 65], last below 2 kBins (floor and ceil of values >= 0 by truncation).
        const double lo = from * kPerUnit, hi = (from + len) * kPerUnit;
        const int first = static_cast<int>(lo) + 1;
        const int hi_floor = static_cast<int>(hi);
        const int last = hi_floor + (double(hi_floor) < hi) - 2;
        if (last < first) return false;
        if (last < kBins)
            bins |= bits(first, last);
        else if (first >= kBins)
            bins |= bits(first - kBins, last - kBins);
        else
            bins |= bits(first, kBins - 1) | bits(0, last - kBins);
        return bins == ~std::uint64_t(0);
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
    // By start only, by insertion (a circle has some twenty cuts): within one start the first
    // cut makes any gap and every one after it starts at or before the cursor, which ends at
    // their largest end, so their order does not change the gaps.
    for (std::size_t c = 1; c < cuts.size(); ++c) {
        const Interval cut = cuts[c];
        std::size_t d = c;
        for (; d > 0 && cut.first < cuts[d - 1].first; --d) cuts[d] = cuts[d - 1];
        cuts[d] = cut;
    }
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

// A counting sort's starts after its fill: start[b] was advanced from the first to the end of
// bucket b, i.e. to the next bucket's first; shifted back by one (the last entry, the total,
// was not touched).
void unshift(std::vector<std::uint32_t>& start) {
    std::copy_backward(start.begin(), start.end() - 2, start.end() - 1);
    start[0] = 0;
}

// The steps of build_ses_features, in order: read_balls, bin_spheres, without_duplicates (when
// two balls coincide, the build starts again without the copies), find_neighbours, cut_circles.
// The passes over the atoms run in chunks on all threads and read the balls in bin order, where
// a ball's neighbours lie near it in memory; the work per atom does not grow with the
// structure, and the large arrays are written once.
struct FeatureBuilder {
    // Atoms (or spheres) per task of the passes over them; bins per task of the duplicate check.
    static constexpr std::size_t kChunk = 256;
    static constexpr std::size_t kBinChunk = 4096;
    // Chunks per block of the neighbour search; neighbours per ball reserved (about 45 in
    // proteins; more only cost a copy).
    static constexpr std::size_t kBlockChunks = 64;
    static constexpr std::size_t kNeighboursReserved = 64;

    // A ball: its centre and inflated radius r + probe.
    struct Ball {
        Vec3 c;
        double R;
    };

    const Atoms& atoms;
    const float probe;
    const std::size_t n;
    const std::size_t chunk_count;
    const unsigned threads;
    SesFeatures f;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};  // centres' bounds
    // The balls by sphere (bin order: bin b holds spheres f.sphere_start[b] ..
    // f.sphere_start[b + 1] - 1); sphere s is atom order[s], atom i is sphere sphere_of[i].
    std::vector<Ball> balls;
    std::vector<std::uint32_t> order, sphere_of;
    double bin_margin = 0.0;  // Å: more than the rounding of a ball's bin and of the bins' bounds

    FeatureBuilder(const Atoms& atoms_in, float probe_in)
        : atoms(atoms_in),
          probe(probe_in),
          n(atoms_in.size()),
          chunk_count((n + kChunk - 1) / kChunk),
          threads(thread_count()) {}

    Ball ball_of_atom(std::size_t i) const {
        return {{atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]},
                double(atoms.radius[i]) + probe};
    }

    // Checks each atom's radius and coordinates; the largest inflated radius and the bounds.
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
            const Ball b = ball_of_atom(i);
            f.r_max = std::max(f.r_max, static_cast<float>(b.R));
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], b.c[a]);
                hi[a] = std::max(hi[a], b.c[a]);
            }
        }
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

    // Bins of edge r_max: two balls intersect only within two bins of each other. The spheres
    // in bin order (counting sort, atom order within a bin): order, sphere_of, balls and the
    // features' spheres.
    void bin_spheres() {
        f.bin_size = f.r_max;
        for (int a = 0; a < 3; ++a) {
            f.origin[a] = static_cast<float>(lo[a]);
            f.dims[a] = static_cast<std::uint32_t>(std::floor((hi[a] - lo[a]) / f.bin_size)) + 1;
            bin_margin =
                std::max(bin_margin, 1e-3 + 1e-6 * std::max(std::abs(lo[a]), std::abs(hi[a])));
        }
        // The arrays' fresh pages on all threads first (150 MB on the 2.43 M-atom shell, which
        // their resizes took on one thread, a third of a second).
        std::vector<std::size_t> bin_of;
        std::vector<std::uint32_t>& start = f.sphere_start;
        bin_of.reserve(n);
        start.reserve(f.bin_count() + 1);
        order.reserve(n);
        sphere_of.reserve(n);
        balls.reserve(n);
        f.spheres.reserve(4 * n);
        populate_pages({room_up_to(bin_of, n), room_up_to(start, f.bin_count() + 1),
                        room_up_to(order, n), room_up_to(sphere_of, n), room_up_to(balls, n),
                        room_up_to(f.spheres, 4 * n)});
        bin_of.resize(n);
        parallel_chunks(chunk_count, threads, [&](std::size_t chunk) {
            for (std::size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
                int cell[3];
                bin_of[i] = bin_index(ball_of_atom(i).c, cell);
            }
        });
        start.assign(f.bin_count() + 1, 0);
        for (std::size_t i = 0; i < n; ++i) ++start[bin_of[i] + 1];
        for (std::size_t b = 0; b < f.bin_count(); ++b) start[b + 1] += start[b];
        order.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            order[start[bin_of[i]]++] = static_cast<std::uint32_t>(i);
        unshift(start);
        sphere_of.resize(n);
        balls.resize(n);
        f.spheres.resize(4 * n);
        parallel_chunks(chunk_count, threads, [&](std::size_t chunk) {
            for (std::size_t s = chunk * kChunk; s < std::min(n, (chunk + 1) * kChunk); ++s) {
                const std::uint32_t i = order[s];
                sphere_of[i] = static_cast<std::uint32_t>(s);
                balls[s] = ball_of_atom(i);
                f.spheres[4 * s + 0] = atoms.xyz[3 * i + 0];
                f.spheres[4 * s + 1] = atoms.xyz[3 * i + 1];
                f.spheres[4 * s + 2] = atoms.xyz[3 * i + 2];
                f.spheres[4 * s + 3] = static_cast<float>(balls[s].R);
            }
        });
    }

    // Coincident balls (the same centre and radius: duplicated atoms) are one ball. Kept twice,
    // each would bury the other's face wherever rounding puts the projection a hair inside it,
    // and no circle joins them: d would jump there. The first of each is kept. Balls are the
    // same when their stored float spheres are (centre and float(r + probe), as the shaders read
    // them), so that two radii that round to one inflated radius are one ball there too; such
    // balls share a bin, so each bin's spheres are compared among themselves.
    // Whether there were any; if so, `unique` holds the atoms without them.
    bool without_duplicates(Atoms& unique) const {
        const std::size_t bins = f.bin_count();
        const std::size_t bin_chunks = (bins + kBinChunk - 1) / kBinChunk;
        std::vector<std::uint8_t> duplicate(n, 0), found(bin_chunks, 0);
        auto same = [&](std::uint32_t s, std::uint32_t t) {
            const float* a = &f.spheres[4 * std::size_t(s)];
            const float* b = &f.spheres[4 * std::size_t(t)];
            return a[0] == b[0] && a[1] == b[1] && a[2] == b[2] && a[3] == b[3];
        };
        parallel_chunks(bin_chunks, threads, [&](std::size_t chunk) {
            for (std::size_t b = chunk * kBinChunk; b < std::min(bins, (chunk + 1) * kBinChunk);
                 ++b)
                for (std::uint32_t s = f.sphere_start[b] + 1; s < f.sphere_start[b + 1]; ++s)
                    for (std::uint32_t t = f.sphere_start[b]; t < s; ++t)
                        if (same(s, t)) {
                            duplicate[order[s]] = 1;
                            found[chunk] = 1;
                            break;
                        }
        });
        if (std::find(found.begin(), found.end(), 1) == found.end()) return false;
        for (std::size_t i = 0; i < n; ++i) {
            if (duplicate[i]) continue;
            unique.xyz.insert(unique.xyz.end(), &atoms.xyz[3 * i], &atoms.xyz[3 * i] + 3);
            unique.radius.push_back(atoms.radius[i]);
        }
        return true;
    }

    // The balls that intersect ball s, appended to `out` in bin order (z, y, x, then sphere):
    // the bins within two of s's along each axis, less those wholly farther from its centre
    // than R_s + r_max (with a margin for the rounding of the bins' bounds and of r_max), which
    // hold none; the kept bins of a row are one run of spheres.
    void neighbours_of_sphere(std::size_t s, std::vector<std::uint32_t>& out,
                              std::vector<std::uint32_t>& scratch) const {
        const Ball& a = balls[s];
        int cell[3];
        bin_index(a.c, cell);
        const double reach = a.R + double(f.r_max) * (1.0 + 1e-6) + bin_margin;
        const double reach2 = reach * reach;
        // Squared distances from the centre to the slabs of the cells cell - 2 .. cell + 2
        // (widened by the margin) along each axis; beyond the bins: farther than any reach.
        double gap2[3][5];
        for (int ax = 0; ax < 3; ++ax)
            for (int o = 0; o < 5; ++o) {
                const int c = cell[ax] + o - 2;
                const double lo_edge = double(f.origin[ax]) + double(f.bin_size) * c - bin_margin;
                const double hi_edge = lo_edge + double(f.bin_size) + 2.0 * bin_margin;
                const double g = std::max({0.0, lo_edge - a.c[ax], a.c[ax] - hi_edge});
                gap2[ax][o] = c < 0 || c >= int(f.dims[ax]) ? 2.0 * reach2 : g * g;
            }
        // The bins' runs of spheres, then the test on each (written whole to `scratch`, kept by
        // advancing past it).
        std::uint32_t runs[25][2];
        int n_runs = 0;
        std::size_t candidates = 0;
        for (int oz = 0; oz < 5; ++oz)
            for (int oy = 0; oy < 5; ++oy) {
                const double gyz = gap2[2][oz] + gap2[1][oy];
                if (gyz > reach2) continue;
                int x0 = 0, x1 = 4;
                while (gyz + gap2[0][x0] > reach2) ++x0;
                while (gyz + gap2[0][x1] > reach2) --x1;
                const std::size_t row =
                    (std::size_t(cell[2] + oz - 2) * f.dims[1] + (cell[1] + oy - 2)) * f.dims[0];
                runs[n_runs][0] = f.sphere_start[row + cell[0] + x0 - 2];
                runs[n_runs][1] = f.sphere_start[row + cell[0] + x1 - 1];
                candidates += runs[n_runs][1] - runs[n_runs][0];
                ++n_runs;
            }
        if (scratch.size() < candidates) scratch.resize(candidates);
        std::uint32_t* dst = scratch.data();
        std::size_t kept = 0;
        for (int r = 0; r < n_runs; ++r)
            for (std::uint32_t t = runs[r][0]; t < runs[r][1]; ++t) {
                const Vec3 d = sub(balls[t].c, a.c);
                const double reach_t = a.R + balls[t].R;
                dst[kept] = t;
                kept += (dot(d, d) < reach_t * reach_t) & (t != s);
            }
        out.insert(out.end(), dst, dst + kept);
    }

    // Neighbours: the balls that intersect each ball (compressed rows by sphere, bin order).
    // Blocks of chunks of spheres, each chunk's rows on one of all threads into a list kept
    // from block to block (two sets, alternating), and the previous block's lists appended in
    // sphere order beside them: the rows' memory is touched once, by the append (fresh pages
    // cost more than the search on this kind of machine).
    void find_neighbours() {
        f.neighbour_start.assign(n + 1, 0);
        f.neighbours.clear();
        f.neighbours.reserve(n * kNeighboursReserved);
        const std::size_t block_lists = std::min(chunk_count, kBlockChunks);
        std::vector<std::vector<std::uint32_t>> lists[2] = {
            std::vector<std::vector<std::uint32_t>>(block_lists),
            std::vector<std::vector<std::uint32_t>>(block_lists)};
        std::size_t previous = 0;  // chunks in the previous block
        for (std::size_t block = 0, round = 0; previous > 0 || block < chunk_count;
             block += kBlockChunks, ++round) {
            const std::size_t chunks =
                block < chunk_count ? std::min(kBlockChunks, chunk_count - block) : 0;
            auto& now = lists[round % 2];
            const auto& before = lists[(round + 1) % 2];
            // Task 0: the previous block's append; task 1 + c: chunk c of this block.
            parallel_chunks(chunks + 1, threads, [&](std::size_t task) {
                if (task == 0) {
                    for (std::size_t c = 0; c < previous; ++c)
                        f.neighbours.insert(f.neighbours.end(), before[c].begin(), before[c].end());
                    return;
                }
                std::vector<std::uint32_t>& list = now[task - 1];
                list.clear();
                std::vector<std::uint32_t> scratch;
                const std::size_t chunk = block + task - 1;
                for (std::size_t s = chunk * kChunk; s < std::min(n, (chunk + 1) * kChunk); ++s) {
                    const std::size_t before_s = list.size();
                    neighbours_of_sphere(s, list, scratch);
                    f.neighbour_start[s + 1] = static_cast<std::uint32_t>(list.size() - before_s);
                }
            });
            previous = chunks;
        }
        for (std::size_t s = 0; s < n; ++s) f.neighbour_start[s + 1] += f.neighbour_start[s];
    }

    // The circle where balls i and j meet: centre m, radius rho, plane spanned by e1 and e2.
    struct Circle {
        Vec3 m, e1, e2;
        double rho, rho2;
    };

    // One atom's neighbours (the balls of its row, in its order) as arrays, and per circle what
    // each does to it: with w = m - c_k, |P(theta) - c_k|^2 = |w|^2 + rho^2 + 2 rho (A cos
    // theta + B sin theta), inside ball k where that is below R_k^2, i.e. where
    // 2 rho M cos(theta - phi) < E, M = |(A, B)|, E = R_k^2 - |w|^2 - rho^2. Then the balls
    // that cut the circle (neither missing nor covering it) and the intervals they bury.
    struct Row {
        std::vector<double> x, y, z, R2;            // centres, squared inflated radii
        std::vector<std::uint32_t> atom;            // atom indices
        std::vector<double> A, B, E, M;             // by row entry, for the current circle
        std::vector<std::uint32_t> cutting;         // the balls that cut it
        std::vector<std::uint8_t> depth;            // their depth classes
        std::vector<double> t;                      // their E / 2 rho M
        std::vector<double> sA, sB, sM, sT;         // their A, B, M, t in depth order
        std::vector<double> from, len;              // their buried intervals, in depth order
        std::size_t size = 0;
        void resize(std::size_t k) {
            size = k;
            if (atom.size() >= k) return;
            for (auto* v : {&x, &y, &z, &R2, &A, &B, &E, &M, &t, &sA, &sB, &sM, &sT, &from, &len})
                v->resize(k);
            for (auto* v : {&atom, &cutting}) v->resize(k);
            depth.resize(k);
        }
    };

    // Cutting balls' intervals computed at once before the cover bins see them.
    static constexpr std::size_t kIntervalBlock = 8;

    // Whether the neighbours of i other than row entry q (ball j) bury the circle whole; else
    // the buried intervals of pseudo-angle into `buried`. The ball that buried the last circle
    // of i whole often buries the next (`last_burier`, a row entry): tried first (two circles in
    // five are buried by one ball). Then every ball's cut in one vectorised loop, and the
    // cutting balls' intervals, the deeper first, a block at a time, into the cover bins until
    // they are full. The verdict and the intervals depend on the set of balls, not on the order
    // they are tried in (exposed_parts sorts them).
    static bool buried_whole(const Circle& circle, std::size_t q, std::size_t& last_burier,
                             Row& row, std::vector<Interval>& buried) {
        const double two_rho = 2.0 * circle.rho, minus_two_rho = -2.0 * circle.rho;
        buried.clear();
        double* A = row.A.data();
        double* B = row.B.data();
        double* E = row.E.data();
        double* M = row.M.data();
        auto cuts = [&](std::size_t first, std::size_t count) {
            circle_cuts(count, row.x.data() + first, row.y.data() + first, row.z.data() + first,
                        row.R2.data() + first, circle.m, circle.e1, circle.e2, circle.rho2,
                        A + first, B + first, E + first, M + first);
        };
        // No point of the circle in ball p; every point in it.
        auto misses = [=](std::size_t p) { return E[p] <= minus_two_rho * M[p]; };
        auto covers = [=](std::size_t p) { return !misses(p) && E[p] >= two_rho * M[p]; };
        if (last_burier != q && last_burier < row.size) {
            cuts(last_burier, 1);
            if (covers(last_burier)) return true;
        }
        const std::size_t k = row.size;
        cuts(0, k);
        E[q] = -std::numeric_limits<double>::infinity();  // ball j: not one of the others
        // The balls that cut the circle (neither miss nor cover it), and whether one covers it.
        std::uint32_t* cutting = row.cutting.data();
        std::size_t n_cut = 0, covering = k;
        for (std::size_t p = 0; p < k; ++p) {
            const bool in = !misses(p);
            covering = in & (E[p] >= two_rho * M[p]) ? p : covering;
            cutting[n_cut] = static_cast<std::uint32_t>(p);
            n_cut += in;
        }
        if (covering < k) {
            last_burier = covering;
            return true;
        }
        // The deeper balls first (by t = E / 2 rho M in [-1, 1), the longer buried intervals, in
        // kDepths classes): a few bury most circles.
        constexpr int kDepths = 8;
        std::uint8_t* depth = row.depth.data();
        double* t = row.t.data();
        std::uint32_t first[kDepths + 1] = {};
        for (std::size_t h = 0; h < n_cut; ++h) {
            const std::uint32_t p = cutting[h];
            t[h] = E[p] / (two_rho * M[p]);
            const int c =
                std::clamp(static_cast<int>((1.0 - t[h]) * (0.5 * kDepths)), 0, kDepths - 1);
            depth[h] = static_cast<std::uint8_t>(c);
            ++first[c + 1];
        }
        for (int c = 0; c < kDepths; ++c) first[c + 1] += first[c];
        double* sA = row.sA.data();
        double* sB = row.sB.data();
        double* sM = row.sM.data();
        double* sT = row.sT.data();
        for (std::size_t h = 0; h < n_cut; ++h) {
            const std::uint32_t p = cutting[h], slot = first[depth[h]]++;
            sA[slot] = A[p], sB[slot] = B[p], sM[slot] = M[p], sT[slot] = t[h];
        }
        // The intervals a block at a time (one vectorised loop each), into the cover bins until
        // they are full: most circles buried by several balls are found so within a block or two.
        double* from = row.from.data();
        double* len = row.len.data();
        CoverBins cover;
        for (std::size_t h0 = 0; h0 < n_cut; h0 += kIntervalBlock) {
            const std::size_t h1 = std::min(n_cut, h0 + kIntervalBlock);
            buried_intervals(h1 - h0, sA + h0, sB + h0, sM + h0, sT + h0, from + h0, len + h0);
            for (std::size_t h = h0; h < h1; ++h)
                if (len[h] > 0.0 && cover.add(from[h], len[h])) return true;
        }
        for (std::size_t h = 0; h < n_cut; ++h)
            if (len[h] > 0.0) buried.push_back({from[h], len[h]});
        return false;
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

    // One thread's arcs, chunk after chunk.
    struct ChunkArcs {
        std::vector<SesArc> arcs;
        // Each arc's bin (of its circle's centre); bins number fewer than 2^32 (their spheres'
        // starts alone would take 16 GB).
        std::vector<std::uint32_t> bins;
        std::size_t circles = 0, buried_circles = 0;
        float rho_max = 0.0f;
    };
    // Where a chunk's arcs went: the thread's arrays and the run in them.
    struct ChunkRun {
        std::size_t part = 0, first = 0, count = 0;
    };

    // Where balls i and j meet: their centres' distance d, the circle's distance a from c_i and
    // squared radius rho2; false when one is inside the other (or they touch).
    struct Meeting {
        Vec3 dij;
        double d, a, rho2;
    };
    static bool meet(const Ball& bi, const Ball& bj, Meeting& w) {
        w.dij = sub(bj.c, bi.c);
        w.d = std::sqrt(dot(w.dij, w.dij));
        if (w.d <= std::abs(bi.R - bj.R) || w.d == 0.0) return false;  // one ball inside the other
        w.a = (w.d * w.d + bi.R * bi.R - bj.R * bj.R) / (2.0 * w.d);
        w.rho2 = bi.R * bi.R - w.a * w.a;
        return w.rho2 > 0.0;
    }
    static Circle circle_of(const Ball& bi, const Meeting& w) {
        const Vec3 u = scale(w.dij, 1.0 / w.d);
        const Vec3 e1 = perpendicular(u);
        return {add(bi.c, scale(u, w.a)), e1, cross(u, e1), std::sqrt(w.rho2), w.rho2};
    }

    // A thread's scratch space for the arcs of its atoms.
    struct ArcScratch {
        std::vector<Interval> buried, cuts, gaps, parts;
        Row row, kept;                          // ball i's neighbours; the cell's kept ones
        // Per row entry, its place in `kept`; none when its circle has no point in the cell.
        std::vector<std::uint32_t> kept_entry;
        PowerCell cell;
        std::vector<CellPlane> planes;
        std::vector<std::uint32_t> plane_entry;  // per plane, its row entry
        std::vector<std::uint32_t> order, keep;
    };
    static constexpr std::uint32_t kNotKept = ~std::uint32_t(0);
    // A neighbour whose cap is within this (in h, the unit frame) of the whole sphere or of
    // none of it (a ball inside the other, or all but) is left to the plain cut.
    static constexpr double kCapEdge = 1e-9;

    // Ball i's power cell among its row (power_cell.hpp): Buried when no point of its sphere is
    // outside every other ball, so no circle of i has an exposed point; Filtered when only the
    // balls of `kept_entry` can shape the exposed part: an exposed point of circle (i, j) is on
    // j's plane and inside the others', so j is one of them, and the others bury on the sphere
    // only what those do. Nor has circle (i, j) when j's face of the cell lies inside the ball
    // (PowerCell::face_in_ball), though j is kept for the other circles. Unknown (the plain cut)
    // for a twin centre, a cap all but whole or empty, or rounding the cell gives up on.
    CellVerdict cell_of(const Ball& bi, const std::uint32_t* nb, ArcScratch& w) const {
        const Row& row = w.row;
        w.planes.clear();
        w.plane_entry.clear();
        w.kept_entry.assign(row.size, kNotKept);
        for (std::size_t p = 0; p < row.size; ++p) {
            const Ball& bk = balls[nb[p]];
            const Vec3 e = sub(bk.c, bi.c);
            const double d2 = dot(e, e);
            if (d2 == 0.0) return CellVerdict::Unknown;
            const double d = std::sqrt(d2);
            const double h = (d2 + bi.R * bi.R - bk.R * bk.R) / (2.0 * d * bi.R);
            if (h < -1.0 - kCapEdge) return CellVerdict::Buried;  // inside ball k
            if (h > 1.0 + kCapEdge) continue;                      // ball k inside this one
            if (std::abs(h) >= 1.0 - kCapEdge) return CellVerdict::Unknown;
            w.planes.push_back({scale(e, 1.0 / d), h});
            w.plane_entry.push_back(std::uint32_t(p));
        }
        if (w.planes.empty()) return CellVerdict::Unknown;  // nothing cuts the circles
        order_largest_first(w.planes, w.order);
        const CellVerdict verdict = w.cell.filter(w.planes, w.order, w.keep);
        if (verdict != CellVerdict::Filtered) return verdict;
        // The kept balls as a row of their own, in row order.
        Row& kept = w.kept;
        kept.resize(w.keep.size());
        for (std::size_t k = 0; k < w.keep.size(); ++k) {
            const std::uint32_t p = w.plane_entry[w.keep[k]];
            w.kept_entry[p] = w.cell.face_in_ball(w.keep[k]) ? kNotKept : std::uint32_t(k);
            kept.x[k] = row.x[p], kept.y[k] = row.y[p], kept.z[k] = row.z[p];
            kept.R2[k] = row.R2[p];
            kept.atom[k] = row.atom[p];
        }
        return verdict;
    }

    // The circles of the pairs i < j of chunk `chunk`'s atoms i, cut by the other neighbours of
    // i (for an atom with `cell_from` neighbours j > i or more, only by those its power cell
    // keeps): their exposed arcs appended to `out`, with the thread's scratch `w`.
    FDMSURF_AVX2_CLONES void arcs_of_chunk(std::size_t chunk, std::size_t cell_from,
                                           ArcScratch& w, ChunkArcs& out) const {
        Row& row = w.row;
        for (std::size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
            const std::size_t s = sphere_of[i];
            const std::uint32_t* nb = f.neighbours.data() + f.neighbour_start[s];
            row.resize(f.neighbour_start[s + 1] - f.neighbour_start[s]);
            for (std::size_t p = 0; p < row.size; ++p) {
                const Ball& k = balls[nb[p]];
                row.x[p] = k.c[0], row.y[p] = k.c[1], row.z[p] = k.c[2];
                row.R2[p] = k.R * k.R;
                row.atom[p] = order[nb[p]];
            }
            const Ball& bi = balls[s];
            std::size_t later = 0;
            for (std::size_t q = 0; q < row.size; ++q) later += row.atom[q] > i;
            const bool cell = later >= cell_from;
            const CellVerdict verdict = cell ? cell_of(bi, nb, w) : CellVerdict::Unknown;
            const bool plain = verdict == CellVerdict::Unknown;
            std::size_t last_burier = std::numeric_limits<std::size_t>::max();
            for (std::size_t q = 0; q < row.size; ++q) {
                if (row.atom[q] <= i) continue;
                Meeting meeting;
                if (!meet(bi, balls[nb[q]], meeting)) continue;
                ++out.circles;
                // A circle the cell leaves no exposed point is counted, not cut.
                const std::uint32_t k = plain ? std::uint32_t(q) : w.kept_entry[q];
                if (k == kNotKept) {
                    ++out.buried_circles;
                    continue;
                }
                const Circle circle = circle_of(bi, meeting);
                if (buried_whole(circle, k, last_burier, plain ? row : w.kept, w.buried)) {
                    w.parts.clear();
                } else {
                    exposed_parts(w.buried, w.cuts, w.gaps, w.parts);
                }
                if (w.parts.empty()) ++out.buried_circles;
                add_arcs(circle, w.parts, out.arcs);
            }
        }
    }

    // Circles of the pairs i < j, cut by the other neighbours of i: chunks of atoms taken in
    // turn by all threads, each thread's arcs in arrays of its own (reserved for three arcs an
    // atom: the 2.43 M-atom shell has two; more only grow them), so that they are a few large
    // blocks of huge pages rather than a vector per chunk grown in the allocator's arenas, and
    // are freed just before the host's index of them takes as many pages again.
    // The arcs by the bin of their circle's centre (on the segment between two centres: in
    // range), in atom order within a bin (the result does not depend on the thread count):
    // each part of the bins, with about as many arcs as the others, filled on its own thread.
    void cut_circles(std::size_t cell_from) {
        const std::size_t parts =
            std::max<std::size_t>(1, std::min<std::size_t>(threads, chunk_count));
        std::vector<ChunkArcs> part_arcs(parts);
        std::vector<ChunkRun> runs(chunk_count);
        std::atomic<std::size_t> next_chunk{0};
        parallel_chunks(parts, unsigned(parts), [&](std::size_t part) {
            ChunkArcs& out = part_arcs[part];
            try {
                out.arcs.reserve(3 * n / parts + 1024);
            } catch (const std::bad_alloc&) {
                // Address space refused (strict overcommit): grown as the arcs come.
            }
            ArcScratch scratch;
            for (std::size_t chunk; (chunk = next_chunk++) < chunk_count;) {
                const std::size_t first = out.arcs.size();
                arcs_of_chunk(chunk, cell_from, scratch, out);
                runs[chunk] = {part, first, out.arcs.size() - first};
            }
            out.bins.resize(out.arcs.size());
            for (std::size_t k = 0; k < out.arcs.size(); ++k) {
                const SesArc& arc = out.arcs[k];
                int cell[3];
                out.bins[k] =
                    std::uint32_t(bin_index(Vec3{arc.m[0], arc.m[1], arc.m[2]}, cell));
                out.rho_max = std::max(out.rho_max, arc.rho);
            }
        });
        const std::size_t bins = f.bin_count();
        std::size_t total = 0;
        for (const ChunkArcs& part : part_arcs) {
            f.circles += part.circles;
            f.buried_circles += part.buried_circles;
            f.rho_max = std::max(f.rho_max, part.rho_max);
            total += part.arcs.size();
        }
        // The arcs' array (its fresh pages, on all threads first: 210 MB on the 2.43 M-atom
        // shell, which the resize alone took on one thread while the other counted) beside the
        // count of each bin's arcs.
        f.arcs.reserve(total);
        populate_pages({room_up_to(f.arcs, total)});
        parallel_chunks(2, threads, [&](std::size_t task) {
            if (task == 0) {
                f.arcs.resize(total);
                return;
            }
            f.arc_start.assign(bins + 1, 0);
            for (const ChunkArcs& part : part_arcs)
                for (const std::uint32_t b : part.bins) ++f.arc_start[std::size_t(b) + 1];
            for (std::size_t b = 0; b < bins; ++b) f.arc_start[b + 1] += f.arc_start[b];
        });
        std::vector<std::size_t> part_start(threads + 1, bins);
        for (unsigned part = 0; part < threads; ++part)
            part_start[part] =
                std::size_t(std::lower_bound(f.arc_start.begin(), f.arc_start.end() - 1,
                                             total * part / threads) -
                            f.arc_start.begin());
        parallel_chunks(threads, threads, [&](std::size_t part) {
            const std::size_t first = part_start[part], end = part_start[part + 1];
            for (const ChunkRun& run : runs) {
                const ChunkArcs& from = part_arcs[run.part];
                for (std::size_t k = run.first; k < run.first + run.count; ++k)
                    if (from.bins[k] >= first && from.bins[k] < end)
                        f.arcs[f.arc_start[from.bins[k]]++] = from.arcs[k];
            }
        });
        unshift(f.arc_start);
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

namespace {

SesFeatures build_features(const Atoms& atoms, float probe, std::size_t cell_from) {
    if (atoms.empty()) throw Error(ErrorCode::EmptySelection, "no atoms to build a surface from");
    if (atoms.xyz.size() != 3 * atoms.size())
        throw Error(ErrorCode::InvalidArgument, "atoms: xyz must hold 3 floats per radius");
    if (!(probe > 0.0f) || !std::isfinite(probe))
        throw Error(ErrorCode::InvalidArgument,
                    "the exact SES needs a probe radius > 0 Å (probe 0 is the vdw surface)");
    FeatureBuilder b(atoms, probe);
    b.read_balls();
    b.bin_spheres();
    Atoms unique;
    if (b.without_duplicates(unique)) return build_features(unique, probe, cell_from);
    trace("ses features: balls binned");
    b.find_neighbours();
    trace("ses features: neighbours");
    b.cut_circles(cell_from);
    trace("ses features: arcs");
    return std::move(b.f);
}

}  // namespace

SesFeatures build_ses_features(const Atoms& atoms, float probe, std::size_t cell_from) {
    return build_features(atoms, probe, cell_from);
}

SesFeatures build_ses_features_plain(const Atoms& atoms, float probe) {
    return build_features(atoms, probe, std::numeric_limits<std::size_t>::max());
}

}  // namespace fdmsurf::detail
