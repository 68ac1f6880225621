#include "areas/power_cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fdmsurf::detail {
namespace {

// The box round the unit ball: its faces touch the sphere at one point each, so none of them can
// shape its exposed part. The tighter the box, the sooner the planes cut its corners away.
constexpr double kBox = 1.0;
// Vertex v of the box is at (±kBox, ±kBox, ±kBox), bit 0 the sign of x, bit 1 of y, bit 2 of
// z; each face's corners counter-clockwise seen from outside.
constexpr std::uint16_t kBoxFaces[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3},
                                           {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
// A plane whose farthest vertex is at most this far inside P is kept without clipping: it
// touches P within rounding.
constexpr double kTouch = 1e-10;
// How far outside the unit ball (in squared radius) a face may be and still count as meeting
// it: rounding of the cell's vertices.
constexpr double kReach = 1e-9;

// The most corners a face may have (a face of a protein atom's cell has a handful); a face that
// would have more gives up the filter.
constexpr std::size_t kCorners = 30;
// A vertex cut away: NaN, which the distance loop counts neither in nor out.
const double kGone = std::numeric_limits<double>::quiet_NaN();

// Each vertex's signed distance beyond the plane; how many are beyond it and how many within
// kTouch of it or beyond. Counts rather than a maximum, and in doubles (exact below 2^53), so
// that the loop vectorises (with -fno-trapping-math, set in CMakeLists.txt); NaN counts as
// neither.
struct Sides {
    double outside, near;
};
Sides signed_distances(const double* __restrict x, const double* __restrict y,
                       const double* __restrict z, std::size_t count, const CellPlane& plane,
                       double* __restrict dist) {
    const double ux = plane.u[0], uy = plane.u[1], uz = plane.u[2], h = plane.h;
    double outside = 0.0, near = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
        const double d = ux * x[v] + uy * y[v] + uz * z[v] - h;
        dist[v] = d;
        outside += d > 0.0 ? 1.0 : 0.0;
        near += d > -kTouch ? 1.0 : 0.0;
    }
    return {outside, near};
}

}  // namespace

void PowerCell::reset() {
    x_.clear();
    y_.clear();
    z_.clear();
    vertex_faces_.clear();
    for (int v = 0; v < 8; ++v) {
        x_.push_back(v & 1 ? kBox : -kBox);
        y_.push_back(v & 2 ? kBox : -kBox);
        z_.push_back(v & 4 ? kBox : -kBox);
        // The faces of kBoxFaces that hold it.
        vertex_faces_.push_back({std::uint16_t(v & 1 ? 0 : 1), std::uint16_t(v & 2 ? 2 : 3),
                                 std::uint16_t(v & 4 ? 4 : 5)});
    }
    live_ = 8;
    beyond_ = 8;
    free_.clear();
    edges_made_.assign(8, 0);
    edge_from_.resize(24);
    face_plane_.assign(6, -1);
    face_size_.assign(6, 4);
    corners_.resize(6 * kCorners);
    for (std::size_t f = 0; f < 6; ++f)
        std::copy(kBoxFaces[f], kBoxFaces[f] + 4, corners_.begin() + std::ptrdiff_t(f * kCorners));
    face_mark_.assign(6, 0);
}

// The polyhedron is simple: each vertex is on three faces (the box's are, and a clip makes each
// new vertex on an edge's two faces and the new one), so the faces a clip cuts are those of the
// vertices it cuts away, and only they are rewritten. Faces keep their places, each in a run of
// kCorners corners; a vertex cut away becomes NaN and its place is reused.
PowerCell::Clip PowerCell::clip(const CellPlane& plane, std::int32_t id) {
    const std::size_t nv = x_.size();
    dist_.resize(nv);
    double* dist = dist_.data();
    const auto [outside, near] = signed_distances(x_.data(), y_.data(), z_.data(), nv, plane, dist);
    if (outside == 0.0) return near > 0.0 ? Clip::Touched : Clip::Missed;
    if (outside == double(live_)) return Clip::Emptied;

    // The faces to rewrite: those of the vertices cut away.
    const std::size_t faces = face_plane_.size();
    cut_faces_.clear();
    gone_.resize(nv);
    std::size_t gone = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        gone_[gone] = std::uint16_t(v);
        gone += dist[v] > 0.0;
    }
    for (std::size_t g = 0; g < gone; ++g) {
        edges_made_[gone_[g]] = 0;
        for (const std::uint16_t f : vertex_faces_[gone_[g]])
            if (!face_mark_[f]) {
                face_mark_[f] = 1;
                cut_faces_.push_back(f);
            }
    }
    link_.clear();
    made_.clear();
    std::size_t reused = 0;  // places in free_ (cut away before this clip) taken
    std::uint16_t cut[2 * kCorners];
    for (const std::uint16_t f : cut_faces_) {
        face_mark_[f] = 0;
        const std::size_t n = face_size_[f];
        std::uint16_t* corner = corners_.data() + std::size_t(f) * kCorners;
        std::size_t written = 0;
        std::int64_t leaves = -1, enters = -1;
        int runs = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t a = corner[i], b = corner[i + 1 < n ? i + 1 : 0];
            const bool a_in = !(dist[a] > 0.0), b_in = !(dist[b] > 0.0);
            if (a_in) cut[written++] = std::uint16_t(a);
            if (a_in == b_in) continue;
            // Where edge (in, out) crosses the plane: made once, for the edge's two faces.
            const std::uint32_t in = a_in ? a : b, out = a_in ? b : a;
            // The edges made from `out` so far (it has three): new vertex k of edge (in, out).
            const std::size_t made_from_out = edges_made_[out];
            std::size_t k = made_.size();
            for (std::size_t e = 0; e < made_from_out; ++e)
                if (edge_from_[3 * out + e].in == in) k = edge_from_[3 * out + e].k;
            if (k == made_.size()) {
                // dist[in] <= 0 < dist[out], so t is in [0, 1).
                const double t = dist[in] / (dist[in] - dist[out]);
                const double px = x_[in] + t * (x_[out] - x_[in]);
                const double py = y_[in] + t * (y_[out] - y_[in]);
                const double pz = z_[in] + t * (z_[out] - z_[in]);
                beyond_ += !(px * px + py * py + pz * pz < 1.0 - kReach);
                std::uint16_t place;
                if (reused < free_.size()) {
                    place = free_[free_.size() - 1 - reused++];
                    x_[place] = px;
                    y_[place] = py;
                    z_[place] = pz;
                } else {
                    if (x_.size() >= 0xffff) return Clip::Broken;
                    place = std::uint16_t(x_.size());
                    x_.push_back(px);
                    y_.push_back(py);
                    z_.push_back(pz);
                    vertex_faces_.push_back({});
                    edges_made_.push_back(0);
                    edge_from_.resize(edge_from_.size() + 3);
                }
                vertex_faces_[place] = {f, f, std::uint16_t(faces)};
                if (made_from_out == 3) return Clip::Broken;
                edge_from_[3 * out + made_from_out] = {std::uint16_t(in), std::uint16_t(k)};
                edges_made_[out] = std::uint8_t(made_from_out + 1);
                link_.push_back(-1);
                made_.push_back(place);
            } else {
                vertex_faces_[made_[k]][1] = f;  // the edge's other face
            }
            cut[written++] = made_[k];
            if (a_in) {
                leaves = std::int64_t(k);
                ++runs;
            } else {
                enters = std::int64_t(k);
            }
        }
        face_size_[f] = std::uint8_t(written);
        if (written == 0) continue;  // wholly cut away
        // A convex face loses one run of corners; more is rounding's doing.
        if (runs > 1 || written < 3 || written > kCorners) return Clip::Broken;
        std::copy(cut, cut + written, corner);
        // The face runs ... → leaves → enters → ... along the new edge; the new face, seen from
        // its own outside, runs that edge the other way: from `enters` on to `leaves`.
        if (runs == 1) link_[std::size_t(enters)] = std::int32_t(leaves);
    }
    // The new face: the new vertices, one cycle.
    const std::size_t count = link_.size();
    if (count < 3 || count > kCorners || faces >= 0xffff) return Clip::Broken;
    face_plane_.push_back(id);
    face_size_.push_back(std::uint8_t(count));
    face_mark_.push_back(0);
    corners_.resize(corners_.size() + kCorners);
    std::uint16_t* corner = corners_.data() + faces * kCorners;
    std::size_t k = 0;
    for (std::size_t step = 0; step < count; ++step) {
        corner[step] = made_[k];
        if (link_[k] < 0) return Clip::Broken;
        k = std::size_t(link_[k]);
        if (k == 0 && step + 1 < count) return Clip::Broken;
    }
    if (k != 0) return Clip::Broken;
    free_.resize(free_.size() - reused);
    for (std::size_t g = 0; g < gone; ++g) {
        const std::uint16_t v = gone_[g];
        beyond_ -= !(x_[v] * x_[v] + y_[v] * y_[v] + z_[v] * z_[v] < 1.0 - kReach);
        x_[v] = y_[v] = z_[v] = kGone;
        free_.push_back(v);
    }
    live_ = live_ + count - gone;
    // P inside the open ball: the sphere misses it, and every later clip leaves it inside.
    if (beyond_ == 0) return Clip::Emptied;
    return Clip::Cut;
}

CellVerdict PowerCell::filter(const std::vector<CellPlane>& planes,
                              const std::vector<std::uint32_t>& order,
                              std::vector<std::uint32_t>& keep) {
    reset();
    touched_.assign(planes.size(), 0);
    for (const std::uint32_t p : order) {
        const Clip result = clip(planes[p], std::int32_t(p));
        if (result == Clip::Emptied) return CellVerdict::Buried;
        if (result == Clip::Broken) return CellVerdict::Unknown;
        if (result == Clip::Touched) touched_[p] = 1;
    }
    // P inside the open ball: the sphere misses it.
    bool inside = true;
    for (std::size_t v = 0; v < x_.size(); ++v)
        inside = inside && !(x_[v] * x_[v] + y_[v] * y_[v] + z_[v] * z_[v] >= 1.0 - kReach);
    if (inside) return CellVerdict::Buried;
    // The faces that meet the ball are kept; so is a plane that touched P within rounding, face
    // or not.
    std::vector<std::uint8_t>& wanted = touched_;
    bool any = false;
    const std::size_t faces = face_plane_.size();
    for (std::size_t f = 0; f < faces; ++f) {
        const std::int32_t id = face_plane_[f];
        if (id < 0) continue;
        const std::uint16_t* corner = corners_.data() + f * kCorners;
        const std::size_t n = face_size_[f];
        const Vec3 u = planes[std::size_t(id)].u;
        const double h = planes[std::size_t(id)].h;
        bool meets = false, holds_centre = n > 0;
        for (std::size_t i = 0; i < n && !meets; ++i) {
            const std::uint32_t a = corner[i], b = corner[i + 1 < n ? i + 1 : 0];
            const Vec3 pa{x_[a], y_[a], z_[a]}, ab{x_[b] - x_[a], y_[b] - y_[a], z_[b] - z_[a]};
            // The edge's point nearest the centre.
            const double len2 = dot(ab, ab);
            const double t = len2 > 0.0 ? std::clamp(-dot(pa, ab) / len2, 0.0, 1.0) : 0.0;
            const Vec3 q = add(pa, scale(ab, t));
            meets = dot(q, q) <= 1.0 + kReach;
            // The circle's centre h u on the inner side of the edge (the face is convex).
            const Vec3 to_centre = sub(scale(u, h), pa);
            holds_centre = holds_centre && dot(cross(ab, to_centre), u) >= -kReach;
        }
        if (meets || holds_centre) {
            wanted[std::size_t(id)] = 1;
            any = true;
        }
    }
    // No face in the ball: the ball is wholly inside P or wholly outside, and each plane cuts
    // it (a cap is a proper part of the sphere), so outside.
    if (!any) return CellVerdict::Buried;
    keep.clear();
    for (std::size_t p = 0; p < planes.size(); ++p)
        if (wanted[p]) keep.push_back(std::uint32_t(p));
    return CellVerdict::Filtered;
}

}  // namespace fdmsurf::detail
