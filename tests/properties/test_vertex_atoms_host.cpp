// The host's vertex atoms (groups of vertex cells sharing candidate lists, eight lanes) against
// the plain float reference, every atom tried per vertex: the same atom for every vertex tested,
// bit for bit, on real structures' surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"
#include "properties/vertex_atoms_cpu.hpp"
#include "properties/vertex_atoms_host.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using fdmsurf::test::data_path;

namespace {

class VertexAtomsHost : public GpuTest {};

Mesh surface(Engine& e, const Atoms& atoms, SurfaceKind kind, float spacing) {
    SurfaceOptions o;
    o.surface = kind;
    o.spacing = spacing;
    return e.make_surface(atoms, o).mesh;
}

// Every `step`-th vertex's atom (stride 2 in `out`, to check that the other words stay) against
// the reference; returns the number that differ (the first five reported).
std::size_t count_differing(const Mesh& mesh, const Atoms& atoms, float add, std::size_t step,
                            const std::string& name) {
    const std::size_t n = mesh.vertex_count();
    std::vector<std::uint32_t> out(2 * n, 7u);
    detail::host_vertex_atoms(atoms, mesh.positions.data(), n, add, out.data(), 2);
    std::vector<float> sample;
    std::vector<std::size_t> which;
    for (std::size_t v = 0; v < n; v += step) {
        which.push_back(v);
        sample.insert(sample.end(), &mesh.positions[3 * v], &mesh.positions[3 * v + 3]);
    }
    const std::vector<std::uint32_t> ref =
        detail::vertex_atoms_float_cpu(sample.data(), which.size(), atoms, add);
    std::size_t differ = 0;
    for (std::size_t k = 0; k < which.size(); ++k) {
        EXPECT_EQ(out[2 * which[k] + 1], 7u);
        if (out[2 * which[k]] != ref[k] && ++differ <= 5)
            ADD_FAILURE() << name << " vertex " << which[k] << ": host atom " << out[2 * which[k]]
                          << ", reference " << ref[k];
    }
    std::printf("  %s: %zu of %zu vertices tested, %zu differ\n", name.c_str(), which.size(), n,
                differ);
    return differ;
}

}  // namespace

TEST_F(VertexAtomsHost, EqualsFloatReferenceOnRealSurfaces) {
    // 4HHB's SES (every vertex); crambin's SAS (crease vertices are exact ties), also moved
    // 3,000 Å from the origin (coordinates' differences then round to 2.4e-4 Å); 4YVS's SES at
    // 1 Å (every 7th vertex), and a copy of 4YVS 400 Å away from it (a box mostly
    // empty, as the capsid-like shells).
    EXPECT_EQ(count_differing(surface(engine(), read_structure(data_path("4hhb.pdb.gz")).atoms,
                                      SurfaceKind::Ses, 0.5f),
                              read_structure(data_path("4hhb.pdb.gz")).atoms, 0.0f, 1, "4hhb"),
              0u);
    for (const bool far : {false, true}) {
        Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
        if (far)
            for (float& c : atoms.xyz) c += 3000.0f;
        const Mesh mesh = surface(engine(), atoms, SurfaceKind::Sas, 0.5f);
        EXPECT_EQ(count_differing(mesh, atoms, 1.4f, 1, far ? "1crn sas far" : "1crn sas"), 0u);
    }
    Atoms pair = read_structure(data_path("4yvs.cif.gz")).atoms;
    const Mesh one = surface(engine(), pair, SurfaceKind::Ses, 1.0f);
    EXPECT_EQ(count_differing(one, pair, 0.0f, 7, "4yvs"), 0u);
    const std::size_t n = pair.size();
    pair.xyz.resize(6 * n);
    pair.radius.resize(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) pair.xyz[3 * (n + i) + a] = pair.xyz[3 * i + a] + 400.0f;
        pair.radius[n + i] = pair.radius[i];
    }
    pair.meta.clear();
    pair.element.clear();
    Mesh two = one;  // the first copy's surface, and the same moved onto the second copy
    two.positions.resize(2 * one.positions.size());
    for (std::size_t k = 0; k < one.positions.size(); ++k)
        two.positions[one.positions.size() + k] = one.positions[k] + 400.0f;
    two.normals.resize(two.positions.size());
    EXPECT_EQ(count_differing(two, pair, 0.0f, 13, "4yvs pair"), 0u);
}

TEST_F(VertexAtomsHost, VertexNotFiniteHasNoAtomAndLeavesOthersAlone) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    Mesh mesh = surface(engine(), atoms, SurfaceKind::Ses, 0.5f);
    mesh.positions[3] = std::numeric_limits<float>::quiet_NaN();
    mesh.positions[8] = std::numeric_limits<float>::infinity();
    std::vector<std::uint32_t> out(mesh.vertex_count());
    detail::host_vertex_atoms(atoms, mesh.positions.data(), out.size(), 0.0f, out.data(), 1);
    const std::vector<std::uint32_t> ref =
        detail::vertex_atoms_float_cpu(mesh.positions.data(), out.size(), atoms, 0.0f);
    EXPECT_EQ(out[1], 0xffffffffu);
    EXPECT_EQ(out[2], 0xffffffffu);
    EXPECT_EQ(out, ref);
}
