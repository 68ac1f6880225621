// --areas for one input of the fdmsurf program: --relative and --buried checked against the
// structure before any device work, the areas file written with the report's lines for it, and
// the areas alone without -o (vdw and sas: exact sphere patches, no mesh, no device).
#include "cli/input_run.hpp"

#include <algorithm>
#include <cstdio>

#include "cli/messages.hpp"
#include "cli/standard_output.hpp"

namespace fdmsurf::cli {

AreasPlan plan_areas(const CliOptions& options, const Structure& structure,
                     const std::string& input) {
    AreasPlan plan;
    if (options.areas.empty()) return plan;
    plan.wanted = true;
    const Atoms& atoms = structure.atoms;
    const bool residues = atoms.has_residues();
    if (options.relative != RelativeTable::None && !residues)
        throw Error(ErrorCode::InvalidArgument,
                    input + ": --relative needs residues, and " + to_string(structure.info.format) +
                        (structure.info.format == StructureFormat::Xyzrn
                             ? " input names none: give names in MSMS's "
                               "chain_number_icode_residue_atom form, or PDB, mmCIF or PQR"
                             : " input has none (only coordinates and radii): give PDB, mmCIF, "
                               "PQR or XYZRN"));
    if (!options.buried.empty()) {
        try {
            plan.groups =
                match_buried_groups(atoms, options.buried, plan.names, structure.info.model);
        } catch (const Error& e) {
            throw Error(ErrorCode::InvalidArgument, input + ": --buried: " + e.what());
        }
        plan.outside = std::size_t(std::count(plan.groups.begin(), plan.groups.end(), 0));
    }
    return plan;
}

// The --areas file and the report's lines for it.
void write_areas_file(const CliOptions& options, const std::string& input,
                      const std::string& output, const Atoms& atoms, const AtomAreas& areas,
                      const BuriedAreas* buried, double mesh_area, bool has_mesh,
                      RunReport& report) {
    auto t = Clock::now();
    std::vector<ResidueArea> residues;
    if (atoms.has_residues()) residues = residue_areas(atoms, areas, options.relative);
    AreasReport file;
    file.input = input;
    file.output = output;
    file.surface = options.surface;
    file.has_mesh = has_mesh;
    file.mesh_area = mesh_area;
    file.relative = options.relative;
    file.atoms = &atoms;
    file.areas = &areas;
    file.residues = &residues;
    file.buried = buried;
    write_areas(file, options.areas);
    report.times.push_back({"write-areas", ms_since(t), false});
    report.areas_file = options.areas;
    report.areas_exact = areas.exact;
    report.areas_total = 0.0;
    for (double a : areas.area) report.areas_total += a;
    report.areas_mesh_total = -1.0;
    if (!areas.mesh_area.empty()) {
        report.areas_mesh_total = 0.0;
        for (double a : areas.mesh_area) report.areas_mesh_total += a;
        report.areas_on_patches = areas.exact ? areas.mesh_on_patches : 0.0;
    }
    report.areas_residues = residues.size();
    if (buried) {
        report.buried = options.buried;
        report.buried_area = buried->buried();
        for (int g = 0; g < 2; ++g)
            report.buried_groups[g] = buried->area_alone[g] - buried->area_in_complex[g];
        report.buried_mesh_area = has_mesh ? buried->mesh_buried() : -1.0;
    }
}

// The warning for --areas on a structure without residues (XYZR, or XYZRN whose names are not
// MSMS's): per-atom and total areas only.
std::string no_residues_warning(const std::string& input, const Structure& structure) {
    return "--areas: " + input + " has no residues (" + to_string(structure.info.format) +
           " input): the file has per-atom and total areas only";
}

// --areas with no -o: the exact vdw or sas areas, no mesh and no device.
int areas_only(const CliOptions& options, const Structure& structure, double parse_ms,
               const AreasPlan& plan) {
    const auto start = Clock::now();
    RunReport report;
    report.times.push_back({"parse", parse_ms, false});
    for (const std::string& message : structure.info.warnings) {
        print_warning(message);
        report.warnings.push_back(message);
    }
    const std::string& input = options.inputs.front();
    if (!structure.atoms.has_residues()) {
        const std::string message = no_residues_warning(input, structure);
        print_warning(message);
        report.warnings.push_back(message);
    }
    auto t = Clock::now();
    if (!plan.groups.empty()) {
        const BuriedAreas buried =
            buried_areas(nullptr, structure.atoms, plan.groups, plan.names, options.surface);
        report.times.push_back({"areas", ms_since(t), false});
        write_areas_file(options, input, "", buried.complex, buried.in_complex, &buried, 0.0, false,
                         report);
        report.atoms_outside_groups = plan.outside;
        report.atoms_used = buried.complex.size();
    } else {
        const AtomAreas areas = surface_atom_areas(structure.atoms, options.surface, nullptr);
        report.times.push_back({"areas", ms_since(t), false});
        write_areas_file(options, input, "", structure.atoms, areas, nullptr, 0.0, false, report);
        report.atoms_used = structure.atoms.size();
    }
    report.version = version();
    report.input = input;
    report.surface = options.surface.surface;
    report.model = structure.info.model;
    report.info = structure.info;
    report.total_ms = ms_since(start) + parse_ms;
    if (options.json)
        put_noting_errors(areas_only_json(report) + "\n", stdout);
    else if (!options.quiet)
        put_noting_errors(areas_only_text(report), stdout);
    flush_noting_errors(stdout);
    return kExitOk;
}

}  // namespace fdmsurf::cli
