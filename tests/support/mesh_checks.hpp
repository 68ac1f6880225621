// Test helpers: a GoogleTest assertion that a mesh is closed, manifold and outward-oriented, and
// expectations that two meshes' statistics are equal.
#pragma once

#include <gtest/gtest.h>

#include <exception>
#include <string>

#include "fdmsurf/mesh.hpp"

// Use as EXPECT_TRUE(IsClosedManifold(mesh)); a failure lists every invariant that broke.
inline ::testing::AssertionResult IsClosedManifold(const fdmsurf::Mesh& mesh) {
    fdmsurf::MeshStats s;
    try {
        s = fdmsurf::compute_stats(mesh);
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "invalid mesh: " << e.what();
    }
    if (s.is_closed_manifold()) return ::testing::AssertionSuccess();
    auto failure = ::testing::AssertionFailure();
    failure << "mesh of " << s.vertices << " vertices, " << s.triangles << " triangles is not "
            << "a closed manifold:";
    auto count = [&failure](std::size_t n, const char* what) {
        if (n != 0) failure << " " << n << " " << what << ";";
    };
    count(s.boundary_edges, "boundary edges");
    count(s.nonmanifold_edges, "non-manifold edges");
    count(s.nonmanifold_vertices, "non-manifold vertices");
    count(s.inconsistent_edges, "inconsistently oriented edges");
    count(s.degenerate_triangles, "degenerate triangles");
    if (!(s.volume > 0.0)) failure << " volume " << s.volume << " A^3 is not positive;";
    return failure;
}

// Every field of two MeshStats equal, the area and volume bit for bit.
inline void ExpectSameStats(const fdmsurf::MeshStats& a, const fdmsurf::MeshStats& b) {
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.volume, b.volume);
    EXPECT_EQ(a.pieces, b.pieces);
    EXPECT_EQ(a.closed_pieces, b.closed_pieces);
    EXPECT_EQ(a.boundary_edges, b.boundary_edges);
    EXPECT_EQ(a.nonmanifold_edges, b.nonmanifold_edges);
    EXPECT_EQ(a.nonmanifold_vertices, b.nonmanifold_vertices);
    EXPECT_EQ(a.inconsistent_edges, b.inconsistent_edges);
    EXPECT_EQ(a.degenerate_triangles, b.degenerate_triangles);
    EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
}
