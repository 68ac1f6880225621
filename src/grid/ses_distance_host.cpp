// The exact SES field on the host: balls and arcs scattered over the points they reach
// (ses_distance_host.hpp).
#include "grid/ses_distance_host.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "base/cpu_features.hpp"
#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "fdmsurf/error.hpp"
#include "grid/ses_distance_cpu.hpp"

// The row kernels are FDMSURF_AVX2_CLONES: eight floats a vector where the CPU has AVX2; so are
// the field's steps around them and the cursor's distance (VEX code, no fused multiply-add).

namespace fdmsurf::detail {

namespace {

constexpr double kTwoPi = 6.283185307179586;
// Planes per task: a ball spans about 13 planes at 0.5 Å, so each is set up about four times.
constexpr std::uint32_t kChunkPlanes = 4;

// The first index i in [0, n) with lo + h * i >= v (float grid points; n when none), and the
// last with lo + h * i <= v (-1 when none): a point range from coordinates, one spacing wider
// on each side than rounding could need (the points themselves are tested after).
int first_at_or_above(double v, double lo, double h, int n) {
    const double t = std::floor((v - lo) / h) - 1.0;
    return static_cast<int>(std::clamp(t, 0.0, double(n)));
}
int last_at_or_below(double v, double lo, double h, int n) {
    const double t = std::ceil((v - lo) / h) + 1.0;
    return static_cast<int>(std::clamp(t, -1.0, double(n - 1)));
}

// The bin of `f` holding coordinate x along axis a, clamped to the bins (as the shaders' and
// the reference's lookups are).
int bin_cell(const SesFeatures& f, int a, double x) {
    return static_cast<int>(
        std::clamp(std::floor((x - f.origin[a]) / f.bin_size), 0.0, double(f.dims[a] - 1)));
}

// The squared gap along axis a from coordinate x to bin `cell`'s box widened by `margin` (0
// within it). With `open_ends` an end bin's box reaches on outwards, as a lookup's clamp has the
// points beyond the bins in it.
double bin_gap2(const SesFeatures& f, int a, int cell, double x, double margin, bool open_ends) {
    const double lo_edge = double(f.origin[a]) + double(f.bin_size) * cell - margin;
    const double hi_edge = lo_edge + double(f.bin_size) + 2.0 * margin;
    double g = 0.0;
    if (x < lo_edge && (!open_ends || cell > 0)) g = lo_edge - x;
    if (x > hi_edge && (!open_ends || cell + 1 < int(f.dims[a]))) g = x - hi_edge;
    return g * g;
}

// Ball i (centre x cx, radius R) in points x0 .. x1 of a row dyz² from its centre: each point's
// depth, kept where it is the deepest (l: the depth, deep: the ball, t: whether another ties).
// Selects, not branches: the row vectorises.
FDMSURF_AVX2_CLONES
void depth_row(const float* xs, float cx, float R, float dyz, std::uint32_t i, int x0, int x1,
               float* l, std::uint32_t* deep, std::uint32_t* t) {
    for (int x = x0; x <= x1; ++x) {
        const float dx = xs[x] - cx;
        const float v = R - std::sqrt(dx * dx + dyz);
        const float old = l[x];
        const std::uint32_t deeper = -std::uint32_t(v >= old);  // all ones
        const std::uint32_t same = std::uint32_t(v == old);
        t[x] = (same & deeper) | (t[x] & ~deeper);
        l[x] = v >= old ? v : old;
        deep[x] = (i & deeper) | (deep[x] & ~deeper);
    }
}

// The cursor's first test of each kept arc, a vector at a time: d2[j] = |p - c_j|² and near[j]
// all ones where d2[j] < (r[j] + add)² (c_j, r[j] the arc's ball), for j in [0, n); the same
// operations in the same order as one point's (no fused multiply-add). Its callers take the
// kept arcs in blocks of kNearBlock, whose results fit on the stack.
constexpr std::size_t kNearBlock = 64;
FDMSURF_AVX2_CLONES
void near_row(const double* __restrict x, const double* __restrict y, const double* __restrict z,
              const double* __restrict r, double add, double px, double py, double pz,
              std::size_t n, double* __restrict d2, std::uint64_t* __restrict near) {
    for (std::size_t j = 0; j < n; ++j) {
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        const double d = dx * dx + dy * dy + dz * dz, reach = r[j] + add;
        d2[j] = d;
        near[j] = d < reach * reach ? ~std::uint64_t(0) : 0;
    }
}

// The cursor's depths of its kept balls at p, a vector at a time: depth[j] = r[j] - |p - c_j|
// where the ball holds p (|p - c_j|² < r[j]², near_row's test), -infinity elsewhere, for j in
// [0, n); the same operations in the same order as one ball's (no fused multiply-add).
FDMSURF_AVX2_CLONES
void depth_at(const double* __restrict x, const double* __restrict y, const double* __restrict z,
              const double* __restrict r, double px, double py, double pz, std::size_t n,
              double* __restrict depth) {
    for (std::size_t j = 0; j < n; ++j) {
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        const double d = dx * dx + dy * dy + dz * dz, R = r[j];
        const double v = R - std::sqrt(d);
        depth[j] = d < R * R ? v : -std::numeric_limits<double>::infinity();
    }
}

// What every task of one SesHostField::evaluate call shares: the grid's points as the shaders
// compute them, the clamps, and where the planes go (row y of plane z at
// out + ((z - z_begin) * ny + y) * pitch).
struct EvalGrid {
    std::vector<float> xs, ys, zs;
    int nx, ny;
    float h, d_min, d_max;
    float reach_out;  // outside the balls d = lb < 0 matters only above the lower clamp
    float* out;
    std::size_t pitch;
    std::uint32_t z_begin;

    EvalGrid(const GridPlan& plan, std::uint32_t z_begin_in, float* out_in, std::size_t pitch_in)
        : xs(plan.info.dims[0]),
          ys(plan.info.dims[1]),
          zs(plan.info.dims[2]),
          nx(int(plan.info.dims[0])),
          ny(int(plan.info.dims[1])),
          h(plan.info.spacing),
          d_min(plan.ses_d_min),
          d_max(plan.ses_d_max),
          reach_out(std::max(0.0f, -plan.ses_d_min)),
          out(out_in),
          pitch(pitch_in),
          z_begin(z_begin_in) {
        for (int x = 0; x < nx; ++x) xs[x] = plan.info.origin[0] + h * float(x);
        for (int y = 0; y < ny; ++y) ys[y] = plan.info.origin[1] + h * float(y);
        for (std::uint32_t z = 0; z < plan.info.dims[2]; ++z)
            zs[z] = plan.info.origin[2] + h * float(z);
    }
};

}  // namespace

// Scratch per task, taken from the object's pool and given back at the task's end: kept from
// chunk to chunk and from call to call (a slab's evaluate is one call; fresh pages for each
// would cost more than the work on them: 1.1 GB of them on the 2.4 M-atom shell at 1 Å, 15
// slabs), freed by release_scratch or with the object.
struct SesHostField::Scratch {
    std::vector<float> lb, arc_best;
    std::vector<std::uint32_t> deepest, tie;  // tie: 32 bits, as deepest (one vector width)
    std::vector<std::uint64_t> waiting_bits;
    // Per row of the slab: whether a ball reaches it (the others are not filled: most of a
    // capsid's shell grid, inside and outside the shell).
    std::vector<std::uint8_t> row_reached;
};
struct SesHostField::ScratchPool {
    std::mutex mutex;
    std::vector<std::unique_ptr<Scratch>> free;
    struct Lease {
        ScratchPool& pool;
        std::unique_ptr<Scratch> scratch;
        explicit Lease(ScratchPool& p) : pool(p) {
            const std::lock_guard<std::mutex> lock(pool.mutex);
            if (pool.free.empty()) {
                scratch = std::make_unique<Scratch>();
            } else {
                scratch = std::move(pool.free.back());
                pool.free.pop_back();
            }
        }
        ~Lease() {
            const std::lock_guard<std::mutex> lock(pool.mutex);
            pool.free.push_back(std::move(scratch));
        }
    };
};

// An exposed arc with what its distance needs precomputed (double precision): the angle test
// by cross products against the ends' in-plane directions, the distance off the arc to the
// nearer end in space (the nearer in angle, as ses_features.cpp's arc_distance takes it: the
// chord grows with the angle), so no atan2 and no sine per point.
//
// Only what takes trigonometry is kept beside the features' stored circle (SesArc, read with it
// by ArcView): the axis and the end points are recomputed where they are needed, from the same
// doubles by the same operations (the build has no fused multiply-add), so bit for bit the
// values that were kept before; the arc's ball is arc_ball_'s alone; the field's float copies
// are made per arc by its arcs step (FloatArc). 40 bytes, not 240: on the 2.43 M-atom shell at
// 1 Å (4.4 M arcs) 0.9 GB fewer fresh pages, on a VM where a fresh page costs more than the
// work on it.
struct SesHostField::Arc {
    double start_dir[2], end_dir[2];  // cos, sin of the ends' angles
    bool longer_than_half;  // length > pi: the test is on the complement
    // The whole circle (length float(2 pi), just above 2 pi, or rounded to it): every direction
    // is on it, as arc_distance has it; the ends' test would cut a wedge of the rounding's width.
    bool full;

    Arc() = default;  // uninitialised: filled by assignment, on all threads
    explicit Arc(const SesArc& a) {
        const double end = double(a.start) + double(a.length);
        start_dir[0] = std::cos(double(a.start)), start_dir[1] = std::sin(double(a.start));
        end_dir[0] = std::cos(end), end_dir[1] = std::sin(end);
        longer_than_half = double(a.length) > 0.5 * kTwoPi;
        full = double(a.length) >= kTwoPi;
    }

    // Whether the in-plane direction (a, b) lies on the arc: after its start and before its
    // end, counter-clockwise (a point on the axis, (0, 0), counts as on it, as in arc_distance).
    bool on_arc(double a, double b) const {
        if (full) return true;
        const double after_start = start_dir[0] * b - start_dir[1] * a;
        const double before_end = a * end_dir[1] - b * end_dir[0];
        return longer_than_half ? !(after_start < 0.0 && before_end < 0.0)
                                : after_start >= 0.0 && before_end >= 0.0;
    }
};

static_assert(sizeof(SesHostField::Arc) <= 40, "an arc's bytes: every one is a fresh page's share");

// An arc read whole: its circle as the features store it (centre, in-plane basis, radius, in
// float: the double arithmetic below converts these exactly, so they serve both it and the
// field's row kernel) and what SesHostField::Arc keeps beside it. Both are found by the arc's
// index (SesHostField::arc_view), so their loads do not wait on each other.
struct SesHostField::ArcView {
    const SesHostField::Arc& x;
    const SesArc& c;

    // The circle's axis, e1 x e2 in double.
    void axis(double out[3]) const {
        const double e1[3] = {c.e1[0], c.e1[1], c.e1[2]}, e2[3] = {c.e2[0], c.e2[1], c.e2[2]};
        out[0] = e1[1] * e2[2] - e1[2] * e2[1];
        out[1] = e1[2] * e2[0] - e1[0] * e2[2];
        out[2] = e1[0] * e2[1] - e1[1] * e2[0];
    }

    // The arc's end points, m + rho (cos t e1 + sin t e2) at its start and end angles.
    void end_points(double start_point[3], double end_point[3]) const {
        const double rho = c.rho;
        for (int k = 0; k < 3; ++k) {
            const double m = c.m[k], e1 = c.e1[k], e2 = c.e2[k];
            start_point[k] = m + rho * (x.start_dir[0] * e1 + x.start_dir[1] * e2);
            end_point[k] = m + rho * (x.end_dir[0] * e1 + x.end_dir[1] * e2);
        }
    }

    // A ball holding the arc: up to half a turn, around its chord's midpoint with the half-chord
    // as radius (the arc's middle is rho (1 - cos(L/2)) <= rho sin(L/2) from there); else the
    // circle's. Widened by 1e-9 Å relative for rounding.
    std::array<double, 4> ball() const {
        const double m[3] = {c.m[0], c.m[1], c.m[2]}, rho = c.rho;
        std::array<double, 4> out;
        if (x.longer_than_half) {
            out = {m[0], m[1], m[2], rho};
        } else {
            double s[3], e[3];
            end_points(s, e);
            out = {0.5 * (s[0] + e[0]), 0.5 * (s[1] + e[1]), 0.5 * (s[2] + e[2]),
                   rho * std::sin(0.5 * double(c.length))};
        }
        out[3] += 1e-9 * (rho + std::abs(m[0]) + std::abs(m[1]) + std::abs(m[2]));
        return out;
    }

    // The arc's point nearest to p: on the circle towards p, or the nearer end (the start
    // for a point on the axis, as arc_distance).
    void nearest(const double p[3], double q[3]) const {
        const double m[3] = {c.m[0], c.m[1], c.m[2]}, rho = c.rho;
        const double e1[3] = {c.e1[0], c.e1[1], c.e1[2]}, e2[3] = {c.e2[0], c.e2[1], c.e2[2]};
        const double v[3] = {p[0] - m[0], p[1] - m[1], p[2] - m[2]};
        const double a = v[0] * e1[0] + v[1] * e1[1] + v[2] * e1[2];
        const double b = v[0] * e2[0] + v[1] * e2[1] + v[2] * e2[2];
        const double r = std::sqrt(a * a + b * b);
        if (r > 0.0 && x.on_arc(a, b)) {
            for (int k = 0; k < 3; ++k) q[k] = m[k] + rho * (a * e1[k] + b * e2[k]) / r;
            return;
        }
        double start_point[3], end_point[3];
        end_points(start_point, end_point);
        if (r == 0.0) {
            for (int k = 0; k < 3; ++k) q[k] = start_point[k];
            return;
        }
        double ds = 0.0, de = 0.0;
        for (int k = 0; k < 3; ++k) {
            ds += (p[k] - start_point[k]) * (p[k] - start_point[k]);
            de += (p[k] - end_point[k]) * (p[k] - end_point[k]);
        }
        for (int k = 0; k < 3; ++k) q[k] = ds <= de ? start_point[k] : end_point[k];
    }

    // The distance from p to the nearer end point.
    double end_distance(const double p[3]) const {
        double start_point[3], end_point[3];
        end_points(start_point, end_point);
        auto dist2 = [&](const double* q) {
            const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            return dx * dx + dy * dy + dz * dz;
        };
        return std::sqrt(std::min(dist2(start_point), dist2(end_point)));
    }

    // The distance from p, or `bound` when the arc is certainly not nearer.
    double distance(const double p[3], double bound) const {
        const double m[3] = {c.m[0], c.m[1], c.m[2]}, rho = c.rho;
        const double e1[3] = {c.e1[0], c.e1[1], c.e1[2]}, e2[3] = {c.e2[0], c.e2[1], c.e2[2]};
        const double v[3] = {p[0] - m[0], p[1] - m[1], p[2] - m[2]};
        double n[3];
        axis(n);
        const double height = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
        if (std::abs(height) >= bound) return bound;
        const double a = v[0] * e1[0] + v[1] * e1[1] + v[2] * e1[2];
        const double b = v[0] * e2[0] + v[1] * e2[1] + v[2] * e2[2];
        const double r = std::sqrt(a * a + b * b);
        if (std::abs(r - rho) >= bound) return bound;
        if (x.on_arc(a, b)) {
            const double rr = r - rho;
            return std::sqrt(height * height + rr * rr);
        }
        return end_distance(p);
    }

    // distance()'s values without a bound: the distance, |height| and |r - rho|. distance(p,
    // b) is this distance for every b above all three, and b where b is at or below one of
    // the last two.
    struct Parts {
        double distance, height, off_circle;
    };
    Parts distance_parts(const double p[3]) const {
        const double m[3] = {c.m[0], c.m[1], c.m[2]}, rho = c.rho;
        const double e1[3] = {c.e1[0], c.e1[1], c.e1[2]}, e2[3] = {c.e2[0], c.e2[1], c.e2[2]};
        const double v[3] = {p[0] - m[0], p[1] - m[1], p[2] - m[2]};
        double n[3];
        axis(n);
        const double height = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
        const double a = v[0] * e1[0] + v[1] * e1[1] + v[2] * e1[2];
        const double b = v[0] * e2[0] + v[1] * e2[1] + v[2] * e2[2];
        const double r = std::sqrt(a * a + b * b);
        if (x.on_arc(a, b)) {
            const double rr = r - rho;
            return {std::sqrt(height * height + rr * rr), std::abs(height), std::abs(r - rho)};
        }
        return {end_distance(p), std::abs(height), std::abs(r - rho)};
    }
};

SesHostField::ArcView SesHostField::arc_view(std::size_t k) const { return {arcs_[k], f_.arcs[k]}; }

// The field's row kernel's copy of an arc, in float, positions relative to fm (the shader's
// precision): made by the arcs step for each arc it evaluates on some row (fewer than the arcs,
// and once per task of planes, not per row).
struct SesHostField::FloatArc {
    float fm[3], fe1[3], fe2[3], frho;
    float faxis[3], fstart_dir[2], fend_dir[2], fstart[3], fend[3];
    bool longer_than_half, full;

    explicit FloatArc(const ArcView& a) {
        double axis[3], start_point[3], end_point[3];
        a.axis(axis);
        a.end_points(start_point, end_point);
        for (int k = 0; k < 3; ++k) {
            const double m = a.c.m[k];
            fm[k] = a.c.m[k], faxis[k] = float(axis[k]), fe1[k] = a.c.e1[k], fe2[k] = a.c.e2[k];
            fstart[k] = float(start_point[k] - m), fend[k] = float(end_point[k] - m);
        }
        frho = a.c.rho;
        for (int k = 0; k < 2; ++k)
            fstart_dir[k] = float(a.x.start_dir[k]), fend_dir[k] = float(a.x.end_dir[k]);
        longer_than_half = a.x.longer_than_half, full = a.x.full;
    }
};

SesHostField::~SesHostField() = default;

void SesHostField::arc_row_distances(std::size_t arc, const float* xs, float y, float z, int xa,
                                     int xb, float* best) const {
    if (arc >= f_.arcs.size())
        throw Error(ErrorCode::InvalidArgument, "host SES field: no such arc");
    arc_row(FloatArc(arc_view(arc)), xs, y, z, xa, xb, best);
}

namespace {

// best[x] = min(best[x], the distance from (xs[x], y, z) to the arc) for x in [xa, xb], in
// float relative to the circle's centre: the on-arc distance and the nearer end's, selected by
// the angle test, with no branch, so that the compiler vectorises the row (four lanes on any
// x86-64, eight where the CPU has AVX2: the same operations in each lane, no fused multiply-add).
FDMSURF_AVX2_CLONES
void arc_row_kernel(const SesHostField::FloatArc& arc, const float* xs, float y, float z, int xa,
                    int xb, float* best) {
    const float vy = y - arc.fm[1], vz = z - arc.fm[2];
    const float h0 = vy * arc.faxis[1] + vz * arc.faxis[2];
    const float a0 = vy * arc.fe1[1] + vz * arc.fe1[2];
    const float b0 = vy * arc.fe2[1] + vz * arc.fe2[2];
    const float sy = vy - arc.fstart[1], sz = vz - arc.fstart[2];
    const float ey = vy - arc.fend[1], ez = vz - arc.fend[2];
    const float s_yz = sy * sy + sz * sz, e_yz = ey * ey + ez * ez;
    const float ax = arc.faxis[0], e1x = arc.fe1[0], e2x = arc.fe2[0], mx = arc.fm[0];
    const float rho = arc.frho, sx0 = arc.fstart[0], ex0 = arc.fend[0];
    const float sd0 = arc.fstart_dir[0], sd1 = arc.fstart_dir[1];
    const float ed0 = arc.fend_dir[0], ed1 = arc.fend_dir[1];
    // More than half a turn: on the arc unless within the complement (both tests negative); the
    // whole circle: on it everywhere. Masks of all ones or none.
    const std::uint32_t longer = arc.longer_than_half ? ~0u : 0u;
    const std::uint32_t full = arc.full ? ~0u : 0u;
    for (int x = xa; x <= xb; ++x) {
        const float vx = xs[x] - mx;
        const float hh = vx * ax + h0, a = vx * e1x + a0, b = vx * e2x + b0;
        const float rr = std::sqrt(a * a + b * b) - rho;
        const float on_d2 = hh * hh + rr * rr;
        const float after_start = sd0 * b - sd1 * a, before_end = a * ed1 - b * ed0;
        const std::uint32_t after = after_start >= 0.0f ? ~0u : 0u;
        const std::uint32_t before = before_end >= 0.0f ? ~0u : 0u;
        const std::uint32_t on = full | (longer & (after | before)) | (~longer & after & before);
        const float sx = vx - sx0, ex = vx - ex0;
        const float ds = sx * sx + s_yz, de = ex * ex + e_yz;
        const float off_d2 = ds < de ? ds : de;
        // A select: the blend on * on_d2 + (1 - on) * off_d2 that this replaces, with on 1 or
        // 0, gave either square exactly (a finite one times 0, plus 0).
        const float d = std::sqrt(on != 0 ? on_d2 : off_d2);
        const float old = best[x];
        best[x] = d < old ? d : old;
    }
}

}  // namespace

namespace {

// The point-distance steps that SesHostField::distance and its Cursor share, with one
// arithmetic (the cursor's values are distance()'s bit for bit).

void set_gradient(double* gradient, double x, double y, double z) {
    if (gradient) gradient[0] = x, gradient[1] = y, gradient[2] = z;
}

// The unit direction from the nearest point q to p (0 where they coincide).
void gradient_from(const double p[3], const double q[3], double* gradient) {
    const double w[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    const double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (l > 0.0)
        set_gradient(gradient, w[0] / l, w[1] / l, w[2] / l);
    else
        set_gradient(gradient, 0, 0, 0);
}

// The radial projection q of p onto sphere `ball` of `s` (x, y, z, R per sphere); a fixed
// point of the sphere when p is at its centre.
void face_point(const float* s, std::uint32_t ball, const double p[3], double q[3]) {
    const double c[3] = {s[4 * ball], s[4 * ball + 1], s[4 * ball + 2]};
    const double R = s[4 * ball + 3];
    const double v[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    q[0] = c[0] + R, q[1] = c[1], q[2] = c[2];
    if (len > 1e-6)
        for (int a = 0; a < 3; ++a) q[a] = c[a] + (R / len) * v[a];
}

// Whether q lies inside sphere k of `s`.
bool inside_sphere(const float* s, std::uint32_t k, const double q[3]) {
    const double wx = q[0] - s[4 * k], wy = q[1] - s[4 * k + 1], wz = q[2] - s[4 * k + 2];
    const double Rk = s[4 * k + 3];
    return wx * wx + wy * wy + wz * wz < Rk * Rk;
}

// The end of the arcs' step: `best`, and the gradient from the nearest arc (none: 0).
double arcs_result(const SesHostField::ArcView* best_arc, double best, const double p[3],
                   double* gradient) {
    if (best_arc == nullptr) {
        set_gradient(gradient, 0, 0, 0);
        return best;
    }
    if (gradient) {
        double q[3];
        best_arc->nearest(p, q);
        gradient_from(p, q, gradient);
    }
    return best;
}

}  // namespace

void SesHostField::list_arcs_by_bin() const {
    std::call_once(bins_listed_, [this] { fill_bin_lists(); });
}

// Each arc in every bin that its box widened by reach_ overlaps and whose box (widened by
// bin_margin_; an outer bin's box reaching on outwards, since points beyond the bins are
// clamped into it) comes nearer than ball_radius + reach_ to the arc's ball's centre: any
// other bin's points all fail distance()'s first test of the arc (its ball comes within
// d_max <= reach_ of p), so the lists give the same values, with a fifth fewer entries
// (the 12-copy shell). In arc order within a bin. Each part of the bins' planes (about as many
// arcs' lowest planes each) counted and filled on its own thread, every arc tried by its
// planes first.
void SesHostField::fill_bin_lists() const {
    const SesFeatures& f = f_;
    const std::size_t n_arcs = f.arcs.size(), bins = f.bin_count();
    auto bin_range = [&](const Box& box, int lo[3], int hi[3]) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = bin_cell(f, a, double(box.lo[a]) - reach_);
            hi[a] = bin_cell(f, a, double(box.hi[a]) + reach_);
        }
    };
    // The squared gap along axis a from the ball's centre c to bin `cell`'s widened box.
    auto gap2 = [&](int a, int cell, double c) {
        return bin_gap2(f, a, cell, c, bin_margin_, true);
    };
    // The parts' first planes of bins, about as many arcs' lowest planes each (the arcs lie in
    // their circles' bins, planes of bins in order).
    std::vector<int> part_plane(threads_ + 1, int(f.dims[2]));
    part_plane[0] = 0;
    for (unsigned part = 1; part < threads_; ++part)
        part_plane[part] =
            n_arcs == 0
                ? int(f.dims[2])
                : std::max(part_plane[part - 1],
                           bin_cell(f, 2,
                                    double(arc_box_[n_arcs * part / threads_].lo[2]) - reach_));
    // body(k, b) for every bin b of arc k within the part's planes, arcs in order.
    auto each_bin = [&](std::size_t part, auto&& body) {
        double gap_x[64], gap_y[64];
        for (std::size_t k = 0; k < n_arcs; ++k) {
            const Box& box = arc_box_[k];
            const int z0 = std::max(bin_cell(f, 2, double(box.lo[2]) - reach_), part_plane[part]);
            const int z1 =
                std::min(bin_cell(f, 2, double(box.hi[2]) + reach_), part_plane[part + 1] - 1);
            if (z0 > z1) continue;
            int lo[3], hi[3];
            bin_range(box, lo, hi);
            const std::array<double, 4>& ball = arc_ball_[k];
            // Relative slack for the rounding of the test against distance()'s.
            const double reach = (ball[3] + reach_) * (1.0 + 1e-9) + 1e-9;
            const double r2 = reach * reach;
            const bool cull = hi[0] - lo[0] < 64 && hi[1] - lo[1] < 64;
            if (cull) {
                for (int x = lo[0]; x <= hi[0]; ++x) gap_x[x - lo[0]] = gap2(0, x, ball[0]);
                for (int y = lo[1]; y <= hi[1]; ++y) gap_y[y - lo[1]] = gap2(1, y, ball[1]);
            }
            for (int z = z0; z <= z1; ++z) {
                const double gz = cull ? gap2(2, z, ball[2]) : 0.0;
                for (int y = lo[1]; y <= hi[1]; ++y) {
                    const double gyz = cull ? gz + gap_y[y - lo[1]] : 0.0;
                    if (gyz >= r2) continue;
                    const std::size_t row = (std::size_t(z) * f.dims[1] + y) * f.dims[0];
                    for (int x = lo[0]; x <= hi[0]; ++x)
                        if (!cull || gyz + gap_x[x - lo[0]] < r2) body(k, row + x);
                }
            }
        }
    };
    bin_arc_start_.assign(bins + 1, 0);
    parallel_chunks(threads_, threads_, [&](std::size_t part) {
        each_bin(part, [&](std::size_t, std::size_t b) { ++bin_arc_start_[b + 1]; });
    });
    for (std::size_t b = 0; b < bins; ++b) bin_arc_start_[b + 1] += bin_arc_start_[b];
    bin_arcs_ = std::make_unique_for_overwrite<std::uint32_t[]>(bin_arc_start_[bins]);
    // Each bin's start advanced past its arcs as they are filled, then shifted back.
    parallel_chunks(threads_, threads_, [&](std::size_t part) {
        each_bin(part, [&](std::size_t k, std::size_t b) {
            bin_arcs_[bin_arc_start_[b]++] = static_cast<std::uint32_t>(k);
        });
    });
    std::copy_backward(bin_arc_start_.begin(), bin_arc_start_.end() - 2, bin_arc_start_.end() - 1);
    bin_arc_start_[0] = 0;
    trace("ses host: arcs' bins listed");
}

void SesHostField::arc_row(const FloatArc& arc, const float* xs, float y, float z, int xa, int xb,
                           float* best) {
    arc_row_kernel(arc, xs, y, z, xa, xb, best);
}

SesHostField::SesHostField(const SesFeatures& f, double d_max, unsigned threads)
    : f_(f),
      threads_(thread_count(threads)),
      reach_(d_max),
      scratch_(std::make_unique<ScratchPool>()) {
    const std::size_t n = f.sphere_count(), n_arcs = f.arcs.size();
    if (f.neighbour_start.size() != n + 1)
        throw Error(ErrorCode::InvalidArgument, "host SES field: features without neighbour lists");
    constexpr std::size_t kChunk = 4096;  // balls or arcs per task
    // As the features' binning has it: more than the rounding of a centre's bin and of the bins'
    // bounds.
    for (int a = 0; a < 3; ++a) {
        const double far = std::max(std::abs(double(f.origin[a])),
                                    std::abs(double(f.origin[a]) + double(f.bin_size) * f.dims[a]));
        bin_margin_ = std::max(bin_margin_, 1e-3 + 1e-6 * far);
    }

    // Each arc's bounds: along axis a its points are m_a + rho A cos(theta - phi), A and phi from
    // (e1_a, e2_a); the extreme is reached where theta = phi (or phi + pi) lies on the arc, else
    // at an end. Widened by 1e-4 Å for the float rounding of the stored arc. Whether phi lies on
    // the arc is the arc's own cross-product test of the direction (e1_a, e2_a), not an atan2
    // and the angles' test (three atan2 an arc were the step's costliest calls, three times its
    // sines and cosines under perf on the 12-copy shell): the two can differ only for a
    // direction at an end, within rounding, where the extreme is that end, so the bound moves by
    // rounding, far inside the widening. Chunks of arcs on all threads (their fresh pages too).
    arcs_ = std::make_unique_for_overwrite<Arc[]>(n_arcs);
    arc_ball_ = std::make_unique_for_overwrite<std::array<double, 4>[]>(n_arcs);
    arc_box_ = std::make_unique_for_overwrite<Box[]>(n_arcs);
    const std::size_t arc_chunks = (n_arcs + kChunk - 1) / kChunk;
    parallel_chunks(arc_chunks, threads_, [&](std::size_t chunk) {
        for (std::size_t k = chunk * kChunk; k < std::min(n_arcs, (chunk + 1) * kChunk); ++k) {
            const SesArc& a = f.arcs[k];
            arcs_[k] = Arc(a);
            const ArcView added = arc_view(k);
            arc_ball_[k] = added.ball();
            double start_point[3], end_point[3];
            added.end_points(start_point, end_point);
            Box& box = arc_box_[k];
            for (int ax = 0; ax < 3; ++ax) {
                const double e1 = a.e1[ax], e2 = a.e2[ax];
                // The ends, m + rho (cos t e1 + sin t e2) at t = start and start + length, are
                // the arc's own end points (the same arithmetic).
                double lo = std::min(start_point[ax], end_point[ax]);
                double hi = std::max(start_point[ax], end_point[ax]);
                const double amp = std::hypot(e1, e2);
                if (added.x.on_arc(e1, e2)) hi = a.m[ax] + a.rho * amp;
                if (added.x.on_arc(-e1, -e2)) lo = a.m[ax] - a.rho * amp;
                box.lo[ax] = static_cast<float>(lo - 1e-4);
                box.hi[ax] = static_cast<float>(hi + 1e-4);
            }
        }
    });
    trace("ses host: arcs prepared");
}

double SesHostField::distance(const double p[3], double d_max, double* gradient) const {
    if (!(d_max <= reach_)) return ses_distance(f_, p, d_max, gradient, false);
    list_arcs_by_bin();
    const float* s = f_.spheres.data();
    int lo[3], hi[3], bin[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = bin_cell(f_, a, p[a] - f_.r_max);
        hi[a] = bin_cell(f_, a, p[a] + f_.r_max);
        bin[a] = bin_cell(f_, a, p[a]);
    }
    // The balls holding p, as the reference's depth loop (which also sees farther balls, whose
    // depth is negative: the same deepest, the same ties, where one ball holds p).
    // Only the bins whose box (widened by bin_margin_) lies within r_max of p can hold a ball
    // holding p: a bit more than half of the 27 in range.
    double lb = -std::numeric_limits<double>::infinity();
    std::uint32_t deepest = 0;
    bool tie = false;
    const double r_max = double(f_.r_max) * (1.0 + 1e-6), r2 = r_max * r_max;
    auto gap2 = [&](int a, int cell) { return bin_gap2(f_, a, cell, p[a], bin_margin_, false); };
    for (int z = lo[2]; z <= hi[2]; ++z) {
        const double gz = gap2(2, z);
        if (gz > r2) continue;
        for (int y = lo[1]; y <= hi[1]; ++y) {
            const double gyz = gz + gap2(1, y);
            if (gyz > r2) continue;
            for (int x = lo[0]; x <= hi[0]; ++x) {
                if (gyz + gap2(0, x) > r2) continue;
                const std::size_t b = (std::size_t(z) * f_.dims[1] + y) * f_.dims[0] + x;
                for (std::uint32_t i = f_.sphere_start[b]; i < f_.sphere_start[b + 1]; ++i) {
                    const double dx = p[0] - s[4 * i], dy = p[1] - s[4 * i + 1],
                                 dz = p[2] - s[4 * i + 2];
                    const double R = s[4 * i + 3], d2 = dx * dx + dy * dy + dz * dz;
                    // A ball not holding p is not the deepest of a point inside the balls (and
                    // the others take the reference below): no square root for it.
                    if (d2 >= R * R) continue;
                    const double v = R - std::sqrt(d2);
                    tie = v == lb || (tie && v < lb);
                    if (v > lb) lb = v, deepest = i;
                }
            }
        }
    }
    if (!(lb > 0.0) || tie) return ses_distance(f_, p, d_max, gradient, false);
    if (lb >= d_max) {
        set_gradient(gradient, 0, 0, 0);
        return d_max;
    }
    // The deepest face, against the deepest ball's neighbours.
    {
        double q[3];
        face_point(s, deepest, p, q);
        bool buried = false;
        for (std::uint32_t n = f_.neighbour_start[deepest];
             n < f_.neighbour_start[deepest + 1] && !buried; ++n)
            buried = inside_sphere(s, f_.neighbours[n], q);
        if (!buried) {
            gradient_from(p, q, gradient);
            return lb;
        }
    }
    // The arcs of p's bin.
    const std::size_t b = (std::size_t(bin[2]) * f_.dims[1] + bin[1]) * f_.dims[0] + bin[0];
    // In blocks: first, without a branch, the arcs whose ball comes within d_max of p (the
    // others fail the test below whatever the bound, which only falls), then these alone, in
    // order, against the bound so far: the same arcs reach ArcView::distance as one loop would.
    double best = d_max;
    std::uint32_t best_k = std::uint32_t(-1);
    constexpr std::uint32_t kBlock = 64;
    std::uint32_t near[kBlock];
    double near_d2[kBlock];
    for (std::uint32_t n0 = bin_arc_start_[b]; n0 < bin_arc_start_[b + 1]; n0 += kBlock) {
        const std::uint32_t n1 = std::min(n0 + kBlock, bin_arc_start_[b + 1]);
        std::uint32_t count = 0;
        for (std::uint32_t n = n0; n < n1; ++n) {
            const double* ball = arc_ball_[bin_arcs_[n]].data();
            const double vx = p[0] - ball[0], vy = p[1] - ball[1], vz = p[2] - ball[2];
            const double d2 = vx * vx + vy * vy + vz * vz, r = ball[3] + d_max;
            near[count] = n;
            near_d2[count] = d2;
            count += d2 < r * r;
        }
        for (std::uint32_t j = 0; j < count; ++j) {
            const std::uint32_t k = bin_arcs_[near[j]];
            const double r = arc_ball_[k][3] + best;
            if (near_d2[j] >= r * r) continue;
            const double d = arc_view(k).distance(p, best);
            if (d < best) best = d, best_k = k;
        }
    }
    if (best_k == std::uint32_t(-1)) return arcs_result(nullptr, best, p, gradient);
    const ArcView best_arc = arc_view(best_k);
    return arcs_result(&best_arc, best, p, gradient);
}

namespace {

// The points x, along axis a, with bin_cell(f, a, x + shift) == cell certainly (whatever its
// rounding): those more than `margin` inside the cell's bounds (a clamped end cell has no
// bound on that side).
void narrow_to_cell(const SesFeatures& f, int a, int cell, double shift, double margin,
                    double& lo, double& hi) {
    const double edge = double(f.origin[a]) + double(f.bin_size) * cell - shift;
    if (cell > 0) lo = std::max(lo, edge + margin);
    if (cell < int(f.dims[a]) - 1) hi = std::min(hi, edge + double(f.bin_size) - margin);
}

}  // namespace

// The balls of the bins [lo, hi], bin by bin in z, y, x order (the gap test of distance() is
// left out: a ball of a bin it skips does not hold the point).
void SesHostField::Cursor::gather_balls(const int lo[3], const int hi[3]) {
    const SesFeatures& f = field_.f_;
    const float* s = f.spheres.data();
    ball_x_.clear(), ball_y_.clear(), ball_z_.clear(), ball_r_.clear(), ball_index_.clear();
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) {
                const std::size_t b = (std::size_t(z) * f.dims[1] + y) * f.dims[0] + x;
                for (std::uint32_t i = f.sphere_start[b]; i < f.sphere_start[b + 1]; ++i) {
                    ball_x_.push_back(s[4 * i]), ball_y_.push_back(s[4 * i + 1]);
                    ball_z_.push_back(s[4 * i + 2]), ball_r_.push_back(s[4 * i + 3]);
                    ball_index_.push_back(i);
                }
            }
    ball_depth_.resize(ball_index_.size());
    for (int a = 0; a < 3; ++a) lo_[a] = lo[a], hi_[a] = hi[a];
}

// The arcs of bin `bin`'s list, in its order, their balls side by side.
void SesHostField::Cursor::gather_arcs(std::size_t bin) {
    arc_x_.clear(), arc_y_.clear(), arc_z_.clear(), arc_r_.clear(), arc_index_.clear();
    for (std::uint32_t n = field_.bin_arc_start_[bin]; n < field_.bin_arc_start_[bin + 1]; ++n) {
        const std::uint32_t k = field_.bin_arcs_[n];
        const std::array<double, 4>& ball = field_.arc_ball_[k];
        arc_x_.push_back(ball[0]), arc_y_.push_back(ball[1]), arc_z_.push_back(ball[2]);
        arc_r_.push_back(ball[3]), arc_index_.push_back(k);
        // The arc's circle and ends, which nearest_arc reads for the arcs it measures: their
        // first loads were its costliest (the lists hold arcs of some 27 bins' runs).
        __builtin_prefetch(&field_.f_.arcs[k]);
        __builtin_prefetch(&field_.arcs_[k]);
    }
    near_.resize(arc_index_.size());
    near_d2_.resize(arc_index_.size());
    arc_bin_ = bin;
    // The last arc's place, for nearest_arc's first bound: the bins list their arcs in order
    // (where one did not, the search would only miss it).
    const auto at = std::lower_bound(arc_index_.begin(), arc_index_.end(), last_arc_);
    last_at_ = at != arc_index_.end() && *at == last_arc_ ? std::size_t(at - arc_index_.begin())
                                                          : kNoArc;
}

// distance()'s arc step, which ends at the first arc of the least distance, with fewer arcs
// measured. That loop tries each arc in order against the bound so far (d_max at first):
// an arc whose height over its plane or distance off its circle is at or above the bound
// stops early (ArcView::distance), and its distance to an end may round a hair below these, so
// the loop is followed exactly, not just its least. Here a first bound U comes from one arc:
// the one the last point ended at (the next Newton step, the next vertex), else the near arc
// of the nearest ball. An arc whose ball lies at U or beyond lies farther than U (the balls
// are widened by 1e-9 relative, far above the rounding); the others are measured, their
// least B at arc j, the first of it. The loop's bound never rises and an arc lowers it only
// to its own distance, so on reaching j it is at least the least of d_max, the distances
// measured before j, and (above) U: where that lies above j's three values and passes j's
// ball test, the loop takes j, and no arc after it goes below B. Else settled_ is false and
// the caller runs the loop. Returns j's place in the kept arcs and `distance` B (kNoArc with
// settled_ true: no arc near). With the last point's arc the first, one pass over the kept
// balls against U finds the arcs to measure, without the list of those within d_max.
FDMSURF_AVX2_CLONES
std::size_t SesHostField::Cursor::nearest_arc(const double p[3], double d_max, double& distance) {
    const SesHostField& h = field_;
    settled_ = false;
    const std::size_t arcs = arc_index_.size();
    // The first bound's arc: the last point's, where the kept list holds it and its ball comes
    // within d_max of p (near_row's test, the same arithmetic), else the nearest ball's.
    std::size_t first = kNoArc;
    if (last_at_ < arcs) {
        const std::size_t j = last_at_;
        const double dx = p[0] - arc_x_[j], dy = p[1] - arc_y_[j], dz = p[2] - arc_z_[j];
        const double d2 = dx * dx + dy * dy + dz * dz, reach = arc_r_[j] + d_max;
        if (d2 < reach * reach) first = j;
    }
    if (first == kNoArc) {
        const std::size_t count = near_arcs(p, d_max);
        if (count == 0) {
            settled_ = true;
            return kNoArc;
        }
        double least = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < count; ++j) {
            const double key = std::sqrt(near_d2_[j]) - arc_r_[near_[j]];
            if (key < least) least = key, first = near_[j];
        }
        if (first == kNoArc) return kNoArc;
    }
    const ArcView::Parts first_parts = h.arc_view(arc_index_[first]).distance_parts(p);
    const double bound = first_parts.distance;
    if (!(bound < d_max)) return kNoArc;
    // The arcs whose balls come within the bound of p, in the kept order, a block's as bits:
    // below d_max, the bound's test passes only arcs that the loop's (within d_max) passes too
    // (its reach squared rounds to no more), so these are the arcs the loop measures.
    double least = std::numeric_limits<double>::infinity(), before = d_max, top = 0.0;
    double at_d2 = 0.0;
    std::size_t at = kNoArc;
    double block_d2[kNearBlock];
    std::uint64_t block_near[kNearBlock];
    for (std::size_t n0 = 0; n0 < arcs; n0 += kNearBlock) {
        const std::size_t n1 = std::min(n0 + kNearBlock, arcs);
        near_row(&arc_x_[n0], &arc_y_[n0], &arc_z_[n0], &arc_r_[n0], bound, p[0], p[1], p[2],
                 n1 - n0, block_d2, block_near);
        std::uint64_t bits = 0;
        for (std::size_t j = 0; j < n1 - n0; ++j) bits |= (block_near[j] & 1) << j;
        if (first >= n0 && first < n1) bits |= std::uint64_t(1) << (first - n0);
        for (; bits != 0; bits &= bits - 1) {
            const std::size_t j = n0 + std::size_t(std::countr_zero(bits));
            const ArcView::Parts parts =
                j == first ? first_parts : h.arc_view(arc_index_[j]).distance_parts(p);
            if (parts.distance < least) {
                before = std::min(d_max, least);
                least = parts.distance, at = j, at_d2 = block_d2[j - n0];
                top = std::max({parts.distance, parts.height, parts.off_circle});
            }
        }
    }
    const double floor_bound = std::min(before, bound);
    const double r = arc_r_[at] + floor_bound;
    if (!(top < before && top <= bound && at_d2 < r * r)) return kNoArc;
    settled_ = true;
    distance = least;
    return at;
}

// The kept arcs whose balls come within d_max of p, in the kept order (the others never reach
// distance()'s bound test, whatever the bound): their places into near_, the squared distances
// to their balls' centres into near_d2_; returns their count.
std::size_t SesHostField::Cursor::near_arcs(const double p[3], double d_max) {
    double block_d2[kNearBlock];
    std::uint64_t block_near[kNearBlock];
    const std::size_t arcs = arc_index_.size();
    std::size_t count = 0;
    for (std::size_t n0 = 0; n0 < arcs; n0 += kNearBlock) {
        const std::size_t n1 = std::min(n0 + kNearBlock, arcs);
        near_row(&arc_x_[n0], &arc_y_[n0], &arc_z_[n0], &arc_r_[n0], d_max, p[0], p[1], p[2],
                 n1 - n0, block_d2, block_near);
        for (std::size_t n = n0; n < n1; ++n) {
            near_[count] = std::uint32_t(n);
            near_d2_[count] = block_d2[n - n0];
            count += std::size_t(block_near[n - n0] & 1);
        }
    }
    return count;
}

// SesHostField::distance's steps on the kept copies: the balls holding p in the same order of
// bins (the deepest is the first of the greatest depth, the tie whether two share it), the same
// face test and the same arcs in the same order.
FDMSURF_AVX2_CLONES
double SesHostField::Cursor::distance(const double p[3], double d_max, double* gradient) {
    const SesHostField& h = field_;
    const SesFeatures& f = h.f_;
    if (!(d_max <= h.reach_)) return ses_distance(f, p, d_max, gradient, false);
    const float* s = f.spheres.data();
    // The bins of the last point serve p when it lies well inside the points that have them
    // (the next Newton step, the next vertex of the bin): no divisions.
    const bool same_bins = p[0] > inner_lo_[0] && p[0] < inner_hi_[0] && p[1] > inner_lo_[1] &&
                           p[1] < inner_hi_[1] && p[2] > inner_lo_[2] && p[2] < inner_hi_[2];
    if (!same_bins) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = bin_cell(f, a, p[a] - f.r_max);
            hi[a] = bin_cell(f, a, p[a] + f.r_max);
            bin_[a] = bin_cell(f, a, p[a]);
        }
        if (lo[0] != lo_[0] || lo[1] != lo_[1] || lo[2] != lo_[2] || hi[0] != hi_[0] ||
            hi[1] != hi_[1] || hi[2] != hi_[2])
            gather_balls(lo, hi);
        const double r_max = f.r_max, margin = h.bin_margin_;
        for (int a = 0; a < 3; ++a) {
            inner_lo_[a] = -std::numeric_limits<double>::infinity();
            inner_hi_[a] = std::numeric_limits<double>::infinity();
            narrow_to_cell(f, a, lo[a], -r_max, margin, inner_lo_[a], inner_hi_[a]);
            narrow_to_cell(f, a, hi[a], r_max, margin, inner_lo_[a], inner_hi_[a]);
            narrow_to_cell(f, a, bin_[a], 0.0, margin, inner_lo_[a], inner_hi_[a]);
        }
    }
    // Every kept ball's depth, without a branch, then the greatest (four running maxima: max is
    // exact, so their order does not matter) and the first ball of it: the loop's deepest, in
    // the order of the bins. The loop's tie is whether a second ball has that depth (a deeper
    // one clears it, an equal one sets it): any other ball holding p at the greatest depth.
    const std::size_t balls = ball_index_.size();
    double* depth = ball_depth_.data();
    depth_at(ball_x_.data(), ball_y_.data(), ball_z_.data(), ball_r_.data(), p[0], p[1], p[2],
             balls, depth);
    constexpr double kNone = -std::numeric_limits<double>::infinity();
    double most[4] = {kNone, kNone, kNone, kNone};
    std::size_t j = 0;
    for (; j + 4 <= balls; j += 4)
        for (int k = 0; k < 4; ++k) most[k] = depth[j + k] > most[k] ? depth[j + k] : most[k];
    for (; j < balls; ++j) most[0] = depth[j] > most[0] ? depth[j] : most[0];
    const double lb = std::max(std::max(most[0], most[1]), std::max(most[2], most[3]));
    if (!(lb > 0.0)) return ses_distance(f, p, d_max, gradient, false);
    std::uint32_t deepest = 0;
    bool tie = false;
    for (j = 0; j < balls; ++j)
        if (depth[j] == lb) {
            deepest = ball_index_[j];
            break;
        }
    for (++j; j < balls; ++j)
        if (depth[j] == lb) {
            tie = true;
            break;
        }
    if (tie) return ses_distance(f, p, d_max, gradient, false);
    if (lb >= d_max) {
        set_gradient(gradient, 0, 0, 0);
        return d_max;
    }
    {
        double q[3];
        face_point(s, deepest, p, q);
        // The neighbour that buried this ball's face last, first: one of its neighbours, so
        // the answer is the loop's.
        bool buried = deepest == burier_of_ && inside_sphere(s, burier_, q);
        for (std::uint32_t n = f.neighbour_start[deepest];
             n < f.neighbour_start[deepest + 1] && !buried; ++n) {
            buried = inside_sphere(s, f.neighbours[n], q);
            if (buried) burier_of_ = deepest, burier_ = f.neighbours[n];
        }
        if (!buried) {
            gradient_from(p, q, gradient);
            return lb;
        }
    }
    const std::size_t b = (std::size_t(bin_[2]) * f.dims[1] + bin_[1]) * f.dims[0] + bin_[0];
    if (b != arc_bin_) gather_arcs(b);
    double best = d_max;
    std::size_t best_at = nearest_arc(p, d_max, best);
    if (best_at == kNoArc && !settled_) {
        // distance()'s rule: each arc in order against the bound so far.
        const std::size_t count = near_arcs(p, d_max);
        for (std::size_t n = 0; n < count; ++n) {
            const double r = arc_r_[near_[n]] + best;
            if (near_d2_[n] >= r * r) continue;
            const std::uint32_t k = arc_index_[near_[n]];
            const double d = h.arc_view(k).distance(p, best);
            if (d < best) best = d, best_at = near_[n];
        }
    }
    if (best_at == kNoArc) return arcs_result(nullptr, best, p, gradient);
    last_arc_ = arc_index_[best_at], last_at_ = best_at;
    const ArcView best_arc = h.arc_view(last_arc_);
    return arcs_result(&best_arc, best, p, gradient);
}

// One task of evaluate: planes [za, zb) of the call's planes, on the call's grid, with the
// task's scratch, in the three steps of ses_distance_host.hpp: depths, deepest_faces (the count
// of points left waiting for the arcs), arcs.
struct SesHostField::Slab {
    const SesHostField& field;
    const EvalGrid& grid;
    const std::uint32_t za, zb;
    Scratch& scratch;
    const std::size_t points;  // in the slab
    const std::size_t words;   // of waiting bits per row

    Slab(const SesHostField& field_in, const EvalGrid& grid_in, std::uint32_t za_in,
         std::uint32_t zb_in, Scratch& scratch_in)
        : field(field_in),
          grid(grid_in),
          za(za_in),
          zb(zb_in),
          scratch(scratch_in),
          points(std::size_t(grid_in.nx) * grid_in.ny * (zb_in - za_in)),
          words((std::size_t(grid_in.nx) + 63) / 64) {}

    // The first value of row (z, y) in the slab's per-point scratch.
    std::size_t at(std::uint32_t z, int y) const {
        return (std::size_t(z - za) * grid.ny + y) * grid.nx;
    }
    float* row_out(std::uint32_t z, int y) const {
        return grid.out + (std::size_t(z - grid.z_begin) * grid.ny + y) * grid.pitch;
    }
    std::uint64_t* bits_of(std::uint32_t z, int y) const {
        return &scratch.waiting_bits[(std::size_t(z - za) * grid.ny + y) * words];
    }

    // 1. Depths.
    FDMSURF_AVX2_CLONES void depths() const {
        const std::vector<float>& xs = grid.xs;
        const std::vector<float>& ys = grid.ys;
        const std::vector<float>& zs = grid.zs;
        const int nx = grid.nx, ny = grid.ny;
        const float h = grid.h, reach_out = grid.reach_out;
        const float* s = field.f_.spheres.data();
        std::vector<float>& lb = scratch.lb;
        std::vector<std::uint32_t>& deepest = scratch.deepest;
        std::vector<std::uint32_t>& tie = scratch.tie;
        lb.resize(points);
        deepest.resize(points);
        tie.resize(points);
        std::vector<std::uint8_t>& reached = scratch.row_reached;
        reached.assign(std::size_t(ny) * (zb - za), 0);
        // The balls whose centres can lie within r_max + reach_out of the planes: those of the
        // planes of bins there, consecutive in the features' order (the planes' rows below skip
        // the balls that do not reach them; a point's deepest ball and its ties do not depend
        // on the order the balls come in).
        const float reach = field.f_.r_max + reach_out;
        const auto [ball0, ball1] = field.in_planes_of_bins(
            double(zs[za]) - reach, double(zs[zb - 1]) + reach, field.f_.sphere_start);
        for (std::uint32_t i = ball0; i < ball1; ++i) {
            const float cx = s[4 * i], cy = s[4 * i + 1], cz = s[4 * i + 2], R = s[4 * i + 3];
            const float Rr = R + reach_out, Rr2 = Rr * Rr;
            // Each row that meets the ball takes the ball's whole x range, not its chord (the
            // chord's square root and two divisions cost more than the points they cut). The
            // chord's range was a spacing or more wider than the ball on each side, so a point
            // it left out lies farther than Rr from the centre by h^2 / (2 Rr + h) or more: its
            // depth is below -reach_out, whose value is d_min, as with no ball, and below any
            // positive depth, so the deepest and the ties of the points above 0 are the same.
            const int bx0 = first_at_or_above(cx - Rr, xs[0], h, nx);
            const int bx1 = last_at_or_below(cx + Rr, xs[0], h, nx);
            for (std::uint32_t z = za; z < zb; ++z) {
                const float dz = zs[z] - cz;
                if (dz * dz >= Rr2) continue;
                const double half_y = std::sqrt(double(Rr2 - dz * dz));
                const int y0 = first_at_or_above(cy - half_y, ys[0], h, ny);
                const int y1 = last_at_or_below(cy + half_y, ys[0], h, ny);
                for (int y = y0; y <= y1; ++y) {
                    const float dy = ys[y] - cy;
                    const float dyz = dy * dy + dz * dz;
                    if (dyz >= Rr2) continue;
                    const std::size_t row = at(z, y);
                    std::uint8_t& first_ball = reached[std::size_t(z - za) * ny + y];
                    // The row's depths from -infinity; its ties are not filled: a point's
                    // first ball sets its tie (deeper than -infinity, not equal), and only the
                    // points that a ball reached read theirs.
                    if (!first_ball) {
                        first_ball = 1;
                        std::fill_n(&lb[row], nx, -std::numeric_limits<float>::infinity());
                    }
                    float* l = &lb[row];
                    std::uint32_t* deep = &deepest[row];
                    std::uint32_t* t = &tie[row];
                    depth_row(xs.data(), cx, R, dyz, i, bx0, bx1, l, deep, t);
                }
            }
        }
    }

    // 2. The deepest face. The points waiting for the arcs, a bit each, rows of whole words
    // (the arcs visit only these); returns their count.
    FDMSURF_AVX2_CLONES std::size_t deepest_faces() const {
        const std::vector<float>& xs = grid.xs;
        const std::vector<float>& ys = grid.ys;
        const std::vector<float>& zs = grid.zs;
        const int nx = grid.nx, ny = grid.ny;
        const float d_min = grid.d_min, d_max = grid.d_max;
        const SesFeatures& f = field.f_;
        const float* s = f.spheres.data();
        const std::vector<float>& lb = scratch.lb;
        const std::vector<std::uint32_t>& deepest = scratch.deepest;
        const std::vector<std::uint32_t>& tie = scratch.tie;
        const std::vector<std::uint8_t>& reached = scratch.row_reached;
        std::vector<float>& arc_best = scratch.arc_best;
        arc_best.resize(points);
        scratch.waiting_bits.assign(words * ny * (zb - za), 0);
        std::size_t waiting = 0;
        std::uint32_t last_burier = std::numeric_limits<std::uint32_t>::max();
        auto buried = [&](float qx, float qy, float qz, std::uint32_t self) {
            auto inside = [&](std::uint32_t k) {
                const float wx = qx - s[4 * k], wy = qy - s[4 * k + 1], wz = qz - s[4 * k + 2];
                return wx * wx + wy * wy + wz * wz < s[4 * k + 3] * s[4 * k + 3];
            };
            if (last_burier != std::numeric_limits<std::uint32_t>::max() && last_burier != self &&
                inside(last_burier))
                return true;
            for (std::uint32_t q = f.neighbour_start[self]; q < f.neighbour_start[self + 1]; ++q) {
                const std::uint32_t k = f.neighbours[q];
                if (inside(k)) {
                    last_burier = k;
                    return true;
                }
            }
            return false;
        };
        for (std::uint32_t z = za; z < zb; ++z)
            for (int y = 0; y < ny; ++y) {
                const std::size_t row = at(z, y);
                float* o = row_out(z, y);
                if (!reached[std::size_t(z - za) * ny + y]) {
                    std::fill_n(o, nx, d_min);  // lb = -infinity
                    continue;
                }
                const std::size_t waiting_before = waiting;
                for (int x = 0; x < nx; ++x) {
                    const float l = lb[row + x];
                    if (!(l > 0.0f)) {
                        o[x] = std::max(l, d_min);
                    } else if (l >= d_max) {
                        o[x] = d_max;
                    } else if (tie[row + x]) {
                        const double p[3] = {xs[x], ys[y], zs[z]};
                        o[x] = std::max(
                            static_cast<float>(ses_distance(f, p, d_max, nullptr, false)), d_min);
                    } else {
                        const std::uint32_t i = deepest[row + x];
                        const float cx = s[4 * i], cy = s[4 * i + 1], cz = s[4 * i + 2],
                                    R = s[4 * i + 3];
                        const float vx = xs[x] - cx, vy = ys[y] - cy, vz = zs[z] - cz;
                        const float len = std::sqrt(vx * vx + vy * vy + vz * vz);
                        float qx = cx + R, qy = cy, qz = cz;  // the shader's choice at the centre
                        if (len > 1e-6f) {
                            const float k = R / len;
                            qx = cx + k * vx, qy = cy + k * vy, qz = cz + k * vz;
                        }
                        if (!buried(qx, qy, qz, i)) {
                            o[x] = std::max(l, d_min);
                        } else {
                            o[x] = d_max;
                            bits_of(z, y)[x >> 6] |= std::uint64_t(1) << (x & 63);
                            ++waiting;
                        }
                    }
                }
                // The arcs lower the waiting points' rows from d_max (the others' not read).
                if (waiting != waiting_before) std::fill_n(&arc_best[row], nx, d_max);
            }
        return waiting;
    }

    // 3. Arcs, over the rows of waiting points within d_max of them: each row range in float
    // without a branch (vectorised), into `arc_best` (a value per point, read for the waiting
    // ones only); then the waiting points' values out.
    FDMSURF_AVX2_CLONES void arcs() const {
        const std::vector<float>& xs = grid.xs;
        const std::vector<float>& ys = grid.ys;
        const std::vector<float>& zs = grid.zs;
        const int nx = grid.nx, ny = grid.ny;
        const float h = grid.h, d_min = grid.d_min, d_max = grid.d_max;
        std::vector<float>& arc_best = scratch.arc_best;  // d_max in the waiting points' rows
        const float zlo = zs[za] - d_max, zhi = zs[zb - 1] + d_max;
        // The arcs whose circles' centres can lie within rho_max of [zlo, zhi] (an arc's box
        // lies within rho of its centre, widened by 1e-4 Å): those of the planes of bins there,
        // consecutive in the features' order, read in it (a point's least distance does not
        // depend on the order the arcs come in).
        const double rho = double(field.f_.rho_max) + 1e-3;
        const auto [k0, k1] = field.in_planes_of_bins(double(zlo) - rho, double(zhi) + rho,
                                                      field.f_.arc_start);
        for (std::uint32_t k = k0; k < k1; ++k) {
            const Box& box = field.arc_box_[k];
            if (box.hi[2] < zlo || box.lo[2] > zhi) continue;
            const std::array<double, 4>& ball = field.arc_ball_[k];
            // The kernel's float copy, made at the first row that needs it (most arcs have no
            // waiting point in their box).
            std::optional<FloatArc> arc;
            const double reach = ball[3] + d_max, reach2 = reach * reach;
            const int x0 = first_at_or_above(box.lo[0] - d_max, xs[0], h, nx);
            const int x1 = last_at_or_below(box.hi[0] + d_max, xs[0], h, nx);
            const int y0 = first_at_or_above(box.lo[1] - d_max, ys[0], h, ny);
            const int y1 = last_at_or_below(box.hi[1] + d_max, ys[0], h, ny);
            if (x0 > x1 || y0 > y1) continue;
            // The box's words of each row's waiting bits, the first and last masked to it.
            const int w0 = x0 >> 6, w1 = x1 >> 6;
            const std::uint64_t first_mask = ~std::uint64_t(0) << (x0 & 63);
            const std::uint64_t last_mask = ~std::uint64_t(0) >> (63 - (x1 & 63));
            for (std::uint32_t z = za; z < zb; ++z) {
                if (zs[z] < box.lo[2] - d_max || zs[z] > box.hi[2] + d_max) continue;
                const double dz = zs[z] - ball[2];
                // The plane's rows that meet the ball: rem below is at most reach2 - dz * dz
                // (rounding is monotonic), so none past the plane's chord (and its margin).
                const double rem_z = reach2 - dz * dz;
                if (rem_z <= 0.0) continue;
                const double half_y = std::sqrt(rem_z);
                const int ya = std::max(y0, first_at_or_above(ball[1] - half_y, ys[0], h, ny));
                const int yb = std::min(y1, last_at_or_below(ball[1] + half_y, ys[0], h, ny));
                for (int y = ya; y <= yb; ++y) {
                    // A row that does not meet the ball is left out (its points can lie within
                    // the float kernel's error of reach): tested first, two products (on the
                    // 12-copy shell at 1 Å two rows in five that hold waiting points fail it).
                    const double dy = ys[y] - ball[1];
                    const double rem = reach2 - dy * dy - dz * dz;
                    if (rem <= 0.0) continue;
                    // The first and last point waiting in the box's range, before the kernel.
                    const std::uint64_t* bits = bits_of(z, y);
                    int wa = -1, wb = -1;
                    for (int word = w0; word <= w1; ++word) {
                        std::uint64_t w = bits[word];
                        if (word == w0) w &= first_mask;
                        if (word == w1) w &= last_mask;
                        if (w == 0) continue;
                        if (wa < 0) wa = word * 64 + std::countr_zero(w);
                        wb = word * 64 + 63 - std::countl_zero(w);
                    }
                    if (wa < 0) continue;
                    // A row that meets the ball: the kernel on that whole span, without the
                    // ball's chord (its square root and two divisions cost more than the points
                    // they cut, on 1AON). The chord's range was a spacing or more wider than
                    // the ball on each side, so a point it left out is farther from the ball's
                    // centre than reach by h^2 / (2 reach + h) or more (0.02 Å at 0.5 Å), and
                    // as much farther than d_max from the arc: far above the float kernel's
                    // error (1e-4 Å), it keeps its value.
                    if (!arc) arc.emplace(field.arc_view(k));
                    arc_row(*arc, xs.data(), ys[y], zs[z], wa, wb, &arc_best[at(z, y)]);
                }
            }
        }
        for (std::uint32_t z = za; z < zb; ++z)
            for (int y = 0; y < ny; ++y) {
                float* o = row_out(z, y);
                const std::uint64_t* bits = bits_of(z, y);
                const float* best = &arc_best[at(z, y)];
                for (std::size_t word = 0; word < words; ++word)
                    for (std::uint64_t w = bits[word]; w != 0; w &= w - 1) {
                        const std::size_t x = word * 64 + std::countr_zero(w);
                        o[x] = std::max(best[x], d_min);
                    }
            }
    }
};

std::pair<std::uint32_t, std::uint32_t> SesHostField::in_planes_of_bins(
    double z_lo, double z_hi, const std::vector<std::uint32_t>& start) const {
    // Widened by bin_margin_ (1e-3 Å and a millionth of the coordinates' size): the callers'
    // reaches come from float values (the grid's planes, the arcs' boxes, widened by 1e-4 Å),
    // whose rounding grows with the coordinates.
    const std::size_t plane = std::size_t(f_.dims[0]) * f_.dims[1];
    const int b0 = bin_cell(f_, 2, z_lo - bin_margin_), b1 = bin_cell(f_, 2, z_hi + bin_margin_);
    return {start[std::size_t(b0) * plane], start[std::size_t(b1 + 1) * plane]};
}

void SesHostField::evaluate(const GridPlan& plan, std::uint32_t z_begin, std::uint32_t z_end,
                            float* out, std::size_t pitch) const {
    const auto& dims = plan.info.dims;
    if (!plan.exact_ses || z_begin >= z_end || z_end > dims[2] || pitch < dims[0])
        throw Error(ErrorCode::InvalidArgument,
                    "host SES field: planes [" + std::to_string(z_begin) + ", " +
                        std::to_string(z_end) + ") of a grid of " + std::to_string(dims[2]) +
                        " planes, pitch " + std::to_string(pitch) + " for rows of " +
                        std::to_string(dims[0]) + " points");
    const EvalGrid grid(plan, z_begin, out, pitch);
    // Tasks of at most kChunkPlanes planes, as many for each thread: a slab of 52 planes (the
    // engine's on the 2.4 M-atom shell at 1 Å: 15 of 774) in 13 tasks of 4 left one of two
    // threads idle for the last; in 14 of 3 or 4 they finish about together.
    const std::uint64_t planes = z_end - z_begin;
    std::uint64_t chunks = (planes + kChunkPlanes - 1) / kChunkPlanes;
    chunks = std::min<std::uint64_t>(planes, (chunks + threads_ - 1) / threads_ * threads_);
    parallel_chunks(chunks, threads_, [&](std::size_t chunk) {
        const ScratchPool::Lease lease(*scratch_);
        const std::uint32_t za = z_begin + std::uint32_t(planes * chunk / chunks);
        const std::uint32_t zb = z_begin + std::uint32_t(planes * (chunk + 1) / chunks);
        const Slab slab(*this, grid, za, zb, *lease.scratch);
        slab.depths();
        if (slab.deepest_faces() == 0) return;
        slab.arcs();
    });
}

void SesHostField::release_scratch() const {
    const std::lock_guard<std::mutex> lock(scratch_->mutex);
    scratch_->free.clear();
}

std::vector<float> SesHostField::field(const GridPlan& plan) const {
    std::vector<float> out(plan.field_floats(), 0.0f);
    evaluate(plan, 0, plan.info.dims[2], out.data(), plan.pitch);
    return out;
}

}  // namespace fdmsurf::detail
