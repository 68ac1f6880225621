// Randomized properties (issue: hardening): random atom sets, built to stress the pipeline
// (random-walk chains, dense clusters, pieces far apart, coincident atoms, tiny and large radii),
// through every surface kind and method, must give closed, consistently oriented manifolds; the
// same input must give byte-identical PLY files run after run, and the same surface when slabs
// are forced; the vdw and sas meshes' volume and area must agree with independent estimates
// (stratified Monte Carlo for the volume, Shrake-Rupley for the area). The seed is fixed in CI;
// FDMSURF_TEST_SEED and FDMSURF_TEST_CASES run other and more sets (scripts/random-atoms.sh).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fdmsurf/areas.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "support/ball_union.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SesMethod;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;

std::uint64_t env_or(const char* name, std::uint64_t fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

struct RandomSet {
    std::string what;
    Atoms atoms;
    bool measurable = true;  // radii well above the grid spacing: area and volume checked
};

void add_atom(Atoms& a, double x, double y, double z, double r) {
    a.xyz.insert(a.xyz.end(), {float(x), float(y), float(z)});
    a.radius.push_back(float(r));
}

// A random walk of `n` atoms with steps of 1.3-1.6 Å from `start`.
void add_chain(Atoms& a, std::mt19937_64& rng, int n, std::array<double, 3> p, double r_lo,
               double r_hi) {
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < n; ++i) {
        add_atom(a, p[0], p[1], p[2], r_lo + (r_hi - r_lo) * u(rng));
        double d[3] = {g(rng), g(rng), g(rng)};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + 1e-12;
        const double step = 1.3 + 0.3 * u(rng);
        for (int k = 0; k < 3; ++k) p[k] += d[k] / len * step;
    }
}

// Case `k` of the seed's sequence: the kind of set cycles, its atoms are random.
RandomSet random_set(std::uint64_t seed, int k) {
    std::mt19937_64 rng(seed * 1000003ull + std::uint64_t(k));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    RandomSet s;
    switch (k % 5) {
        case 0:
            s.what = "random-walk chain";
            add_chain(s.atoms, rng, 40 + int(60 * u(rng)), {0, 0, 0}, 1.2, 2.0);
            break;
        case 1: {
            s.what = "dense cluster";
            const int n = 60 + int(60 * u(rng));
            for (int i = 0; i < n; ++i)
                add_atom(s.atoms, 10 * u(rng), 10 * u(rng), 10 * u(rng), 1.4 + 0.6 * u(rng));
            break;
        }
        case 2:
            s.what = "two chains far apart";
            add_chain(s.atoms, rng, 30, {0, 0, 0}, 1.5, 1.9);
            add_chain(s.atoms, rng, 30, {28 + 10 * u(rng), 3, -4}, 1.5, 1.9);
            break;
        case 3: {
            s.what = "chain with coincident atoms";
            add_chain(s.atoms, rng, 40, {0, 0, 0}, 1.5, 1.9);
            const std::size_t n = s.atoms.size();
            for (std::size_t i = 0; i < n; i += 4)  // exact copies, some with another radius
                add_atom(s.atoms, s.atoms.xyz[3 * i], s.atoms.xyz[3 * i + 1],
                         s.atoms.xyz[3 * i + 2], i % 8 == 0 ? s.atoms.radius[i] : 1.2);
            break;
        }
        default:
            s.what = "tiny and large radii";
            s.measurable = false;  // 0.2 Å balls are below the 0.5 Å grid's resolution
            add_chain(s.atoms, rng, 30, {0, 0, 0}, 0.2, 0.4);
            add_chain(s.atoms, rng, 10, {4, 4, 4}, 3.5, 5.0);
            break;
    }
    return s;
}

std::string ply_bytes(const fdmsurf::Mesh& mesh) {
    std::ostringstream out;
    fdmsurf::write_mesh(mesh, out, fdmsurf::MeshFormat::Ply, "random");
    return out.str();
}

class RandomAtoms : public GpuTest {};

TEST_F(RandomAtoms, EveryKindGivesClosedDeterministicSurfaces) {
    const std::uint64_t seed = env_or("FDMSURF_TEST_SEED", 20261126);
    const int cases = int(env_or("FDMSURF_TEST_CASES", 5));
    struct Kind {
        const char* name;
        SurfaceKind surface;
        SesMethod method;
        float add;  // ball radius added (sas: the probe)
    };
    const Kind kinds[] = {{"ses fdm", SurfaceKind::Ses, SesMethod::Fdm, 0.0f},
                          {"ses edt", SurfaceKind::Ses, SesMethod::Edt, 0.0f},
                          {"vdw", SurfaceKind::Vdw, SesMethod::Fdm, 0.0f},
                          {"sas", SurfaceKind::Sas, SesMethod::Fdm, 1.4f}};
    int surfaces = 0;
    for (int k = 0; k < cases; ++k) {
        const RandomSet set = random_set(seed, k);
        for (const Kind& kind : kinds) {
            SCOPED_TRACE("seed " + std::to_string(seed) + ", case " + std::to_string(k) + " (" +
                         set.what + ", " + std::to_string(set.atoms.size()) + " atoms), " +
                         kind.name);
            SurfaceOptions o;
            o.surface = kind.surface;
            o.method = kind.method;
            const fdmsurf::SurfaceResult first = engine().make_surface(set.atoms, o);
            ++surfaces;
            EXPECT_TRUE(IsClosedManifold(first.mesh));
            // Byte-identical on a second run.
            const fdmsurf::SurfaceResult second = engine().make_surface(set.atoms, o);
            EXPECT_TRUE(ply_bytes(first.mesh) == ply_bytes(second.mesh)) << "two runs differ";
            // Forced slabs: the same surface (float rounding where the filter crosses slabs).
            const auto plan = fdmsurf::detail::plan_grid(set.atoms, o);
            const std::uint64_t bytes = plan.field_floats() * sizeof(float);
            const std::uint64_t limit = std::max<std::uint64_t>(
                std::uint64_t(double(bytes) * 0.45) & ~std::uint64_t(0xFFFF), 1u << 16);
            fdmsurf::Engine small(
                fdmsurf::EngineOptions{.validation = true, .max_buffer_range = limit});
            try {
                const fdmsurf::SurfaceResult sliced = small.make_surface(set.atoms, o);
                const fdmsurf::MeshStats a = fdmsurf::compute_stats(first.mesh);
                const fdmsurf::MeshStats b = fdmsurf::compute_stats(sliced.mesh);
                EXPECT_GT(sliced.grid.slabs, 1u);
                EXPECT_TRUE(IsClosedManifold(sliced.mesh));
                EXPECT_EQ(a.pieces, b.pieces);
                // Not byte-identical: the stitched mesh's vertices come in another order, and
                // the snap stage's splits (vdw, sas, edt) depend on it. Measured on these sets up
                // to 2.8e-4 of the area and 2.5e-4 of the volume.
                EXPECT_NEAR(b.area, a.area, 1e-3 * a.area);
                EXPECT_NEAR(b.volume, a.volume, 1e-3 * a.volume);
            } catch (const fdmsurf::Error& e) {
                // A grid whose slabs cannot be thin enough for this limit: refused, not wrong.
                EXPECT_EQ(e.code(), fdmsurf::ErrorCode::DeviceLimit) << e.what();
            }
            const std::vector<std::string> messages = small.take_validation_messages();
            EXPECT_TRUE(messages.empty()) << fdmsurf_test::join_messages(messages);
            if (!set.measurable || kind.surface == SurfaceKind::Ses) continue;
            // vdw and sas against independent estimates of the union of balls.
            const fdmsurf::MeshStats s = fdmsurf::compute_stats(first.mesh);
            const double volume =
                fdmsurf::test::union_volume(fdmsurf::test::balls_of(set.atoms, kind.add), 0.2);
            const std::vector<double> per_atom = fdmsurf::atom_sas_areas(set.atoms, kind.add, 4000);
            const double area = std::accumulate(per_atom.begin(), per_atom.end(), 0.0);
            // Small sets have far more crease per Å² than a protein (where the meshes are within
            // 0.5% and 1%, docs/accuracy.md): measured on seeds 20261126, 1, 2 and 7 (65 sets) up
            // to -0.62% (volume) and -0.52% (area) at 0.5 Å, except the dense clusters' vdw
            // area, -1.3% to -3.1%: random balls packed that densely enclose voids and clefts
            // narrower than the grid spacing, which Shrake-Rupley's points count and a 0.5 Å grid
            // cannot resolve, so that area is printed, not checked (its volume is).
            EXPECT_NEAR(s.volume, volume, 0.01 * volume);
            const bool voids = set.what == "dense cluster" && kind.surface == SurfaceKind::Vdw;
            if (!voids) {
                EXPECT_NEAR(s.area, area, 0.01 * area);
            }
            std::printf("  %s, %s: volume %+.2f%%, area %+.2f%%\n", set.what.c_str(), kind.name,
                        100.0 * (s.volume / volume - 1.0), 100.0 * (s.area / area - 1.0));
        }
    }
    std::printf("  %d random sets, %d surfaces (seed %llu)\n", cases, surfaces,
                static_cast<unsigned long long>(seed));
}

}  // namespace
