// The vertex-property stage against its CPU references on real structures: the atom of each
// vertex (every vertex, near-ties reported), the Coulomb potential (all pairs, double), a point
// charge's closed form, and the colours and scalars gathered from the atoms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"
#include "properties/atom_tables.hpp"
#include "properties/vertex_atoms_cpu.hpp"
#include "properties/vertex_properties_gpu.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using fdmsurf::test::data_path;

namespace {

class VertexProperties : public GpuTest {};

// Every vertex's atom equals the brute-force reference, except near-ties: two atoms whose power
// distances differ by less than kTie Å² in double (float rounding on the device can pick either;
// both are reported). Returns the number of ties.
constexpr double kTie = 1e-4;

std::size_t expect_atoms_match(const Mesh& mesh, const Atoms& atoms, float radius_add) {
    const std::vector<std::uint32_t> ref = detail::vertex_atoms_cpu(mesh, atoms, radius_add);
    EXPECT_EQ(mesh.atoms.size(), mesh.vertex_count());
    std::size_t ties = 0;
    for (std::size_t v = 0; v < ref.size() && v < mesh.atoms.size(); ++v) {
        if (mesh.atoms[v] == ref[v]) continue;
        const double a = detail::power_distance(mesh, v, atoms, mesh.atoms[v], radius_add);
        const double b = detail::power_distance(mesh, v, atoms, ref[v], radius_add);
        EXPECT_LT(std::abs(a - b), kTie) << "vertex " << v << ": device atom " << mesh.atoms[v]
                                         << " (power " << a << "), reference " << ref[v]
                                         << " (power " << b << ")";
        ++ties;
    }
    std::printf("%zu vertices, %zu near-ties\n", ref.size(), ties);
    return ties;
}

SurfaceResult surface(Engine& e, const Atoms& atoms, SurfaceKind kind, SesMethod method,
                      PropertyOptions props = {}) {
    SurfaceOptions o;
    o.surface = kind;
    o.method = method;
    o.properties = std::move(props);
    return e.make_surface(atoms, o);
}

}  // namespace

// Vertices with two atoms at the least power distance within kTie: on the vdw and sas surfaces
// snapped by default (issue 13), every vertex on a crease lies on two spheres, a tie by
// construction.
std::size_t exact_ties(const Mesh& mesh, const Atoms& atoms, float radius_add) {
    std::size_t ties = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        double best = 1e300, second = 1e300;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const double p = detail::power_distance(mesh, v, atoms, i, radius_add);
            if (p < best) {
                second = best;
                best = p;
            } else if (p < second) {
                second = p;
            }
        }
        ties += second - best < kTie;
    }
    return ties;
}

TEST_F(VertexProperties, AtomOfEveryVertexEqualsReferenceOnCrambin) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    for (SurfaceKind kind : {SurfaceKind::Ses, SurfaceKind::Vdw, SurfaceKind::Sas}) {
        SurfaceOptions o;
        o.surface = kind;
        const SurfaceResult r = engine().make_surface(atoms, o);
        ASSERT_GT(r.mesh.vertex_count(), 1000u);
        const float add = kind == SurfaceKind::Sas ? 1.4f : 0.0f;
        const std::size_t ties = expect_atoms_match(r.mesh, atoms, add);
        // Mismatches only at ties (checked above), and no more of them than there are vertices
        // with two atoms at the same power distance (crease vertices), plus 0.1% for rounding.
        const std::size_t allowed = kind == SurfaceKind::Ses ? 0 : exact_ties(r.mesh, atoms, add);
        std::printf("  %s: %zu vertices with an exact tie\n", to_string(kind), allowed);
        EXPECT_LT(ties, allowed + r.mesh.vertex_count() / 1000 + 1) << to_string(kind);
    }
}

TEST_F(VertexProperties, AtomOfEveryVertexEqualsReferenceOnHemoglobin) {
    const Atoms atoms = read_structure(data_path("4hhb.pdb.gz")).atoms;
    for (SesMethod method : {SesMethod::Fdm, SesMethod::Edt}) {
        const SurfaceResult r = surface(engine(), atoms, SurfaceKind::Ses, method);
        ASSERT_GT(r.mesh.vertex_count(), 50000u);
        const std::size_t ties = expect_atoms_match(r.mesh, atoms, 0.0f);
        EXPECT_LT(ties, r.mesh.vertex_count() / 1000 + 1) << to_string(method);
    }
}

TEST_F(VertexProperties, VdwAndSasVerticesLieOnTheirAtomsSphere) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    for (bool snap : {true, false}) {
        for (SurfaceKind kind : {SurfaceKind::Vdw, SurfaceKind::Sas}) {
            const float add = kind == SurfaceKind::Sas ? 1.4f : 0.0f;
            SurfaceOptions o;
            o.surface = kind;
            o.snap = snap;
            const SurfaceResult r = engine().make_surface(atoms, o);
            double worst = 0.0;
            std::size_t on_sphere = 0;
            for (std::size_t v = 0; v < r.mesh.vertex_count(); ++v) {
                const std::uint32_t a = r.mesh.atoms[v];
                double d2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double d = r.mesh.positions[3 * v + k] - atoms.xyz[3 * a + k];
                    d2 += d * d;
                }
                const double off = std::abs(std::sqrt(d2) - (atoms.radius[a] + add));
                worst = std::max(worst, off);
                on_sphere += off < 1e-3;
            }
            const double share = double(on_sphere) / double(r.mesh.vertex_count());
            std::printf("%s, snap %s: %.2f%% of vertices on their atom's sphere (1e-3 Å), worst "
                        "%.4f Å\n",
                        to_string(kind), snap ? "on" : "off", 100.0 * share, worst);
            if (snap) {
                // Snapping (the default) puts every vertex on its ball, a crease vertex on two
                // (its atom, the least power distance, is then one of them).
                EXPECT_LT(worst, 1e-3) << to_string(kind);
            } else {
                // Marching cubes solves the power distance's quadratic on each edge, so a vertex
                // lies on the sphere of its atom, unless the edge crosses a crease (its two ends
                // have different nearest atoms): those vertices are cut across the crease, within
                // a cell of it.
                EXPECT_GT(share, 0.75) << to_string(kind);  // measured 83% (vdw), 90% (sas)
                EXPECT_LT(worst, 0.5) << to_string(kind);
            }
        }
    }
}

TEST_F(VertexProperties, CoulombicEqualsAllPairsReference) {
    for (const char* file : {"1crn.pdb", "4hhb.pdb.gz"}) {
        const Atoms atoms = read_structure(data_path(file)).atoms;
        PropertyOptions p;
        p.scalars = {VertexProperty::Coulombic};
        const SurfaceResult r = surface(engine(), atoms, SurfaceKind::Ses, SesMethod::Fdm, p);
        ASSERT_EQ(r.mesh.scalars.size(), 1u);
        const std::vector<float>& phi = r.mesh.scalars[0].values;
        const std::vector<double> ref =
            detail::coulombic_cpu(r.mesh, atoms, detail::atom_charges(atoms).q, 1.4f);
        double err2 = 0.0, ref2 = 0.0;
        for (std::size_t v = 0; v < ref.size(); ++v) {
            err2 += (phi[v] - ref[v]) * (phi[v] - ref[v]);
            ref2 += ref[v] * ref[v];
        }
        const double rms_ref = std::sqrt(ref2 / ref.size());
        const double rel = std::sqrt(err2 / ref.size()) / rms_ref;
        std::printf("%s: coulombic RMS %.3f kcal/(mol e), relative RMS error %.2e\n", file,
                    rms_ref, rel);
        EXPECT_GT(rms_ref, 0.5) << file;  // a real potential of a few kcal/(mol e)
        EXPECT_LT(rel, 0.01) << file;
        // The built-in charge model is named in a warning.
        bool warned = false;
        for (const std::string& w : r.warnings) warned |= w.find("built-in model") != std::string::npos;
        EXPECT_TRUE(warned) << file;
    }
}

TEST_F(VertexProperties, CoulombicWithEveryAtomChargedReadsNearSitesInBatches) {
    // PQR-like charges on every atom of 4HHB: a cell's near sites (about 1,000) exceed one
    // shared-memory batch (512), so the points sum them over several batches.
    Atoms atoms = read_structure(data_path("4hhb.pdb.gz")).atoms;
    std::vector<float> q(atoms.size());
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        q[i] = 0.05f * float(int(i * 2654435761u % 21) - 10);  // -0.5 .. 0.5, fixed
        atoms.meta[i].charge = q[i];
        atoms.meta[i].has_charge = true;
    }
    PropertyOptions p;
    p.scalars = {VertexProperty::Coulombic};
    const SurfaceResult r = surface(engine(), atoms, SurfaceKind::Ses, SesMethod::Fdm, p);
    const std::vector<double> ref = detail::coulombic_cpu(r.mesh, atoms, q, 1.4f);
    double err2 = 0.0, ref2 = 0.0;
    for (std::size_t v = 0; v < ref.size(); ++v) {
        err2 += (r.mesh.scalars[0].values[v] - ref[v]) * (r.mesh.scalars[0].values[v] - ref[v]);
        ref2 += ref[v] * ref[v];
    }
    const double rel = std::sqrt(err2 / ref2);
    std::printf("4hhb, every atom charged: relative RMS error %.2e\n", rel);
    EXPECT_LT(rel, 0.01);
}

TEST_F(VertexProperties, PointChargeMatchesClosedForm) {
    // One atom of charge +1 (PQR): phi = 83 / |x - c|² at x = p + 1.4 n, and |x - c| = r + 1.4
    // on the exact sphere.
    const Structure s = read_structure_from_memory(
        "ATOM      1  NA  NA      1       1.000   2.000   3.000  1.0000 1.8000\n", "ion.pqr");
    PropertyOptions p;
    p.color = ColorScheme::Coulombic;
    p.scalars = {VertexProperty::Coulombic};
    const SurfaceResult r = surface(engine(), s.atoms, SurfaceKind::Vdw, SesMethod::Fdm, p);
    ASSERT_GT(r.mesh.vertex_count(), 100u);
    const std::vector<float>& phi = r.mesh.scalars[0].values;
    const double sphere = 83.0 / ((1.8 + 1.4) * (1.8 + 1.4));
    for (std::size_t v = 0; v < phi.size(); ++v) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double x = r.mesh.positions[3 * v + k] + 1.4 * r.mesh.normals[3 * v + k] -
                             s.atoms.xyz[k];
            d2 += x * x;
        }
        ASSERT_NEAR(phi[v], 83.0 / d2, 1e-5 * 83.0 / d2) << v;
        ASSERT_NEAR(phi[v], sphere, 0.02 * sphere) << v;  // normals within about 1% of radial
        // 8.1 kcal/(mol e) of +10: blue 0.81 of the way from white.
        EXPECT_EQ(r.mesh.colors[3 * v + 2], 255);
        EXPECT_NEAR(r.mesh.colors[3 * v], 255.0 * (1.0 - phi[v] / 10.0), 1.01);
    }
    EXPECT_TRUE(r.warnings.empty());  // PQR charges: no model warning
}

TEST_F(VertexProperties, ColoursAndScalarsFollowTheVertexAtom) {
    const Atoms atoms = read_structure(data_path("4hhb.pdb.gz")).atoms;
    ASSERT_EQ(atoms.meta.size(), atoms.size());
    PropertyOptions p;
    p.color = ColorScheme::Chain;
    p.scalars = {VertexProperty::BFactor, VertexProperty::Hydrophobicity};
    const SurfaceResult r = surface(engine(), atoms, SurfaceKind::Ses, SesMethod::Fdm, p);
    const Mesh& m = r.mesh;
    ASSERT_EQ(m.colors.size(), 3 * m.vertex_count());
    ASSERT_EQ(m.scalars.size(), 2u);
    EXPECT_EQ(m.scalars[0].name, "bfactor");
    EXPECT_EQ(m.scalars[1].name, "hydrophobicity");
    std::map<std::string, std::size_t> chain_vertices;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const AtomMeta& a = atoms.meta[m.atoms[v]];
        ++chain_vertices[a.chain];
        const std::size_t n = std::string("ABCD").find(a.chain);  // 4HHB lists A, B, C, D
        ASSERT_NE(n, std::string::npos) << a.chain;
        const detail::Rgb c = detail::chain_color(n);
        ASSERT_EQ(m.colors[3 * v], c[0]);
        ASSERT_EQ(m.colors[3 * v + 1], c[1]);
        ASSERT_EQ(m.colors[3 * v + 2], c[2]);
        ASSERT_EQ(m.scalars[0].values[v], a.b_factor);
        const float kd = detail::kyte_doolittle(a.residue_name);
        ASSERT_EQ(m.scalars[1].values[v], std::isnan(kd) ? 0.0f : kd);
    }
    EXPECT_EQ(chain_vertices.size(), 4u);
}

TEST_F(VertexProperties, ElementColoursAndBareXyzrAtoms) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    PropertyOptions p;
    p.color = ColorScheme::Element;
    const SurfaceResult r = surface(engine(), atoms, SurfaceKind::Ses, SesMethod::Fdm, p);
    for (std::size_t v = 0; v < r.mesh.vertex_count(); ++v) {
        const detail::Rgb c = detail::element_color(atoms.element[r.mesh.atoms[v]]);
        ASSERT_EQ(r.mesh.colors[3 * v], c[0]);
        ASSERT_EQ(r.mesh.colors[3 * v + 2], c[2]);
    }
    // XYZR atoms have no residues: a residue-based scheme is refused, atoms are still mapped.
    const Atoms bare = read_structure(data_path("1crn.xyzr")).atoms;
    p.color = ColorScheme::Hydrophobicity;
    try {
        surface(engine(), bare, SurfaceKind::Ses, SesMethod::Fdm, p);
        ADD_FAILURE() << "hydrophobicity colours of XYZR atoms were accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("XYZR"), std::string::npos) << e.what();
    }
    const SurfaceResult plain = surface(engine(), bare, SurfaceKind::Ses, SesMethod::Fdm);
    EXPECT_EQ(plain.mesh.atoms.size(), plain.mesh.vertex_count());
    EXPECT_TRUE(plain.mesh.colors.empty());
}

TEST_F(VertexProperties, HostSearchGivesTheDevicePassesAtoms) {
    // The shader's search in C++ (a CPU device's default) against the pass on the device, on
    // 4HHB's surface and on crambin's sas surface, whose crease vertices are exact ties: the
    // same atom for every vertex, or one within kTie of it in power (float rounding), with
    // attributes.
    detail::EngineImpl& e = impl();
    const bool default_place = e.vertex_properties.on_host();
    EXPECT_EQ(default_place, e.context.info().type == "CPU");
    // EngineOptions::vertex_atoms sets it.
    for (const auto& [place, host] : {std::pair{fdmsurf::StagePlace::Device, false},
                                      std::pair{fdmsurf::StagePlace::Host, true}}) {
        Engine placed(EngineOptions{.vertex_atoms = place});
        EXPECT_EQ(placed.impl().vertex_properties.on_host(), host);
    }
    for (const char* name : {"4hhb.pdb.gz", "1crn.pdb"}) {
        const Atoms atoms = read_structure(data_path(name)).atoms;
        const SurfaceKind kind = name[0] == '4' ? SurfaceKind::Ses : SurfaceKind::Sas;
        const float add = kind == SurfaceKind::Sas ? 1.4f : 0.0f;
        Mesh mesh = surface(engine(), atoms, kind, SesMethod::Fdm).mesh;
        std::vector<std::uint32_t> attributes(2 * atoms.size());
        for (std::size_t i = 0; i < attributes.size(); ++i) attributes[i] = std::uint32_t(3 * i + 1);
        std::vector<std::uint32_t> words[2];
        for (int host = 0; host < 2; ++host) {
            e.vertex_properties.set_on_host(host == 1);
            words[host] = e.vertex_properties.vertex_atoms(e.commands, mesh, atoms, add, attributes, 2);
        }
        e.vertex_properties.set_on_host(default_place);
        ASSERT_EQ(words[1].size(), 3 * mesh.vertex_count());
        std::size_t differ = 0;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            const std::uint32_t a = words[1][3 * v];
            ASSERT_LT(a, atoms.size());
            EXPECT_EQ(words[1][3 * v + 1], attributes[2 * a]);
            EXPECT_EQ(words[1][3 * v + 2], attributes[2 * a + 1]);
            if (a == words[0][3 * v]) continue;
            ++differ;
            EXPECT_LT(std::abs(detail::power_distance(mesh, v, atoms, a, add) -
                               detail::power_distance(mesh, v, atoms, words[0][3 * v], add)),
                      kTie)
                << name << " vertex " << v;
        }
        std::printf("  %s: %zu vertices, %zu atoms differ (near-ties)\n", name, mesh.vertex_count(),
                    differ);
        EXPECT_LT(differ, mesh.vertex_count() / 1000 + 1) << name;
    }
}

TEST_F(VertexProperties, HostSearchEqualsFloatBruteForceExactly) {
    // The host's search (cells of vertices sharing candidate lists) against every atom tried in
    // the same float arithmetic, ties to the lower index: the same atom for every vertex, on
    // 4HHB's surface and on crambin's sas surface (crease vertices are exact ties), also moved
    // 3,000 Å from the origin (coordinates' differences then round to 2.4e-4 Å).
    detail::EngineImpl& e = impl();
    const bool default_place = e.vertex_properties.on_host();
    for (const char* name : {"4hhb.pdb.gz", "1crn.pdb", "1crn.pdb far"}) {
        const std::string file = std::string(name).substr(0, std::string(name).find(' '));
        Atoms atoms = read_structure(data_path(file)).atoms;
        if (file != name)
            for (float& c : atoms.xyz) c += 3000.0f;
        const SurfaceKind kind = name[0] == '4' ? SurfaceKind::Ses : SurfaceKind::Sas;
        const float add = kind == SurfaceKind::Sas ? 1.4f : 0.0f;
        const Mesh mesh = surface(engine(), atoms, kind, SesMethod::Fdm).mesh;
        e.vertex_properties.set_on_host(true);
        const std::vector<std::uint32_t> words =
            e.vertex_properties.vertex_atoms(e.commands, mesh, atoms, add, {}, 0);
        e.vertex_properties.set_on_host(default_place);
        ASSERT_EQ(words.size(), mesh.vertex_count());
        const std::vector<std::uint32_t> brute = detail::vertex_atoms_float_cpu(
            mesh.positions.data(), mesh.vertex_count(), atoms, add);
        std::size_t differ = 0;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
            if (words[v] != brute[v] && ++differ <= 5)
                ADD_FAILURE() << name << " vertex " << v << ": host atom " << words[v]
                              << ", brute force " << brute[v];
        EXPECT_EQ(differ, 0u) << name;
    }
}

TEST_F(VertexProperties, ChunkedDispatchesAndRepeatedRunsGiveIdenticalWords) {
    // A device whose bindings hold 1 MiB: 4HHB's 167k vertices go through both passes in
    // several chunks. Every word equals the one-chunk result, and a second run the first.
    const Atoms atoms = read_structure(data_path("4hhb.pdb.gz")).atoms;
    const Mesh mesh = surface(engine(), atoms, SurfaceKind::Ses, SesMethod::Fdm).mesh;
    const std::vector<float> q = detail::atom_charges(atoms).q;
    detail::EngineImpl& one = impl();
    // The device's pass (a CPU device would search on the host: HostSearchGivesTheDevicePassesAtoms).
    const bool one_on_host = one.vertex_properties.on_host();
    one.vertex_properties.set_on_host(false);
    const auto atoms_one = one.vertex_properties.vertex_atoms(one.commands, mesh, atoms, 0.0f, {}, 0);
    const auto phi_one = one.vertex_properties.coulombic(one.commands, mesh, atoms, q, 1.4f, true);
    EXPECT_EQ(phi_one, one.vertex_properties.coulombic(one.commands, mesh, atoms, q, 1.4f, true));

    Engine small(EngineOptions{.validation = true,
                               .max_buffer_range = 1u << 20,
                               .vertex_atoms = fdmsurf::StagePlace::Device});
    detail::EngineImpl& many = small.impl();
    EXPECT_EQ(atoms_one, many.vertex_properties.vertex_atoms(many.commands, mesh, atoms, 0.0f, {}, 0));
    // Vertices in mesh order (a GPU's default) and sorted by cell (a CPU device's), one chunk
    // and several: the same words, with attributes.
    const std::vector<std::uint32_t> attributes(atoms.size(), 7u);
    for (detail::EngineImpl* e : {&one, &many}) {
        std::vector<std::vector<std::uint32_t>> words;
        for (bool sort : {true, false}) {
            e->vertex_properties.set_sort_vertices(sort);
            words.push_back(e->vertex_properties.vertex_atoms(e->commands, mesh, atoms, 0.0f, attributes, 1));
        }
        e->vertex_properties.set_sort_vertices(e->context.info().type == "CPU");
        EXPECT_EQ(words[0], words[1]);
        ASSERT_EQ(words[0].size(), 2 * mesh.vertex_count());
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) ASSERT_EQ(words[0][2 * v], atoms_one[v]);
    }
    EXPECT_EQ(phi_one, many.vertex_properties.coulombic(many.commands, mesh, atoms, q, 1.4f, true));
    one.vertex_properties.set_on_host(one_on_host);
    const std::vector<std::string> messages = small.take_validation_messages();
    EXPECT_TRUE(messages.empty()) << fdmsurf_test::join_messages(messages);
}
