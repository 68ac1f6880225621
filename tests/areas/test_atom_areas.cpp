// Per-atom areas: Shrake-Rupley SAS against closed forms (one ball, two and three overlapping
// balls, twins) and a mesh's area shared out to its atoms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <numbers>
#include <numeric>

#include "fdmsurf/fdmsurf.hpp"
#include "mesh/mesh_shapes.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using fdmsurf_test::make_atoms;

namespace {

constexpr double kPi = std::numbers::pi;

// The exposed area of ball 1 (radius a) cut by ball 2 (radius b) at distance d:
// 2π a (a + x), x = (d² + a² − b²) / (2d) the distance from centre 1 to the cutting plane.
double cut_sphere(double a, double b, double d) {
    const double x = (d * d + a * a - b * b) / (2 * d);
    return 2 * kPi * a * (a + std::clamp(x, -a, a));
}

}  // namespace

TEST(AtomSasAreas, OneBallIsItsWholeSphere) {
    const std::vector<double> a = atom_sas_areas(make_atoms({{1, 2, 3, 1.7f}}), 1.4f, 500);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_NEAR(a[0], 4 * kPi * 3.1 * 3.1, 1e-4);  // float radii
}

TEST(AtomAreas, BadAtomsAreInvalidArgumentsNamingTheAtom) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto code_and_message = [](auto&& f) -> std::pair<ErrorCode, std::string> {
        try {
            f();
        } catch (const Error& e) {
            return {e.code(), e.what()};
        }
        return {ErrorCode::Internal, "no error"};
    };
    const Atoms nan_xyz = make_atoms({{0, 0, 0, 1.5f}, {nan, 0, 0, 1.5f}});
    const Atoms zero_radius = make_atoms({{0, 0, 0, 1.5f}, {2, 0, 0, 0.0f}});
    const Atoms negative_radius = make_atoms({{0, 0, 0, 1.5f}, {2, 0, 0, -1.0f}});
    // A radius of 0 is a ball of the probe's radius in the sas, as for the surface.
    EXPECT_GT(atom_exact_areas(zero_radius, 1.4f)[1], 0.0);
    EXPECT_GT(atom_sas_areas(zero_radius, 1.4f)[1], 0.0);
    for (const auto& bad : {std::pair{&nan_xyz, 1.4f}, std::pair{&zero_radius, 0.0f},
                            std::pair{&negative_radius, 1.4f}}) {
        const Atoms* atoms = bad.first;  // not a structured binding: clang 14 cannot capture one
        const float probe = bad.second;
        const auto sas = code_and_message([&] { atom_sas_areas(*atoms, probe); });
        const auto exact = code_and_message([&] { atom_exact_areas(*atoms, probe); });
        EXPECT_EQ(sas.first, ErrorCode::InvalidArgument) << sas.second;
        EXPECT_EQ(exact.first, ErrorCode::InvalidArgument) << exact.second;
        EXPECT_NE(sas.second.find("atom_sas_areas: atom 2 has"), std::string::npos) << sas.second;
        EXPECT_NE(exact.second.find("atom_exact_areas: atom 2 has"), std::string::npos)
            << exact.second;
    }
}

TEST(AtomSasAreas, OverlappingBallsMatchTheClosedForm) {
    // Two balls of radii 1.5 and 1.9 (probe 1.4: 2.9 and 3.3), 3 Å apart: caps of 40% and 55%.
    const Atoms two = make_atoms({{0, 0, 0, 1.5f}, {3, 0, 0, 1.9f}});
    const std::vector<double> a = atom_sas_areas(two, 1.4f, 2000);
    EXPECT_NEAR(a[0], cut_sphere(2.9, 3.3, 3.0), 0.005 * cut_sphere(2.9, 3.3, 3.0));
    EXPECT_NEAR(a[1], cut_sphere(3.3, 2.9, 3.0), 0.005 * cut_sphere(3.3, 2.9, 3.0));
    // Three balls on a line, the middle one cut on both sides by caps that do not meet.
    const Atoms three = make_atoms({{-4, 0, 0, 1.6f}, {0, 0, 0, 1.6f}, {4, 0, 0, 1.6f}});
    const std::vector<double> b = atom_sas_areas(three, 1.0f, 2000);
    const double whole = 4 * kPi * 2.6 * 2.6, cap = whole - cut_sphere(2.6, 2.6, 4.0);
    EXPECT_NEAR(b[1], whole - 2 * cap, 0.005 * whole);
    EXPECT_NEAR(b[0], whole - cap, 0.005 * whole);
    // vdW area (probe 0): the same closed form with the bare radii.
    const std::vector<double> c = atom_sas_areas(two, 0.0f, 2000);
    EXPECT_NEAR(c[0], cut_sphere(1.5, 1.9, 3.0), 0.005 * cut_sphere(1.5, 1.9, 3.0));
}

TEST(AtomSasAreas, BuriedTwinsAndContainedBalls) {
    // Twins: the first keeps its area; a ball inside a larger one has none.
    const Atoms atoms = make_atoms({{0, 0, 0, 1.5f}, {0, 0, 0, 1.5f}, {10, 0, 0, 2.0f},
                                    {10.2f, 0, 0, 0.5f}});
    const std::vector<double> a = atom_sas_areas(atoms, 1.4f, 400);
    EXPECT_NEAR(a[0], 4 * kPi * 2.9 * 2.9, 1e-4);
    EXPECT_EQ(a[1], 0.0);
    EXPECT_EQ(a[3], 0.0);
    EXPECT_THROW(atom_sas_areas(atoms, -1.0f), Error);
    EXPECT_THROW(atom_sas_areas(atoms, 1.4f, 0), Error);
    EXPECT_TRUE(atom_sas_areas(Atoms{}, 1.4f).empty());
}

TEST(AtomSasAreas, CrambinTotalConvergesWithPoints) {
    // Shrake-Rupley converges: 1CRN's total with 1,000 points per atom is within 0.2% of
    // 10,000 points, and far-apart copies of the molecule (wide cells) change nothing.
    const Atoms atoms = read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    const std::vector<double> coarse = atom_sas_areas(atoms, 1.4f, 1000);
    const std::vector<double> fine = atom_sas_areas(atoms, 1.4f, 10000);
    const double tc = std::accumulate(coarse.begin(), coarse.end(), 0.0);
    const double tf = std::accumulate(fine.begin(), fine.end(), 0.0);
    EXPECT_NEAR(tc, tf, 0.002 * tf);
    EXPECT_GT(tf, 2500.0);  // crambin's SASA is about 3,000 Å²
    EXPECT_LT(tf, 3500.0);
    Atoms far = atoms;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        far.xyz.insert(far.xyz.end(), {atoms.xyz[3 * i] + 5000.0f, atoms.xyz[3 * i + 1],
                                       atoms.xyz[3 * i + 2]});
        far.radius.push_back(atoms.radius[i]);
    }
    const std::vector<double> twice = atom_sas_areas(far, 1.4f, 1000);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        EXPECT_NEAR(twice[i], coarse[i], 1e-3);
        EXPECT_NEAR(twice[i + atoms.size()], coarse[i], 0.25);  // moved: a point may flip
    }
}

TEST(AtomMeshAreas, ThirdsOfEachTriangleSumToTheArea) {
    Mesh mesh = fdmsurf::test::icosphere(2.0, 3);
    mesh.atoms.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) mesh.atoms[v] = mesh.positions[3 * v] > 0;
    const std::vector<double> a = atom_mesh_areas(mesh, 2);
    EXPECT_NEAR(a[0] + a[1], compute_stats(mesh).area, 1e-9 * a[0]);
    EXPECT_NEAR(a[0], a[1], 0.1 * a[0]);  // halves of a symmetric sphere
    EXPECT_THROW(atom_mesh_areas(mesh, 1), Error);  // atom 1 out of range
    mesh.atoms.clear();
    EXPECT_THROW(atom_mesh_areas(mesh, 2), Error);
    EXPECT_EQ(atom_mesh_areas(Mesh{}, 3), std::vector<double>(3, 0.0));
}
