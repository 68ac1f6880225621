// Buried interface area between two groups of atoms: the surfaces of the complex and of each
// group alone, on one engine, and the area each atom loses in the complex.
#include <algorithm>
#include <string>

#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf {

namespace {

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, message);
}

std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
    return out;
}

// "A" or "A,C,E1": chain ids (letters and digits) separated by commas.
bool is_chain_list(const std::string& text) {
    if (text.empty() || text.front() == ',' || text.back() == ',') return false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                        (c >= '0' && c <= '9') || (c == ',' && text[i - 1] != ',');
        if (!ok) return false;
    }
    return true;
}

std::vector<std::uint8_t> match_group(const Atoms& atoms, const std::string& text, int model,
                                      const std::vector<std::string>& chains) {
    std::vector<std::uint8_t> in(atoms.size(), 0);
    if (is_chain_list(text)) {
        std::vector<std::string> wanted;
        for (std::size_t start = 0;;) {
            const std::size_t comma = text.find(',', start);
            wanted.push_back(
                text.substr(start, comma == std::string::npos ? comma : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        std::vector<std::string> missing;
        for (const std::string& c : wanted)
            if (std::find(chains.begin(), chains.end(), c) == chains.end()) missing.push_back(c);
        if (!missing.empty())
            invalid("buried group '" + text + "': chain" + (missing.size() == 1 ? " " : "s ") +
                    joined(missing) + (missing.size() == 1 ? " is" : " are") +
                    " not in the structure; chains present: " + joined(chains));
        for (std::size_t i = 0; i < atoms.size(); ++i)
            in[i] = std::find(wanted.begin(), wanted.end(), atoms.meta[i].chain) != wanted.end();
        return in;
    }
    check_selection(text, "buried group '" + text + "'");
    return match_selection(atoms, text, model);
}

}  // namespace

std::vector<std::uint8_t> match_buried_groups(const Atoms& atoms, const std::string& spec,
                                              std::array<std::string, 2>& names, int model) {
    const std::size_t colon = spec.find(':');
    if (colon == std::string::npos || spec.find(':', colon + 1) != std::string::npos)
        invalid("buried groups '" + spec +
                "': give two groups separated by one ':' (chain ids, e.g. A:B or A,C:B,D, or "
                "gemmi selections, e.g. A/1-50:B)");
    names = {spec.substr(0, colon), spec.substr(colon + 1)};
    for (const std::string& g : names)
        if (g.empty()) invalid("buried groups '" + spec + "': a group is empty");
    if (!atoms.has_residues())
        invalid("buried groups '" + spec +
                "' need chains: the atoms have none (XYZR input has only coordinates and radii, "
                "XYZRN names chains only in MSMS's chain_number_icode_residue_atom form; give "
                "PDB, mmCIF, PQR or such XYZRN)");
    std::vector<std::string> chains;
    for (const AtomMeta& m : atoms.meta)
        if (std::find(chains.begin(), chains.end(), m.chain) == chains.end())
            chains.push_back(m.chain);
    std::vector<std::uint8_t> group(atoms.size(), 0);
    std::array<std::size_t, 2> count{};
    std::size_t shared = 0;
    for (int g = 0; g < 2; ++g) {
        const std::vector<std::uint8_t> in = match_group(atoms, names[g], model, chains);
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            if (!in[i]) continue;
            ++count[g];
            if (group[i] != 0)
                ++shared;
            else
                group[i] = std::uint8_t(g + 1);
        }
        if (count[g] == 0)
            invalid("buried group '" + names[g] + "' selects none of the " +
                    std::to_string(atoms.size()) + " atoms");
    }
    if (shared != 0)
        invalid("buried groups '" + names[0] + "' and '" + names[1] +
                "' overlap: " + std::to_string(shared) + " atom" + (shared == 1 ? " is" : "s are") +
                " in both; the groups must be disjoint");
    return group;
}

BuriedAreas buried_areas(Engine* engine, const Atoms& atoms, const std::vector<std::uint8_t>& group,
                         const std::array<std::string, 2>& names, const SurfaceOptions& options) {
    if (group.size() != atoms.size()) invalid("buried_areas: one group entry per atom needed");
    BuriedAreas out;
    out.names = names;
    out.group = group;
    std::vector<std::uint8_t> keep(atoms.size(), 0), in_group[2];
    for (int g = 0; g < 2; ++g) in_group[g].assign(atoms.size(), 0);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        if (group[i] == 0) continue;
        if (group[i] > 2) invalid("buried_areas: group entries are 0, 1 or 2");
        keep[i] = 1;
        in_group[group[i] - 1][i] = 1;
        out.complex_atoms.push_back(std::uint32_t(i));
    }
    out.complex = subset(atoms, keep);
    if (engine != nullptr) {
        out.complex_surface = engine->make_surface(out.complex, options);
        out.in_complex = surface_atom_areas(out.complex, options, &out.complex_surface.mesh);
    } else {
        out.in_complex = surface_atom_areas(out.complex, options, nullptr);
    }
    const std::size_t n = out.complex.size();
    out.alone.area.assign(n, 0.0);
    out.alone.exact = out.in_complex.exact;
    if (engine != nullptr) out.alone.mesh_area.assign(n, 0.0);
    // Each group alone: no colours or properties are needed for areas.
    SurfaceOptions alone_options = options;
    alone_options.properties = PropertyOptions{};
    for (int g = 0; g < 2; ++g) {
        // Complex index of each of the group's atoms, in order.
        std::vector<std::size_t> where;
        for (std::size_t k = 0; k < n; ++k)
            if (group[out.complex_atoms[k]] == g + 1) where.push_back(k);
        out.atom_count[g] = where.size();
        const Atoms part = subset(atoms, in_group[g]);
        AtomAreas a;
        if (engine != nullptr) {
            const SurfaceResult surface = engine->make_surface(part, alone_options);
            a = surface_atom_areas(part, alone_options, &surface.mesh);
            out.alone.mesh_on_patches += a.mesh_on_patches;
        } else {
            a = surface_atom_areas(part, alone_options, nullptr);
        }
        for (std::size_t k = 0; k < where.size(); ++k) {
            out.alone.area[where[k]] = a.area[k];
            out.area_alone[g] += a.area[k];
            out.area_in_complex[g] += out.in_complex.area[where[k]];
            if (engine != nullptr) {
                out.alone.mesh_area[where[k]] = a.mesh_area[k];
                out.mesh_area_alone[g] += a.mesh_area[k];
                out.mesh_area_in_complex[g] += out.in_complex.mesh_area[where[k]];
            }
        }
    }
    return out;
}

}  // namespace fdmsurf
