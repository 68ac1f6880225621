// The power cell of one ball among its neighbours, cut to what the exact areas and the exact
// SES's arcs need: which neighbours' caps can shape the exposed part of the ball's sphere.
//
// In the unit frame of ball i, neighbour j buries the cap {n : n·u_j > h_j} of the sphere; the
// plane n·u_j = h_j is the two balls' radical plane. The points that no neighbour buries are
// the sphere's points inside the convex polyhedron P = ∩_j {x : x·u_j <= h_j} (the power cell
// of ball i, Aurenhammer 1987). So a neighbour whose plane is not a face of P changes nothing
// (without it P is the same), and neither does one whose face lies outside the ball: were it
// dropped, P would grow across that face only, and a segment from a new point in the ball to
// a point of P in the ball would cross the face inside the ball. In a protein a ball has about
// 40 neighbours, of which a third or less meet those tests; and when P lies inside the ball,
// or misses it, the whole sphere is buried. The cell is built by clipping a box round the ball
// with each plane in turn, largest cap first (Voro++ builds Voronoi cells the same way).
//
// The polyhedron is kept as a graph of vertices, each on three planes with three neighbours (the
// box's are, and a clip keeps it so), as Voro++ does: a clip makes a vertex on each edge from a
// vertex it cuts away to one it keeps, and joins two new vertices when they share an old face,
// so its work is that of the corner it cuts off.
//
// Every test leans towards keeping a cap: a kept cap that could have been dropped costs time,
// never area. Whatever rounding makes of the polyhedron that is not a proper convex one (a face
// cut twice) gives up the filter, and every cap is kept.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace fdmsurf::detail {

// A plane x·u <= h of the unit ball's frame (a cap's, seen from the side it leaves exposed).
struct CellPlane {
    Vec3 u;
    double h;
};

enum class CellVerdict {
    Buried,    // no point of the sphere is in P: the area is 0
    Filtered,  // `keep` lists the planes that can shape the exposed part
    Unknown,   // rounding left no proper polyhedron: keep every plane
};

// The planes' indices, largest cap (least h) first, roughly, into `order`: so that the cell
// shrinks soonest. Sixteen bins of h (a counting sort) do as well as a full sort, for less.
void order_largest_first(const std::vector<CellPlane>& planes, std::vector<std::uint32_t>& order);

// Scratch space of one thread, reused from ball to ball.
class PowerCell {
public:
    // The planes in `planes` (at least one), taken in the order of `order`, a permutation of
    // their indices (largest cap first makes P shrink soonest). `keep` gets the indices (into
    // `planes`, increasing) of the planes to keep.
    CellVerdict filter(const std::vector<CellPlane>& planes,
                       const std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& keep);

    // After a Filtered verdict: whether a plane was kept for touching P within rounding (and so
    // never cut it), and the edges of P between two planes that come into the ball with an end
    // outside it (those that can cross the sphere), as the planes' indices.
    bool touched() const { return touched_any_; }
    const std::vector<std::array<std::uint32_t, 2>>& edges_in_ball() const { return edges_; }
    // After a Filtered verdict: whether plane p is a face of P whose every vertex is inside the
    // ball (by the margin of a Buried verdict). Its circle then has no point in P: each point of
    // it is beyond another face's plane, i.e. inside that neighbour's ball.
    bool face_in_ball(std::uint32_t p) const { return in_ball_[p] != 0; }

private:
    enum class Clip { Missed, Touched, Cut, Emptied, Broken };
    void reset();
    Clip clip(const CellPlane& plane, std::int32_t id);

    // Planes are numbered from 0 (the caller's) with the box's six before them, -6 to -1.
    static constexpr std::int32_t kBoxPlanes = 6;
    // Vertices: coordinates apart, for the distance loop (NaN once cut away, and the place
    // reused); per vertex its three planes and, in slot s, the neighbour along the edge that
    // leaves plane s (the edge on the other two planes).
    std::vector<double> x_, y_, z_;
    std::vector<std::array<std::int32_t, 3>> planes_;
    std::vector<std::array<std::uint16_t, 3>> next_;
    std::size_t live_ = 0;
    std::size_t beyond_ = 0;  // live vertices not inside the ball (by kReach)
    std::vector<std::uint16_t> free_;
    // Per clip: each vertex's signed distance; the vertices cut away; per plane (offset by
    // kBoxPlanes), the new vertex and slot waiting for the other new vertex on that plane's face.
    std::vector<double> dist_;
    std::vector<std::uint16_t> gone_;
    struct Waiting {
        std::int32_t vertex;  // -1: none; -2: the face has its two
        std::uint32_t slot;
    };
    std::vector<Waiting> waiting_;
    std::vector<std::int32_t> waited_;  // the planes whose entries to clear
    std::vector<std::uint8_t> touched_;  // per plane: within rounding of touching P
    std::vector<std::uint8_t> wanted_;   // per plane: to keep
    std::vector<std::uint8_t> present_;  // per plane: a face of P
    std::vector<std::uint8_t> in_ball_;  // per plane: a face of P inside the ball
    bool touched_any_ = false;
    std::vector<std::array<std::uint32_t, 2>> edges_;
};

}  // namespace fdmsurf::detail
