// Palettes, hydropathy and the built-in charge model (values listed in docs/properties.md).
#include "properties/atom_tables.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include "base/cell_list.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {

namespace {

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

Rgb hex(std::uint32_t v) {
    return {std::uint8_t(v >> 16), std::uint8_t((v >> 8) & 0xff), std::uint8_t(v & 0xff)};
}

bool is_amino_acid(std::string_view r) { return !std::isnan(kyte_doolittle(r)); }

}  // namespace

Rgb element_color(std::string_view element) {
    static const std::unordered_map<std::string, std::uint32_t> table = {
        {"H", 0xFFFFFF},  {"C", 0x909090},  {"N", 0x3050F8},  {"O", 0xFF0D0D},
        {"F", 0x90E050},  {"NA", 0xAB5CF2}, {"MG", 0x8AFF00}, {"P", 0xFF8000},
        {"S", 0xFFFF30},  {"CL", 0x1FF01F}, {"K", 0x8F40D4},  {"CA", 0x3DFF00},
        {"MN", 0x9C7AC7}, {"FE", 0xE06633}, {"CO", 0xF090A0}, {"NI", 0x50D050},
        {"CU", 0xC88033}, {"ZN", 0x7D80B0}, {"SE", 0xFFA100}, {"BR", 0xA62929},
        {"I", 0x940094},  {"CD", 0xFFD98F}, {"HG", 0xB8B8D0}, {"D", 0xFFFFC0}};
    auto it = table.find(upper(element));
    return hex(it == table.end() ? 0xFF1493 : it->second);
}

Rgb residue_color(std::string_view residue_name) {
    static const std::unordered_map<std::string, std::uint32_t> table = {
        {"ALA", 0x8CFF8C}, {"ARG", 0x00007C}, {"ASN", 0xFF7C70}, {"ASP", 0xA00042},
        {"CYS", 0xFFFF70}, {"GLN", 0xFF4C4C}, {"GLU", 0x660000}, {"GLY", 0xFFFFFF},
        {"HIS", 0x7070FF}, {"ILE", 0x004C00}, {"LEU", 0x455E45}, {"LYS", 0x4747B8},
        {"MET", 0xB8A042}, {"PHE", 0x534C42}, {"PRO", 0x525252}, {"SER", 0xFF7042},
        {"THR", 0xB84C00}, {"TRP", 0x4F4600}, {"TYR", 0x8C704C}, {"VAL", 0xFF8CFF},
        {"A", 0xA0A0FF},   {"DA", 0xA0A0FF},  {"C", 0xFF8C4B},   {"DC", 0xFF8C4B},
        {"G", 0xFF7070},   {"DG", 0xFF7070},  {"T", 0xA0FFA0},   {"DT", 0xA0FFA0},
        {"U", 0xFF8080},   {"DU", 0xFF8080}};
    auto it = table.find(upper(residue_name));
    return hex(it == table.end() ? 0xBEA06E : it->second);
}

Rgb chain_color(std::size_t n) {
    // PyMOL-like cycle of distinct, light colours (green, cyan, magenta, yellow, salmon, slate,
    // orange, teal, violet, wheat, light blue, lime).
    static const std::uint32_t cycle[] = {0x33FF33, 0x00FFFF, 0xFF33CC, 0xFFFF00,
                                          0xFF9999, 0x7F7FFF, 0xFF8000, 0x00BFBF,
                                          0xBF7FFF, 0xFFDEAD, 0x99CCFF, 0xBFFF3F};
    return hex(cycle[n % std::size(cycle)]);
}

float kyte_doolittle(std::string_view residue_name) {
    static const std::unordered_map<std::string, float> table = {
        {"ILE", 4.5f},  {"VAL", 4.2f},  {"LEU", 3.8f},  {"PHE", 2.8f},  {"CYS", 2.5f},
        {"MET", 1.9f},  {"ALA", 1.8f},  {"GLY", -0.4f}, {"THR", -0.7f}, {"SER", -0.8f},
        {"TRP", -0.9f}, {"TYR", -1.3f}, {"PRO", -1.6f}, {"HIS", -3.2f}, {"GLU", -3.5f},
        {"GLN", -3.5f}, {"ASP", -3.5f}, {"ASN", -3.5f}, {"LYS", -3.9f}, {"ARG", -4.5f}};
    auto it = table.find(upper(residue_name));
    return it == table.end() ? std::numeric_limits<float>::quiet_NaN() : it->second;
}

Rgb diverging(float t, const Rgb& low, const Rgb& high) {
    t = std::clamp(std::isnan(t) ? 0.0f : t, -1.0f, 1.0f);
    const Rgb& end = t < 0.0f ? low : high;
    const float s = std::abs(t);
    Rgb out;
    for (int k = 0; k < 3; ++k)
        out[k] = static_cast<std::uint8_t>(std::lround(255.0f + (float(end[k]) - 255.0f) * s));
    return out;
}

std::vector<AtomLabel> atom_labels(const Atoms& atoms) {
    std::vector<AtomLabel> out(atoms.size());
    if (atoms.meta.size() != atoms.size()) return out;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const AtomMeta& m = atoms.meta[i];
        AtomLabel& l = out[i];
        l.chain = m.chain;
        l.residue_name = m.residue_name;
        l.atom_name = m.name;
        if (!m.residue_name.empty())
            l.residue_key = m.chain + '\x1f' + std::to_string(m.residue_number) + m.insertion_code;
    }
    return out;
}

Charges atom_charges(const Atoms& atoms) {
    Charges c;
    c.q.assign(atoms.size(), 0.0f);
    if (atoms.meta.size() == atoms.size() && !atoms.meta.empty() &&
        std::all_of(atoms.meta.begin(), atoms.meta.end(),
                    [](const AtomMeta& m) { return m.has_charge; })) {
        for (std::size_t i = 0; i < atoms.size(); ++i) c.q[i] = atoms.meta[i].charge;
        c.from_file = true;
        return c;
    }
    const std::vector<AtomLabel> labels = atom_labels(atoms);
    // The residues in file order, with their N, CA and C atoms. An amino acid is one of the 20
    // or any residue with N, CA and C (MSE, D-amino acids, other modified residues).
    struct Residue {
        std::string chain;
        long n = -1, ca = -1, c = -1;
        bool named_amino_acid = false;
        bool amino_acid() const { return named_amino_acid || (n >= 0 && ca >= 0 && c >= 0); }
    };
    std::vector<Residue> residues;
    std::vector<std::size_t> residue_of(atoms.size(), std::size_t(-1));
    std::map<std::string, bool> has_oxt;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const AtomLabel& l = labels[i];
        if (l.residue_key.empty()) continue;
        if (residues.empty() || labels[i - 1].residue_key != l.residue_key)  // i > 0 there
            residues.push_back({l.chain, -1, -1, -1, is_amino_acid(l.residue_name)});
        residue_of[i] = residues.size() - 1;
        Residue& r = residues.back();
        const std::string a = upper(l.atom_name);
        if (a == "N" && r.n < 0) r.n = long(i);
        else if (a == "CA" && r.ca < 0) r.ca = long(i);
        else if (a == "C" && r.c < 0) r.c = long(i);
        else if (a == "OXT") has_oxt[l.residue_key] = true;
    }
    // The N-terminus of each chain: the N of its first amino acid, unless something is bonded
    // to it: a heavy atom of another residue within 1.9 Å, wherever it stands in the file (an
    // acetyl ACE, a formyl, a myristoyl's C1; a metal's bond is longer), or pyroglutamate (PCA),
    // whose N closes its own lactam ring. Gaps further on are not termini (the residues are
    // only unobserved).
    const auto heavy = [&atoms, &labels](std::size_t i) {
        const std::string e = i < atoms.element.size() ? upper(atoms.element[i]) : std::string();
        if (!e.empty()) return e != "H" && e != "D";
        const std::string a = upper(labels[i].atom_name);
        return a.empty() || (a[0] != 'H' && a[0] != 'D');
    };
    std::vector<char> n_terminal(atoms.size(), 0);
    std::map<std::string, bool> chain_started;
    std::vector<std::size_t> candidates;
    for (const Residue& r : residues) {
        if (!r.amino_acid() || chain_started[r.chain]) continue;
        chain_started[r.chain] = true;
        if (r.n >= 0 && upper(labels[std::size_t(r.n)].residue_name) != "PCA")
            candidates.push_back(std::size_t(r.n));
    }
    if (!candidates.empty()) {
        constexpr double kBond = 1.9;  // Å
        const CellList cells = make_cell_list(atoms.xyz, kBond);
        for (std::size_t n : candidates) {
            const double p[3] = {atoms.xyz[3 * n], atoms.xyz[3 * n + 1], atoms.xyz[3 * n + 2]};
            bool capped = false;
            cells.for_each_near(p, [&](std::uint32_t j) {
                if (capped || residue_of[j] == residue_of[n] || !heavy(j)) return;
                double d2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double d = double(atoms.xyz[3 * j + k]) - p[k];
                    d2 += d * d;
                }
                capped = d2 < kBond * kBond;
            });
            if (!capped) n_terminal[n] = 1;
        }
    }
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const AtomLabel& l = labels[i];
        const std::string r = upper(l.residue_name), a = upper(l.atom_name);
        float q = 0.0f;
        if (r == "ASP" && (a == "OD1" || a == "OD2")) q = -0.5f;
        else if (r == "GLU" && (a == "OE1" || a == "OE2")) q = -0.5f;
        else if (r == "LYS" && a == "NZ") q = 1.0f;
        else if (r == "ARG" && (a == "NE" || a == "NH1" || a == "NH2")) q = 1.0f / 3.0f;
        else if (a == "OP1" || a == "OP2" || a == "O1P" || a == "O2P") q = -0.5f;
        if (n_terminal[i]) q += 1.0f;
        if (residue_of[i] != std::size_t(-1) && residues[residue_of[i]].amino_acid()) {
            if ((a == "O" || a == "OXT") && has_oxt.count(l.residue_key)) q = -0.5f;
        } else if (!r.empty() && (r == a || (r == "IOD" && a == "I"))) {
            // monatomic ions: residue and atom named alike (iodide: IOD / I)
            static const std::unordered_map<std::string, float> ions = {
                {"NA", 1.0f}, {"K", 1.0f},  {"MG", 2.0f}, {"CA", 2.0f}, {"ZN", 2.0f},
                {"MN", 2.0f}, {"CO", 2.0f}, {"NI", 2.0f}, {"CU", 2.0f}, {"CD", 2.0f},
                {"CL", -1.0f}, {"BR", -1.0f}, {"IOD", -1.0f}, {"I", -1.0f}};
            auto it = ions.find(r);
            if (it != ions.end()) q = it->second;
        }
        c.q[i] = q;
    }
    return c;
}

std::vector<Rgb> atom_colors(const Atoms& atoms, const PropertyOptions& options) {
    std::vector<Rgb> out(atoms.size(), options.rgb);
    const std::vector<AtomLabel> labels = atom_labels(atoms);
    switch (options.color) {
        case ColorScheme::None:
        case ColorScheme::Uniform:
        case ColorScheme::Coulombic:
            break;
        case ColorScheme::Element:
            for (std::size_t i = 0; i < atoms.size(); ++i)
                out[i] = element_color(i < atoms.element.size() ? atoms.element[i] : "");
            break;
        case ColorScheme::Chain: {
            std::map<std::string, std::size_t> order;
            for (std::size_t i = 0; i < atoms.size(); ++i)
                out[i] = chain_color(order.emplace(labels[i].chain, order.size()).first->second);
            break;
        }
        case ColorScheme::Residue:
            for (std::size_t i = 0; i < atoms.size(); ++i)
                out[i] = residue_color(labels[i].residue_name);
            break;
        case ColorScheme::Hydrophobicity:
            for (std::size_t i = 0; i < atoms.size(); ++i) {
                float kd = kyte_doolittle(labels[i].residue_name);
                out[i] = std::isnan(kd) ? kUnknownResidue
                                        : diverging(kd / 4.5f, kHydrophilic, kHydrophobic);
            }
            break;
        case ColorScheme::BFactor: {
            if (atoms.meta.size() != atoms.size()) break;
            float lo = std::numeric_limits<float>::max(), hi = -lo;
            for (const AtomMeta& m : atoms.meta) {
                lo = std::min(lo, m.b_factor);
                hi = std::max(hi, m.b_factor);
            }
            const float mid = 0.5f * (lo + hi), half = std::max(0.5f * (hi - lo), 1e-6f);
            for (std::size_t i = 0; i < atoms.size(); ++i)
                out[i] = diverging((atoms.meta[i].b_factor - mid) / half, kPositive, kNegative);
            break;
        }
    }
    return out;
}

}  // namespace fdmsurf::detail

namespace fdmsurf {

const char* to_string(ColorScheme scheme) noexcept {
    switch (scheme) {
        case ColorScheme::None: return "none";
        case ColorScheme::Uniform: return "uniform";
        case ColorScheme::Chain: return "chain";
        case ColorScheme::Element: return "element";
        case ColorScheme::Residue: return "residue";
        case ColorScheme::Hydrophobicity: return "hydrophobicity";
        case ColorScheme::BFactor: return "bfactor";
        case ColorScheme::Coulombic: return "coulombic";
    }
    return "?";
}

const char* to_string(VertexProperty property) noexcept {
    switch (property) {
        case VertexProperty::Coulombic: return "coulombic";
        case VertexProperty::Hydrophobicity: return "hydrophobicity";
        case VertexProperty::BFactor: return "bfactor";
        case VertexProperty::MeanCurvature: return "mean_curvature";
        case VertexProperty::GaussianCurvature: return "gaussian_curvature";
        case VertexProperty::ShapeIndex: return "shape_index";
    }
    return "?";
}

}  // namespace fdmsurf
