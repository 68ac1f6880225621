// Atom selection on metadata: gemmi's selection syntax, chain filters, subsets of Atoms.
#include <algorithm>
#include <new>

// gemmi's select.hpp includes sprintf.hpp, which wants stb_sprintf.h: Debian's gemmi-dev ships
// without it (libstb-dev is not a dependency). Its std::snprintf fallback serves
// Selection::str(), which is not used here.
#define USE_STD_SNPRINTF
#include <gemmi/polyheur.hpp>
#include <gemmi/select.hpp>

#include "structure/detail.hpp"

namespace fdmsurf {

namespace detail {

namespace {

constexpr const char* kSyntaxHint =
    "gemmi selection syntax: /model/chain/residues/atoms[elements]:altlocs;conditions, any part "
    "left out or '*' for all, e.g. 'A', 'A,B', 'A/10-50', '(HOH)', 'A/*/CA', 'CA[C]', '[S]', "
    "'/1/A/10-50/CA[C]', ';b>20', ';q<0.5', ';polymer', ';!solvent'";

gemmi::Selection parse(const std::string& expr, const std::string& context) {
    try {
        return gemmi::Selection(expr);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(ErrorCode::InvalidArgument, context + ": bad selection '" + expr +
                                                    "': " + e.what() + " (" + kSyntaxHint + ")");
    }
}

bool same_residue(const AtomMeta& a, const AtomMeta& b) {
    return a.residue_number == b.residue_number && a.insertion_code == b.insertion_code &&
           a.residue_name == b.residue_name && a.hetero == b.hetero;
}

gemmi::Atom gemmi_atom(const Atoms& atoms, std::size_t i) {
    const AtomMeta& m = atoms.meta[i];
    gemmi::Atom a;
    a.name = m.name;
    a.element = gemmi::Element(i < atoms.element.size() ? atoms.element[i] : std::string());
    a.serial = m.serial;
    a.occ = m.occupancy;
    a.b_iso = m.b_factor;
    return a;
}

// Runs of atoms with one chain name become a gemmi::Chain, runs with one residue within them a
// gemmi::Residue, so that gemmi's own matches() (and its entity-type heuristic) decide.
void mark_chain(const Atoms& atoms, std::size_t begin, std::size_t end, const gemmi::Selection& sel,
                std::vector<std::uint8_t>& mask) {
    const std::vector<AtomMeta>& meta = atoms.meta;
    gemmi::Chain chain(meta[begin].chain);
    for (std::size_t i = begin; i < end;) {
        gemmi::Residue res;
        res.name = meta[i].residue_name;
        res.seqid = gemmi::SeqId(meta[i].residue_number, meta[i].insertion_code);
        res.het_flag = meta[i].hetero ? 'H' : 'A';
        std::size_t j = i;
        for (; j < end && same_residue(meta[j], meta[i]); ++j)
            res.atoms.push_back(gemmi_atom(atoms, j));
        chain.residues.push_back(std::move(res));
        i = j;
    }
    gemmi::add_entity_types(chain, false);
    if (!sel.matches(chain)) return;
    std::size_t i = begin;
    for (const gemmi::Residue& res : chain.residues) {
        const bool residue = sel.matches(res);
        for (const gemmi::Atom& atom : res.atoms) mask[i++] = residue && sel.matches(atom);
    }
}

std::string counted_atoms(std::size_t n) {
    return std::to_string(n) + (n == 1 ? " atom" : " atoms");
}

}  // namespace

Selection::Selection(const std::string& expr, const std::string& context)
    : sel_(std::make_unique<gemmi::Selection>(parse(expr, context))) {}
Selection::~Selection() = default;
Selection::Selection(Selection&&) noexcept = default;
Selection& Selection::operator=(Selection&&) noexcept = default;

bool Selection::matches_model(int model) const { return sel_->mdl == 0 || sel_->mdl == model; }
bool Selection::matches(const gemmi::Chain& chain) const { return sel_->matches(chain); }
bool Selection::matches(const gemmi::Residue& residue) const { return sel_->matches(residue); }
bool Selection::matches(const gemmi::Atom& atom) const { return sel_->matches(atom); }

std::vector<std::uint8_t> selection_mask(const Atoms& atoms, const std::string& expr, int model,
                                         const std::string& context) {
    const gemmi::Selection sel = parse(expr, context);
    if (atoms.meta.size() != atoms.size())
        throw Error(ErrorCode::InvalidArgument,
                    context + ": selection '" + expr +
                        "' needs atom metadata (chain, residue, atom name), and these " +
                        counted_atoms(atoms.size()) + " have none (XYZR input, or built by hand)");
    std::vector<std::uint8_t> mask(atoms.size(), 0);
    if (sel.mdl != 0 && sel.mdl != model) return mask;
    for (std::size_t begin = 0; begin < atoms.size();) {
        std::size_t end = begin;
        while (end < atoms.size() && atoms.meta[end].chain == atoms.meta[begin].chain) ++end;
        mark_chain(atoms, begin, end, sel, mask);
        begin = end;
    }
    return mask;
}

std::string chain_list(const std::vector<std::string>& chains) {
    std::string list;
    for (const std::string& c : chains)
        list += (list.empty() ? "" : ", ") + (c.empty() ? std::string("(blank)") : c);
    return list;
}

void check_chains_present(const std::vector<std::string>& requested,
                          const std::vector<std::string>& present, const std::string& name,
                          const std::string& where) {
    std::vector<std::string> missing;
    for (const std::string& c : requested)
        if (std::find(present.begin(), present.end(), c) == present.end()) missing.push_back(c);
    if (missing.empty()) return;
    throw Error(ErrorCode::InvalidArgument,
                name + ": chain" + (missing.size() == 1 ? " " : "s ") + chain_list(missing) +
                    (missing.size() == 1 ? " is" : " are") + " not in " + where +
                    "; chains present: " + chain_list(present));
}

void filter_read_atoms(Structure& s, const ReadOptions& options, const std::string& name) {
    if (options.chains.empty() && options.select.empty()) return;
    Atoms& atoms = s.atoms;
    const std::string format = to_string(s.info.format);
    if (atoms.meta.size() != atoms.size())
        throw Error(ErrorCode::InvalidArgument,
                    name + ": " + (options.chains.empty() ? "select" : "chains") +
                        " needs chain, residue and atom names, which " + format +
                        " input does not carry (PDB, mmCIF, PQR and XYZRN with MSMS names do)");
    std::vector<std::uint8_t> keep(atoms.size(), 1);
    std::string removed;
    if (!options.chains.empty()) {
        std::vector<std::string> present;
        for (const AtomMeta& m : atoms.meta)
            if (std::find(present.begin(), present.end(), m.chain) == present.end())
                present.push_back(m.chain);
        if (present.size() == 1 && present[0].empty())
            throw Error(ErrorCode::InvalidArgument,
                        name + ": chains " + chain_list(options.chains) + " requested, but the " +
                            format + " file has no chain ids");
        check_chains_present(options.chains, present, name, "the file");
        std::size_t other = 0;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const std::string& c = atoms.meta[i].chain;
            if (std::find(options.chains.begin(), options.chains.end(), c) ==
                options.chains.end()) {
                keep[i] = 0;
                ++other;
            }
        }
        if (other) removed = counted_atoms(other) + " of other chains";
    }
    if (!options.select.empty()) {
        std::vector<std::uint8_t> match =
            selection_mask(atoms, options.select, s.info.model, name);
        std::size_t unmatched = 0;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            if (keep[i] && !match[i]) {
                keep[i] = 0;
                ++unmatched;
            }
        }
        if (unmatched)
            removed += (removed.empty() ? "" : ", ") + counted_atoms(unmatched) +
                       " not matching select '" + options.select + "'";
    }
    Atoms kept = subset(atoms, keep);
    if (kept.empty())
        throw Error(ErrorCode::EmptySelection, name + ": no atoms left after selection (" +
                                                   counted_atoms(atoms.size()) +
                                                   " read; removed: " + removed + ")");
    atoms = std::move(kept);
}

}  // namespace detail

std::vector<std::uint8_t> match_selection(const Atoms& atoms, const std::string& expr,
                                          int model) {
    return detail::selection_mask(atoms, expr, model, "selection");
}

void check_selection(const std::string& expr, const std::string& option) {
    detail::parse(expr, option);
}

Atoms subset(const Atoms& atoms, const std::vector<std::uint8_t>& keep) {
    if (keep.size() != atoms.size())
        throw Error(ErrorCode::InvalidArgument, "subset: " + std::to_string(keep.size()) +
                                                    " keep flags for " +
                                                    std::to_string(atoms.size()) + " atoms");
    const bool elements = atoms.element.size() == atoms.size();
    const bool meta = atoms.meta.size() == atoms.size();
    Atoms out;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        if (!keep[i]) continue;
        out.xyz.insert(out.xyz.end(), atoms.xyz.begin() + 3 * static_cast<std::ptrdiff_t>(i),
                       atoms.xyz.begin() + 3 * static_cast<std::ptrdiff_t>(i) + 3);
        out.radius.push_back(atoms.radius[i]);
        if (elements) out.element.push_back(atoms.element[i]);
        if (meta) out.meta.push_back(atoms.meta[i]);
    }
    return out;
}

}  // namespace fdmsurf
