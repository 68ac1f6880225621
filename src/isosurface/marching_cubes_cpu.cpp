// CPU reference of marching cubes (Lorensen & Cline, SIGGRAPH 1987), the model the GPU copies.
//
// Every float expression here is written in the order the shader evaluates it, so that the two
// agree on vertex order exactly and on values up to the GPU's division and sqrt rounding.
#include "isosurface/marching_cubes_cpu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include "base/fresh_pages.hpp"
#include "base/trace.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf_generated/mc_tables.hpp"

namespace fdmsurf::detail {
namespace {

struct Point {
    std::uint32_t c[3];
};

Point step(Point q, int axis) {
    ++q.c[axis];
    return q;
}

float value(const FieldView& f, Point q) { return f.at(q.c[0], q.c[1], q.c[2]); }

}  // namespace

void check_mc_arguments(bool has_data, std::uint32_t nx, std::uint32_t ny, std::uint32_t nz,
                        std::uint32_t pitch, const McParams& p) {
    auto fail = [](const std::string& why) {
        throw Error(ErrorCode::InvalidArgument, "marching cubes: " + why);
    };
    if (!has_data || nx == 0 || ny == 0 || nz == 0) fail("empty grid");
    if (pitch < nx) fail("row pitch smaller than nx");
    if (p.z_begin > p.z_end || p.z_end >= nz) {
        fail("z range [" + std::to_string(p.z_begin) + ", " + std::to_string(p.z_end) +
             "] outside the grid's " + std::to_string(nz) + " planes");
    }
    if (!(p.spacing > 0.0f) || !std::isfinite(p.spacing)) fail("spacing must be positive");
}

void grow_mesh_for_part(Mesh& mesh, std::size_t vertices, std::size_t indices,
                        double reserve_scale) {
    if (mesh.normals.size() != mesh.positions.size() || !mesh.atoms.empty() ||
        !mesh.colors.empty() || !mesh.scalars.empty())
        throw Error(ErrorCode::Internal, "marching cubes: appending to a mesh of another kind");
    const std::size_t v = mesh.vertex_count() + vertices, n = mesh.indices.size() + indices;
    if (v > std::numeric_limits<std::uint32_t>::max() - 3)
        throw Error(ErrorCode::InvalidArgument,
                    "marching cubes: more than 2^32 vertices; use smaller slabs");
    // Each array too small for the part is copied into a new one of `scale` times the room,
    // its pages up to the part's end provided on all threads first: a vector's own reserve
    // would copy it into fresh pages on one thread (0.3 GB, half a second on one core, when the
    // 2.43 M-atom shell's parts outgrew the first guess). One array at a time, so that the old
    // one is freed before the next grows. The others' pages for the part likewise, before resize
    // writes them on one thread (fresh pages cost more than the zeros written to them: 0.9 GB
    // of them on the 2.43 M-atom shell at 1 Å).
    const double scale = std::max(reserve_scale, 1.0);
    std::vector<FreshRange> fresh;
    bool grown = false;
    auto room = [&](auto& array, std::size_t size) {
        if (array.capacity() >= size) {
            fresh.push_back(room_up_to(array, size));
            return;
        }
        std::remove_reference_t<decltype(array)> bigger;
        try {
            bigger.reserve(std::max(std::size_t(double(size) * scale), size));
        } catch (const std::bad_alloc&) {
            // Address space refused (strict overcommit): what this part needs is enough.
            bigger.reserve(size);
        }
        populate_pages({room_up_to(bigger, size)});
        bigger.assign(array.begin(), array.end());
        array.swap(bigger);
        grown = true;
    };
    room(mesh.positions, 3 * v);
    room(mesh.normals, 3 * v);
    room(mesh.indices, n);
    if (grown) trace("marching cubes: mesh arrays reserved");
    populate_pages(fresh);
    mesh.positions.resize(3 * v);
    mesh.normals.resize(3 * v);
    mesh.indices.resize(n);
}

Mesh marching_cubes_cpu(const FieldView& f, const McParams& p) {
    check_mc_arguments(f.data != nullptr, f.nx, f.ny, f.nz, f.pitch, p);
    const float iso = p.iso;
    const std::uint32_t planes = p.z_end - p.z_begin + 1;
    const std::size_t point_count = std::size_t(f.nx) * f.ny * planes;
    auto point_id = [&](Point q) {
        return (std::size_t(q.c[2] - p.z_begin) * f.ny + q.c[1]) * f.nx + q.c[0];
    };
    auto inside = [&](Point q) { return value(f, q) >= iso; };
    auto owns = [&](Point q, int axis) {
        return axis == 0 ? q.c[0] + 1 < f.nx : axis == 1 ? q.c[1] + 1 < f.ny : q.c[2] < p.z_end;
    };

    // Pass 1: vertices in point order. first_vertex and crossed_mask let pass 2 find the vertex
    // of any edge without a hash map, as the GPU does after its prefix sum over per-point counts.
    Mesh mesh;
    std::vector<std::uint32_t> first_vertex(point_count);
    std::vector<std::uint8_t> crossed_mask(point_count);
    std::size_t vertex_count = 0;
    Point q{};
    for (q.c[2] = p.z_begin; q.c[2] <= p.z_end; ++q.c[2]) {
        for (q.c[1] = 0; q.c[1] < f.ny; ++q.c[1]) {
            for (q.c[0] = 0; q.c[0] < f.nx; ++q.c[0]) {
                const std::size_t id = point_id(q);
                if (vertex_count > std::numeric_limits<std::uint32_t>::max() - 3) {
                    throw Error(ErrorCode::InvalidArgument,
                                "marching cubes: more than 2^32 vertices; use smaller slabs");
                }
                first_vertex[id] = std::uint32_t(vertex_count);
                std::uint8_t mask = 0;
                const float v0 = value(f, q);
                for (int a = 0; a < 3; ++a) {
                    if (!owns(q, a)) continue;
                    const Point r = step(q, a);
                    const float v1 = value(f, r);
                    if ((v0 >= iso) == (v1 >= iso)) continue;
                    mask |= std::uint8_t(1u << a);
                    ++vertex_count;
                    float position[3], normal[3];
                    mc_vertex(f, q.c, a, p, position, normal);
                    mesh.positions.insert(mesh.positions.end(), position, position + 3);
                    mesh.normals.insert(mesh.normals.end(), normal, normal + 3);
                }
                crossed_mask[id] = mask;
            }
        }
    }

    // Pass 2: triangles in cell order, each edge resolved to the vertex its owner point emitted.
    if (f.nx < 2 || f.ny < 2) return mesh;
    for (q.c[2] = p.z_begin; q.c[2] < p.z_end; ++q.c[2]) {
        for (q.c[1] = 0; q.c[1] + 1 < f.ny; ++q.c[1]) {
            for (q.c[0] = 0; q.c[0] + 1 < f.nx; ++q.c[0]) {
                unsigned cube = 0;
                for (unsigned c = 0; c < 8; ++c) {
                    const Point corner{
                        {q.c[0] + (c & 1), q.c[1] + ((c >> 1) & 1), q.c[2] + ((c >> 2) & 1)}};
                    if (inside(corner)) cube |= 1u << c;
                }
                const int triangles = mc::kTriCount[cube];
                for (int i = 0; i < 3 * triangles; ++i) {
                    const int e = mc::kTriEdges[cube][i];
                    const int axis = mc::kEdgeAxis[e];
                    const Point owner{{q.c[0] + mc::kEdgeOwner[e][0], q.c[1] + mc::kEdgeOwner[e][1],
                                       q.c[2] + mc::kEdgeOwner[e][2]}};
                    const std::size_t id = point_id(owner);
                    const unsigned before = crossed_mask[id] & ((1u << axis) - 1u);
                    const unsigned offset = (before & 1u) + ((before >> 1) & 1u);
                    if (!((crossed_mask[id] >> axis) & 1u)) {
                        throw Error(ErrorCode::Internal, "marching cubes: table edge not crossed");
                    }
                    mesh.indices.push_back(first_vertex[id] + offset);
                }
            }
        }
    }
    return mesh;
}

float edge_crossing(float v0, float v1, const McParams& p) {
    float t = (p.iso - v0) / (v1 - v0);
    if (p.power_sigma2 > 0.0f && v0 > 0.0f && v1 > 0.0f) {
        // pi(t) = a t^2 + b t + pi0 with a = h^2; solve pi(t) = pi_iso.
        const float pi0 = -p.power_sigma2 * std::log(v0 / p.power_t);
        const float pi1 = -p.power_sigma2 * std::log(v1 / p.power_t);
        const float pii = -p.power_sigma2 * std::log(p.iso / p.power_t);
        const float a = p.spacing * p.spacing;
        const float b = pi1 - pi0 - a;
        const float c = pi0 - pii;
        const float disc = b * b - 4.0f * a * c;
        if (disc >= 0.0f) {
            const float s = std::sqrt(disc);
            const float r1 = (-b - s) / (2.0f * a), r2 = (-b + s) / (2.0f * a);
            const bool ok1 = r1 >= 0.0f && r1 <= 1.0f, ok2 = r2 >= 0.0f && r2 <= 1.0f;
            if (ok1 && ok2)
                t = std::abs(r1 - t) <= std::abs(r2 - t) ? r1 : r2;
            else if (ok1)
                t = r1;
            else if (ok2)
                t = r2;
        }
    }
    return std::min(std::max(t, 0.001f), 0.999f);
}

}  // namespace fdmsurf::detail
