// Areas per atom, per residue and in total: the exact sphere patches of the vdw and sas surfaces,
// a mesh's area shared out to its atoms, relative SASA, buried interface area (docs/areas.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf {

// The solvent-accessible area of every atom (Å², in the order of `atoms`): the part of its
// sphere of radius r + probe that no other atom's such sphere covers, by Shrake & Rupley's test
// points (1973): `points` points per atom on a golden-section spiral, each exposed point
// standing for 4π(r + probe)² / points. probe >= 0 (Å; 0 gives the van der Waals area);
// points >= 1. Runs on all threads. Throws Error(InvalidArgument) for a negative probe or no
// points. Of identical atoms (same centre and radius) the first keeps the area, the others get 0.
std::vector<double> atom_sas_areas(const Atoms& atoms, float probe, int points = 1000);

// The same areas exactly (Å²): each atom's patch of the boundary of the union of the balls of
// radius r + probe, by the Gauss-Bonnet theorem on the arcs where the spheres meet (no
// sampling; exact to rounding). probe >= 0 (0: the van der Waals area). Runs on all threads.
// Twins as atom_sas_areas. Throws Error(InvalidArgument) for a negative probe.
std::vector<double> atom_exact_areas(const Atoms& atoms, float probe);

// A mesh's area shared out to the atoms of its vertices (mesh.atoms, as make_surface fills it):
// each triangle gives a third of its area to the atom of each of its three vertices. The sum
// is the mesh's area. atom_count: the number of atoms mesh.atoms indexes. Throws
// Error(InvalidArgument) when mesh.atoms is empty (on a non-empty mesh) or out of range.
std::vector<double> atom_mesh_areas(const Mesh& mesh, std::size_t atom_count);

// Per-atom areas of a surface of `atoms` as make_surface(atoms, options) computes it.
struct AtomAreas {
    // Å² per atom. vdw and sas: the exact area of the atom's sphere patch (atom_exact_areas on
    // the balls the surface bounds, whatever the spacing). ses: the mesh's area split by the
    // atom of each vertex (atom_mesh_areas); empty without a mesh.
    std::vector<double> area;
    // Å² per atom: the mesh's own (flat) triangles, each given whole to the atom of the sphere
    // patch it lies on (vdw and sas: its three vertices on that atom's sphere), else a third to
    // the atom of each vertex; sums to the mesh's area. Empty when no mesh was given.
    std::vector<double> mesh_area;
    double mesh_on_patches = 0.0;  // Å² of mesh_area given by sphere patch (the rest by thirds)
    bool exact = false;            // `area` is the exact sphere patches (vdw, sas)
};

// The areas of the surface `options` describes (kind, probe, level). mesh: the surface computed
// by make_surface(atoms, options), or null (vdw and sas only: exact areas without a mesh). A
// mesh without per-vertex atoms, out-of-range atoms, or ses without a mesh throw
// Error(InvalidArgument). Runs on all threads.
AtomAreas surface_atom_areas(const Atoms& atoms, const SurfaceOptions& options,
                             const Mesh* mesh = nullptr);

// Published maximal accessible areas of the 20 amino acids, the denominators of relative SASA.
enum class RelativeTable {
    None,
    Tien2013,    // Tien, Meyer, Sydykova, Spielman & Wilke, PLoS ONE 8:e80635 (2013), theoretical
    Miller1987,  // Miller, Janin, Lesk & Chothia, J. Mol. Biol. 196:641 (1987)
    Sander1994,  // Sander & Rost, Proteins 20:216 (1994)
};

// The table's maximal area (Å²) of the residue named `name` ("ALA", upper case), or a negative
// number when the table has none (ligands, nucleotides, None).
double residue_max_area(std::string_view name, RelativeTable table);
// "tien2013", "miller1987", "sander1994" ("none" for None).
const char* to_string(RelativeTable table) noexcept;

// One residue: the atoms sharing chain, residue number, insertion code and name.
struct ResidueArea {
    std::string chain;
    std::int32_t number = 0;
    char insertion_code = ' ';
    std::string name;
    std::vector<std::uint32_t> atoms;  // indices into Atoms, in input order
    double area = 0.0;                 // Å², sum of AtomAreas::area
    double mesh_area = 0.0;            // Å², sum of AtomAreas::mesh_area (0 without a mesh)
    double max_area = -1.0;            // the table's maximum, < 0 when none
    double relative = -1.0;            // area / max_area, < 0 when none
};

// The residues of `atoms` in order of first appearance, with their areas. Needs atoms.meta:
// Error(InvalidArgument) for atoms without metadata (XYZR input).
std::vector<ResidueArea> residue_areas(const Atoms& atoms, const AtomAreas& areas,
                                       RelativeTable table = RelativeTable::None);

// Buried interface area between two groups of atoms: each group's surface alone against their
// complex (the union of the two groups), the three surfaces computed on one engine.
struct BuriedAreas {
    std::array<std::string, 2> names;          // the groups as given ("A", "B,D", "A/1-50")
    std::vector<std::uint8_t> group;           // per atom of `atoms`: 1 or 2, 0 in neither group
    Atoms complex;                             // the atoms of both groups, in input order
    std::vector<std::uint32_t> complex_atoms;  // their indices in `atoms`
    SurfaceResult complex_surface;             // make_surface(complex); empty in areas-only mode
    AtomAreas in_complex;                      // per atom of `complex`
    AtomAreas alone;  // per atom of `complex`, each in its own group's surface
    std::array<std::size_t, 2> atom_count{};
    std::array<double, 2> area_alone{};       // Å², AtomAreas::area summed per group
    std::array<double, 2> area_in_complex{};  // Å²
    std::array<double, 2> mesh_area_alone{};  // Å² (0 in areas-only mode)
    std::array<double, 2> mesh_area_in_complex{};
    double buried() const {
        return area_alone[0] + area_alone[1] - area_in_complex[0] - area_in_complex[1];
    }
    double mesh_buried() const {
        return mesh_area_alone[0] + mesh_area_alone[1] - mesh_area_in_complex[0] -
               mesh_area_in_complex[1];
    }
};

// The two groups of `spec` ("GROUP1:GROUP2"; each a comma-separated list of chain ids, "A,C",
// or a gemmi selection, "A/1-50"), matched on `atoms` (model `model`): per atom 0, 1 or 2.
// Throws Error(InvalidArgument) naming the reason for a spec without exactly one ':', a chain
// the atoms do not have (listing those they have), a group that selects no atom, groups that
// share atoms, or atoms without metadata.
std::vector<std::uint8_t> match_buried_groups(const Atoms& atoms, const std::string& spec,
                                              std::array<std::string, 2>& names, int model = 1);

// Buried areas of the groups `group` marks (from match_buried_groups): the surfaces of the
// complex and of each group alone on `engine` (three make_surface calls), or with
// engine == nullptr none (vdw and sas only: exact areas). Throws as make_surface and
// surface_atom_areas do.
BuriedAreas buried_areas(Engine* engine, const Atoms& atoms, const std::vector<std::uint8_t>& group,
                         const std::array<std::string, 2>& names, const SurfaceOptions& options);

// What an areas file holds (write_areas). atoms/areas: the structure whose surface was written
// (with --buried, the complex). residues: empty for atoms without metadata. buried: null when
// not asked for; its per-atom arrays index `atoms`.
struct AreasReport {
    std::string input;
    std::string output;      // the mesh written, "" in areas-only mode
    SurfaceOptions surface;  // kind, probe, spacing, method
    bool has_mesh = false;   // false: areas-only (exact sphere patches, no mesh)
    double mesh_area = 0.0;  // Å², the written mesh's area (compute_stats)
    RelativeTable relative = RelativeTable::None;
    const Atoms* atoms = nullptr;
    const AtomAreas* areas = nullptr;
    const std::vector<ResidueArea>* residues = nullptr;
    const BuriedAreas* buried = nullptr;
};

enum class AreasFormat { Csv, Json };

// The format for `path` by its extension (.csv or .json, any case); Error(InvalidArgument)
// naming both for any other.
AreasFormat areas_format_for_path(const std::string& path);

// Writes the report as CSV or JSON by the extension of `path` (layouts: docs/areas.md), through
// a temporary file renamed into place: no partial file is ever left at `path`. Throws
// Error(InvalidArgument) for an unknown extension (before creating anything), Error(Io) when
// the file cannot be written.
void write_areas(const AreasReport& report, const std::string& path);

}  // namespace fdmsurf
