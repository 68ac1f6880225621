// Tests of the CPU marching-cubes reference: analytic sphere, closed manifolds, order and slabs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <numbers>
#include <random>
#include <unordered_map>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf_generated/mc_tables.hpp"
#include "isosurface/marching_cubes_cpu.hpp"

namespace {

using fdmsurf::Mesh;
using fdmsurf::detail::FieldView;
using fdmsurf::detail::marching_cubes_cpu;
using fdmsurf::detail::McParams;

// A dense grid with x fastest, and a view of it.
struct Grid {
    std::uint32_t nx, ny, nz;
    std::vector<float> v;
    Grid(std::uint32_t x, std::uint32_t y, std::uint32_t z, float fill = 0.0f)
        : nx(x), ny(y), nz(z), v(std::size_t(x) * y * z, fill) {}
    float& at(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        return v[(std::size_t(z) * ny + y) * nx + x];
    }
    FieldView view() const { return FieldView{v.data(), nx, ny, nz, nx}; }
};

McParams full_range(const Grid& g, float iso = 0.0f, float spacing = 1.0f) {
    McParams p;
    p.spacing = spacing;
    p.iso = iso;
    p.z_begin = 0;
    p.z_end = g.nz - 1;
    return p;
}

// Edge topology of a triangle mesh, written here so that these tests do not lean on src/mesh/.
struct Topology {
    std::size_t boundary_edges = 0;        // used by one triangle
    std::size_t nonmanifold_edges = 0;     // used by more than two
    std::size_t repeated_directed = 0;     // a directed edge used twice: orientation flips
    std::size_t nonmanifold_vertices = 0;  // incident triangles not one closed fan
    std::size_t unused_vertices = 0;
    std::size_t degenerate_triangles = 0;
    long euler = 0;  // V - E + F over used vertices
    double area = 0.0;
    double volume = 0.0;  // signed, divergence theorem

    bool closed_manifold() const {
        return boundary_edges == 0 && nonmanifold_edges == 0 && repeated_directed == 0 &&
               nonmanifold_vertices == 0 && degenerate_triangles == 0;
    }
};

std::array<double, 3> vertex(const Mesh& m, std::uint32_t i) {
    return {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
}

Topology topology(const Mesh& m) {
    Topology t;
    const std::size_t nv = m.vertex_count();
    std::unordered_map<std::uint64_t, int> undirected, directed;
    auto key = [](std::uint64_t a, std::uint64_t b) { return a << 32 | b; };
    // Per vertex, the link: for each incident triangle (v, a, b), the step a -> b.
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> link(nv);
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        const std::uint32_t* tri = &m.indices[3 * f];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) ++t.degenerate_triangles;
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = tri[i], b = tri[(i + 1) % 3], c = tri[(i + 2) % 3];
            ++undirected[key(std::min(a, b), std::max(a, b))];
            ++directed[key(a, b)];
            link[a].push_back({b, c});
        }
        const auto a = vertex(m, tri[0]), b = vertex(m, tri[1]), c = vertex(m, tri[2]);
        const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const std::array<double, 3> w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const std::array<double, 3> n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                      u[0] * w[1] - u[1] * w[0]};
        t.area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        t.volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0])) /
                    6.0;
    }
    for (const auto& [k, n] : undirected) {
        if (n == 1) ++t.boundary_edges;
        if (n > 2) ++t.nonmanifold_edges;
    }
    for (const auto& [k, n] : directed) {
        if (n > 1) ++t.repeated_directed;
    }
    std::size_t used = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (link[v].empty()) {
            ++t.unused_vertices;
            continue;
        }
        ++used;
        // One fan: following a -> b from any incident triangle comes back after visiting all.
        std::unordered_map<std::uint32_t, std::uint32_t> next;
        bool ok = true;
        for (const auto& [a, b] : link[v]) ok &= next.emplace(a, b).second;
        std::size_t steps = 0;
        std::uint32_t at = link[v][0].first;
        while (ok && steps <= link[v].size()) {
            auto it = next.find(at);
            if (it == next.end()) break;
            at = it->second;
            ++steps;
            if (at == link[v][0].first) break;
        }
        if (!ok || steps != link[v].size() || at != link[v][0].first) ++t.nonmanifold_vertices;
    }
    t.euler = long(used) - long(undirected.size()) + long(m.triangle_count());
    return t;
}

void expect_closed_manifold(const Mesh& m, const char* what) {
    const Topology t = topology(m);
    EXPECT_EQ(t.boundary_edges, 0u) << what;
    EXPECT_EQ(t.nonmanifold_edges, 0u) << what;
    EXPECT_EQ(t.repeated_directed, 0u) << what;
    EXPECT_EQ(t.nonmanifold_vertices, 0u) << what;
    EXPECT_EQ(t.unused_vertices, 0u) << what;
    EXPECT_EQ(t.degenerate_triangles, 0u) << what;
    EXPECT_EQ(t.euler % 2, 0) << what;
    if (m.triangle_count() > 0) {
        EXPECT_GT(t.volume, 0.0) << what;
    }
}

// Uniform in [-1, 1] from raw mt19937 words, so the fields are the same on every standard library.
Grid random_grid(std::mt19937& rng, std::uint32_t n, bool border_outside) {
    Grid g(n, n, n);
    for (float& v : g.v) v = float(rng() >> 8) / float(1u << 23) - 1.0f;
    if (border_outside) {
        for (std::uint32_t z = 0; z < n; ++z) {
            for (std::uint32_t y = 0; y < n; ++y) {
                for (std::uint32_t x = 0; x < n; ++x) {
                    if (x == 0 || y == 0 || z == 0 || x == n - 1 || y == n - 1 || z == n - 1) {
                        g.at(x, y, z) = -1.0f;
                    }
                }
            }
        }
    }
    return g;
}

TEST(MarchingCubesCpu, SphereMatchesAnalyticAreaVolumeAndNormals) {
    const double r = 3.0;
    const double centre[3] = {0.11, -0.07, 0.03};  // off the grid's symmetry
    const float h = 0.25f;
    Grid g(33, 33, 33);
    McParams p = full_range(g, 0.0f, h);
    for (float& o : p.origin) o = -4.0f;
    for (std::uint32_t z = 0; z < g.nz; ++z) {
        for (std::uint32_t y = 0; y < g.ny; ++y) {
            for (std::uint32_t x = 0; x < g.nx; ++x) {
                const double d[3] = {-4.0 + h * x - centre[0], -4.0 + h * y - centre[1],
                                     -4.0 + h * z - centre[2]};
                g.at(x, y, z) = float(r * r - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
            }
        }
    }
    const Mesh m = marching_cubes_cpu(g.view(), p);
    expect_closed_manifold(m, "sphere");
    const Topology t = topology(m);
    EXPECT_EQ(t.euler, 2);
    EXPECT_NEAR(t.area, 4.0 * std::numbers::pi * r * r, 0.01 * 4.0 * std::numbers::pi * r * r);
    EXPECT_NEAR(t.volume, 4.0 / 3.0 * std::numbers::pi * r * r * r,
                0.01 * 4.0 / 3.0 * std::numbers::pi * r * r * r);

    ASSERT_EQ(m.normals.size(), m.positions.size());
    double worst = 0.0;
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
        const auto v = vertex(m, i);
        double radial[3], len = 0.0, dot = 0.0, nlen = 0.0;
        for (int k = 0; k < 3; ++k) {
            radial[k] = v[k] - centre[k];
            len += radial[k] * radial[k];
        }
        for (int k = 0; k < 3; ++k) {
            dot += radial[k] * m.normals[3 * i + k];
            nlen += double(m.normals[3 * i + k]) * m.normals[3 * i + k];
        }
        EXPECT_NEAR(nlen, 1.0, 1e-5);
        worst = std::max(worst, std::acos(std::clamp(dot / std::sqrt(len * nlen), -1.0, 1.0)));
    }
    EXPECT_LT(worst * 180.0 / std::numbers::pi, 2.0);
}

TEST(MarchingCubesCpu, RandomFieldsGiveClosedOrientedManifolds) {
    std::mt19937 rng(20240601u);
    for (int i = 0; i < 20; ++i) {
        const Grid g = random_grid(rng, 12, true);
        const Mesh m = marching_cubes_cpu(g.view(), full_range(g));
        ASSERT_GT(m.triangle_count(), 0u);
        expect_closed_manifold(m, ("random field " + std::to_string(i)).c_str());
    }
}

TEST(MarchingCubesCpu, ValuesEqualToIsoGiveNoDegenerateTriangles) {
    // Inside is value >= iso, so grid values on the iso value are inside; the t clamp keeps the
    // vertices of edges meeting there apart.
    std::mt19937 rng(7u);
    for (int i = 0; i < 10; ++i) {
        Grid g = random_grid(rng, 10, true);
        for (float& v : g.v) v = v < -0.99f ? v : std::round(v * 1.4f);  // -1, 0 or 1 inside
        const Mesh m = marching_cubes_cpu(g.view(), full_range(g));
        expect_closed_manifold(m, ("ties " + std::to_string(i)).c_str());
        for (std::uint32_t a = 0; a < m.vertex_count(); ++a) {
            for (std::uint32_t b = a + 1; b < m.vertex_count(); ++b) {
                ASSERT_NE(vertex(m, a), vertex(m, b)) << "coincident vertices " << a << " " << b;
            }
        }
    }
}

TEST(MarchingCubesCpu, EverySingleCubeConfigurationIsClosed) {
    for (int cube = 0; cube < 256; ++cube) {
        Grid g(4, 4, 4, -1.0f);
        for (int c = 0; c < 8; ++c) {
            // Different inside values, so that vertices do not all sit at mid-edge.
            if ((cube >> c) & 1)
                g.at(1 + (c & 1), 1 + ((c >> 1) & 1), 1 + ((c >> 2) & 1)) = 0.2f + 0.1f * c;
        }
        const Mesh m = marching_cubes_cpu(g.view(), full_range(g));
        if (cube == 0) {
            EXPECT_EQ(m.triangle_count(), 0u);
            EXPECT_EQ(m.vertex_count(), 0u);
            continue;
        }
        expect_closed_manifold(m, ("case " + std::to_string(cube)).c_str());
    }
}

TEST(MarchingCubesCpu, SlabsReproduceTheFullRange) {
    std::mt19937 rng(99u);
    const Grid g = random_grid(rng, 12, false);
    const Mesh full = marching_cubes_cpu(g.view(), full_range(g));
    std::map<std::array<float, 3>, std::uint32_t> by_position;
    for (std::uint32_t i = 0; i < full.vertex_count(); ++i) {
        const std::array<float, 3> pos{full.positions[3 * i], full.positions[3 * i + 1],
                                       full.positions[3 * i + 2]};
        ASSERT_TRUE(by_position.emplace(pos, i).second) << "two vertices at one position";
    }
    for (std::uint32_t k : {1u, 5u, 10u}) {
        std::vector<std::uint32_t> joined;
        std::size_t vertices = 0;
        for (auto [z0, z1] : {std::pair{0u, k}, std::pair{k, g.nz - 1}}) {
            McParams p = full_range(g);
            p.z_begin = z0;
            p.z_end = z1;
            const Mesh slab = marching_cubes_cpu(g.view(), p);
            vertices += slab.vertex_count();
            std::vector<std::uint32_t> to_full(slab.vertex_count());
            for (std::uint32_t i = 0; i < slab.vertex_count(); ++i) {
                const std::array<float, 3> pos{slab.positions[3 * i], slab.positions[3 * i + 1],
                                               slab.positions[3 * i + 2]};
                auto it = by_position.find(pos);
                ASSERT_NE(it, by_position.end()) << "slab vertex not in the full mesh";
                to_full[i] = it->second;
                // Same buffer, same border: the normals agree to the bit.
                EXPECT_EQ(std::memcmp(&slab.normals[3 * i], &full.normals[3 * it->second],
                                      3 * sizeof(float)),
                          0);
            }
            for (std::uint32_t idx : slab.indices) joined.push_back(to_full[idx]);
        }
        // Cells come in z order, so the two slabs' triangles concatenate to the full list.
        EXPECT_EQ(joined, full.indices) << "split at z = " << k;
        // The only duplicates are plane k's x and y vertices.
        std::size_t plane_k = 0;
        for (std::uint32_t y = 0; y < g.ny; ++y) {
            for (std::uint32_t x = 0; x < g.nx; ++x) {
                const bool in = g.view().at(x, y, k) >= 0.0f;
                if (x + 1 < g.nx && (g.view().at(x + 1, y, k) >= 0.0f) != in) ++plane_k;
                if (y + 1 < g.ny && (g.view().at(x, y + 1, k) >= 0.0f) != in) ++plane_k;
            }
        }
        EXPECT_EQ(vertices, full.vertex_count() + plane_k) << "split at z = " << k;
    }
}

TEST(MarchingCubesCpu, VerticesComeInPointOrderWithAxesXYZ) {
    // One inside corner at the origin: its three edges give vertices x, y, z, then one triangle.
    Grid g(2, 2, 2, -1.0f);
    g.at(0, 0, 0) = 1.0f;
    McParams p = full_range(g, 0.0f, 2.0f);
    p.origin[0] = 10.0f;
    p.origin[1] = 20.0f;
    p.origin[2] = 30.0f;
    const Mesh m = marching_cubes_cpu(g.view(), p);
    ASSERT_EQ(m.vertex_count(), 3u);
    EXPECT_EQ(m.positions, (std::vector<float>{11, 20, 30, 10, 21, 30, 10, 20, 31}));
    EXPECT_EQ(m.indices, (std::vector<std::uint32_t>{0, 1, 2}));
    // One-sided differences: g(0,0,0) = (-1,-1,-1), g(1,0,0) = (-1,0,0) per unit h = 2.
    const float s = 1.0f / std::sqrt(6.0f);
    EXPECT_NEAR(m.normals[0], 2 * s, 1e-6);
    EXPECT_NEAR(m.normals[1], s, 1e-6);
    EXPECT_NEAR(m.normals[2], s, 1e-6);
}

TEST(MarchingCubesCpu, FlatGradientFallsBackToTheEdgeDirectionOutward) {
    // Along x: -1, 1, -1, 1. Central differences vanish at x = 1 and x = 2, so the edge 1 -> 2
    // (inside to outside) has no gradient; its normal must still point out, along +x.
    Grid g(4, 2, 2);
    for (std::uint32_t z = 0; z < 2; ++z) {
        for (std::uint32_t y = 0; y < 2; ++y) {
            for (std::uint32_t x = 0; x < 4; ++x) g.at(x, y, z) = x % 2 ? 1.0f : -1.0f;
        }
    }
    const Mesh m = marching_cubes_cpu(g.view(), full_range(g));
    ASSERT_EQ(m.vertex_count(), 12u);  // 3 x-edges on each of the 4 rows
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
        const float x = m.positions[3 * i];
        const float expected = x > 1.0f && x < 2.0f ? 1.0f : -1.0f;
        EXPECT_EQ(m.normals[3 * i], expected) << "vertex at x = " << x;
        EXPECT_EQ(m.normals[3 * i + 1], 0.0f);
        EXPECT_EQ(m.normals[3 * i + 2], 0.0f);
    }
}

TEST(MarchingCubesCpu, RowPitchPaddingIsIgnored) {
    std::mt19937 rng(5u);
    const Grid g = random_grid(rng, 8, true);
    const std::uint32_t pitch = 11;
    std::vector<float> padded(std::size_t(pitch) * g.ny * g.nz, 1e30f);
    for (std::size_t row = 0; row < std::size_t(g.ny) * g.nz; ++row) {
        std::copy_n(&g.v[row * g.nx], g.nx, &padded[row * pitch]);
    }
    const Mesh a = marching_cubes_cpu(g.view(), full_range(g));
    const Mesh b =
        marching_cubes_cpu(FieldView{padded.data(), g.nx, g.ny, g.nz, pitch}, full_range(g));
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.indices, b.indices);
}

TEST(MarchingCubesCpu, RejectsBadGridsAndRanges) {
    const Grid g(4, 4, 4, -1.0f);
    auto expect_invalid = [](const FieldView& f, const McParams& p) {
        try {
            marching_cubes_cpu(f, p);
            ADD_FAILURE() << "no exception";
        } catch (const fdmsurf::Error& e) {
            EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
        }
    };
    McParams p = full_range(g);
    p.z_end = 4;
    expect_invalid(g.view(), p);
    p = full_range(g);
    p.z_begin = 3;
    p.z_end = 2;
    expect_invalid(g.view(), p);
    p = full_range(g);
    p.spacing = 0.0f;
    expect_invalid(g.view(), p);
    expect_invalid(FieldView{g.v.data(), 4, 4, 4, 3}, full_range(g));
    expect_invalid(FieldView{nullptr, 0, 0, 0, 0}, McParams{});
}

TEST(MarchingCubesCpu, SinglePlaneEmitsItsVerticesAndNoTriangles) {
    std::mt19937 rng(3u);
    const Grid g = random_grid(rng, 6, false);
    McParams p = full_range(g);
    p.z_begin = p.z_end = 2;
    const Mesh m = marching_cubes_cpu(g.view(), p);
    EXPECT_EQ(m.triangle_count(), 0u);
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) EXPECT_EQ(m.positions[3 * i + 2], 2.0f);
}

}  // namespace
