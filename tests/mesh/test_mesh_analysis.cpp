// Tests of the mesh analysis (mesh_stats_detail.hpp): the pieces and their statistics found once,
// the cavity removal reading them, and the statistics of the pieces kept, against the
// statistics computed on the mesh after the removal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "mesh/cavities.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_shapes.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"

namespace fdmsurf {
namespace {

// Appends `add`'s vertices to `m` and puts its triangles (turned inside out with `inward`) at
// `at` among m's, so that pieces interleave in the triangle order.
void insert_piece(Mesh& m, const Mesh& add, bool inward, std::size_t at) {
    const auto base = static_cast<std::uint32_t>(m.vertex_count());
    m.positions.insert(m.positions.end(), add.positions.begin(), add.positions.end());
    for (float n : add.normals) m.normals.push_back(inward ? -n : n);
    std::vector<std::uint32_t> tris;
    for (std::size_t t = 0; t < add.triangle_count(); ++t) {
        tris.push_back(base + add.indices[3 * t]);
        tris.push_back(base + add.indices[3 * t + (inward ? 2 : 1)]);
        tris.push_back(base + add.indices[3 * t + (inward ? 1 : 2)]);
    }
    m.indices.insert(m.indices.begin() + std::ptrdiff_t(3 * at), tris.begin(), tris.end());
}

// Several chunks of triangles (kTriangleChunk), with pieces whose triangles interleave: an
// outer sphere (327,680 triangles), six cavities of several sizes whose triangles sit among
// the outer one's (so that removing them moves every chunk boundary after them), a sphere
// outside it, a speck, and a vertex no triangle uses. The cavities' vertices come first, so
// that they are the first pieces.
Mesh interleaved_pieces() {
    Mesh m;
    const std::array<std::array<double, 4>, 6> voids = {{{2.0, 0, 0, 0},
                                                         {0.9, 5, 0, 0},
                                                         {0.6, -5, 0, 0},
                                                         {1.2, 0, 5, 0},
                                                         {0.5, 0, -5, 0},
                                                         {1.5, 0, 0, 5}}};
    std::size_t at = 0;
    for (const auto& v : voids) {
        insert_piece(m, test::icosphere(v[0], 3, {v[1], v[2], v[3]}), true, at);
        at = m.triangle_count();
    }
    const Mesh outer = test::icosphere(10.0, 7);
    insert_piece(m, outer, false, m.triangle_count());
    // Move each cavity's triangles in among the outer sphere's.
    std::vector<std::uint32_t> cavities(m.indices.begin(), m.indices.begin() + 3 * at);
    m.indices.erase(m.indices.begin(), m.indices.begin() + 3 * at);
    const std::size_t per = at / voids.size();
    for (std::size_t i = 0; i < voids.size(); ++i) {
        const std::size_t where = (i + 1) * 45'000 + i * per;
        m.indices.insert(m.indices.begin() + std::ptrdiff_t(3 * where),
                         cavities.begin() + std::ptrdiff_t(3 * i * per),
                         cavities.begin() + std::ptrdiff_t(3 * (i + 1) * per));
    }
    insert_piece(m, test::icosphere(3.0, 4, {30, 0, 0}), false, 100'000);
    insert_piece(m, test::icosphere(0.05, 1, {0, 30, 0}), false, m.triangle_count());
    test::add_vertex(m, 50, 50, 50);
    m.normals.insert(m.normals.end(), {1, 0, 0});
    return m;
}

// The plain removal: the pieces of negative volume above -max_volume dropped, the other
// vertices (unreferenced ones too) and triangles kept in order, one by one.
Mesh plainly_removed(const Mesh& mesh, double max_volume) {
    const detail::VertexPieces pieces = detail::vertex_pieces(mesh);
    std::vector<double> volume(pieces.count, 0.0);
    const auto at = [&](std::uint32_t v) {
        return std::array<double, 3>{mesh.positions[3 * v], mesh.positions[3 * v + 1],
                                     mesh.positions[3 * v + 2]};
    };
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const auto a = at(mesh.indices[3 * t]), b = at(mesh.indices[3 * t + 1]),
                   c = at(mesh.indices[3 * t + 2]);
        volume[pieces.of_vertex[mesh.indices[3 * t]]] +=
            (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
             a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    const auto dropped = [&](std::uint32_t v) {
        const std::uint32_t p = pieces.of_vertex[v];
        return p != detail::kNoPiece && volume[p] < 0.0 && -volume[p] < max_volume;
    };
    Mesh out;
    std::vector<std::uint32_t> remap(mesh.vertex_count());
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        if (dropped(v)) continue;
        remap[v] = std::uint32_t(out.vertex_count());
        for (int k = 0; k < 3; ++k) {
            out.positions.push_back(mesh.positions[3 * v + k]);
            out.normals.push_back(mesh.normals[3 * v + k]);
        }
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        if (!dropped(mesh.indices[3 * t]))
            for (int k = 0; k < 3; ++k) out.indices.push_back(remap[mesh.indices[3 * t + k]]);
    return out;
}

TEST(MeshAnalysis, StatisticsOfThePiecesKeptEqualThoseOfTheMeshAfter) {
    const Mesh mesh = interleaved_pieces();
    ASSERT_GT(mesh.triangle_count(), 5 * detail::kTriangleChunk);
    ASSERT_EQ(compute_stats(mesh).pieces, 9u);
    for (double max_volume : {5.0, std::numeric_limits<double>::infinity()}) {
        // The plain way: the cavities removed, then the statistics of what is left.
        Mesh plain = mesh;
        const std::size_t removed = remove_cavities(plain, max_volume);
        EXPECT_EQ(removed, max_volume < 10.0 ? 3u : 6u);
        // (The removal moves vertices and triangles in place, chunk by chunk: the same as one
        // by one.)
        const Mesh one_by_one = plainly_removed(mesh, max_volume);
        EXPECT_EQ(plain.positions, one_by_one.positions);
        EXPECT_EQ(plain.normals, one_by_one.normals);
        EXPECT_EQ(plain.indices, one_by_one.indices);
        const MeshStats after = compute_stats(plain);
        std::vector<MeshStats> pieces = piece_stats(plain);
        for (unsigned threads : {1u, 2u, 3u, 0u}) {
            // The fused way: one analysis, the cavities removed with it, its sums of the rest.
            Mesh fused = mesh;
            detail::MeshAnalysis analysis = detail::analyse_mesh(fused, true, "test", threads);
            EXPECT_EQ(detail::remove_cavities_below(fused, max_volume, &analysis), removed);
            EXPECT_EQ(fused.positions, plain.positions);
            EXPECT_EQ(fused.normals, plain.normals);
            EXPECT_EQ(fused.indices, plain.indices);
            ExpectSameStats(detail::total_stats(analysis, fused), after);
            std::vector<MeshStats> kept = analysis.stats;
            std::stable_sort(kept.begin(), kept.end(), [](const MeshStats& a, const MeshStats& b) {
                return a.area > b.area;
            });
            ASSERT_EQ(kept.size(), pieces.size());
            for (std::size_t p = 0; p < kept.size(); ++p) ExpectSameStats(kept[p], pieces[p]);
            // And the analysis kept up to date is the analysis of the mesh after.
            const detail::MeshAnalysis fresh = detail::analyse_mesh(fused, true, "test", threads);
            EXPECT_EQ(analysis.pieces.of_vertex, fresh.pieces.of_vertex);
            ASSERT_EQ(analysis.runs.size(), fresh.runs.size());
            for (std::size_t r = 0; r < fresh.runs.size(); ++r) {
                EXPECT_EQ(analysis.runs[r].piece, fresh.runs[r].piece);
                EXPECT_EQ(analysis.runs[r].triangles, fresh.runs[r].triangles);
            }
        }
    }
}

// keep_pieces against its plain reference on `mesh`, for topology and volumes alone: the same
// vertices, normals and triangles after, and the same analysis (pieces, statistics to the bit,
// runs) as the plain copy's analysis found again; without the update, the same mesh.
void ExpectKeptAsPlainly(const Mesh& mesh, const std::vector<char>& drop, const char* what) {
    for (bool topology : {false, true}) {
        SCOPED_TRACE(std::string(what) + (topology ? ", with topology" : ", volumes only"));
        const detail::MeshAnalysis before = detail::analyse_mesh(mesh, topology, "test");
        ASSERT_EQ(drop.size(), before.pieces.count);
        Mesh fast = mesh, plain = mesh, alone = mesh;
        detail::MeshAnalysis a = before, b = before, c = before;
        detail::keep_pieces(fast, a, drop, true);
        detail::keep_pieces_plain(plain, b, drop, true);
        detail::keep_pieces(alone, c, drop, false);
        EXPECT_EQ(fast.positions, plain.positions);
        EXPECT_EQ(fast.normals, plain.normals);
        EXPECT_EQ(fast.indices, plain.indices);
        EXPECT_EQ(alone.positions, plain.positions);
        EXPECT_EQ(alone.normals, plain.normals);
        EXPECT_EQ(alone.indices, plain.indices);
        EXPECT_EQ(a.pieces.count, b.pieces.count);
        EXPECT_EQ(a.pieces.of_vertex, b.pieces.of_vertex);
        ASSERT_EQ(a.stats.size(), b.stats.size());
        for (std::size_t q = 0; q < a.stats.size(); ++q) ExpectSameStats(a.stats[q], b.stats[q]);
        ASSERT_EQ(a.runs.size(), b.runs.size());
        for (std::size_t r = 0; r < a.runs.size(); ++r) {
            EXPECT_EQ(a.runs[r].piece, b.runs[r].piece);
            EXPECT_EQ(a.runs[r].triangles, b.runs[r].triangles);
        }
    }
}

// Drop sets over a real surface's pieces: its cavities (negative volume), every other piece,
// the largest alone, all but the largest, and the first cavity alone.
void ExpectKeptAsPlainlyOn(const Mesh& mesh) {
    const detail::MeshAnalysis a = detail::analyse_mesh(mesh, false, "test");
    const std::size_t n = a.pieces.count;
    ASSERT_GE(n, 2u);
    std::size_t largest = 0, first_cavity = n;
    for (std::size_t q = 0; q < n; ++q) {
        if (a.stats[q].triangles > a.stats[largest].triangles) largest = q;
        if (a.stats[q].volume < 0.0 && first_cavity == n) first_cavity = q;
    }
    ASSERT_LT(first_cavity, n);
    std::vector<char> cavities(n), alternate(n), only_largest(n, 0), but_largest(n, 1), one(n, 0);
    for (std::size_t q = 0; q < n; ++q) {
        cavities[q] = a.stats[q].volume < 0.0;
        alternate[q] = q % 2;
    }
    only_largest[largest] = 1;
    but_largest[largest] = 0;
    one[first_cavity] = 1;
    ExpectKeptAsPlainly(mesh, cavities, "the cavities");
    ExpectKeptAsPlainly(mesh, alternate, "every other piece");
    ExpectKeptAsPlainly(mesh, only_largest, "the largest piece");
    ExpectKeptAsPlainly(mesh, but_largest, "all but the largest piece");
    ExpectKeptAsPlainly(mesh, one, "one cavity");
}

TEST(MeshAnalysis, PiecesKeptAsThePlainCopyOnCrambinAndInterleavedPieces) {
    ExpectKeptAsPlainlyOn(read_mesh(test::data_path("1crn-fdm-0.5.ply")));
    ExpectKeptAsPlainlyOn(interleaved_pieces());
}

// Haemoglobin's FDM surface at 0.3 Å with every void kept: many chunks, voids among them.
class PiecesKept : public GpuTest {};

TEST_F(PiecesKept, AsThePlainCopyOnHaemoglobin) {
    const Atoms atoms = read_structure(test::data_path("4hhb.pdb.gz")).atoms;
    const Mesh mesh =
        engine()
            .make_surface(atoms, SurfaceOptions{.spacing = 0.3f, .min_cavity_volume = 0.0f})
            .mesh;
    ASSERT_GT(mesh.triangle_count(), 10 * detail::kTriangleChunk);
    ExpectKeptAsPlainlyOn(mesh);
}

TEST(MeshAnalysis, PiecesAreThoseOfTheUnionFindInAnyVertexOrder) {
    // The analysis sweeps the vertices in order for the pieces; the union-find of vertex_pieces
    // takes the triangles. Both number pieces by their smallest vertex. Degenerate triangles
    // join their vertices too (one of them used by nothing else), and in a shuffled vertex
    // order every block's triangles span the mesh (the plan's fallback).
    Mesh mesh = interleaved_pieces();
    const auto n = static_cast<std::uint32_t>(mesh.vertex_count());
    test::add_vertex(mesh, 40, 0, 0);
    test::add_vertex(mesh, 41, 0, 0);
    mesh.normals.insert(mesh.normals.end(), {1, 0, 0, 1, 0, 0});
    mesh.indices.insert(mesh.indices.end(), {n, n, 0, n + 1, n + 1, n + 1});
    Mesh shuffled = mesh;
    std::vector<std::uint32_t> order(shuffled.vertex_count());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(7));
    for (std::uint32_t& v : shuffled.indices) v = order[v];
    for (std::size_t v = 0; v < order.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            shuffled.positions[3 * order[v] + k] = mesh.positions[3 * v + k];
            shuffled.normals[3 * order[v] + k] = mesh.normals[3 * v + k];
        }
    // Crambin's surface from the grid (its triangles in the order of their vertices: the plan's
    // blocks), and two copies of it sharing a vertex, the copy's triangles first (pieces meet
    // across the threads' vertex ranges).
    const Mesh crambin = read_mesh(test::data_path("1crn-fdm-0.5.ply"));
    Mesh glued = crambin;
    std::vector<std::uint32_t> copy;
    for (std::uint32_t v : crambin.indices)
        copy.push_back(v == 7 ? 7 : v + std::uint32_t(crambin.vertex_count()));
    glued.indices.insert(glued.indices.begin(), copy.begin(), copy.end());
    glued.positions.insert(glued.positions.end(), crambin.positions.begin(),
                           crambin.positions.end());
    glued.normals.insert(glued.normals.end(), crambin.normals.begin(), crambin.normals.end());
    glued.atoms.clear();
    for (const Mesh* m : {&crambin, static_cast<const Mesh*>(&glued)}) {
        const detail::VertexPieces expected = detail::vertex_pieces(*m, 1);
        for (unsigned threads : {1u, 2u, 5u})
            EXPECT_EQ(detail::analyse_mesh(*m, true, "test", threads).pieces.of_vertex,
                      expected.of_vertex);
    }
    EXPECT_EQ(compute_stats(glued).pieces, 2 * compute_stats(crambin).pieces - 1);
    EXPECT_EQ(compute_stats(glued).nonmanifold_vertices, 1u);
    for (const Mesh* m : {&mesh, &shuffled}) {
        const detail::VertexPieces expected = detail::vertex_pieces(*m, 1);
        for (unsigned threads : {1u, 2u, 5u}) {
            const detail::MeshAnalysis a = detail::analyse_mesh(*m, true, "test", threads);
            EXPECT_EQ(a.pieces.count, expected.count);
            EXPECT_EQ(a.pieces.of_vertex, expected.of_vertex);
            const detail::MeshAnalysis plain = detail::analyse_mesh(*m, false, "test", threads);
            EXPECT_EQ(plain.pieces.of_vertex, expected.of_vertex);
        }
        const MeshStats s = compute_stats(*m);
        EXPECT_EQ(s.pieces, 10u);  // the nine and the lone vertex of a degenerate triangle
        EXPECT_EQ(s.closed_pieces, 10u);
        EXPECT_EQ(s.degenerate_triangles, 2u);
    }
    // The same figures in either order (the sums up to their order: pieces are numbered
    // differently, so their sums are added in another order).
    const MeshStats a = compute_stats(mesh), b = compute_stats(shuffled);
    EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
    EXPECT_EQ(a.boundary_edges + a.nonmanifold_edges + a.nonmanifold_vertices, 0u);
    EXPECT_EQ(b.boundary_edges + b.nonmanifold_edges + b.nonmanifold_vertices, 0u);
    EXPECT_NEAR(a.area, b.area, 1e-9 * a.area);
    EXPECT_NEAR(a.volume, b.volume, 1e-9 * a.volume);
}

}  // namespace
}  // namespace fdmsurf
