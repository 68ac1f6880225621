// The PQR, XYZR and XYZRN readers' two ways (structure/read_plain.cpp): pieces on all threads
// against the one-thread pass, on real files and on generated text cut into many pieces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "structure/detail.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf::test {
namespace {

using Reader = std::function<Structure(std::string_view, const std::string&)>;
using PieceReader = std::function<Structure(std::string_view, const std::string&, std::size_t)>;

struct Format {
    const char* name;
    Reader plain;
    PieceReader pieces;
};

const Format kPqr{"pqr", detail::read_pqr_plain, detail::read_pqr_pieces};
const Format kXyzr{"xyzr", detail::read_xyzr_plain, detail::read_xyzr_pieces};
const Format kXyzrn{"xyzrn", detail::read_xyzrn_plain, detail::read_xyzrn_pieces};

// Piece sizes from a line a piece to a few pieces per file.
const std::size_t kPieceSizes[] = {1, 61, 200, 4096, 65536};

// Everything a reader gives, field by field, or the error it throws ("Format: message").
std::string describe(const std::function<Structure()>& read) {
    Structure s;
    try {
        s = read();
    } catch (const Error& e) {
        return std::string(to_string(e.code())) + ": " + e.what();
    }
    const Atoms& a = s.atoms;
    std::string out = std::to_string(a.size()) + " atoms, format " + to_string(s.info.format) +
                      ", in file " + std::to_string(s.info.atoms_in_file) + ", radius 0 " +
                      std::to_string(s.info.zero_radius_skipped) + " from line " +
                      std::to_string(s.info.first_zero_radius_line) + ", models " +
                      std::to_string(s.info.models_in_file) + "\n";
    for (const std::string& w : s.info.warnings) out += "warning: " + w + "\n";
    if (a.xyz.size() != 3 * a.size() || a.element.size() != a.size() ||
        !(a.meta.empty() || a.meta.size() == a.size()))
        return out + "arrays of different sizes";
    char buffer[256];
    for (std::size_t i = 0; i < a.size(); ++i) {
        // %a: the floats' exact bits.
        std::snprintf(buffer, sizeof buffer, "%a %a %a %a %s", a.xyz[3 * i], a.xyz[3 * i + 1],
                      a.xyz[3 * i + 2], a.radius[i], a.element[i].c_str());
        out += buffer;
        if (!a.meta.empty()) {
            const AtomMeta& m = a.meta[i];
            std::snprintf(buffer, sizeof buffer, " | %d '%s' '%s' %d '%c' '%s' %d %a %a %a %d '%s' %d",
                          m.serial, m.name.c_str(), m.residue_name.c_str(), m.residue_number,
                          m.insertion_code, m.chain.c_str(), int(m.hetero), m.b_factor,
                          m.occupancy, m.charge, int(m.has_charge), m.xyzrn_name.c_str(),
                          int(m.in_residue));
            out += buffer;
        }
        out += "\n";
    }
    return out;
}

// The pieces' read of `text` at every piece size against the one-thread read.
void expect_pieces_as_plain(const Format& format, const std::string& text,
                            const std::string& name) {
    const std::string plain = describe([&] { return format.plain(text, name); });
    ASSERT_FALSE(plain.empty());
    for (std::size_t piece : kPieceSizes)
        EXPECT_EQ(describe([&] { return format.pieces(text, name, piece); }), plain)
            << format.name << " " << name << ", pieces of " << piece << " bytes";
}

// A PQR of a real structure's atoms as pdb2pqr writes its records, some HETATM, some with
// insertion codes or without chain.
std::string pqr_of(const Structure& s) {
    std::string text = "REMARK   1 written by the test\n";
    char line[160];
    for (std::size_t i = 0; i < s.atoms.size(); ++i) {
        const AtomMeta& m = s.atoms.meta[i];
        std::string residue = std::to_string(m.residue_number);
        if (m.insertion_code != ' ') residue += m.insertion_code;
        const std::string chain = i % 97 == 5 ? std::string() : m.chain + " ";
        std::snprintf(line, sizeof line, "%-6s %5d %-4s %3s %s%5s    %8.3f %8.3f %8.3f %7.4f %6.4f\n",
                      m.hetero ? "HETATM" : "ATOM", m.serial, m.name.c_str(),
                      m.residue_name.c_str(), chain.c_str(), residue.c_str(), s.atoms.xyz[3 * i],
                      s.atoms.xyz[3 * i + 1], s.atoms.xyz[3 * i + 2], 0.01 * double(i % 50) - 0.2,
                      double(s.atoms.radius[i]));
        text += line;
        if (i % 500 == 499) text += "TER\n";
    }
    return text + "END\n";
}

// About `atoms` atoms of a capsid-like shell in `format` (bench/make_synthetic.py's lines),
// with what the readers must carry across pieces: comments, blank and CRLF lines, radius-0 atoms,
// PQR records in fixed columns, and a last line without its newline.
std::string shell_text(const std::string& format, std::size_t atoms, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586), unit(-1.0, 1.0);
    const double radii[] = {1.70, 1.55, 1.52, 1.80};
    const char* const elements[] = {"C", "N", "O", "S"};
    std::string text = format == "pqr" ? "REMARK   1 shell\n" : "# shell\n";
    char line[160];
    for (std::size_t n = 0; n < atoms; ++n) {
        const double phi = angle(random), z = unit(random), rho = std::sqrt(1.0 - z * z);
        const double shell = 300.0 + 10.0 * unit(random);
        const double x = shell * rho * std::cos(phi), y = shell * rho * std::sin(phi);
        const std::size_t kind = random() % 4;
        const double r = n % 1777 == 300 ? 0.0 : radii[kind];
        const char chain = char('A' + (n / 1000) % 26);
        const std::size_t residue = n / 10 % 10000;
        if (format == "xyzr") {
            std::snprintf(line, sizeof line, "%.3f %.3f %.3f %.2f\n", x, y, shell * z, r);
        } else if (format == "xyzrn") {
            std::snprintf(line, sizeof line, "%.3f %.3f %.3f %.2f 1 %c_%zu_x_ALA_%s%s\n", x, y,
                          shell * z, r, chain, residue, elements[kind],
                          n % 3 == 0 ? "_Blue" : "");
        } else if (n % 2003 == 7) {  // wide coordinates run together: PDB's fixed columns
            std::snprintf(line, sizeof line,
                          "ATOM  %5zu  %-3s ALA  %4zu    %8.3f%8.3f%8.3f %7.4f %6.4f\n",
                          n % 100000, elements[kind], residue, 2000.0 + x, 2000.0 + y,
                          -500.0 + 0.3 * shell * z, 0.1, r);
        } else {
            std::snprintf(line, sizeof line,
                          "ATOM  %7zu %-4s ALA %c%5zu    %8.3f %8.3f %8.3f %7.4f %6.4f\n", n + 1,
                          elements[kind], chain, residue, x, y, shell * z, 0.0, r);
        }
        text += line;
        if (n % 997 == 13) text += format == "pqr" ? "TER\n" : "# copy\n";
        if (n % 1499 == 2) text += "\n";
        if (n % 1201 == 9) {
            text.pop_back();
            text += "\r\n";
        }
    }
    text.pop_back();  // the last line without its newline
    return text;
}

// Line `number` (from 1) of `text` replaced by `replacement`.
std::string replace_line(std::string text, std::size_t number, const std::string& replacement) {
    std::size_t start = 0;
    for (std::size_t k = 1; k < number; ++k) start = text.find('\n', start) + 1;
    const std::size_t end = text.find('\n', start);
    return text.replace(start, end - start, replacement);
}

TEST(ReadPlain, PiecesReadRealFilesAsOneThread) {
    for (const char* file : {"1crn.xyzr", "4hhb.xyzr"})
        expect_pieces_as_plain(kXyzr, read_text_file(data_path(file)), file);
    for (const char* file : {"1crn.xyzrn", "4hhb.xyzrn"})
        expect_pieces_as_plain(kXyzrn, read_text_file(data_path(file)), file);
    for (const char* file : {"lenient/columns.pqr", "lenient/ions.pqr", "lenient/zero-radii.pqr"})
        expect_pieces_as_plain(kPqr, read_text_file(data_path(file)), file);
    for (const char* file : {"1crn.pdb", "4hhb.pdb.gz", "3al1.pdb"}) {
        const std::string pqr = pqr_of(read_structure(data_path(file)));
        expect_pieces_as_plain(kPqr, pqr, std::string(file) + ".pqr");
    }
}

TEST(ReadPlain, PiecesReadShellTextAsOneThread) {
    for (const Format* format : {&kPqr, &kXyzr, &kXyzrn}) {
        const std::string text = shell_text(format->name, 12000, 7);
        const std::string plain = describe([&] { return format->plain(text, "shell"); });
        // Radius-0 atoms (and, for PQR, fixed columns) in several pieces: their warnings.
        EXPECT_NE(plain.find("7 atom(s) with radius 0 left out (the first at line"),
                  std::string::npos)
            << format->name << "\n" << plain.substr(0, 600);
        if (format == &kPqr) {
            EXPECT_NE(plain.find("6 record(s) read in PDB's fixed columns"), std::string::npos)
                << plain.substr(0, 600);
        }
        expect_pieces_as_plain(*format, text, "shell");
    }
}

// The readers' entry points, in pieces of 1 MiB: the same as the one-thread pass.
TEST(ReadPlain, LargeTextsReadOnAllThreadsAsOneThread) {
    for (const Format* format : {&kPqr, &kXyzr, &kXyzrn}) {
        const std::string text = shell_text(format->name, 90000, 11);
        ASSERT_GT(text.size(), std::size_t{2} << 20) << format->name;
        const std::string name = std::string("shell.") + format->name;
        EXPECT_EQ(describe([&] { return read_structure_from_memory(text, name); }),
                  describe([&] { return format->plain(text, name); }))
            << format->name;
    }
}

TEST(ReadPlain, FirstBadLineInFileOrderWinsAcrossPieces) {
    struct Case {
        const Format* format;
        std::string first, second;  // bad lines
        std::string message;        // part of the first's message
    };
    const Case cases[] = {
        {&kXyzr, "1.0 2.0 abc 1.5", "1.0 2.0", "non-numeric z coordinate 'abc'"},
        {&kXyzr, "1.0 2.0 3.0 -1.5", "1.0 2.0 nan 1.5", "radius -1.5 is not > 0"},
        {&kXyzrn, "1.0 2.0", "1.0 2.0 3.0 x 1 A_1_x_ALA_C", "too few fields for an XYZRN atom"},
        {&kXyzrn, "1.0 2.0 3.0 inf 1 A_1_x_ALA_C", "1.0", "NaN or infinite radius 'inf'"},
        {&kPqr, "ATOM 1 C ALA A B12 1.0 2.0 3.0 0.0 1.5", "ATOM 2 C",
         "non-numeric residue number 'B12'"},
        {&kPqr, "ATOM 1 C ALA", "ATOM 2 C ALA A 1 1.0 2.0 x 0.0 1.5",
         "too few fields for a PQR atom"},
    };
    for (const Case& c : cases) {
        const std::string good = shell_text(c.format->name, 3000, 3);
        // Lines 1000 and 2000: pieces apart at every size but the largest; the second bad line
        // alone names line 2000.
        const std::string both = replace_line(replace_line(good, 2000, c.second), 1000, c.first);
        const std::string second = replace_line(good, 2000, c.second);
        const std::string plain = describe([&] { return c.format->plain(both, "bad"); });
        EXPECT_NE(plain.find(c.message), std::string::npos) << plain;
        EXPECT_NE(plain.find("at line 1000"), std::string::npos) << plain;
        EXPECT_NE(describe([&] { return c.format->plain(second, "bad"); }).find("at line 2000"),
                  std::string::npos);
        for (std::size_t piece : kPieceSizes)
            EXPECT_EQ(describe([&] { return c.format->pieces(both, "bad", piece); }), plain)
                << c.format->name << ", pieces of " << piece;
    }
}

TEST(ReadPlain, XyzrnSerialsCountSphereLinesAcrossPieces) {
    const std::string text = "# a comment\n1 2 3 1.5 1 A_1_x_ALA_C\n\n4 5 6 0 1 A_1_x_ALA_N\n"
                             "7 8 9 1.6 1 A_2_x_GLY_O\r\n  # another\n10 11 12 1.7 1 odd\n";
    for (std::size_t piece : kPieceSizes) {
        const Structure s = detail::read_xyzrn_pieces(text, "t.xyzrn", piece);
        ASSERT_EQ(s.atoms.size(), 3u);
        EXPECT_EQ(s.atoms.meta[0].serial, 1);
        EXPECT_EQ(s.atoms.meta[1].serial, 3);  // the radius-0 sphere keeps its number
        EXPECT_EQ(s.atoms.meta[2].serial, 4);
        EXPECT_FALSE(s.atoms.meta[2].in_residue);
        EXPECT_EQ(s.info.first_zero_radius_line, 4u);
    }
    expect_pieces_as_plain(kXyzrn, text, "t.xyzrn");
}

TEST(ReadPlain, PqrWithoutRadiiAcrossPiecesTakesElementRadii) {
    std::string text = shell_text("pqr", 2000, 5);
    // Every radius 0: the elements' radii, with one warning, whatever the pieces.
    std::string zero;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        if (line.rfind("ATOM", 0) == 0) line = line.substr(0, line.rfind(' ')) + " 0.0000";
        zero += line + (end < text.size() ? "\n" : "");
        start = end + 1;
    }
    const std::string plain = describe([&] { return detail::read_pqr_plain(zero, "z.pqr"); });
    EXPECT_NE(plain.find("atoms have radius 0 (a PQR written without radii?)"), std::string::npos)
        << plain.substr(0, 600);
    expect_pieces_as_plain(kPqr, zero, "z.pqr");
}

}  // namespace
}  // namespace fdmsurf::test
