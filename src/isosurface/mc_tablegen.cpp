// Build-time generator of the marching-cubes tables, derived from cube topology, written both as
// a C++ header and as a GLSL include so that the CPU reference and the shader cannot drift apart.
//
// Marching cubes: W. E. Lorensen and H. E. Cline, "Marching cubes: a high resolution 3D surface
// construction algorithm", SIGGRAPH 1987. The classic 256-case table has faces whose ambiguous
// cases are resolved differently in neighbouring cubes (holes); here every face is resolved by
// one face-local rule, always separating the inside corners, so neighbours agree and the surface
// is watertight. Usage: fdmsurf_mc_tablegen OUT.hpp OUT.glsl
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "base/vec3.hpp"

namespace {

using fdmsurf::detail::add;
using fdmsurf::detail::cross;
using fdmsurf::detail::dot;
using fdmsurf::detail::scale;
using fdmsurf::detail::sub;
using fdmsurf::detail::Vec3;

// A broken invariant means the derivation is wrong: no table is better than a wrong one.
void check(bool ok, const char* what, int cube = -1) {
    if (!ok) {
        std::fprintf(stderr, "fdmsurf_mc_tablegen: %s (case %d)\n", what, cube);
        std::exit(1);
    }
}

int corner_coord(int c, int axis) { return (c >> axis) & 1; }

Vec3 corner_pos(int c) {
    return {double(corner_coord(c, 0)), double(corner_coord(c, 1)), double(corner_coord(c, 2))};
}

struct Edge {
    int owner[3];
    int axis;
    int corners[2];  // corners[0] at the owner, corners[1] = owner + e_axis
};

// Edge 4*axis + k runs along +axis from the owner offset whose other two coordinates (in
// increasing axis order) are (k & 1, k >> 1).
std::array<Edge, 12> make_edges() {
    std::array<Edge, 12> edges{};
    for (int e = 0; e < 12; ++e) {
        Edge& edge = edges[e];
        edge.axis = e / 4;
        const int k = e % 4;
        const int u = edge.axis == 0 ? 1 : 0;
        const int v = edge.axis == 2 ? 1 : 2;
        edge.owner[edge.axis] = 0;
        edge.owner[u] = k & 1;
        edge.owner[v] = k >> 1;
        edge.corners[0] = edge.owner[0] | (edge.owner[1] << 1) | (edge.owner[2] << 2);
        edge.corners[1] = edge.corners[0] | (1 << edge.axis);
    }
    return edges;
}

int edge_between(const std::array<Edge, 12>& edges, int a, int b) {
    for (int e = 0; e < 12; ++e) {
        const Edge& edge = edges[e];
        if ((edge.corners[0] == a && edge.corners[1] == b) ||
            (edge.corners[0] == b && edge.corners[1] == a)) {
            return e;
        }
    }
    check(false, "corners are not adjacent");
    return -1;
}

bool share_face(const std::array<Edge, 12>& edges, int a, int b) {
    for (int d = 0; d < 3; ++d) {
        for (int s = 0; s < 2; ++s) {
            bool all = true;
            for (int e : {a, b}) {
                for (int c : edges[e].corners) all = all && corner_coord(c, d) == s;
            }
            if (all) return true;
        }
    }
    return false;
}

struct CaseTable {
    std::vector<int> edges;  // 3 per triangle
};

// Derives one case: face segments, chained into loops, each loop fanned from a vertex whose fan
// keeps every diagonal off the cube's faces.
CaseTable make_case(const std::array<Edge, 12>& edges, int cube) {
    auto inside = [cube](int c) { return ((cube >> c) & 1) != 0; };
    auto crossed = [&](int e) {
        return inside(edges[e].corners[0]) != inside(edges[e].corners[1]);
    };
    auto midpoint = [&](int e) {
        return scale(add(corner_pos(edges[e].corners[0]), corner_pos(edges[e].corners[1])), 0.5);
    };

    std::array<int, 12> next{};
    std::array<int, 12> incoming{};
    next.fill(-1);
    incoming.fill(0);

    for (int d = 0; d < 3; ++d) {
        for (int s = 0; s < 2; ++s) {
            const int u = d == 0 ? 1 : 0;
            const int v = d == 2 ? 1 : 2;
            Vec3 normal{0.0, 0.0, 0.0};
            normal[d] = s == 1 ? 1.0 : -1.0;
            // The face's corners in cyclic order, so that consecutive ones share an edge.
            std::array<int, 4> ring{};
            const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int i = 0; i < 4; ++i) {
                ring[i] = (s << d) | (uv[i][0] << u) | (uv[i][1] << v);
            }
            std::array<int, 4> ring_edge{};  // between ring[i] and ring[i + 1]
            int n_inside = 0;
            for (int i = 0; i < 4; ++i) {
                ring_edge[i] = edge_between(edges, ring[i], ring[(i + 1) % 4]);
                n_inside += inside(ring[i]) ? 1 : 0;
            }
            if (n_inside == 0 || n_inside == 4) continue;

            Vec3 face_centre{0.0, 0.0, 0.0};
            for (int c : ring) face_centre = add(face_centre, scale(corner_pos(c), 0.25));

            // Segments as (edge, edge, direction towards the outside corners they separate).
            struct Segment {
                int a, b;
                Vec3 out;
            };
            std::vector<Segment> segments;
            const bool ambiguous = n_inside == 2 && inside(ring[0]) == inside(ring[2]);
            if (ambiguous) {
                // Separate the inside corners: each gets a segment across its own two edges.
                for (int i = 0; i < 4; ++i) {
                    if (!inside(ring[i])) continue;
                    segments.push_back({ring_edge[(i + 3) % 4], ring_edge[i],
                                        sub(face_centre, corner_pos(ring[i]))});
                }
            } else {
                Vec3 in_mean{0.0, 0.0, 0.0};
                Vec3 out_mean{0.0, 0.0, 0.0};
                std::vector<int> cut;
                for (int i = 0; i < 4; ++i) {
                    if (inside(ring[i])) {
                        in_mean = add(in_mean, scale(corner_pos(ring[i]), 1.0 / n_inside));
                    } else {
                        out_mean = add(out_mean, scale(corner_pos(ring[i]), 1.0 / (4 - n_inside)));
                    }
                    if (crossed(ring_edge[i])) cut.push_back(ring_edge[i]);
                }
                check(cut.size() == 2, "unambiguous face without two crossed edges", cube);
                segments.push_back({cut[0], cut[1], sub(out_mean, in_mean)});
            }

            for (Segment& seg : segments) {
                check(crossed(seg.a) && crossed(seg.b), "segment on an uncrossed edge", cube);
                // Seen from outside the cube, the inside corners lie to the right of p->q; the
                // neighbouring cube sees this face with the opposite normal and so walks the
                // same segment q->p, which is what makes shared edges match.
                const double side =
                    dot(sub(midpoint(seg.b), midpoint(seg.a)), cross(seg.out, normal));
                check(side != 0.0, "segment parallel to its outside direction", cube);
                if (side < 0.0) std::swap(seg.a, seg.b);
                check(next[seg.a] == -1, "edge starts two segments", cube);
                next[seg.a] = seg.b;
                ++incoming[seg.b];
            }
        }
    }

    for (int e = 0; e < 12; ++e) {
        const bool c = crossed(e);
        check(c == (next[e] != -1) && incoming[e] == (c ? 1 : 0),
              "crossed edge not on exactly one incoming and one outgoing segment", cube);
    }

    CaseTable out;
    std::array<bool, 12> visited{};
    for (int start = 0; start < 12; ++start) {
        if (!crossed(start) || visited[start]) continue;
        std::vector<int> loop;
        for (int e = start; !visited[e]; e = next[e]) {
            visited[e] = true;
            loop.push_back(e);
        }
        check(loop.front() == next[loop.back()] && loop.size() >= 3, "segments do not close", cube);

        // Orientation: the loop's vector area must point from its inside corners to its
        // outside corners (out of the molecule); a wrong sign here would flip whole cases.
        const Vec3 centre{0.5, 0.5, 0.5};
        Vec3 area{0.0, 0.0, 0.0};
        Vec3 in_to_out{0.0, 0.0, 0.0};
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const Vec3 p = sub(midpoint(loop[i]), centre);
            const Vec3 q = sub(midpoint(loop[(i + 1) % loop.size()]), centre);
            area = add(area, cross(p, q));
            const Edge& edge = edges[loop[i]];
            const bool owner_inside = inside(edge.corners[0]);
            const Vec3 step = sub(corner_pos(edge.corners[1]), corner_pos(edge.corners[0]));
            in_to_out = add(in_to_out, owner_inside ? step : scale(step, -1.0));
        }
        check(dot(area, in_to_out) > 0.0, "loop oriented into the molecule", cube);

        // A fan diagonal between two vertices on one cube face would also be an edge of the
        // neighbour across that face if it chose the same diagonal: four triangles on one edge.
        // Such pairs exist only on faces with four crossed edges; fan from the first vertex of
        // the loop (lowest edge id first) whose diagonals all cross the cube's interior.
        const std::size_t n = loop.size();
        std::size_t apex = n;
        for (std::size_t j = 0; j < n && apex == n; ++j) {
            bool ok = true;
            for (std::size_t k = 2; k + 1 < n; ++k) {
                ok = ok && !share_face(edges, loop[j], loop[(j + k) % n]);
            }
            if (ok) apex = j;
        }
        check(apex < n, "no fan without a diagonal on a cube face", cube);
        std::rotate(loop.begin(), loop.begin() + apex, loop.end());
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
            out.edges.push_back(loop[0]);
            out.edges.push_back(loop[i]);
            out.edges.push_back(loop[i + 1]);
        }
    }
    return out;
}

// One line per `per_line` values; `braces` wraps each line as a row of a 2-D C++ array.
std::string join(const std::vector<int>& values, int per_line, const char* indent,
                 const char* suffix = "", bool braces = false) {
    std::ostringstream s;
    for (std::size_t i = 0; i < values.size(); ++i) {
        const bool first = i % per_line == 0;
        const bool last = (i + 1) % per_line == 0 || i + 1 == values.size();
        if (first) s << indent << (braces ? "{" : "");
        s << values[i] << suffix;
        if (last && braces) s << "}";
        if (i + 1 < values.size()) s << ",";
        s << (last ? "\n" : " ");
    }
    return s.str();
}

bool write_file(const char* path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) {
        std::fprintf(stderr, "fdmsurf_mc_tablegen: cannot write %s\n", path);
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fdmsurf_mc_tablegen OUT.hpp OUT.glsl\n");
        return 2;
    }

    const std::array<Edge, 12> edges = make_edges();
    std::vector<CaseTable> cases;
    int max_triangles = 0;
    for (int cube = 0; cube < 256; ++cube) {
        cases.push_back(make_case(edges, cube));
        max_triangles = std::max(max_triangles, int(cases.back().edges.size() / 3));
    }
    const int row = 3 * max_triangles;

    std::vector<int> owner, axis, corners, tri_count, tri_edges;
    for (const Edge& e : edges) {
        owner.insert(owner.end(), {e.owner[0], e.owner[1], e.owner[2]});
        axis.push_back(e.axis);
        corners.insert(corners.end(), {e.corners[0], e.corners[1]});
    }
    for (const CaseTable& c : cases) {
        tri_count.push_back(int(c.edges.size() / 3));
        std::vector<int> padded = c.edges;
        padded.resize(row, -1);
        tri_edges.insert(tri_edges.end(), padded.begin(), padded.end());
    }

    const char* conventions =
        "Corner c of a cell is at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1); bit c of the\n"
        "cube index is set when corner c is inside (value >= iso). Edge e runs along axis\n"
        "e / 4 from its owner offset; its corners are (owner, owner + e_axis). Triangles are\n"
        "counter-clockwise seen from outside (normal points from inside to outside corners).\n"
        "Each loop of face segments is one fan of triangles; no fan diagonal lies on a face.\n"
        "Unused triangle entries are -1.";
    auto commented = [conventions](const char* prefix) {
        std::string out;
        std::istringstream lines(conventions);
        for (std::string line; std::getline(lines, line);) out += prefix + line + "\n";
        return out;
    };

    std::ostringstream hpp;
    hpp << "// Marching-cubes tables, generated by fdmsurf_mc_tablegen from cube topology: do not "
           "edit.\n"
        << commented("// ") << "#pragma once\n\n#include <cstdint>\n\n"
        << "namespace fdmsurf::detail::mc {\n\n"
        << "inline constexpr int kNoEdge = -1;\n"
        << "inline constexpr int kMaxTriangles = " << max_triangles << ";\n\n"
        << "inline constexpr std::uint8_t kEdgeOwner[12][3] = {\n"
        << join(owner, 3, "    ", "", true) << "};\n\n"
        << "inline constexpr std::uint8_t kEdgeAxis[12] = {\n"
        << join(axis, 12, "    ") << "};\n\n"
        << "inline constexpr std::uint8_t kEdgeCorners[12][2] = {\n"
        << join(corners, 2, "    ", "", true) << "};\n\n"
        << "inline constexpr std::uint8_t kTriCount[256] = {\n"
        << join(tri_count, 16, "    ") << "};\n\n"
        << "inline constexpr std::int8_t kTriEdges[256][3 * kMaxTriangles] = {\n"
        << join(tri_edges, row, "    ", "", true) << "};\n\n"
        << "}  // namespace fdmsurf::detail::mc\n";

    auto glsl_array = [](const char* type, const char* name, const std::string& size,
                         const std::vector<int>& values, int per_line) {
        return std::string("const ") + type + " " + name + "[" + size + "] = " + type + "[" + size +
               "](\n" + join(values, per_line, "    ", std::string(type) == "uint" ? "u" : "") +
               ");\n";
    };
    std::ostringstream glsl;
    glsl << "// Marching-cubes tables, generated by fdmsurf_mc_tablegen from cube topology: do not "
            "edit.\n"
         << commented("// ")
         << "// Flat arrays: edge e's owner is MC_EDGE_OWNER[3 * e + i], its corners\n"
         << "// MC_EDGE_CORNERS[2 * e + j], case k's triangle edges\n"
         << "// MC_TRI_EDGES[k * 3 * MC_MAX_TRIANGLES + 3 * t + j].\n"
         << "#ifndef FDMSURF_MC_TABLES_GLSL\n#define FDMSURF_MC_TABLES_GLSL\n\n"
         << "#define MC_NO_EDGE (-1)\n"
         << "#define MC_MAX_TRIANGLES " << max_triangles << "\n\n"
         << glsl_array("uint", "MC_EDGE_OWNER", "36", owner, 3) << "\n"
         << glsl_array("uint", "MC_EDGE_AXIS", "12", axis, 12) << "\n"
         << glsl_array("uint", "MC_EDGE_CORNERS", "24", corners, 2) << "\n"
         << glsl_array("uint", "MC_TRI_COUNT", "256", tri_count, 16) << "\n"
         << glsl_array("int", "MC_TRI_EDGES", "256 * 3 * MC_MAX_TRIANGLES", tri_edges, row)
         << "\n#endif  // FDMSURF_MC_TABLES_GLSL\n";

    return write_file(argv[1], hpp.str()) && write_file(argv[2], glsl.str()) ? 0 : 1;
}
