// The vertex-property stage: per-atom colours and values gathered on the device by the atom
// each vertex belongs to, the Coulomb potential on the device, curvatures on the host.
#include "properties/vertex_properties.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "fdmsurf/error.hpp"
#include "properties/atom_tables.hpp"
#include "properties/curvature.hpp"
#include "properties/vertex_properties_gpu.hpp"
#include "vulkan/commands.hpp"

namespace fdmsurf::detail {

namespace {

std::uint32_t pack(const Rgb& c) {
    return std::uint32_t(c[0]) | (std::uint32_t(c[1]) << 8) | (std::uint32_t(c[2]) << 16);
}

void unpack_colors(const std::vector<std::uint32_t>& words, std::uint32_t stride,
                   std::uint32_t at, std::vector<std::uint8_t>& colors) {
    const std::size_t nv = words.size() / stride;
    colors.resize(3 * nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const std::uint32_t c = words[stride * v + at];
        colors[3 * v] = std::uint8_t(c & 0xff);
        colors[3 * v + 1] = std::uint8_t((c >> 8) & 0xff);
        colors[3 * v + 2] = std::uint8_t((c >> 16) & 0xff);
    }
}

bool wants(const PropertyOptions& o, VertexProperty p) {
    return std::find(o.scalars.begin(), o.scalars.end(), p) != o.scalars.end();
}

void add_time(SurfaceResult& r, const char* name, double ms, bool gpu) {
    r.times.push_back({name, ms, gpu});
}

// The stage times of the last submission, and the rest of `wall_ms` as the host stage `host`.
void add_device_times(SurfaceResult& r, const Commands& cmds, const char* host, double wall_ms,
                      bool submitted) {
    if (!submitted) return;
    double device = 0.0;
    for (const StageTime& t : cmds.stage_times()) {
        r.times.push_back(t);
        device += t.ms;
    }
    add_time(r, host, std::max(wall_ms - device, 0.0), false);
}

}  // namespace

std::vector<std::string> check_property_inputs(const Atoms& atoms, const PropertyOptions& po) {
    const bool bfactor = po.color == ColorScheme::BFactor || wants(po, VertexProperty::BFactor);
    const bool need_meta = bfactor || po.color == ColorScheme::Chain ||
                           po.color == ColorScheme::Residue ||
                           po.color == ColorScheme::Hydrophobicity ||
                           wants(po, VertexProperty::Hydrophobicity);
    if (need_meta && atoms.meta.size() != atoms.size())
        throw Error(ErrorCode::InvalidArgument,
                    "colours and properties by chain, residue, hydrophobicity or B-factor need "
                    "atom records (PDB, mmCIF, PQR or XYZRN input), not bare XYZR atoms");
    std::vector<std::string> warnings;
    if (po.color == ColorScheme::Element &&
        std::all_of(atoms.element.begin(), atoms.element.end(),
                    [](const std::string& e) { return e.empty(); }))
        warnings.push_back(
            "colour by element: the atoms carry no elements (XYZR input?); every atom gets the "
            "colour of an unknown element");
    const bool by_residue = po.color == ColorScheme::Chain || po.color == ColorScheme::Residue ||
                            po.color == ColorScheme::Hydrophobicity ||
                            wants(po, VertexProperty::Hydrophobicity);
    if (by_residue && !atoms.has_residues())
        warnings.push_back(
            "colours and properties by chain, residue or hydrophobicity: the atoms name no "
            "residues (XYZRN names not in MSMS's chain_number_icode_residue_atom form); every "
            "atom gets those of an unknown residue");
    if (bfactor && std::all_of(atoms.meta.begin(), atoms.meta.end(),
                               [](const AtomMeta& m) { return m.b_factor == 0.0f; }))
        warnings.push_back(
            "B-factor: every atom's B-factor is 0 (PQR and XYZRN carry none); the B-factor "
            "colours and values are uniform");
    return warnings;
}

std::uint32_t pack_rgba(const std::array<std::uint8_t, 3>& rgb) {
    return pack(rgb) | 0xff000000u;
}

Buffer device_mesh_attributes(VertexPropertiesPass& pass, Commands& cmds, const Atoms& atoms,
                              const SurfaceOptions& options, const GpuMesh& mesh,
                              const GridInfo& grid, std::vector<StageTime>& times) {
    const PropertyOptions& po = options.properties;
    if (po.color == ColorScheme::Coulombic)
        throw Error(ErrorCode::InvalidArgument,
                    "make_device_surface: the coulombic colours are computed on the host mesh "
                    "only (make_surface, then Engine::upload_mesh)");
    const double t0 = now_ms();
    std::vector<std::uint32_t> colors(atoms.size());
    const std::vector<Rgb> rgb = atom_colors(atoms, po);
    for (std::size_t i = 0; i < atoms.size(); ++i) colors[i] = pack_rgba(rgb[i]);
    // The grid's box holds every vertex (refined ones move along the surface, within a cell).
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = grid.origin[a] - grid.spacing;
        hi[a] = grid.origin[a] + grid.spacing * float(grid.dims[a]);
    }
    Buffer out = pass.device_vertex_atoms(cmds, mesh.vertices, mesh.vertex_count, lo, hi, atoms,
                                          vertex_radius_add(options), colors);
    double device = 0.0;
    if (mesh.vertex_count > 0 && !atoms.empty()) {
        for (const StageTime& t : cmds.stage_times()) {
            times.push_back(t);
            device += t.ms;
        }
    }
    times.push_back({"vertex-atoms-host", std::max(now_ms() - t0 - device, 0.0), false});
    return out;
}

float vertex_radius_add(const SurfaceOptions& options) {
    return options.surface == SurfaceKind::Sas ? options.probe : 0.0f;
}

void add_vertex_properties(VertexPropertiesPass& pass, Commands& cmds, const Atoms& atoms,
                           const SurfaceOptions& options, SurfaceResult& result) {
    const PropertyOptions& po = options.properties;
    Mesh& mesh = result.mesh;
    const std::size_t nv = mesh.vertex_count();
    // Per-atom words the vertex pass copies to each vertex: the colour, then the per-atom
    // scalars (float bits) in the order asked for.
    const bool atom_colored = po.color != ColorScheme::None && po.color != ColorScheme::Coulombic;
    std::vector<VertexProperty> gathered;
    for (VertexProperty p : po.scalars)
        if (p == VertexProperty::Hydrophobicity || p == VertexProperty::BFactor)
            gathered.push_back(p);
    const std::uint32_t per_atom = (atom_colored ? 1u : 0u) + std::uint32_t(gathered.size());
    std::vector<std::uint32_t> attributes(std::size_t(per_atom) * atoms.size());
    if (per_atom > 0) {
        const std::vector<Rgb> colors =
            atom_colored ? atom_colors(atoms, po) : std::vector<Rgb>{};
        const std::vector<AtomLabel> labels = atom_labels(atoms);
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            std::uint32_t* w = &attributes[per_atom * i];
            if (atom_colored) *w++ = pack(colors[i]);
            for (VertexProperty p : gathered) {
                float value = 0.0f;
                if (p == VertexProperty::BFactor) value = atoms.meta[i].b_factor;
                if (p == VertexProperty::Hydrophobicity) {
                    const float kd = kyte_doolittle(labels[i].residue_name);
                    value = std::isnan(kd) ? 0.0f : kd;
                }
                *w++ = std::bit_cast<std::uint32_t>(value);
            }
        }
    }
    const std::uint32_t stride = 1 + per_atom;
    // Host work (binning, ordering vertices, scattering results) is timed apart from the pass.
    const double t_atoms = now_ms();
    const std::vector<std::uint32_t> words =
        pass.vertex_atoms(cmds, mesh, atoms, vertex_radius_add(options), attributes, per_atom);
    if (pass.on_host())  // the search itself on the host: nothing submitted
        add_time(result, "vertex-atoms", now_ms() - t_atoms, false);
    else
        add_device_times(result, cmds, "vertex-atoms-host", now_ms() - t_atoms, nv > 0);
    mesh.atoms.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) mesh.atoms[v] = words[stride * v];
    if (atom_colored) unpack_colors(words, stride, 1, mesh.colors);

    std::vector<float> coulombic;
    if (po.color == ColorScheme::Coulombic || wants(po, VertexProperty::Coulombic)) {
        const Charges charges = atom_charges(atoms);
        if (!charges.from_file) {
            const bool any = std::any_of(charges.q.begin(), charges.q.end(),
                                         [](float q) { return q != 0.0f; });
            result.warnings.push_back(
                any ? "coulombic: the atoms carry no partial charges (PQR gives them); using "
                      "the built-in model of formal charges of ionised groups at pH 7 "
                      "(docs/properties.md)"
                    : "coulombic: the atoms carry no charges and the built-in model of ionised "
                      "groups finds none (no residue names): the potential is 0 everywhere");
        }
        const bool color = po.color == ColorScheme::Coulombic;
        const double t_coulomb = now_ms();
        const std::vector<std::uint32_t> out =
            pass.coulombic(cmds, mesh, atoms, charges.q, po.coulombic_offset, color);
        add_device_times(result, cmds, "coulombic-host", now_ms() - t_coulomb, nv > 0);
        const std::uint32_t cs = color ? 2 : 1;
        coulombic.resize(nv);
        for (std::size_t v = 0; v < nv; ++v) coulombic[v] = std::bit_cast<float>(out[cs * v]);
        if (color) unpack_colors(out, cs, 1, mesh.colors);
    }
    VertexCurvature curvature;
    if (wants(po, VertexProperty::MeanCurvature) || wants(po, VertexProperty::GaussianCurvature) ||
        wants(po, VertexProperty::ShapeIndex)) {
        const double t0 = now_ms();
        curvature = fitted_curvature(mesh, 2.0f * options.spacing);
        add_time(result, "curvature", now_ms() - t0, false);
    }
    mesh.scalars.clear();
    std::size_t next_gathered = 0;
    for (VertexProperty p : po.scalars) {
        VertexScalars s{to_string(p), {}};
        switch (p) {
            case VertexProperty::Coulombic: s.values = coulombic; break;
            case VertexProperty::Hydrophobicity:
            case VertexProperty::BFactor: {
                const std::uint32_t at = (atom_colored ? 2u : 1u) + std::uint32_t(next_gathered++);
                s.values.resize(nv);
                for (std::size_t v = 0; v < nv; ++v)
                    s.values[v] = std::bit_cast<float>(words[stride * v + at]);
                break;
            }
            case VertexProperty::MeanCurvature: s.values = curvature.mean; break;
            case VertexProperty::GaussianCurvature: s.values = curvature.gaussian; break;
            case VertexProperty::ShapeIndex: s.values = curvature.shape_index; break;
        }
        mesh.scalars.push_back(std::move(s));
    }
}

}  // namespace fdmsurf::detail
