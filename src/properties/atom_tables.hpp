// Per-atom values behind the colour schemes and scalars: palettes, Kyte-Doolittle
// hydrophobicity, and the built-in charge model (docs/properties.md lists every value).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/properties.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

using Rgb = std::array<std::uint8_t, 3>;

// Jmol's CPK colours for an element symbol (case-insensitive); deep pink for unknown elements.
Rgb element_color(std::string_view element);
// Jmol/RasMol "shapely" residue colours (amino acids and nucleotides); grey-violet otherwise.
Rgb residue_color(std::string_view residue_name);
// The n-th colour of the chain cycle (chains numbered by first appearance).
Rgb chain_color(std::size_t n);
// Kyte & Doolittle (1982) hydropathy of a standard amino acid; NaN for any other residue.
float kyte_doolittle(std::string_view residue_name);

// t in [-1, 1] through `low` (-1), white (0) and `high` (+1).
Rgb diverging(float t, const Rgb& low, const Rgb& high);
constexpr Rgb kHydrophilic{30, 144, 255};  // dodger blue
constexpr Rgb kHydrophobic{255, 140, 0};   // dark orange
constexpr Rgb kNegative{255, 0, 0};        // coulombic < 0 (and low B-factors: blue)
constexpr Rgb kPositive{0, 0, 255};
constexpr Rgb kUnknownResidue{200, 200, 200};

// Chain, residue name and atom name of an atom, from AtomMeta (XYZRN readers fill them from
// MSMS-style names); empty without metadata.
struct AtomLabel {
    std::string chain, residue_name, atom_name;
    std::string residue_key;  // chain, number and insertion code: one residue
};
std::vector<AtomLabel> atom_labels(const Atoms& atoms);

// Charges (e) for the Coulomb potential: PQR's when the atoms have them; else the built-in
// model (formal charges of the groups ionised at pH 7 spread over their atoms: Asp OD1/OD2 and
// Glu OE1/OE2 -1/2 each, Lys NZ +1, Arg NE/NH1/NH2 +1/3 each, the N of each chain's first amino
// acid (one of the 20, or any residue with N, CA and C: MSE) +1 unless a heavy atom of another
// residue lies within 1.9 Å of it (a cap: ACE, a myristoyl) or it is pyroglutamate's (PCA), O and
// OXT of
// a C-terminus that has OXT -1/2 each, nucleic-acid phosphate OP1/OP2 (O1P/O2P) -1/2 each,
// monatomic ions by name; His neutral). `from_file` tells which.
struct Charges {
    std::vector<float> q;
    bool from_file = false;
};
Charges atom_charges(const Atoms& atoms);

// The colour of each atom under `scheme` (not Coulombic, which colours vertices by potential).
std::vector<Rgb> atom_colors(const Atoms& atoms, const PropertyOptions& options);

}  // namespace fdmsurf::detail
