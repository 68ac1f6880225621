// Valid but unusual input (issue 16, item 7), each read by fdmsurf and compared with gemmi's own
// reading of the same text (its first model, or the one asked for, the first alternate location
// of each atom kept): mmCIF with '?' and '.' values, multi-character chains, insertion codes,
// alternate locations whose occupancies sum over 1, models of different sizes, hybrid-36
// serials, PDB without element columns, lowercase elements, CRLF line ends, a byte-order mark
// and empty lines; PQR with extra columns against the same file without them. The inputs are
// tests/data's crambin edited in place, so every case holds a real structure.
//
// C++17 only: clang compiles this file as C++17, like src/structure/read_gemmi.cpp (gemmi's
// CIF document does not compile with clang in C++20; tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <gemmi/modify.hpp>
#include <gemmi/cif.hpp>
#include <gemmi/mmcif.hpp>
#include <gemmi/pdb.hpp>

#include <cctype>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;
using test::read_text_file;

// One atom as both readers see it.
struct Seen {
    std::string chain;
    int residue = 0;
    char icode = ' ';
    std::string name;
    std::string element;
    float x = 0, y = 0, z = 0;
};

ReadOptions keep_everything(int model = 1) {
    ReadOptions o;
    o.keep_waters = true;
    o.keep_hydrogens = true;
    o.keep_ligands = true;
    o.model = model;
    return o;
}

std::string upper(std::string s) {
    for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

// gemmi's reading: model `model` (1-based), every atom in file order but the second and later
// alternate locations of an atom (chain, residue number, insertion code, name); with
// `first_conformer`, gemmi's own remove_alternative_conformations instead (which also keeps
// only the first residue at a position).
std::vector<Seen> gemmi_reading(const std::string& text, bool cif, int model = 1,
                                bool first_conformer = false) {
    gemmi::Structure st =
        cif ? gemmi::make_structure(gemmi::cif::read_memory(text.data(), text.size(), "ref"))
            : gemmi::read_pdb_from_memory(text.data(), text.size(), "ref");
    EXPECT_GE(st.models.size(), std::size_t(model));
    if (first_conformer) gemmi::remove_alternative_conformations(st);
    std::vector<Seen> out;
    std::set<std::tuple<std::string, int, char, std::string>> seen;
    for (const gemmi::Chain& ch : st.models.at(std::size_t(model - 1)).chains)
        for (const gemmi::Residue& r : ch.residues)
            for (const gemmi::Atom& a : r.atoms) {
                const char icode = r.seqid.icode == '\0' ? ' ' : r.seqid.icode;
                if (a.altloc != '\0' && !seen.insert({ch.name, *r.seqid.num, icode, a.name}).second)
                    continue;
                out.push_back({ch.name, *r.seqid.num, icode, a.name, upper(a.element.name()),
                               float(a.pos.x), float(a.pos.y), float(a.pos.z)});
            }
    return out;
}

std::vector<Seen> fdmsurf_reading(const Structure& s) {
    std::vector<Seen> out;
    for (std::size_t i = 0; i < s.atoms.size(); ++i) {
        const AtomMeta& m = s.atoms.meta.at(i);
        out.push_back({m.chain, m.residue_number, m.insertion_code, m.name, s.atoms.element.at(i),
                       s.atoms.xyz[3 * i], s.atoms.xyz[3 * i + 1], s.atoms.xyz[3 * i + 2]});
    }
    return out;
}

void expect_same(const std::vector<Seen>& ours, const std::vector<Seen>& gemmis) {
    ASSERT_EQ(ours.size(), gemmis.size());
    for (std::size_t i = 0; i < ours.size(); ++i) {
        SCOPED_TRACE("atom " + std::to_string(i));
        EXPECT_EQ(ours[i].chain, gemmis[i].chain);
        EXPECT_EQ(ours[i].residue, gemmis[i].residue);
        EXPECT_EQ(ours[i].icode, gemmis[i].icode);
        EXPECT_EQ(ours[i].name, gemmis[i].name);
        EXPECT_EQ(ours[i].element, gemmis[i].element);
        EXPECT_NEAR(ours[i].x, gemmis[i].x, 1e-4);
        EXPECT_NEAR(ours[i].y, gemmis[i].y, 1e-4);
        EXPECT_NEAR(ours[i].z, gemmis[i].z, 1e-4);
    }
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string joined(const std::vector<std::string>& lines, const char* end = "\n") {
    std::string out;
    for (const std::string& l : lines) out += l + end;
    return out;
}

bool is_atom_line(const std::string& l) {
    return l.rfind("ATOM  ", 0) == 0 || l.rfind("HETATM", 0) == 0;
}

// 1CRN's mmCIF with `edit(row, column, value)` applied to every _atom_site row's values.
template <class Edit>
std::string edited_cif(Edit edit) {
    std::vector<std::string> lines = lines_of(read_text_file(data_path("1crn.cif")));
    std::vector<std::string> columns;
    int row = 0;
    for (std::string& l : lines) {
        if (l.rfind("_atom_site.", 0) == 0) {
            columns.push_back(l.substr(11, l.find_last_not_of(' ') - 10));
        } else if (!columns.empty() && (l.rfind("ATOM ", 0) == 0 || l.rfind("HETATM ", 0) == 0)) {
            std::istringstream in(l);
            std::vector<std::string> values;
            for (std::string v; in >> v;) values.push_back(v);
            EXPECT_EQ(values.size(), columns.size()) << l;
            for (std::size_t c = 0; c < columns.size(); ++c) edit(row, columns[c], values[c]);
            l.clear();
            for (const std::string& v : values) l += v + " ";
            ++row;
        }
    }
    EXPECT_EQ(row, 327);
    return joined(lines);
}

TEST(UnusualInputs, MmcifQuestionMarksAndDotsInOptionalColumns) {
    const std::string text = edited_cif([](int row, const std::string& column, std::string& v) {
        if (column == "B_iso_or_equiv" || column == "pdbx_formal_charge") v = row % 2 ? "?" : ".";
        if (column == "occupancy" && row % 3 == 0) v = "?";
        if (column == "pdbx_PDB_ins_code") v = row % 2 ? "?" : ".";
    });
    const Structure s = read_structure_from_memory(text, "unusual.cif", keep_everything());
    expect_same(fdmsurf_reading(s), gemmi_reading(text, true));
    EXPECT_EQ(s.atoms.size(), 327u);
}

TEST(UnusualInputs, MmcifMissingCoordinateIsRefusedWithItsLine) {
    const std::string text = edited_cif([](int row, const std::string& column, std::string& v) {
        if (column == "Cartn_y" && row == 10) v = "?";
    });
    try {
        read_structure_from_memory(text, "holey.cif", keep_everything());
        FAIL() << "a '?' coordinate was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Format);
        EXPECT_NE(std::string(e.what()).find("holey.cif"), std::string::npos) << e.what();
    }
}

TEST(UnusualInputs, MmcifMultiCharacterChainsAndInsertionCodes) {
    const std::string text = edited_cif([](int row, const std::string& column, std::string& v) {
        if (column == "auth_asym_id") v = row < 150 ? "AB1" : "xyz";
        if (column == "pdbx_PDB_ins_code" && row >= 20 && row < 40) v = "C";
    });
    ReadOptions options = keep_everything();
    const Structure s = read_structure_from_memory(text, "chains.cif", options);
    expect_same(fdmsurf_reading(s), gemmi_reading(text, true));
    options.chains = {"xyz"};
    EXPECT_EQ(read_structure_from_memory(text, "chains.cif", options).atoms.size(), 327u - 150u);
}

// 1CRN's PDB with `edit(index, line)` applied to each ATOM/HETATM line.
template <class Edit>
std::string edited_pdb(Edit edit) {
    std::vector<std::string> lines = lines_of(read_text_file(data_path("1crn.pdb")));
    int index = 0;
    for (std::string& l : lines)
        if (is_atom_line(l)) edit(index++, l);
    return joined(lines);
}

// An ATOM line as two alternate locations: A where it is, B moved to x = 1.000.
std::pair<std::string, std::string> altloc_copies(const std::string& line) {
    std::string a = line, b = line;
    a[16] = 'A';
    b[16] = 'B';
    b.replace(30, 8, "   1.000");
    return {a, b};
}

TEST(UnusualInputs, PdbInsertionCodesAndAltlocsWhoseOccupanciesSumOverOne) {
    // Residue 5's atoms twice, as altlocs A and B of occupancy 0.80 each (sum 1.6), and
    // insertion codes on residues 10-12.
    std::vector<std::string> lines = lines_of(read_text_file(data_path("1crn.pdb")));
    std::vector<std::string> out;
    for (std::string l : lines) {
        if (is_atom_line(l) && l.substr(22, 4) == "   5") {
            auto [a, b] = altloc_copies(l);
            a.replace(54, 6, "  0.80");
            b.replace(54, 6, "  0.80");
            out.push_back(a);
            out.push_back(b);
            continue;
        }
        if (is_atom_line(l) && l.substr(22, 4) >= "  10" && l.substr(22, 4) <= "  12") l[26] = 'Q';
        out.push_back(l);
    }
    const std::string text = joined(out);
    const Structure s = read_structure_from_memory(text, "alt.pdb", keep_everything());
    expect_same(fdmsurf_reading(s), gemmi_reading(text, false));
    EXPECT_EQ(s.atoms.size(), 327u);
    EXPECT_GT(s.info.altlocs_skipped, 0u);
}

TEST(UnusualInputs, PdbMicroheterogeneityKeepsTheFirstResidue) {
    // Residue 5 as two residues at one position: altloc A as in the file, altloc B renamed TRP
    // (not in crambin), moved and with an atom the first lacks. The position keeps the first
    // residue whole and nothing of the second (the B residue's own atom included), as gemmi's
    // remove_alternative_conformations does.
    std::vector<std::string> out;
    std::vector<std::string> second;
    for (std::string l : lines_of(read_text_file(data_path("1crn.pdb")))) {
        if (is_atom_line(l) && l.substr(22, 4) == "   5") {
            auto [a, b] = altloc_copies(l);
            b.replace(17, 3, "TRP");
            out.push_back(a);
            second.push_back(b);
            continue;
        }
        if (!second.empty()) {  // right after residue 5: the B residue, then one atom more
            std::string extra = second.back();
            extra.replace(12, 4, " OH ");
            second.push_back(extra);
            out.insert(out.end(), second.begin(), second.end());
            second.clear();
        }
        out.push_back(l);
    }
    const std::string text = joined(out);
    const Structure s = read_structure_from_memory(text, "micro.pdb", keep_everything());
    expect_same(fdmsurf_reading(s), gemmi_reading(text, false, 1, true));
    EXPECT_EQ(s.atoms.size(), 327u);
    std::size_t trp = 0, residue_5 = 0;
    for (const AtomMeta& m : s.atoms.meta) {
        trp += m.residue_name == "TRP";
        residue_5 += m.residue_number == 5;
    }
    EXPECT_EQ(trp, 0u);
    EXPECT_GT(residue_5, 0u);
    EXPECT_EQ(s.info.altlocs_skipped, residue_5 + 1);  // the B residue, its extra atom too
}

TEST(UnusualInputs, PdbModelsOfDifferentSizes) {
    std::vector<std::string> atoms;
    for (const std::string& l : lines_of(read_text_file(data_path("1crn.pdb"))))
        if (is_atom_line(l)) atoms.push_back(l);
    std::vector<std::string> file = {"MODEL        1"};
    file.insert(file.end(), atoms.begin(), atoms.end());
    file.push_back("ENDMDL");
    file.push_back("MODEL        2");
    file.insert(file.end(), atoms.begin() + 40, atoms.end() - 7);  // 280 atoms
    file.push_back("ENDMDL");
    const std::string text = joined(file) + "END\n";
    for (int model : {1, 2}) {
        SCOPED_TRACE("model " + std::to_string(model));
        const Structure s = read_structure_from_memory(text, "models.pdb", keep_everything(model));
        expect_same(fdmsurf_reading(s), gemmi_reading(text, false, model));
        EXPECT_EQ(s.info.models_in_file, 2u);
    }
    EXPECT_EQ(read_structure_from_memory(text, "models.pdb", keep_everything(2)).atoms.size(), 280u);
}

TEST(UnusualInputs, PdbHybrid36Serials) {
    // Serials from 99,990 up, past 99,999 into hybrid-36 (A0000 = 100,000).
    const std::string text = edited_pdb([](int i, std::string& l) {
        const int serial = 99990 + i;
        char field[12];  // five characters used; room for any int (this file is built -fwrapv)
        if (serial <= 99999) {
            std::snprintf(field, sizeof field, "%5d", serial);
        } else {
            const char* digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";
            int n = serial - 100000 + 10 * 36 * 36 * 36 * 36;  // "A0000" is 10 * 36^4 in base 36
            for (int k = 4; k >= 0; --k, n /= 36) field[k] = digits[n % 36];
            field[5] = '\0';
        }
        l.replace(6, 5, field, 5);
    });
    const Structure s = read_structure_from_memory(text, "h36.pdb", keep_everything());
    expect_same(fdmsurf_reading(s), gemmi_reading(text, false));
    ASSERT_EQ(s.atoms.size(), 327u);
    EXPECT_EQ(s.atoms.meta[9].serial, 99999);
    EXPECT_EQ(s.atoms.meta[10].serial, 100000);
    EXPECT_EQ(s.atoms.meta[326].serial, 99990 + 326);
}

TEST(UnusualInputs, PdbWithoutElementColumnsOrWithLowercaseElements) {
    const std::string bare = edited_pdb([](int, std::string& l) { l = l.substr(0, 66); });
    const std::string lower = edited_pdb([](int, std::string& l) {
        for (std::size_t k = 76; k < 78 && k < l.size(); ++k)
            l[k] = char(std::tolower(static_cast<unsigned char>(l[k])));
    });
    const Structure plain =
        read_structure_from_memory(read_text_file(data_path("1crn.pdb")), "1crn.pdb", keep_everything());
    for (const std::string* text : {&bare, &lower}) {
        SCOPED_TRACE(text == &bare ? "no element columns" : "lowercase elements");
        const Structure s = read_structure_from_memory(*text, "elements.pdb", keep_everything());
        expect_same(fdmsurf_reading(s), gemmi_reading(*text, false));
        EXPECT_EQ(s.atoms.element, plain.atoms.element);
        EXPECT_EQ(s.atoms.radius, plain.atoms.radius);
    }
}

TEST(UnusualInputs, CrlfByteOrderMarkAndEmptyLines) {
    const std::string original = read_text_file(data_path("1crn.pdb"));
    std::vector<std::string> lines = lines_of(original);
    std::string text = "\xEF\xBB\xBF";  // UTF-8 byte-order mark
    for (std::size_t i = 0; i < lines.size(); ++i) {
        text += lines[i] + "\r\n";
        if (i % 50 == 0) text += "\r\n";  // empty lines here and there
    }
    const Structure s = read_structure_from_memory(text, "windows.pdb", keep_everything());
    expect_same(fdmsurf_reading(s), gemmi_reading(original, false));
    // The same for mmCIF.
    const std::string cif = read_text_file(data_path("1crn.cif"));
    std::string cif_text = "\xEF\xBB\xBF";
    for (const std::string& l : lines_of(cif)) cif_text += l + "\r\n";
    const Structure c = read_structure_from_memory(cif_text, "windows.cif", keep_everything());
    expect_same(fdmsurf_reading(c), gemmi_reading(cif, true));
}

// A line longer than 120 characters is read to column 120, whatever its tail holds. gemmi
// alone would read the tail that follows a byte >= 0x80 as a line of its own (its skipping stops
// there): an ATOM record hidden so would become an atom, a short LINK record an overflow.
TEST(UnusualInputs, PdbLinesPastColumn120AreCutWhateverTheirTailHolds) {
    const std::string original = read_text_file(data_path("1crn.pdb"));
    const std::string hidden =
        "ATOM      1  N   THR A 900      17.047  14.099   3.625  1.00 13.79           N";
    const std::string link =
        "LINK         O   THR A   1                NA    NA A 101     1555   1555 ";  // 73 columns
    // The first REMARK line of `remark` gets a tail: past column 120, `high` and then `tail`.
    auto with_tail = [](std::vector<std::string> lines, const char* remark, char high,
                        const std::string& tail) {
        for (std::string& l : lines)
            if (l.rfind(remark, 0) == 0) {
                l += std::string(125 - l.size(), '.') + high + tail;
                return joined(lines);
            }
        ADD_FAILURE() << "no " << remark << " line";
        return std::string();
    };
    const std::string atom_hidden = with_tail(lines_of(original), "REMARK   1", '\xE9', hidden);
    // gemmi alone finds the hidden atom: the case is real. (Not given the hidden LINK record:
    // gemmi would read past its line, which AddressSanitizer reports.)
    EXPECT_EQ(gemmi_reading(atom_hidden, false).size(), gemmi_reading(original, false).size() + 1);
    const std::string both = with_tail(lines_of(atom_hidden), "REMARK   2", '\xC3', link);
    for (const std::string& text : {atom_hidden, both}) {
        const Structure s = read_structure_from_memory(text, "long-lines.pdb", keep_everything());
        expect_same(fdmsurf_reading(s), gemmi_reading(original, false));
    }
}

// PQR lines are read from their end (x y z charge radius last, the chain column being optional),
// so extra columns after the radius cannot be told apart from the atom's own: refused, naming
// the line and the field; extra whitespace, a chain column or none are read alike.
TEST(UnusualInputs, PqrExtraColumnsAreRefusedAndSpacingIsFree) {
    const std::string plain =
        "ATOM      1  N   THR     1      17.047  14.099   3.625  0.1812 1.8240\n"
        "ATOM      2  CA  THR A   1      16.967  12.784   4.338  0.0034 1.9080\n"
        "HETATM    3 ZN    ZN A 100       5.000   5.000   5.000  2.0000 1.3900\n";
    const std::string spaced =
        "ATOM 1 N THR 1 17.047 14.099 3.625 0.1812 1.8240\n"
        "  ATOM\t2  CA  THR  A  1  16.967  12.784  4.338  0.0034  1.9080   \n"
        "\n"
        "HETATM 3 ZN ZN A 100 5.000 5.000 5.000 2.0000 1.3900\r\n";
    const Structure a = read_structure_from_memory(plain, "plain.pqr");
    const Structure b = read_structure_from_memory(spaced, "spaced.pqr");
    ASSERT_EQ(a.atoms.size(), 3u);
    EXPECT_EQ(a.atoms.xyz, b.atoms.xyz);
    EXPECT_EQ(a.atoms.radius, b.atoms.radius);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(a.atoms.meta[i].charge, b.atoms.meta[i].charge);
    const std::string extra =
        "ATOM      1  N   THR     1      17.047  14.099   3.625  0.1812 1.8240\n"
        "ATOM      2  CA  THR A   1      16.967  12.784   4.338  0.0034 1.9080 C extra\n";
    try {
        read_structure_from_memory(extra, "extra.pqr");
        FAIL() << "extra columns were read as the atom's own";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Format);
        const std::string what = e.what();
        EXPECT_NE(what.find("extra.pqr"), std::string::npos) << what;
        EXPECT_NE(what.find("line 2"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace fdmsurf
