// PowerCell: a ball's power cell clipped plane by plane, and the caps and edges it keeps.
#include "base/power_cell.hpp"

#include "base/cpu_features.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fdmsurf::detail {
namespace {

// The box round the unit ball: its faces touch the sphere at one point each, so none of them can
// shape its exposed part. The tighter the box, the sooner the planes cut its corners away.
constexpr double kBox = 1.0;
// A plane whose farthest vertex is at most this far inside P is kept without clipping: it
// touches P within rounding.
constexpr double kTouch = 1e-10;
// How far outside the unit ball (in squared radius) a face may be and still count as meeting
// it: rounding of the cell's vertices.
constexpr double kReach = 1e-9;
// How far beyond a plane a circle's centre may be and still count as on its inner side.
constexpr double kBeyond = 1e-9;

// A vertex cut away: NaN, which the distance loop counts neither in nor out.
const double kGone = std::numeric_limits<double>::quiet_NaN();

// Each vertex's signed distance beyond the plane; how many are beyond it and how many within
// kTouch of it or beyond. Counts rather than a maximum, and in doubles (exact below 2^53), so
// that the loop vectorises (with -fno-trapping-math and -fopenmp-simd, set in CMakeLists.txt);
// NaN counts as neither.
struct Sides {
    double outside, near;
};
Sides signed_distances(const double* __restrict x, const double* __restrict y,
                       const double* __restrict z, std::size_t count, const CellPlane& plane,
                       double* __restrict dist) {
    const double ux = plane.u[0], uy = plane.u[1], uz = plane.u[2], h = plane.h;
    double outside = 0.0, near = 0.0;
    // The sums of 0s and 1s are exact in any order: let them be vectorised (-fopenmp-simd).
#pragma omp simd reduction(+ : outside, near)
    for (std::size_t v = 0; v < count; ++v) {
        const double d = ux * x[v] + uy * y[v] + uz * z[v] - h;
        dist[v] = d;
        outside += d > 0.0 ? 1.0 : 0.0;
        near += d > -kTouch ? 1.0 : 0.0;
    }
    return {outside, near};
}

bool beyond_ball(double x, double y, double z) { return !(x * x + y * y + z * z < 1.0 - kReach); }

}  // namespace

void order_largest_first(const std::vector<CellPlane>& planes, std::vector<std::uint32_t>& order) {
    constexpr int kBins = 16;
    std::array<std::uint32_t, kBins + 1> first{};
    auto bin_of = [](double h) { return std::clamp(int((h + 1.0) * (0.5 * kBins)), 0, kBins - 1); };
    for (const CellPlane& p : planes) ++first[std::size_t(bin_of(p.h)) + 1];
    for (int b = 0; b < kBins; ++b) first[std::size_t(b) + 1] += first[std::size_t(b)];
    order.resize(planes.size());
    for (std::size_t p = 0; p < planes.size(); ++p)
        order[first[std::size_t(bin_of(planes[p].h))]++] = std::uint32_t(p);
}

void PowerCell::reset() {
    x_.clear();
    y_.clear();
    z_.clear();
    planes_.clear();
    next_.clear();
    // Vertex v at (±kBox, ±kBox, ±kBox), bit 0 the sign of x, bit 1 of y, bit 2 of z; the box's
    // planes x <= kBox, x >= -kBox, y <= kBox, ... are -6, -5, ..., -1. Leaving the x plane
    // flips bit 0.
    for (std::uint16_t v = 0; v < 8; ++v) {
        x_.push_back(v & 1 ? kBox : -kBox);
        y_.push_back(v & 2 ? kBox : -kBox);
        z_.push_back(v & 4 ? kBox : -kBox);
        planes_.push_back({v & 1 ? -6 : -5, v & 2 ? -4 : -3, v & 4 ? -2 : -1});
        next_.push_back({std::uint16_t(v ^ 1), std::uint16_t(v ^ 2), std::uint16_t(v ^ 4)});
    }
    live_ = 8;
    beyond_ = 8;
    free_.clear();
}

FDMSURF_AVX2_CLONES
PowerCell::Clip PowerCell::clip(const CellPlane& plane, std::int32_t id) {
    const std::size_t nv = x_.size();
    dist_.resize(nv);
    double* dist = dist_.data();
    const auto [outside, near] = signed_distances(x_.data(), y_.data(), z_.data(), nv, plane, dist);
    if (outside == 0.0) return near > 0.0 ? Clip::Touched : Clip::Missed;
    if (outside == double(live_)) return Clip::Emptied;

    gone_.resize(nv);
    std::size_t gone = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        gone_[gone] = std::uint16_t(v);
        gone += dist[v] > 0.0;
    }
    // A new vertex on each edge from a vertex cut away (v) to one kept (w), at the plane.
    std::size_t reused = 0, made = 0;  // places in free_ (cut away before this clip) taken
    waited_.clear();
    auto wait_or_join = [&](std::int32_t face, std::uint16_t n, std::uint32_t slot) {
        Waiting& entry = waiting_[std::size_t(face + kBoxPlanes)];
        if (entry.vertex == -1) {
            entry = {n, slot};
            waited_.push_back(face);
            return true;
        }
        if (entry.vertex < 0) return false;  // a third new vertex on one face
        next_[n][slot] = std::uint16_t(entry.vertex);
        next_[std::size_t(entry.vertex)][entry.slot] = n;
        entry.vertex = -2;
        return true;
    };
    for (std::size_t g = 0; g < gone; ++g) {
        const std::uint16_t v = gone_[g];
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint16_t w = next_[v][k];
            if (dist[w] > 0.0) continue;
            // dist[w] <= 0 < dist[v], so t is in [0, 1).
            const double t = dist[w] / (dist[w] - dist[v]);
            const double px = x_[w] + t * (x_[v] - x_[w]);
            const double py = y_[w] + t * (y_[v] - y_[w]);
            const double pz = z_[w] + t * (z_[v] - z_[w]);
            std::uint16_t n;
            if (reused < free_.size()) {
                n = free_[free_.size() - 1 - reused++];
                x_[n] = px;
                y_[n] = py;
                z_[n] = pz;
            } else {
                if (x_.size() >= 0xffff) return Clip::Broken;
                n = std::uint16_t(x_.size());
                x_.push_back(px);
                y_.push_back(py);
                z_.push_back(pz);
                planes_.push_back({});
                next_.push_back({});
            }
            ++made;
            beyond_ += beyond_ball(px, py, pz);
            // The edge v-w is on v's two planes other than its k-th: a and b. The new vertex is
            // on the cutting plane (slot 0, whose edge goes back to w), a and b.
            const std::int32_t a = planes_[v][(k + 1) % 3], b = planes_[v][(k + 2) % 3];
            planes_[n] = {id, a, b};
            next_[n][0] = w;
            // Selects, not branches: which slot of w leads back to v is anyone's guess.
            for (std::uint32_t s = 0; s < 3; ++s) next_[w][s] = next_[w][s] == v ? n : next_[w][s];
            // Leaving a (slot 1) runs along the new face and face b to the other new vertex on
            // b; leaving b (slot 2), to the other on a.
            if (!wait_or_join(b, n, 1) || !wait_or_join(a, n, 2)) return Clip::Broken;
        }
    }
    // Each cut face has exactly two new vertices.
    bool paired = true;
    for (const std::int32_t face : waited_) {
        paired = paired && waiting_[std::size_t(face + kBoxPlanes)].vertex == -2;
        waiting_[std::size_t(face + kBoxPlanes)].vertex = -1;
    }
    if (!paired || made < 3) return Clip::Broken;
    free_.resize(free_.size() - reused);
    for (std::size_t g = 0; g < gone; ++g) {
        const std::uint16_t v = gone_[g];
        beyond_ -= beyond_ball(x_[v], y_[v], z_[v]);
        x_[v] = y_[v] = z_[v] = kGone;
        free_.push_back(v);
    }
    live_ = live_ + made - gone;
    // P inside the open ball: the sphere misses it, and every later clip leaves it inside.
    if (beyond_ == 0) return Clip::Emptied;
    return Clip::Cut;
}

FDMSURF_AVX2_CLONES
CellVerdict PowerCell::filter(const std::vector<CellPlane>& planes,
                              const std::vector<std::uint32_t>& order,
                              std::vector<std::uint32_t>& keep) {
    reset();
    touched_.assign(planes.size(), 0);
    touched_any_ = false;
    edges_.clear();
    waiting_.assign(planes.size() + kBoxPlanes, {-1, 0});
    for (const std::uint32_t p : order) {
        const Clip result = clip(planes[p], std::int32_t(p));
        if (result == Clip::Emptied) return CellVerdict::Buried;
        if (result == Clip::Broken) return CellVerdict::Unknown;
        if (result == Clip::Touched) touched_[p] = 1;
        touched_any_ = touched_any_ || result == Clip::Touched;
    }
    // The faces that meet the ball are kept; so is a plane that touched P within rounding, face
    // or not. A face meets the ball where one of its edges does, or else when it holds the
    // centre of its circle (and so the whole disk).
    std::vector<std::uint8_t>& wanted = wanted_;
    wanted.assign(touched_.begin(), touched_.end());
    present_.assign(planes.size(), 0);
    in_ball_.assign(planes.size(), 1);
    bool any = false;
    constexpr double kLimit = 1.0 + kReach;
    dist_.resize(x_.size());  // each vertex's squared distance from the centre
    for (std::size_t v = 0; v < x_.size(); ++v)
        dist_[v] = x_[v] * x_[v] + y_[v] * y_[v] + z_[v] * z_[v];
    for (std::size_t v = 0; v < x_.size(); ++v) {
        if (std::isnan(x_[v])) continue;
        const bool vertex_inside = dist_[v] < 1.0 - kReach;  // as beyond_ball counts it
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::int32_t face = planes_[v][k];
            if (face >= 0) {
                present_[std::size_t(face)] = 1;
                in_ball_[std::size_t(face)] &= std::uint8_t(vertex_inside);
            }
            const std::uint16_t w = next_[v][k];
            if (w < v) continue;  // each edge once
            // The edge comes into the ball when an end does or, both ends outside, its point
            // nearest the centre does: v + t (w - v) with t = s / |w - v|² in (0, 1).
            if (!(dist_[v] <= kLimit || dist_[w] <= kLimit)) {
                const Vec3 pa{x_[v], y_[v], z_[v]}, ab{x_[w] - x_[v], y_[w] - y_[v], z_[w] - z_[v]};
                const double len2 = dot(ab, ab), s = -dot(pa, ab);
                if (!(s > 0.0 && s < len2 && dist_[v] * len2 - s * s <= kLimit * len2)) continue;
            }
            const std::int32_t a = planes_[v][(k + 1) % 3], b = planes_[v][(k + 2) % 3];
            // An edge with both ends inside the ball crosses no circle: only the others are
            // handed on.
            const bool inside = dist_[v] < 1.0 - kReach && dist_[w] < 1.0 - kReach;
            if (a >= 0 && b >= 0 && !inside) edges_.push_back({std::uint32_t(a), std::uint32_t(b)});
            for (const std::int32_t f : {a, b})
                if (f >= 0) {
                    wanted[std::size_t(f)] = 1;
                    any = true;
                }
        }
    }
    for (std::size_t j = 0; j < planes.size(); ++j) {
        if (!present_[j] || wanted[j]) continue;
        const Vec3 centre = scale(planes[j].u, planes[j].h);
        bool holds = true;
        for (std::size_t k = 0; k < planes.size() && holds; ++k)
            holds = k == j || !present_[k] || dot(planes[k].u, centre) <= planes[k].h + kBeyond;
        if (holds) {
            wanted[j] = 1;
            any = true;
        }
    }
    // Only a face of P counts: a plane never clipped (missed, or touched within rounding) has
    // no vertex to go by.
    for (std::size_t j = 0; j < planes.size(); ++j)
        in_ball_[j] &= std::uint8_t(present_[j] & !touched_[j]);
    // No face in the ball: the ball is wholly inside P or wholly outside, and each plane cuts
    // it (a cap is a proper part of the sphere), so outside.
    if (!any) return CellVerdict::Buried;
    keep.clear();
    for (std::size_t p = 0; p < planes.size(); ++p)
        if (wanted[p]) keep.push_back(std::uint32_t(p));
    return CellVerdict::Filtered;
}

}  // namespace fdmsurf::detail
