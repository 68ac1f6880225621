// The power cell of one ball among its neighbours, cut to what the exact areas need: which
// neighbours' caps can shape the exposed part of the ball's sphere.
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
// Every test leans towards keeping a cap: a kept cap that could have been dropped costs time,
// never area. Whatever rounding makes of the polyhedron that is not a proper convex one (a face
// cut twice, a new face that is not one cycle) gives up the filter, and every cap is kept.
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

// Scratch space of one thread, reused from ball to ball.
class PowerCell {
public:
    // The planes in `planes`, taken in the order of `order` (largest cap first makes P shrink
    // soonest). `keep` gets the indices (into `planes`, increasing) of the planes to keep.
    CellVerdict filter(const std::vector<CellPlane>& planes,
                       const std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& keep);

private:
    enum class Clip { Missed, Touched, Cut, Emptied, Broken };
    void reset();
    Clip clip(const CellPlane& plane, std::int32_t id);

    // Vertices (coordinates apart, for the distance loop; NaN once cut away), the three faces
    // each is on, how many are live and the places of those cut away; faces, each with the
    // plane that made it (-1: the box) and its corners (vertex indices, counter-clockwise seen
    // from outside) in a run of its own.
    std::vector<double> x_, y_, z_;
    std::vector<std::array<std::uint16_t, 3>> vertex_faces_;
    std::size_t live_ = 0;
    std::size_t beyond_ = 0;  // live vertices not inside the ball (by kReach)
    std::vector<std::uint16_t> free_;
    std::vector<std::int32_t> face_plane_;
    std::vector<std::uint8_t> face_size_;
    std::vector<std::uint16_t> corners_;
    // Per clip: each vertex's signed distance, the vertices cut away and the faces they are on;
    // the new vertices' edges, places and links.
    std::vector<double> dist_;
    std::vector<std::uint16_t> gone_, cut_faces_;
    std::vector<std::uint8_t> face_mark_;
    // Per vertex cut away, the edges from it made so far: new vertex k on edge (in, it).
    struct EdgeFrom {
        std::uint16_t in, k;
    };
    std::vector<EdgeFrom> edge_from_;     // three per vertex
    std::vector<std::uint8_t> edges_made_;  // how many of the three
    std::vector<std::int32_t> link_;                 // the new face goes from new vertex k to link_[k]
    std::vector<std::uint16_t> made_;                // new vertex k's place
    std::vector<std::uint8_t> touched_;              // per plane: within rounding of touching P
};

}  // namespace fdmsurf::detail
