// PDB and mmCIF through gemmi, with our own checks where gemmi is lenient; selection and radii.
// C++17 only here: clang compiles this file as C++17 (CMakeLists.txt says why: gemmi 0.5).
#include <algorithm>
#include <array>
#include <limits>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <gemmi/assembly.hpp>
#include <gemmi/cif.hpp>
#include <gemmi/mmcif.hpp>
#include <gemmi/pdb.hpp>
#include <gemmi/polyheur.hpp>
#include <gemmi/resinfo.hpp>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "structure/detail.hpp"

namespace fdmsurf::detail {

namespace {

// True for a number outside int's range ("99999999999"): gemmi's string_to_int does not check
// for overflow (found by fuzz_mmcif), so such a value would come out as another number
// (read_gemmi.cpp is compiled with -fwrapv, which makes it defined). `value` is the token as
// gemmi reads it (quotes and text-field markers taken off).
bool integer_out_of_int_range(const std::string& value) {
    std::size_t i = 0;
    auto space = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };  // gemmi's is_space
    while (i < value.size() && space(value[i])) ++i;
    const bool negative = i < value.size() && value[i] == '-';
    if (i < value.size() && (value[i] == '-' || value[i] == '+')) ++i;
    while (i < value.size() && value[i] == '0') ++i;
    std::size_t digits = 0;
    while (i + digits < value.size() && value[i + digits] >= '0' && value[i + digits] <= '9')
        ++digits;
    const char* const largest = negative ? "2147483648" : "2147483647";
    return digits > 10 || (digits == 10 && value.compare(i, 10, largest) > 0);
}

// The _atom_site columns that gemmi reads as ints and fdmsurf uses (serials in messages,
// residue numbers in names and per-residue areas; the charge, read and not used, would still
// be read wrong): a value outside int's range is refused with its row rather than read as a
// wrapped number. pdbx_PDB_model_num is not among them: gemmi keeps it as the model's name.
void check_cif_integers(gemmi::cif::Block& block, const std::string& name) {
    static const char* const kIntegerColumns[] = {"id", "label_seq_id", "auth_seq_id",
                                                  "pdbx_formal_charge"};
    for (const char* tag : kIntegerColumns) {
        const gemmi::cif::Column column = block.find_values(std::string("_atom_site.") + tag);
        std::size_t row = 0;
        for (const std::string& raw : column) {
            ++row;
            const std::string value = gemmi::cif::as_string(raw);
            if (integer_out_of_int_range(value))
                fail_format(name + ": _atom_site." + tag + " " + gemmi::trim_str(value) +
                            " in row " + std::to_string(row) +
                            " is out of range (integers from -2147483648 to 2147483647)");
        }
    }
}

// The _atom_site of the first block, a loop (or, for one atom, name-value pairs), row by row.
class AtomSite {
public:
    explicit AtomSite(gemmi::cif::Block& block) : block_(block) {
        gemmi::cif::Item* item = block.find_values("_atom_site.Cartn_x").item();
        if (item && item->type == gemmi::cif::ItemType::Loop) loop_ = &item->loop;
    }
    std::size_t rows() const { return loop_ ? loop_->length() : 1; }
    bool has(const char* tag) const { return block_.has_tag(std::string("_atom_site.") + tag); }
    // The value as gemmi reads it ("" for '?' and '.', and for a column that is not there).
    std::string value(std::size_t row, const char* tag) const {
        const std::string full = std::string("_atom_site.") + tag;
        if (loop_) {
            int col = loop_->find_tag(full);
            return col < 0 ? "" : gemmi::cif::as_string(loop_->val(row, std::size_t(col)));
        }
        const std::string* v = block_.find_value(full);
        return v ? gemmi::cif::as_string(*v) : "";
    }
    // Appends a column, `make(row)` giving each value (written as CIF: quoted where needed,
    // '.' for "").
    template <typename F>
    void add(const char* tag, F make_value) {
        auto make = [&](std::size_t r) {
            std::string v = make_value(r);
            return v.empty() ? std::string(".") : gemmi::cif::quote(v);
        };
        const std::string full = std::string("_atom_site.") + tag;
        if (!loop_) {
            block_.set_pair(full, make(0));
            return;
        }
        const std::size_t width = loop_->width(), n = loop_->length();
        std::vector<std::string> values;
        values.reserve((width + 1) * n);
        for (std::size_t r = 0; r < n; ++r) {
            auto row = loop_->values.begin() + std::ptrdiff_t(r * width);
            values.insert(values.end(), std::make_move_iterator(row),
                          std::make_move_iterator(row + std::ptrdiff_t(width)));
            values.push_back(make(r));
        }
        loop_->tags.push_back(full);
        loop_->values.swap(values);
    }

private:
    gemmi::cif::Block& block_;
    gemmi::cif::Loop* loop_ = nullptr;
};

bool all_digits(const std::string& s) {
    std::size_t i = !s.empty() && s[0] == '-' ? 1 : 0;
    return i < s.size() && std::all_of(s.begin() + std::ptrdiff_t(i), s.end(),
                                       [](char c) { return c >= '0' && c <= '9'; });
}

// Residue numbers where _atom_site has no auth_seq_id: label_seq_id where it is a number, and
// for the rows without one (waters and ligands have '.'), numbers from past the largest
// label_seq_id on, a new one where the chain or residue name changes or an atom name repeats.
std::vector<std::string> residue_numbers_from_labels(const AtomSite& site, long& first_made) {
    long largest = 0;
    std::vector<std::string> out(site.rows());
    for (std::size_t r = 0; r < site.rows(); ++r) {
        out[r] = site.value(r, "label_seq_id");
        if (all_digits(out[r]) && out[r].size() < 10) largest = std::max(largest, std::stol(out[r]));
    }
    first_made = largest + 1;
    long next = first_made, current = 0;
    std::string key, model;
    std::set<std::string> names;
    bool in_made = false;
    for (std::size_t r = 0; r < site.rows(); ++r) {
        const std::string m = site.value(r, "pdbx_PDB_model_num");
        if (m != model) model = m, next = first_made, in_made = false;
        if (all_digits(out[r]) && out[r].size() < 10) {
            in_made = false;
            continue;
        }
        const std::string k = site.value(r, "label_asym_id") + ' ' + site.value(r, "auth_asym_id") +
                              ' ' + site.value(r, "label_comp_id") + ' ' +
                              site.value(r, "auth_comp_id");
        std::string atom = site.value(r, "label_atom_id") + ' ' + site.value(r, "auth_atom_id");
        if (!in_made || k != key || !names.insert(atom).second) {
            current = next++;
            names = {atom};
            key = k;
            in_made = true;
        }
        out[r] = std::to_string(current);
    }
    return out;
}

// The element from an atom name, as for PQR: its first letter after leading digits.
std::string element_from_name(const std::string& atom) {
    for (char c : atom)
        if (std::isalpha(static_cast<unsigned char>(c))) return std::string(1, c);
    return "X";
}

// gemmi needs _atom_site columns that a surface does not: files that keep only the label_*
// items (PyMOL, ChimeraX) or minimal ones written by libraries lack them. They are filled in,
// each with a warning that says what was assumed; only the coordinates are required.
void complete_cif_columns(gemmi::cif::Document& doc, const std::string& name,
                          std::vector<std::string>& warnings) {
    if (doc.blocks.empty()) fail_format(name + ": no data block (not an mmCIF file)");
    gemmi::cif::Block& block = doc.blocks[0];
    static const char* const kKnown[] = {
        "id",          "type_symbol",   "label_alt_id", "label_asym_id", "auth_asym_id",
        "Cartn_x",     "Cartn_y",       "Cartn_z",      "occupancy",     "B_iso_or_equiv",
        "auth_seq_id", "label_seq_id", "label_atom_id", "auth_atom_id",  "label_comp_id"};
    AtomSite site(block);
    if (std::none_of(std::begin(kKnown), std::end(kKnown), [&](const char* t) { return site.has(t); }))
        fail_format(name + ": no _atom_site table (no atoms)");
    std::string missing;
    for (const char* tag : {"Cartn_x", "Cartn_y", "Cartn_z"})
        if (!site.has(tag)) missing += std::string(missing.empty() ? "" : ", ") + tag;
    if (!missing.empty())
        fail_format(name + ": _atom_site lacks column(s) " + missing + " (needed to read atoms)");
    check_cif_integers(block, name);

    const std::string lacks = name + ": _atom_site has no ";
    if (!site.has("auth_seq_id")) {
        long first_made = 0;
        std::vector<std::string> numbers = residue_numbers_from_labels(site, first_made);
        site.add("auth_seq_id", [&](std::size_t r) { return numbers[r]; });
        warnings.push_back(lacks + "auth_seq_id; residue numbers are label_seq_id (rows without "
                                   "one, waters and ligands, numbered from " +
                           std::to_string(first_made) + " on in file order)");
    }
    const bool label_asym = site.has("label_asym_id"), auth_asym = site.has("auth_asym_id");

    if (!label_asym && auth_asym) {
        site.add("label_asym_id", [&](std::size_t r) { return site.value(r, "auth_asym_id"); });
        warnings.push_back(lacks + "label_asym_id; auth_asym_id used for it");
    } else if (!label_asym) {
        site.add("label_asym_id", [](std::size_t) { return std::string(); });
        warnings.push_back(lacks + "chain ids (auth_asym_id, label_asym_id); one blank chain");
    }  // without auth_asym_id, gemmi takes label_asym_id for the chains, as it always has
    if (!site.has("type_symbol")) {
        const bool auth_atom = site.has("auth_atom_id");
        site.add("type_symbol", [&](std::size_t r) {
            return element_from_name(site.value(r, auth_atom ? "auth_atom_id" : "label_atom_id"));
        });
        warnings.push_back(lacks + "type_symbol; elements from the atom names' first letter");
    }
    if (!site.has("id")) {
        site.add("id", [](std::size_t r) { return std::to_string(r + 1); });
        warnings.push_back(lacks + "id; atom serials are row numbers");
    }
    if (!site.has("label_alt_id")) {
        site.add("label_alt_id", [](std::size_t) { return std::string(); });
        warnings.push_back(lacks + "label_alt_id; no alternate locations");
    }
    if (!site.has("occupancy")) {
        site.add("occupancy", [](std::size_t) { return std::string("1"); });
        warnings.push_back(lacks + "occupancy; 1 assumed");
    }
    if (!site.has("B_iso_or_equiv")) {
        site.add("B_iso_or_equiv", [](std::size_t) { return std::string("0"); });
        warnings.push_back(lacks + "B_iso_or_equiv; B-factor 0 assumed");
    }
}

// Element symbols as the file writes them, by "residue atom": gemmi keeps only the parsed
// element, and the unknown-element warning should name what the file says.
using SymbolMap = std::unordered_map<std::string, std::string>;

SymbolMap pdb_symbols(std::string_view text) {
    SymbolMap symbols;
    LineReader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        if (is_end_record(line)) break;
        if (!is_atom_record(line)) continue;
        std::string key =
            std::string(trim(line.substr(17, 3))) + ' ' + std::string(trim(line.substr(12, 4)));
        symbols.emplace(key, line.size() > 76 ? trim(line.substr(76, 2)) : "");
    }
    return symbols;
}

SymbolMap cif_symbols(gemmi::cif::Block& block) {
    SymbolMap symbols;
    gemmi::cif::Table table = block.find(
        "_atom_site.",
        {"type_symbol", "?auth_comp_id", "?label_comp_id", "?auth_atom_id", "?label_atom_id"});
    if (table.length() == 0) return symbols;
    const int comp = table.first_of(1, 2);  // auth_ names first, as gemmi reads them
    const int atom = table.first_of(3, 4);
    if (!table.has_column(comp) || !table.has_column(atom)) return symbols;
    for (auto row : table)
        symbols.emplace(gemmi::cif::as_string(row[comp]) + ' ' + gemmi::cif::as_string(row[atom]),
                        gemmi::cif::as_string(row[0]));
    return symbols;
}

std::string counted(std::size_t n, const std::string& noun) {
    if (n != 1 && !noun.empty() && noun.back() == 'y')
        return std::to_string(n) + " " + noun.substr(0, noun.size() - 1) + "ies";
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// The protonation states and caps of the AMBER and CHARMM force fields, which gemmi's table
// does not hold: amino acids, as far as their atoms' elements go.
bool is_force_field_residue(const std::string& name) {
    static const std::set<std::string> names = {"HIE", "HID", "HIP", "HSD", "HSE", "HSP",
                                                "CYX", "CYM", "ASH", "GLH", "LYN", "ARN",
                                                "TYM", "ACE", "NME", "NHE"};
    return names.count(name) != 0;
}

// A PDB atom name that starts in column 13 with no element columns is read by gemmi as a
// two-letter element (AMBER's and other MD programs' "CA  " in ALA becomes calcium, "HG2 " in
// ARG mercury) or as no element ("CB  " in ALA, "CH3 " in ACE). Standard amino acids and nucleotides
// (with the force fields' HIE, CYX, ACE, NME, ...)
// hold no two-letter element, nor does a name of three or four characters from H in a residue
// of several atoms (HE1 in AMBER's HIE is no helium: a mercury ion is named HG, alone), and a
// name gemmi finds no element in starts with its element in the files that write them: there
// the element is the name's first letter when it is H, C, N, O, S or P, with one warning for
// each of the two cases.
void elements_from_names(gemmi::Structure& st, const std::string& name,
                         std::vector<std::string>& warnings) {
    std::size_t metals = 0, unknown = 0;
    std::string metal_example, unknown_example;
    for (gemmi::Model& model : st.models)
        for (gemmi::Chain& chain : model.chains)
            for (gemmi::Residue& res : chain.residues) {
                const gemmi::ResidueInfo info = gemmi::find_tabulated_residue(res.name);
                const bool standard =
                    (info.is_standard() && (info.is_amino_acid() || info.is_nucleic_acid())) ||
                    is_force_field_residue(res.name);
                for (gemmi::Atom& atom : res.atoms) {
                    const char* symbol = atom.element.uname();
                    std::size_t first = atom.name.find_first_not_of("0123456789");
                    if (first == std::string::npos) continue;
                    const char letter =
                        static_cast<char>(std::toupper(static_cast<unsigned char>(atom.name[first])));
                    if (std::string_view("HCNOSP").find(letter) == std::string_view::npos) continue;
                    if (atom.element == gemmi::El::X) {
                        if (unknown++ == 0) unknown_example = atom.name + " in " + res.name;
                    } else if (symbol[0] == letter && symbol[1] != '\0' && first == 0 &&
                               (standard || (letter == 'H' && atom.name.size() > 2 &&
                                             res.atoms.size() > 1))) {
                        if (metals++ == 0)
                            metal_example = atom.name + " in " + res.name + " (not " +
                                            atom.element.name() + ")";
                    } else {
                        continue;
                    }
                    atom.element = gemmi::Element(std::string(1, letter));
                }
            }
    if (metals)
        warnings.push_back(name + ": " + counted(metals, "atom") +
                           " named from column 13 without an element symbol (in standard "
                           "residues, or hydrogens named like HE1), e.g. " + metal_example +
                           ", read as the element of the name's first letter");
    if (unknown)
        warnings.push_back(name + ": " + counted(unknown, "atom") +
                           " without an element symbol or a name that starts with one, e.g. " +
                           unknown_example + ", read as the element of the name's first letter");
}

// An mmCIF file whose first item comes before any data_ header (a table cut out of a file, as
// Biopython's tests keep one): the text with a header in front, with a warning; "" when the
// file has its header.
std::string with_block_header(std::string_view text, const std::string& name,
                              std::vector<std::string>& warnings) {
    LineReader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        std::string_view t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        if (t.size() >= 5 && iequals(t.substr(0, 5), "data_")) return "";
        if (!(t[0] == '_' || (t.size() >= 5 && iequals(t.substr(0, 5), "loop_")))) return "";
        warnings.push_back(name + ": no data_ header before the first item" + at_line(lines.number()) +
                           "; the file read as one data block");
        return "data_file\n" + std::string(text);
    }
    return "";
}

// Radii by element; atoms of unknown element get the default radius, and one warning per
// distinct symbol as the file writes it (read again only when such an atom turns up).
class RadiusAssigner {
public:
    RadiusAssigner(std::string_view text, gemmi::cif::Document& doc, StructureFormat format)
        : text_(text), doc_(doc), format_(format) {}

    float radius(const gemmi::Residue& res, const gemmi::Atom& atom) {
        // The radius is the element's: looked up once per element, not per atom.
        float& known = by_element_[std::size_t(atom.element.elem)];
        if (std::isnan(known)) known = vdw_radius(atom.element.name());
        const float r = known;
        if (r > 0.0f) return r;
        if (!symbols_read_) {
            symbols_ =
                format_ == StructureFormat::Pdb ? pdb_symbols(text_) : cif_symbols(doc_.blocks[0]);
            symbols_read_ = true;
        }
        auto it = symbols_.find(res.name + ' ' + atom.name);
        std::string symbol = it == symbols_.end() ? "" : it->second;
        for (char& c : symbol) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        Unknown& u = unknown_[symbol];
        if (u.count++ == 0) u.example = "atom " + atom.name + " in residue " + res.name;
        return kUnknownElementRadius;
    }

    void add_warnings(const std::string& name, std::vector<std::string>& warnings) const {
        char radius[16];
        std::snprintf(radius, sizeof radius, "%.2f", static_cast<double>(kUnknownElementRadius));
        for (const auto& [symbol, u] : unknown_) {
            std::string what = symbol.empty() ? "no element symbol (e.g. " + u.example + ")"
                                              : "unknown element '" + symbol + "'";
            warnings.push_back(name + ": " + what + " for " + counted(u.count, "atom") +
                               "; radius " + radius + " A used");
        }
    }

private:
    struct Unknown {
        std::size_t count = 0;
        std::string example;  // "atom NAME in residue RES"
    };
    std::string_view text_;
    gemmi::cif::Document& doc_;
    StructureFormat format_;
    std::array<float, std::size_t(gemmi::El::END)> by_element_ = make_unknown();
    static std::array<float, std::size_t(gemmi::El::END)> make_unknown() {
        std::array<float, std::size_t(gemmi::El::END)> a;
        a.fill(std::numeric_limits<float>::quiet_NaN());
        return a;
    }
    SymbolMap symbols_;
    bool symbols_read_ = false;
    std::map<std::string, Unknown> unknown_;  // by symbol, for a stable warning order
};

// "model 2", or "assembly 1 of model 2" for an assembly.
std::string what_was_read(const StructureInfo& info) {
    std::string model = "model " + std::to_string(info.model);
    return info.assembly == 0 ? model
                              : "assembly " + std::to_string(info.assembly) + " of " + model;
}

// ReadOptions::chains and ::select, applied to the atoms that the other rules keep. StructureInfo
// has no counts for them; they are kept here for the empty-selection message.
struct AtomFilter {
    const std::vector<std::string>& chains;
    std::optional<Selection> select;
    std::string select_text;
    std::size_t other_chains = 0;
    std::size_t unselected = 0;
};

std::string empty_selection_message(const std::string& name, const StructureInfo& info,
                                    const AtomFilter& filter) {
    std::string removed;
    auto add = [&](std::size_t n, const char* noun, const std::string& option) {
        if (n) removed += (removed.empty() ? "" : ", ") + counted(n, noun) + option;
    };
    add(info.altlocs_skipped, "alternate location", "");
    add(info.waters_skipped, "water atom", " (keep_waters, the CLI's --waters)");
    add(info.ligands_skipped, "ligand atom", " (keep_ligands; the CLI keeps them unless --no-ligands)");
    add(info.hydrogens_skipped, "hydrogen", " (keep_hydrogens, --hydrogens)");
    add(filter.other_chains, "atom", " of other chains (chains " + chain_list(filter.chains) + ")");
    add(filter.unselected, "atom", " not matching select '" + filter.select_text + "'");
    return name + ": no atoms left after selection (" + what_was_read(info) + " has " +
           counted(info.atoms_in_file, "atom") + (removed.empty() ? "" : "; removed: " + removed) +
           ")";
}

std::string assembly_ids(const std::vector<gemmi::Assembly>& assemblies) {
    std::string ids;
    for (const gemmi::Assembly& a : assemblies) ids += (ids.empty() ? "" : ", ") + a.name;
    return ids;
}

// The biological assembly `number` (1-based, file order) of `model`: every operator applied
// to the chains (PDB) or subchains (mmCIF) it names. Atoms that two operators put on the same
// spot (a ligand on a symmetry axis) are kept twice; a max-of-Gaussians density does not
// change. gemmi's complaints about chains the assembly names but the model lacks become
// warnings.
gemmi::Model build_assembly(const gemmi::Structure& st, gemmi::cif::Document& doc,
                            const gemmi::Model& model, int number, const std::string& name,
                            StructureInfo& info) {
    const std::string asked = name + ": assembly " + std::to_string(number) + " requested, but ";
    if (st.assemblies.empty())
        throw Error(ErrorCode::InvalidArgument,
                    asked + "the file lists no assemblies (no " +
                        (info.format == StructureFormat::Pdb ? "REMARK 350 BIOMOLECULE"
                                                             : "_pdbx_struct_assembly") +
                        ")");
    if (static_cast<std::size_t>(number) > st.assemblies.size())
        throw Error(ErrorCode::InvalidArgument,
                    asked + "the file has " + counted(st.assemblies.size(), "assembly") + " (id" +
                        (st.assemblies.size() == 1 ? " " : "s ") + assembly_ids(st.assemblies) +
                        ")");
    const gemmi::Assembly& assembly = st.assemblies[static_cast<std::size_t>(number - 1)];
    // gemmi 0.5.7 reads only the first factor of a product of operators, "(1-60)(61-88)": a
    // part of the assembly would come out as if it were all of it.
    if (!doc.blocks.empty()) {
        gemmi::cif::Table gens =
            doc.blocks[0].find("_pdbx_struct_assembly_gen.", {"assembly_id", "oper_expression"});
        for (auto row : gens) {
            const std::string expr = row.str(1);
            if (row.str(0) == assembly.name && expr.find(')') != std::string::npos &&
                expr.find('(', expr.find(')')) != std::string::npos)
                fail_format(name + ": assembly " + assembly.name +
                            " uses a product of operators ('" + expr +
                            "'), which fdmsurf cannot expand");
        }
    }
    std::ostringstream log;
    gemmi::Model built =
        gemmi::make_assembly(assembly, model, gemmi::HowToNameCopiedChain::AddNumber, &log);
    info.assembly = number;
    info.assembly_name = assembly.name;
    // Chain copies as (chain, operator) pairs: an mmCIF assembly lists a chain's polymer and
    // ligand subchains in separate generators, and gemmi makes one chain object for each.
    std::set<std::pair<std::string, std::string>> copies;
    for (std::size_t g = 0; g < assembly.generators.size(); ++g) {
        const gemmi::Assembly::Gen& gen = assembly.generators[g];
        const bool all = !gen.chains.empty() && gen.chains[0] == "(all)";
        for (std::size_t o = 0; o < gen.operators.size(); ++o) {
            const std::string& op = gen.operators[o].name;
            const std::string op_key =
                op.empty() ? std::to_string(g) + "/" + std::to_string(o) : op;
            for (const gemmi::Chain& chain : model.chains)
                if (all || gemmi::in_vector(chain.name, gen.chains) ||
                    (!gen.subchains.empty() && gemmi::impl::any_subchain_matches(chain, gen)))
                    copies.emplace(chain.name, op_key);
        }
        info.assembly_operators += gen.operators.size();
    }
    info.assembly_chains = copies.size();
    std::string line;
    std::istringstream lines(log.str());
    while (std::getline(lines, line)) {
        if (line.rfind("Warning: ", 0) == 0)
            info.warnings.push_back(name + ": assembly " + assembly.name + ": " + line.substr(9));
    }
    return built;
}

// gemmi reports problems as std::runtime_error (and the odd logic_error): rethrow as ours.
template <typename F>
void with_gemmi(const std::string& name, F&& f) {
    try {
        f();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        std::string what = e.what();
        fail_format(what.rfind(name, 0) == 0 ? what : name + ": " + what);
    }
}

// What the file says of one atom; `chain` is the copy's name in an assembly.
AtomMeta atom_meta(const gemmi::Chain& chain, const gemmi::Residue& res, const gemmi::Atom& atom) {
    AtomMeta m;
    m.serial = atom.serial;
    m.name = atom.name;
    m.residue_name = res.name;
    m.residue_number = res.seqid.num.has_value() ? *res.seqid.num : 0;
    m.insertion_code = res.seqid.icode;
    m.chain = chain.name;
    m.hetero = res.het_flag == 'H';
    m.b_factor = atom.b_iso;
    m.occupancy = atom.occ;
    m.charge = static_cast<float>(atom.charge);
    m.has_charge = false;
    return m;
}

// Every requested chain must be in the model (or assembly) read.
void check_chains(const gemmi::Model& model, const std::vector<std::string>& chains,
                  const std::string& name, const StructureInfo& info) {
    std::vector<std::string> present;
    for (const gemmi::Chain& chain : model.chains)
        if (!gemmi::in_vector(chain.name, present)) present.push_back(chain.name);
    check_chains_present(chains, present, name, what_was_read(info));
}

// Applies the selection rules to one model; see docs/structure.md for the order of counting.
// The selection is evaluated on gemmi's own objects here (entity types from the file, altlocs),
// not on the metadata as match_selection does.
void select_atoms(const gemmi::Model& model, const ReadOptions& options, const std::string& name,
                  RadiusAssigner& radii, AtomFilter& filter, Structure& out) {
    StructureInfo& info = out.info;
    Atoms& atoms = out.atoms;
    if (!filter.chains.empty()) check_chains(model, filter.chains, name, info);
    // Room for every atom of the model up front: no copies of the per-atom strings as the
    // arrays grow (what the rules leave out is only reserved).
    std::size_t in_model = 0;
    for (const gemmi::Chain& chain : model.chains)
        for (const gemmi::Residue& res : chain.residues) in_model += res.atoms.size();
    atoms.xyz.reserve(atoms.xyz.size() + 3 * in_model);
    atoms.radius.reserve(atoms.radius.size() + in_model);
    atoms.element.reserve(atoms.element.size() + in_model);
    atoms.meta.reserve(atoms.meta.size() + in_model);
    const bool model_selected = !filter.select || filter.select->matches_model(info.model);
    for (const gemmi::Chain& chain : model.chains) {
        const bool chain_kept =
            filter.chains.empty() || gemmi::in_vector(chain.name, filter.chains);
        const bool chain_selected =
            model_selected && (!filter.select || filter.select->matches(chain));
        // "seqid atom" of alternate locations kept, with the letter kept: an atom of the same
        // name and letter is another atom (a file whose names repeat, its residue name a
        // column left so that its first letter reads as the altloc), not an alternate.
        std::unordered_map<std::string, char> seen_altloc;
        // seqid -> the residue name whose alternate locations are kept there: where two residues
        // share a position (microheterogeneity: altloc A SER, altloc B THR), the first one's.
        std::unordered_map<std::string, std::string> altloc_residue;
        for (const gemmi::Residue& res : chain.residues) {
            bool water = res.is_water() || res.entity_type == gemmi::EntityType::Water;
            bool ligand =
                !water && res.het_flag == 'H' && res.entity_type != gemmi::EntityType::Polymer;
            for (const gemmi::Atom& atom : res.atoms) {
                ++info.atoms_in_file;
                const gemmi::Position& p = atom.pos;
                // mmCIF values that are not numbers ('?', text, nan) come out of gemmi as NaN.
                if (!std::isfinite(static_cast<float>(p.x)) ||
                    !std::isfinite(static_cast<float>(p.y)) ||
                    !std::isfinite(static_cast<float>(p.z)))
                    fail_format(name + ": non-numeric, NaN or infinite coordinates for atom " +
                                std::to_string(atom.serial) + " (" + chain.name + "/" + res.name +
                                " " + res.seqid.str() + "/" + atom.name + ")");
                if (atom.altloc != '\0' &&
                    (altloc_residue.emplace(res.seqid.str(), res.name).first->second != res.name ||
                     seen_altloc.emplace(res.seqid.str() + ' ' + atom.name, atom.altloc)
                             .first->second != atom.altloc)) {
                    ++info.altlocs_skipped;
                } else if (water && !options.keep_waters) {
                    ++info.waters_skipped;
                } else if (ligand && !options.keep_ligands) {
                    ++info.ligands_skipped;
                } else if (atom.is_hydrogen() && !options.keep_hydrogens) {
                    ++info.hydrogens_skipped;
                } else if (!chain_kept) {
                    ++filter.other_chains;
                } else if (filter.select && !(chain_selected && filter.select->matches(res) &&
                                              filter.select->matches(atom))) {
                    ++filter.unselected;
                } else {
                    atoms.xyz.insert(atoms.xyz.end(),
                                     {static_cast<float>(p.x), static_cast<float>(p.y),
                                      static_cast<float>(p.z)});
                    atoms.radius.push_back(radii.radius(res, atom));
                    atoms.element.emplace_back(atom.element == gemmi::El::X ? "X"
                                                                            : atom.element.uname());
                    atoms.meta.push_back(atom_meta(chain, res, atom));
                }
            }
        }
    }
}

}  // namespace

std::vector<Structure> read_pdb_or_mmcif(std::string_view text_in, const std::string& name,
                                         StructureFormat format, const ReadOptions& options) {
    // gemmi wants a newline after the last record to count its columns right.
    std::string text_nl;
    if (text_in.back() != '\n') text_nl = std::string(text_in) + '\n';
    const std::string_view text = text_nl.empty() ? text_in : text_nl;

    gemmi::Structure st;
    gemmi::cif::Document doc;
    std::vector<std::string> file_warnings;  // about the file, given with every model
    with_gemmi(name, [&] {
        if (format == StructureFormat::Pdb) {
            const std::string prepared = prepare_pdb_text(text, name, file_warnings);
            const std::string_view pdb = prepared.empty() ? text : prepared;
            st = gemmi::read_pdb_from_memory(pdb.data(), pdb.size(), name);
            elements_from_names(st, name, file_warnings);
        } else {
            const std::string headed = with_block_header(text, name, file_warnings);
            const std::string_view cif = headed.empty() ? text : headed;
            doc = gemmi::cif::read_memory(cif.data(), cif.size(), name.c_str());
            complete_cif_columns(doc, name, file_warnings);
            st = gemmi::make_structure(doc);
        }
        // Entity types tell modified residues inside a chain (HETATM MSE) from ligands.
        gemmi::add_entity_types(st, false);
    });

    std::size_t atoms_total = 0;
    for (const gemmi::Model& m : st.models)
        for (const gemmi::Chain& c : m.chains)
            for (const gemmi::Residue& r : c.residues) atoms_total += r.atoms.size();
    if (atoms_total == 0)
        fail_format(name + ": no atoms (no " +
                    (format == StructureFormat::Pdb ? "ATOM/HETATM records" : "_atom_site rows") +
                    ")");
    if (static_cast<std::size_t>(options.model) > st.models.size())
        throw Error(ErrorCode::InvalidArgument, name + ": model " + std::to_string(options.model) +
                                                    " requested, but the file has " +
                                                    counted(st.models.size(), "model"));

    const std::size_t first = options.model == kAllModels ? 0 : std::size_t(options.model - 1);
    const std::size_t last = options.model == kAllModels ? st.models.size() : first + 1;
    std::vector<Structure> out;
    out.reserve(last - first);
    for (std::size_t m = first; m < last; ++m) {
        Structure s;
        s.info.format = format;
        s.info.models_in_file = st.models.size();
        s.info.model = static_cast<int>(m + 1);
        s.info.assemblies_in_file = st.assemblies.size();
        s.info.warnings = file_warnings;
        RadiusAssigner radii(text, doc, format);
        AtomFilter filter{options.chains, std::nullopt, options.select};
        if (!options.select.empty()) filter.select.emplace(options.select, name);
        if (options.assembly == 0) {
            select_atoms(st.models[m], options, name, radii, filter, s);
        } else {
            gemmi::Model built(st.models[m].name);
            with_gemmi(name, [&] {
                built = build_assembly(st, doc, st.models[m], options.assembly, name, s.info);
            });
            select_atoms(built, options, name, radii, filter, s);
        }
        radii.add_warnings(name, s.info.warnings);
        if (s.atoms.empty())
            throw Error(ErrorCode::EmptySelection, empty_selection_message(name, s.info, filter));
        out.push_back(std::move(s));
    }
    return out;
}

}  // namespace fdmsurf::detail
