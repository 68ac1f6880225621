// Analytic test meshes (icosphere, torus, cones) and edits that break them in known ways.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::test {

inline std::uint32_t add_vertex(Mesh& mesh, double x, double y, double z) {
    mesh.positions.insert(mesh.positions.end(), {float(x), float(y), float(z)});
    return std::uint32_t(mesh.vertex_count() - 1);
}

// Subdivided icosahedron with vertices on the sphere, outward, 20 * 4^subdivisions triangles;
// normals are the exact sphere normals.
inline Mesh icosphere(double radius, int subdivisions, std::array<double, 3> center = {}) {
    const double t = std::numbers::phi;
    std::vector<std::array<double, 3>> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::uint32_t> faces = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                        1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                        3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                        4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
    auto normalise = [](std::array<double, 3> p) {
        const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return std::array<double, 3>{p[0] / n, p[1] / n, p[2] / n};
    };
    for (auto& p : unit) p = normalise(p);
    for (int level = 0; level < subdivisions; ++level) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, std::uint32_t(unit.size()));
            if (inserted) {
                unit.push_back(normalise(
                    {unit[a][0] + unit[b][0], unit[a][1] + unit[b][1], unit[a][2] + unit[b][2]}));
            }
            return it->second;
        };
        std::vector<std::uint32_t> finer;
        for (std::size_t f = 0; f < faces.size(); f += 3) {
            const std::uint32_t a = faces[f], b = faces[f + 1], c = faces[f + 2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            finer.insert(finer.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        faces = std::move(finer);
    }
    Mesh mesh;
    for (const auto& p : unit) {
        add_vertex(mesh, center[0] + radius * p[0], center[1] + radius * p[1],
                   center[2] + radius * p[2]);
        mesh.normals.insert(mesh.normals.end(), {float(p[0]), float(p[1]), float(p[2])});
    }
    mesh.indices = std::move(faces);
    return mesh;
}

// Torus around z of tube radius r at distance R, outward, 2 * nu * nv triangles.
inline Mesh torus(double big_r, double r, int nu, int nv) {
    Mesh mesh;
    for (int i = 0; i < nu; ++i) {
        const double u = 2 * std::numbers::pi * i / nu;
        for (int j = 0; j < nv; ++j) {
            const double v = 2 * std::numbers::pi * j / nv;
            add_vertex(mesh, (big_r + r * std::cos(v)) * std::cos(u),
                       (big_r + r * std::cos(v)) * std::sin(u), r * std::sin(v));
        }
    }
    auto at = [&](int i, int j) { return std::uint32_t((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            // d/du x d/dv points out of the tube, so (u, v)-ordered quads are counter-clockwise.
            mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1),
                                                     at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return mesh;
}

// Closed cone along z with its apex at vertex `apex` of `mesh` (at the origin) and its base
// disc at height h (either sign), outward.
inline void add_cone(Mesh& mesh, std::uint32_t apex, double h, double radius, int segments) {
    const std::uint32_t first = std::uint32_t(mesh.vertex_count());
    for (int i = 0; i < segments; ++i) {
        const double a = 2 * std::numbers::pi * i / segments;
        add_vertex(mesh, radius * std::cos(a), radius * std::sin(a), h);
    }
    const std::uint32_t base = add_vertex(mesh, 0, 0, h);
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t p = first + i, q = first + (i + 1) % segments;
        // Ring counter-clockwise about +z: for h > 0 the side runs apex, q, p and the cap
        // base, p, q; a cone below the apex is the mirror image.
        if (h > 0) {
            mesh.indices.insert(mesh.indices.end(), {apex, q, p, base, p, q});
        } else {
            mesh.indices.insert(mesh.indices.end(), {apex, p, q, base, q, p});
        }
    }
}

inline void append(Mesh& into, const Mesh& part) {
    const auto offset = std::uint32_t(into.vertex_count());
    into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
    into.normals.insert(into.normals.end(), part.normals.begin(), part.normals.end());
    for (std::uint32_t i : part.indices) into.indices.push_back(offset + i);
}

inline void flip_triangle(Mesh& mesh, std::size_t t) {
    std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
}

// Every triangle reversed and normals negated: the surface seen from the other side.
inline Mesh turned_inside_out(Mesh mesh) {
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) flip_triangle(mesh, t);
    for (float& n : mesh.normals) n = -n;
    return mesh;
}

inline void remove_triangle(Mesh& mesh, std::size_t t) {
    mesh.indices.erase(mesh.indices.begin() + std::ptrdiff_t(3 * t),
                       mesh.indices.begin() + std::ptrdiff_t(3 * t + 3));
}

}  // namespace fdmsurf::test
