// Structure input: atoms (centres and radii, Å) read from PDB, mmCIF, PQR or XYZR.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace fdmsurf {

// Xyzrn: MSMS's `x y z r n name` lines (pdb_to_xyzrn), the name kept in AtomMeta::name.
enum class StructureFormat { Auto, Pdb, Mmcif, Pqr, Xyzr, Xyzrn };

// What the input file says of one atom. PDB and mmCIF fill every field (author chain and
// residue numbering); PQR the fields its columns carry (no B-factor: 0, occupancy 1); XYZRN
// `xyzrn_name` (the whole name field, e.g. "A_23_x_LYS_NZ_Blue") and, when it follows MSMS's
// chain_resnum_icode_resname_atomname[_colour] convention, chain, residue number, insertion
// code ('x': none), residue and atom name from it (else `name` is the whole field).
struct AtomMeta {
    std::int32_t serial = 0;          // atom serial number (PDB columns 7-11, _atom_site.id;
                                      // XYZRN: the sphere's line among the file's sphere lines,
                                      // from 1, MSMS's atom number)
    std::string name;                 // atom name, "CA"
    std::string residue_name;         // "LYS"
    std::int32_t residue_number = 0;  // author sequence number
    char insertion_code = ' ';        // ' ' when none
    std::string chain;                // author chain id; in an assembly, the copy's chain name
    bool hetero = false;              // HETATM record
    float b_factor = 0.0f;            // Å²
    float occupancy = 1.0f;
    float charge = 0.0f;      // e: PQR's partial charge; PDB/mmCIF: the formal charge column
    bool has_charge = false;  // true for PQR (partial charges a potential can use)
    std::string xyzrn_name;   // XYZRN: the name field as read (MSMS files write it back)
    // False for an XYZRN atom whose name is not MSMS's chain_number_icode_residue_atom: it is
    // in no residue (no chain, residue name or number; per-residue areas leave it out).
    bool in_residue = true;
};

// Atoms as plain arrays. xyz holds 3 floats per atom (Å); radius one float per atom (Å, > 0).
// element holds the upper-case element symbol ("C", "FE"); empty for XYZR input.
// meta: empty (XYZR, or atoms built by hand) or one entry per atom.
// Atom order is the order of the input file (after selection: the atoms kept, in file order;
// with an assembly, chain copy by chain copy in the order of its operators): Mesh::atoms
// indexes it.
struct Atoms {
    std::vector<float> xyz;
    std::vector<float> radius;
    std::vector<std::string> element;
    std::vector<AtomMeta> meta;
    std::size_t size() const { return radius.size(); }
    bool empty() const { return radius.empty(); }
    // Whether the atoms have residues: metadata for every atom, at least one in a residue
    // (XYZRN names not in MSMS's chain_number_icode_residue_atom form give none).
    bool has_residues() const {
        if (meta.size() != size()) return false;
        for (const AtomMeta& m : meta)
            if (m.in_residue) return true;
        return false;
    }
};

// Selection rules for PDB and mmCIF (PQR and XYZR are taken as they are, line by line).
struct ReadOptions {
    StructureFormat format = StructureFormat::Auto;  // Auto: from the extension, then the content
    int model = 1;                 // 1-based model number (the n-th model in the file)
                                   // (kAllModels, 0: every model, for read_models only)
    bool keep_waters = false;      // HOH/WAT/DOD... residues
    bool keep_hydrogens = false;   // H and D atoms
    bool keep_ligands = true;      // HETATM residues other than water
    // 0: the model as deposited (the asymmetric unit); N >= 1: biological assembly N, the n-th
    // one the file lists (_pdbx_struct_assembly / REMARK 350; wwPDB ids are 1, 2, ... in
    // order), built by applying its operators to the model's chains before selection.
    // PDB and mmCIF only.
    int assembly = 0;
    // Keep only these chains (author chain ids, case-sensitive); empty: every chain. A chain
    // that the selected model does not hold is Error(InvalidArgument) listing the chains present.
    std::vector<std::string> chains;
    // gemmi's selection syntax ("/1/A/10-50/CA[C]", "A/*/CA", ";b>20"...), applied after the
    // other rules; empty: none. Bad syntax: Error(InvalidArgument); nothing left:
    // Error(EmptySelection). Needs atoms with metadata (not XYZR).
    std::string select;
};

// ReadOptions::model for read_models: one Structure per model of the file.
constexpr int kAllModels = 0;

// What the reader did, for the summary and for warnings.
struct StructureInfo {
    StructureFormat format = StructureFormat::Auto;  // the format actually read
    std::size_t atoms_in_file = 0;   // atom records in the selected model, before selection
                                     // (with an assembly: in the assembly, copies included)
    std::size_t waters_skipped = 0;
    std::size_t hydrogens_skipped = 0;
    std::size_t ligands_skipped = 0;
    std::size_t altlocs_skipped = 0;  // atoms dropped because another alternate location was kept
    // XYZR, XYZRN and PQR: spheres of radius 0 left out (counted in atoms_in_file), and the 1-based
    // line of the first of them (0: none).
    std::size_t zero_radius_skipped = 0;
    std::size_t first_zero_radius_line = 0;
    std::size_t models_in_file = 0;
    std::vector<std::string> warnings;  // one line each (unknown elements, ...)
    int model = 1;                       // the model read, 1-based (n-th in the file)
    std::size_t assemblies_in_file = 0;  // assemblies the file lists (PDB and mmCIF)
    int assembly = 0;                    // ReadOptions::assembly: 0, or the assembly built
    std::string assembly_name;           // its id in the file ("1"); empty for 0
    std::size_t assembly_operators = 0;  // operators it applies (12 for 4YVS assembly 1)
    std::size_t assembly_chains = 0;     // chain copies: distinct (chain, operator) pairs (180)
};

struct Structure {
    Atoms atoms;
    StructureInfo info;
};

// Reads a structure file; .gz files are decompressed. Throws Error (Io, Format, EmptySelection)
// with a message that names the file and, where it can, the line.
Structure read_structure(const std::string& path, const ReadOptions& options = {});

// Same as read_structure, from text in memory (no gzip). `name` is used in messages and, with
// format Auto, for the extension.
Structure read_structure_from_memory(std::string_view data, const std::string& name,
                                     const ReadOptions& options = {});

// The same from a stream read to its end (the CLI's standard input), gzip data decompressed;
// with format Auto the format comes from `name`'s extension, else from the content (PDB, mmCIF,
// PQR, XYZR, XYZRN). `name` ("standard input") names it in messages. A stream that fails to
// read throws Error(Io).
Structure read_structure(std::istream& in, const std::string& name,
                         const ReadOptions& options = {});

// Every model of a file (options.model == kAllModels), or only options.model, each selected
// as read_structure would: element i is model i+1 (info.model). The file is read and parsed
// once. PQR and XYZR give one Structure.
std::vector<Structure> read_models(const std::string& path, const ReadOptions& options = {});
std::vector<Structure> read_models_from_memory(std::string_view data, const std::string& name,
                                               const ReadOptions& options = {});
std::vector<Structure> read_models(std::istream& in, const std::string& name,
                                   const ReadOptions& options = {});

// Van der Waals radius (Å) used for an element symbol (case-insensitive), or a negative value
// for an unknown element. Table: Bondi (1964) where Bondi gives one, else gemmi's table
// (see docs/structure.md).
float vdw_radius(std::string_view element);
// The radius given to atoms of unknown element (with a warning).
constexpr float kUnknownElementRadius = 1.80f;

const char* to_string(StructureFormat format) noexcept;

// 1 for each atom that gemmi's selection `expr` matches, 0 otherwise (size atoms.size()), the
// atoms taken as model `model` (a selection naming another model matches none). Evaluated on
// the metadata: entity types come from gemmi's heuristic and there are no altlocs, so it can
// differ from ReadOptions::select on PDB/mmCIF files there. Throws Error(InvalidArgument) for
// bad syntax or atoms without metadata.
std::vector<std::uint8_t> match_selection(const Atoms& atoms, const std::string& expr,
                                          int model = 1);

// Throws Error(InvalidArgument), with the syntax, when `expr` is not a gemmi selection; the
// message starts with `option` (the option that gave it, "--patch").
void check_selection(const std::string& expr, const std::string& option = "selection");

// The atoms whose `keep` entry is non-zero, in order, with their metadata.
Atoms subset(const Atoms& atoms, const std::vector<std::uint8_t>& keep);

}  // namespace fdmsurf
