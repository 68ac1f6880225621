// Tests of the generated marching-cubes tables against cube topology, case by case.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "fdmsurf_generated/mc_tables.hpp"

namespace {

namespace mc = fdmsurf::detail::mc;

using Vec = std::array<double, 3>;
using Segment = std::pair<int, int>;  // directed, edge ids

bool inside(int cube, int corner) { return ((cube >> corner) & 1) != 0; }

bool crossed(int cube, int e) {
    return inside(cube, mc::kEdgeCorners[e][0]) != inside(cube, mc::kEdgeCorners[e][1]);
}

Vec corner_pos(int c) { return {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}; }

Vec midpoint(int e) {
    const Vec a = corner_pos(mc::kEdgeCorners[e][0]);
    const Vec b = corner_pos(mc::kEdgeCorners[e][1]);
    return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
}

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::vector<std::array<int, 3>> triangles(int cube) {
    std::vector<std::array<int, 3>> out;
    for (int t = 0; t < mc::kTriCount[cube]; ++t) {
        out.push_back({mc::kTriEdges[cube][3 * t], mc::kTriEdges[cube][3 * t + 1],
                       mc::kTriEdges[cube][3 * t + 2]});
    }
    return out;
}

// The face (axis d, side s) holds an edge when both its corners have coordinate d equal to s.
bool on_face(int e, int d, int s) {
    return ((mc::kEdgeCorners[e][0] >> d) & 1) == s && ((mc::kEdgeCorners[e][1] >> d) & 1) == s;
}

// Directed edges of a case's triangles that are not cancelled by their reverse: the boundary of
// the case's surface patch, which must lie on the cube's faces.
std::vector<Segment> boundary(int cube) {
    std::multiset<Segment> directed;
    for (const auto& t : triangles(cube)) {
        for (int i = 0; i < 3; ++i) directed.insert({t[i], t[(i + 1) % 3]});
    }
    std::vector<Segment> out;
    for (const Segment& s : directed) {
        if (directed.count({s.second, s.first}) == 0) out.push_back(s);
    }
    return out;
}

std::vector<Segment> boundary_on_face(int cube, int d, int s) {
    std::vector<Segment> out;
    for (const Segment& seg : boundary(cube)) {
        if (on_face(seg.first, d, s) && on_face(seg.second, d, s)) out.push_back(seg);
    }
    return out;
}

// The face rule, written independently of the generator: pairs of crossed edges that meet at a
// face corner which is cut off (an inside corner on an ambiguous face, otherwise the face's one
// crossed pair).
std::set<std::set<int>> expected_face_pairs(int cube, int d, int s) {
    std::vector<int> face_edges;
    for (int e = 0; e < 12; ++e) {
        if (on_face(e, d, s) && crossed(cube, e)) face_edges.push_back(e);
    }
    std::set<std::set<int>> pairs;
    if (face_edges.size() == 2) {
        pairs.insert({face_edges[0], face_edges[1]});
    } else if (face_edges.size() == 4) {
        for (int c = 0; c < 8; ++c) {
            if (((c >> d) & 1) != s || !inside(cube, c)) continue;
            std::set<int> pair;
            for (int e : face_edges) {
                if (mc::kEdgeCorners[e][0] == c || mc::kEdgeCorners[e][1] == c) pair.insert(e);
            }
            pairs.insert(pair);
        }
    }
    return pairs;
}

bool ambiguous_face(int cube, int d, int s) {
    int n = 0;
    for (int e = 0; e < 12; ++e) n += on_face(e, d, s) && crossed(cube, e) ? 1 : 0;
    return n == 4;
}

std::array<int, 3> canonical(std::array<int, 3> t) {
    while (t[0] != std::min({t[0], t[1], t[2]})) t = {t[1], t[2], t[0]};
    return t;
}

TEST(McTables, EdgesFollowTheOwnerAxisNumbering) {
    for (int e = 0; e < 12; ++e) {
        const int axis = mc::kEdgeAxis[e];
        EXPECT_EQ(axis, e / 4);
        EXPECT_EQ(mc::kEdgeOwner[e][axis], 0);
        const int k = e % 4;
        const int u = axis == 0 ? 1 : 0;
        const int v = axis == 2 ? 1 : 2;
        EXPECT_EQ(mc::kEdgeOwner[e][u], k & 1) << e;
        EXPECT_EQ(mc::kEdgeOwner[e][v], k >> 1) << e;
        const int c0 = mc::kEdgeOwner[e][0] | mc::kEdgeOwner[e][1] << 1 | mc::kEdgeOwner[e][2] << 2;
        EXPECT_EQ(mc::kEdgeCorners[e][0], c0);
        EXPECT_EQ(mc::kEdgeCorners[e][1], c0 | 1 << axis);
    }
}

TEST(McTables, EmptyAndFullCasesHaveNoTriangles) {
    EXPECT_EQ(mc::kTriCount[0], 0);
    EXPECT_EQ(mc::kTriCount[255], 0);
}

TEST(McTables, TrianglesUseExactlyTheCrossedEdges) {
    int max_count = 0;
    for (int cube = 0; cube < 256; ++cube) {
        max_count = std::max(max_count, int(mc::kTriCount[cube]));
        std::set<int> used;
        for (int i = 0; i < 3 * mc::kMaxTriangles; ++i) {
            const int e = mc::kTriEdges[cube][i];
            if (i < 3 * mc::kTriCount[cube]) {
                ASSERT_TRUE(e >= 0 && e < 12) << cube;
                EXPECT_TRUE(crossed(cube, e)) << "case " << cube << " edge " << e;
                used.insert(e);
            } else {
                EXPECT_EQ(e, mc::kNoEdge) << cube;
            }
        }
        for (int e = 0; e < 12; ++e) {
            EXPECT_EQ(crossed(cube, e), used.count(e) == 1) << "case " << cube << " edge " << e;
        }
        for (const auto& t : triangles(cube)) {
            EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << cube;
        }
    }
    EXPECT_EQ(max_count, mc::kMaxTriangles);
}

TEST(McTables, EachCaseIsAPatchBoundedByItsFaceSegments) {
    for (int cube = 0; cube < 256; ++cube) {
        // Inside a case every directed edge appears once; an edge used twice runs both ways.
        std::multiset<Segment> directed;
        for (const auto& t : triangles(cube)) {
            for (int i = 0; i < 3; ++i) directed.insert({t[i], t[(i + 1) % 3]});
        }
        for (const Segment& s : directed) {
            EXPECT_EQ(directed.count(s), 1u) << cube;
            // An interior edge on a face could also be chosen by the neighbour across it.
            if (directed.count({s.second, s.first}) == 0) continue;
            for (int d = 0; d < 3; ++d) {
                for (int side = 0; side < 2; ++side) {
                    EXPECT_FALSE(on_face(s.first, d, side) && on_face(s.second, d, side))
                        << "case " << cube << " diagonal " << s.first << "-" << s.second;
                }
            }
        }
        // Boundary segments lie on faces, and on each face they are the face rule's pairs, once.
        std::size_t on_faces = 0;
        for (int d = 0; d < 3; ++d) {
            for (int s = 0; s < 2; ++s) {
                std::set<std::set<int>> got;
                for (const Segment& seg : boundary_on_face(cube, d, s)) {
                    EXPECT_TRUE(got.insert({seg.first, seg.second}).second) << cube;
                    ++on_faces;
                }
                EXPECT_EQ(got, expected_face_pairs(cube, d, s))
                    << "case " << cube << " face " << d << "/" << s;
            }
        }
        EXPECT_EQ(on_faces, boundary(cube).size()) << "boundary off the faces, case " << cube;
    }
}

TEST(McTables, NeighbouringCubesWalkSharedFaceSegmentsInOppositeDirections) {
    // Cube A's face (d, 1) is cube B's face (d, 0); B's other four corners are free.
    for (int a = 0; a < 256; ++a) {
        for (int d = 0; d < 3; ++d) {
            for (int b = 0; b < 256; ++b) {
                bool same_face = true;
                for (int c = 0; c < 8; ++c) {
                    if ((c >> d) & 1) same_face &= inside(a, c) == inside(b, c & ~(1 << d));
                }
                if (!same_face) continue;
                auto to_b = [d](int e) {
                    const int c0 = mc::kEdgeCorners[e][0] & ~(1 << d);
                    const int c1 = mc::kEdgeCorners[e][1] & ~(1 << d);
                    for (int f = 0; f < 12; ++f) {
                        if (mc::kEdgeCorners[f][0] == c0 && mc::kEdgeCorners[f][1] == c1) return f;
                    }
                    return -1;
                };
                std::set<Segment> from_a;
                for (const Segment& s : boundary_on_face(a, d, 1)) {
                    from_a.insert({to_b(s.second), to_b(s.first)});
                }
                const std::vector<Segment> in_b = boundary_on_face(b, d, 0);
                EXPECT_EQ(from_a, std::set<Segment>(in_b.begin(), in_b.end()))
                    << "cases " << a << " and " << b << " across axis " << d;
            }
        }
    }
}

TEST(McTables, LoopsAreOrientedFromInsideToOutsideCorners) {
    for (int cube = 0; cube < 256; ++cube) {
        // Loops share no vertex, so the pieces are the triangles linked through shared edges.
        const auto tris = triangles(cube);
        std::map<int, int> piece_of_edge;
        std::vector<int> piece(tris.size());
        for (std::size_t i = 0; i < tris.size(); ++i) {
            piece[i] = int(i);
            for (int e : tris[i]) {
                auto [it, fresh] = piece_of_edge.emplace(e, piece[i]);
                if (!fresh) {
                    const int old = piece[i];
                    for (int& p : piece) {
                        if (p == old) p = it->second;
                    }
                    for (auto& [edge, p] : piece_of_edge) {
                        if (p == old) p = it->second;
                    }
                }
            }
        }
        std::map<int, Vec> area, in_to_out;
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const Vec n = cross(sub(midpoint(tris[i][1]), midpoint(tris[i][0])),
                                sub(midpoint(tris[i][2]), midpoint(tris[i][0])));
            Vec& sum = area[piece[i]];
            for (int k = 0; k < 3; ++k) sum[k] += n[k];
        }
        for (const auto& [e, p] : piece_of_edge) {
            const int c0 = mc::kEdgeCorners[e][0];
            const int c1 = mc::kEdgeCorners[e][1];
            const Vec dir = inside(cube, c0) ? sub(corner_pos(c1), corner_pos(c0))
                                             : sub(corner_pos(c0), corner_pos(c1));
            Vec& sum = in_to_out[p];
            for (int k = 0; k < 3; ++k) sum[k] += dir[k];
        }
        for (const auto& [p, a] : area) {
            EXPECT_GT(dot(a, in_to_out[p]), 0.0) << "case " << cube;
        }
    }
}

TEST(McTables, ComplementCaseIsTheSameSurfaceReversedWithoutAmbiguousFaces) {
    for (int cube = 0; cube < 256; ++cube) {
        const int other = 255 - cube;
        for (int e = 0; e < 12; ++e) EXPECT_EQ(crossed(cube, e), crossed(other, e));
        bool ambiguous = false;
        for (int d = 0; d < 3; ++d) {
            for (int s = 0; s < 2; ++s) {
                if (ambiguous_face(cube, d, s)) {
                    ambiguous = true;
                    continue;
                }
                // Unambiguous faces carry the same segment, walked the other way.
                std::set<Segment> reversed;
                for (const Segment& seg : boundary_on_face(cube, d, s)) {
                    reversed.insert({seg.second, seg.first});
                }
                const std::vector<Segment> theirs = boundary_on_face(other, d, s);
                EXPECT_EQ(reversed, std::set<Segment>(theirs.begin(), theirs.end())) << cube;
            }
        }
        if (ambiguous) continue;
        std::multiset<std::array<int, 3>> mine, theirs;
        for (const auto& t : triangles(cube)) mine.insert(canonical({t[0], t[2], t[1]}));
        for (const auto& t : triangles(other)) theirs.insert(canonical(t));
        EXPECT_EQ(mine, theirs) << cube;
    }
}

}  // namespace
