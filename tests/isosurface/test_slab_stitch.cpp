// Tests of the slab stitch (src/isosurface/slab_stitch.cpp): the in-place stitch of the slab
// pipeline (parts appended to one mesh, each seam stitched as the next part comes) gives
// stitch_slabs' mesh, vertex for vertex and index for index, on the fields of real structures
// and on noise, cut into slabs of every size down to one cell; both equal the single pass's
// surface up to the seams' vertex order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/density_cpu.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "isosurface/marching_cubes_host.hpp"
#include "isosurface/slab_stitch.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"
#include "support/test_fields.hpp"

namespace {

using fdmsurf::Mesh;
using fdmsurf::detail::McParams;
using fdmsurf::detail::PlaneStack;

using Field = fdmsurf::test::TestField;
using fdmsurf::test::structure_field;

Field noise(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz, std::uint32_t seed) {
    return fdmsurf::test::noise_field(nx, ny, nz, seed);
}

// The parts of the slab pipeline: part j the cells of planes starts[j] .. starts[j + 1].
McParams part_params(const Field& f, const std::vector<std::uint32_t>& starts, std::size_t j) {
    McParams p = f.params;
    p.z_begin = starts[j];
    p.z_end = starts[j + 1];
    return p;
}

// stitch_slabs on separate parts against the parts appended to one mesh, each seam stitched in
// place before the next part comes, as src/engine/slabs.cpp does.
void expect_in_place_equals_reference(const Field& f, const std::vector<std::uint32_t>& starts) {
    const PlaneStack s = f.stack();
    std::vector<Mesh> parts;
    Mesh joined;
    for (std::size_t j = 0; j + 1 < starts.size(); ++j) {
        const McParams p = part_params(f, starts, j);
        parts.push_back(fdmsurf::detail::marching_cubes_host(s, p));
        const std::size_t first_vertex = joined.vertex_count(), first_index = joined.indices.size();
        // A small scale: the mesh also grows (and copies) between parts.
        fdmsurf::detail::marching_cubes_host_append(s, p, joined, j % 2 ? 1.0 : 1.3);
        if (j + 2 < starts.size()) {
            const std::uint32_t z = starts[j + 1];
            fdmsurf::detail::stitch_top_plane(joined, first_vertex, first_index, f.plane(z),
                                              f.plane(z + 1), f.nx, f.ny, f.params.iso);
        }
    }
    const fdmsurf::detail::SlabPlanes planes{
        f.nx, f.ny, f.nz, [&](std::uint32_t z) { return f.plane(z); }};
    const Mesh reference = fdmsurf::detail::stitch_slabs(parts, planes, f.params.iso, starts);
    ASSERT_EQ(joined.vertex_count(), reference.vertex_count());
    ASSERT_EQ(joined.triangle_count(), reference.triangle_count());
    EXPECT_TRUE(joined.positions == reference.positions);
    EXPECT_TRUE(joined.normals == reference.normals);
    EXPECT_TRUE(joined.indices == reference.indices);
    // The single pass's surface: the same vertices and triangles, in another order at the seams.
    const Mesh whole = fdmsurf::detail::marching_cubes_cpu(
        fdmsurf::detail::FieldView{f.values.data(), f.nx, f.ny, f.nz, f.nx}, f.params);
    EXPECT_EQ(joined.vertex_count(), whole.vertex_count());
    EXPECT_EQ(joined.triangle_count(), whole.triangle_count());
}

TEST(SlabStitch, InPlaceEqualsTheReferenceOnRealStructures) {
    for (const char* file : {"1crn.pdb", "4hhb.pdb.gz"}) {
        SCOPED_TRACE(file);
        const Field f = structure_field(file, file[0] == '1' ? 0.5f : 1.0f);
        const std::uint32_t last = f.nz - 1;
        // Two and three slabs, a one-cell part, a one-cell part at the top.
        for (const std::vector<std::uint32_t>& starts :
             {std::vector<std::uint32_t>{0, last / 2, last},
              std::vector<std::uint32_t>{0, last / 3, 2 * last / 3, last},
              std::vector<std::uint32_t>{0, 9, 10, last},
              std::vector<std::uint32_t>{0, last - 1, last}}) {
            SCOPED_TRACE(std::to_string(starts.size() - 1) + " parts");
            expect_in_place_equals_reference(f, starts);
        }
        if (HasFailure()) return;
    }
}

TEST(SlabStitch, InPlaceEqualsTheReferenceOnNoise) {
    // Nearly every edge crossed: the seams' vertices and the re-pointed indices at their densest.
    const Field f = noise(67, 23, 19, 31u);
    expect_in_place_equals_reference(f, {0, 1, 2, 5, 11, 17, 18});
    const Field g = noise(1, 9, 6, 7u);
    expect_in_place_equals_reference(g, {0, 3, 5});
}

TEST(SlabStitch, InPlaceJoinIsClosedOnCrambin) {
    const Field f = structure_field("1crn.pdb", 0.5f);
    const PlaneStack s = f.stack();
    Mesh joined;
    const std::vector<std::uint32_t> starts{0, 8, 16, f.nz - 1};
    for (std::size_t j = 0; j + 1 < starts.size(); ++j) {
        const std::size_t first_vertex = joined.vertex_count(), first_index = joined.indices.size();
        fdmsurf::detail::marching_cubes_host_append(s, part_params(f, starts, j), joined);
        if (j + 2 < starts.size())
            fdmsurf::detail::stitch_top_plane(joined, first_vertex, first_index,
                                              f.plane(starts[j + 1]), f.plane(starts[j + 1] + 1),
                                              f.nx, f.ny, f.params.iso);
    }
    EXPECT_TRUE(IsClosedManifold(joined));
}

}  // namespace
