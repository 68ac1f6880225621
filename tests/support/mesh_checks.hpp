// Test helper: a GoogleTest assertion that a mesh is closed, manifold and outward-oriented.
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
