// Tests that malformed structure input is rejected with a specific message, and never crashes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;
using test::expect_error;
using test::expect_memory_error;
using test::pdb_atom;

// Offset of the second record in two_atoms().
std::size_t second_line(const std::string& text) { return text.find('\n') + 1; }

std::string two_atoms() {
    return pdb_atom("ATOM", 1, " N", ' ', "ALA", 'A', 1, 1, 2, 3, "N") +
           pdb_atom("ATOM", 2, " CA", ' ', "ALA", 'A', 1, 2, 2, 3, "C");
}

TEST(StructureErrors, MissingFileCannotBeOpened) {
    expect_error([] { read_structure("/nonexistent/dir/none.pdb"); }, ErrorCode::Io,
                 {"/nonexistent/dir/none.pdb", "cannot open"});
    expect_error([] { read_structure(FDMSURF_TEST_DATA_DIR); }, ErrorCode::Io,
                 {"cannot open", "directory"});
}

TEST(StructureErrors, EmptyInput) {
    expect_memory_error("", "empty.pdb", ErrorCode::Format, {"empty.pdb", "empty file"});
    expect_memory_error(" \n\n\t\n", "blank.xyzr", ErrorCode::Format, {"blank.xyzr", "empty"});
    test::TempFile file("empty.cif", "");
    expect_error([&] { read_structure(file.path()); }, ErrorCode::Format,
                 {"empty.cif", "empty file"});
}

TEST(StructureErrors, BinaryData) {
    std::string with_nul = two_atoms();
    with_nul[100] = '\0';
    expect_memory_error(with_nul, "nul.pdb", ErrorCode::Format,
                        {"nul.pdb is not a text structure file (binary data)"});
    std::string noise;
    std::mt19937 rng(7);
    for (int i = 0; i < 2000; ++i) noise += static_cast<char>(0x80 + rng() % 0x7f);
    expect_memory_error(noise, "noise.cif", ErrorCode::Format, {"binary data"});
    test::TempFile file("noise.pdb", noise);
    expect_error([&] { read_structure(file.path()); }, ErrorCode::Format,
                 {"noise.pdb is not a text structure file (binary data)"});
}

TEST(StructureErrors, GzipDataInMemoryIsNotText) {
    std::string gz = test::read_text_file(data_path("1d3z.pdb.gz"));
    expect_memory_error(gz, "1d3z.pdb.gz", ErrorCode::Format,
                        {"not a text structure file", "gzip"});
}

TEST(StructureErrors, TruncatedAndCorruptGzipFiles) {
    std::string gz = test::read_text_file(data_path("1d3z.pdb.gz"));
    test::TempFile truncated("truncated.pdb.gz", std::string_view(gz).substr(0, gz.size() / 2));
    expect_error([&] { read_structure(truncated.path()); }, ErrorCode::Format,
                 {"truncated.pdb.gz", "truncated gzip stream"});
    test::TempFile header_only("header.pdb.gz", std::string_view(gz).substr(0, 10));
    expect_error([&] { read_structure(header_only.path()); }, ErrorCode::Format,
                 {"truncated gzip stream"});
    std::string corrupt = gz;
    for (std::size_t i = 1000; i < 1100; ++i) corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
    test::TempFile bad("corrupt.pdb.gz", corrupt);
    expect_error([&] { read_structure(bad.path()); }, ErrorCode::Format,
                 {"corrupt.pdb.gz", "corrupt gzip data"});
}

TEST(StructureErrors, UnknownFormat) {
    expect_memory_error("hello\nworld\n", "notes.txt", ErrorCode::Format,
                        {"notes.txt: unknown format (expected .pdb, .cif, .pqr, .xyzr or .xyzrn)"});
}

TEST(StructureErrors, TruncatedPdbAtomRecord) {
    std::string text = two_atoms();
    std::string cut = text.substr(0, second_line(text) + 41);  // x cut off in column 42
    expect_memory_error(cut, "cut.pdb", ErrorCode::Format,
                        {"cut.pdb", "truncated ATOM record at line 2"});
    expect_memory_error("HEADER    TEST\nHETATM    1  O   HOH A   1      1.000\n", "het.pdb",
                        ErrorCode::Format, {"truncated HETATM record at line 2"});
}

TEST(StructureErrors, NonNumericPdbCoordinates) {
    std::string text = two_atoms();
    text.replace(second_line(text) + 38, 8, "  abc.de");  // y of the second record
    expect_memory_error(text, "text.pdb", ErrorCode::Format,
                        {"text.pdb", "non-numeric y coordinate", "columns 39-46", "line 2"});
    std::string blank = two_atoms();
    blank.replace(30, 8, "        ");
    expect_memory_error(blank, "blank.pdb", ErrorCode::Format,
                        {"non-numeric x coordinate", "line 1"});
}

TEST(StructureErrors, NanOrInfinitePdbCoordinates) {
    std::string nan = two_atoms();
    nan.replace(46, 8, "     nan");
    expect_memory_error(nan, "nan.pdb", ErrorCode::Format,
                        {"NaN or infinite z coordinate", "line 1"});
    std::string inf = two_atoms();
    inf.replace(second_line(inf) + 30, 8, "    -inf");
    expect_memory_error(inf, "inf.pdb", ErrorCode::Format, {"NaN or infinite", "line 2"});
    std::string huge = two_atoms();
    huge.replace(30, 8, "  1e+300");
    expect_memory_error(huge, "huge.pdb", ErrorCode::Format, {"x coordinate", "line 1"});
}

TEST(StructureErrors, MmcifLoopWithWrongNumberOfValues) {
    std::string text = std::string(test::kCifAtomSiteHeader) +
                       "ATOM 1 C CA . ALA A 1 1.0 2.0 3.0 1.0 10.0 1 1\n"
                       "ATOM 2 C CB . ALA A 1 1.0 2.0\n";
    expect_memory_error(text, "loop.cif", ErrorCode::Format,
                        {"loop.cif", "Wrong number of values in the loop"});
    // A real file cut in the middle of its atom list.
    std::string cif = test::read_text_file(data_path("1crn.cif"));
    std::size_t cut = cif.find("\nATOM 100 ");
    ASSERT_NE(cut, std::string::npos);
    expect_memory_error(cif.substr(0, cut + 30), "1crn_cut.cif", ErrorCode::Format,
                        {"1crn_cut.cif", "Wrong number of values"});
}

TEST(StructureErrors, MmcifNonNumericOrNanCoordinates) {
    for (const char* value : {"?", "abc", "nan", "inf", "."}) {
        std::string text = std::string(test::kCifAtomSiteHeader) +
                           "ATOM 1 C CA . ALA A 1 1.0 2.0 3.0 1.0 10.0 1 1\n" +
                           "ATOM 2 C CB . ALA A 1 1.0 " + value + " 3.0 1.0 10.0 1 1\n";
        expect_memory_error(
            text, "coord.cif", ErrorCode::Format,
            {"coord.cif", "non-numeric, NaN or infinite coordinates for atom 2", "ALA 1/CB"});
    }
}

// gemmi reads these columns without an overflow check (fuzz_mmcif found it): a number past
// int's range, quoted or not, is refused with its column and row, while the ends of the range and
// leading zeros are read as written.
TEST(StructureErrors, MmcifIntegersPastIntRangeAreRefusedWithTheirRow) {
    struct Case {
        const char* serial;
        const char* seq;
        const char* auth_seq;
        const char* model;
        const char* column;
        const char* value;
    };
    const Case cases[] = {
        {"99999999999", "1", "1", "1", "_atom_site.id", "99999999999"},
        {"2", "-2147483649", "1", "1", "_atom_site.label_seq_id", "-2147483649"},
        {"2", "1", "2147483648", "1", "_atom_site.auth_seq_id", "2147483648"},
        // gemmi takes quotes and text-field markers off before it reads the number
        {"2", "1", "'99999999999'", "1", "_atom_site.auth_seq_id", "99999999999"},
        {"2", "1", "\n;\n+30000000000\n;\n", "1", "_atom_site.auth_seq_id", "+30000000000"}};
    for (const Case& c : cases) {
        const std::string text = std::string(test::kCifAtomSiteHeader) +
                                 "ATOM 1 C CA . ALA A 1 1.0 2.0 3.0 1.0 10.0 1 1\n" + "ATOM " +
                                 c.serial + " C CB . ALA A " + c.seq + " 1.0 3.0 3.0 1.0 10.0 " +
                                 c.auth_seq + " " + c.model + "\n";
        expect_memory_error(text, "big.cif", ErrorCode::Format,
                            {"big.cif", std::string(c.column) + " " + c.value, "in row 2",
                             "out of range"});
    }
    // The ends of int's range, with leading zeros, and a model number of any size (gemmi keeps
    // it as the model's name).
    const std::string fits = std::string(test::kCifAtomSiteHeader) +
                             "ATOM 2147483647 C CA . ALA A 0002147483647 1.0 2.0 3.0 1.0 10.0 "
                             "'-2147483648' 99999999999\n";
    const Structure s = read_structure_from_memory(fits, "fits.cif", {});
    ASSERT_EQ(s.atoms.size(), 1u);
}

TEST(StructureErrors, MmcifWithoutAtoms) {
    expect_memory_error("data_x\n_cell.length_a 10\n", "noatoms.cif", ErrorCode::Format,
                        {"noatoms.cif", "no _atom_site"});
    expect_memory_error(
        "data_x\nloop_\n_atom_site.id\n_atom_site.label_atom_id\n_atom_site.Cartn_x\n"
        "_atom_site.Cartn_y\n1 CA 1 2\n",
        "columns.cif", ErrorCode::Format, {"columns.cif", "lacks column(s)", "Cartn_z"});
    expect_memory_error("# only a comment\n", "comment.cif", ErrorCode::Format, {"comment.cif"});
}

TEST(StructureErrors, PdbWithoutAtomRecords) {
    expect_memory_error("HEADER    NOTHING HERE\nEND\n", "header.pdb", ErrorCode::Format,
                        {"header.pdb", "no atoms", "ATOM/HETATM"});
}

TEST(StructureErrors, GemmiErrorsBecomeFormatErrorsWithTheFileName) {
    std::string text =
        "ANISOU    1  N   ALA A   1     1000   1000   1000      0      0      0\n" + two_atoms();
    expect_memory_error(text, "anisou.pdb", ErrorCode::Format, {"anisou.pdb", "ANISOU"});
    expect_memory_error("data_x\n_a.b\n", "tag.cif", ErrorCode::Format, {"tag.cif"});
}

TEST(StructureErrors, NothingLeftAfterSelection) {
    std::string waters = pdb_atom("HETATM", 1, " O", ' ', "HOH", 'A', 1, 1, 2, 3, "O") +
                         pdb_atom("HETATM", 2, " H1", ' ', "HOH", 'A', 1, 1, 2, 4, "H") +
                         pdb_atom("HETATM", 3, " O", ' ', "HOH", 'A', 2, 5, 2, 3, "O") +
                         pdb_atom("ATOM", 4, " H", ' ', "ALA", 'B', 1, 9, 2, 3, "H");
    expect_memory_error(waters, "water.pdb", ErrorCode::EmptySelection,
                        {"water.pdb", "no atoms left after selection", "has 4 atoms",
                         "3 water atoms (keep_waters, the CLI's --waters)",
                          "1 hydrogen (keep_hydrogens, --hydrogens)"});
    ReadOptions keep;
    keep.keep_waters = true;
    keep.keep_hydrogens = true;
    EXPECT_EQ(read_structure_from_memory(waters, "water.pdb", keep).atoms.size(), 4u);
}

TEST(StructureErrors, PqrLinesWithTooFewOrBadFields) {
    expect_memory_error("ATOM 1 N MET 1 1.0 2.0 3.0 1.8\n", "few.pqr", ErrorCode::Format,
                        {"few.pqr", "too few fields for a PQR atom at line 1"});
    expect_memory_error("REMARK x\nATOM 1 N MET A 1 1.0 two 3.0 -0.3 1.8\n", "text.pqr",
                        ErrorCode::Format,
                        {"text.pqr", "non-numeric y coordinate 'two' at line 2"});
    // Radius 0 for every atom: element radii instead (tests/structure/test_lenient_input.cpp).
    EXPECT_FLOAT_EQ(
        read_structure_from_memory("ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 0\n", "zero.pqr").atoms.radius[0],
        vdw_radius("N"));
    expect_memory_error("ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 -1.5\n", "neg.pqr", ErrorCode::Format,
                        {"radius -1.5 is not > 0"});
    expect_memory_error("ATOM 1 N MET A 1 nan 2.0 3.0 -0.3 1.5\n", "nan.pqr", ErrorCode::Format,
                        {"NaN or infinite x coordinate"});
    expect_memory_error("ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 inf\n", "inf.pqr", ErrorCode::Format,
                        {"NaN or infinite radius"});
    expect_memory_error("ATOM 1 N MET A 1 1.0 2.0 3.0 q 1.5\n", "charge.pqr", ErrorCode::Format,
                        {"non-numeric charge"});
    expect_memory_error("REMARK nothing\n", "none.pqr", ErrorCode::Format,
                        {"none.pqr", "no atoms"});
}

TEST(StructureErrors, ZeroRadiusAtomsAreLeftOutWithAWarning) {
    fdmsurf::Structure s = fdmsurf::read_structure_from_memory(
        "ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 1.8\nATOM 2 H MET A 1 1.5 2.0 3.0 0.3 0.0\n", "h0.pqr");
    EXPECT_EQ(s.atoms.size(), 1u);
    EXPECT_EQ(s.atoms.element.size(), 1u);
    ASSERT_EQ(s.info.warnings.size(), 1u);
    EXPECT_NE(s.info.warnings[0].find("radius 0"), std::string::npos);
    // The warning names the first one's line and what shifts; the file's count still has it.
    EXPECT_NE(s.info.warnings[0].find("the first at line 2"), std::string::npos)
        << s.info.warnings[0];
    EXPECT_NE(s.info.warnings[0].find("count the atoms kept"), std::string::npos);
    EXPECT_EQ(s.info.atoms_in_file, 2u);
    EXPECT_EQ(s.info.zero_radius_skipped, 1u);
    const fdmsurf::Structure x = fdmsurf::read_structure_from_memory(
        "# spheres\n1 2 3 1.5\n4 5 6 0\n7 8 9 0\n1 1 1 1.2\n", "z.xyzr");
    EXPECT_EQ(x.atoms.size(), 2u);
    EXPECT_EQ(x.info.atoms_in_file, 4u);
    ASSERT_EQ(x.info.warnings.size(), 1u);
    EXPECT_NE(x.info.warnings[0].find("2 atom(s) with radius 0 left out (the first at line 3)"),
              std::string::npos)
        << x.info.warnings[0];
    // A radius that rounds to 0 as a float is one of them (the fuzzer's 1.0e-70 had been kept
    // as a ball of radius 0); one above half of float's least (1.4e-45) is kept.
    for (const char* tiny : {"1.0e-70", "1e-46"}) {
        SCOPED_TRACE(tiny);
        const fdmsurf::Structure t = fdmsurf::read_structure_from_memory(
            std::string("1 2 3 1.5\n4 5 6 ") + tiny + "\n", "tiny.xyzr");
        EXPECT_EQ(t.atoms.size(), 1u);
        EXPECT_EQ(t.info.zero_radius_skipped, 1u);
        const fdmsurf::Structure q = fdmsurf::read_structure_from_memory(
            std::string("ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 1.8\nATOM 2 H MET A 1 1.5 2.0 3.0 0.3 ") +
                tiny + "\n",
            "tiny.pqr");
        EXPECT_EQ(q.atoms.size(), 1u);
    }
    const fdmsurf::Structure small =
        fdmsurf::read_structure_from_memory("1 2 3 1.5\n4 5 6 1e-44\n", "small.xyzr");
    ASSERT_EQ(small.atoms.size(), 2u);
    EXPECT_GT(small.atoms.radius[1], 0.0f);
}

TEST(StructureErrors, XyzrLinesWithTooFewOrBadFields) {
    expect_memory_error("1 2 3 1.5\n1 2 3\n", "few.xyzr", ErrorCode::Format,
                        {"few.xyzr", "too few fields for an XYZR atom at line 2"});
    expect_memory_error("1 2 3 1.5\n1 2 3 -1\n", "neg.xyzr", ErrorCode::Format,
                        {"neg.xyzr", "radius -1 is not > 0 at line 2"});
    expect_memory_error("1 2 3 0.0\n", "zero.xyzr", ErrorCode::EmptySelection, {"radius 0"});
    expect_memory_error("1 2 nan 1.5\n", "nan.xyzr", ErrorCode::Format,
                        {"NaN or infinite z coordinate 'nan' at line 1"});
    expect_memory_error("1 2 3 NaN\n", "nanr.xyzr", ErrorCode::Format, {"NaN or infinite radius"});
    expect_memory_error("1 2 3 1e39\n", "big.xyzr", ErrorCode::Format, {"out of range"});
    // Plain decimals of 19 digits and an exponent of 22, past float's range (and past the fast
    // path's mantissa of 2^53, so the general route reads them): refused, not stored as
    // infinite.
    expect_memory_error("1000000000000000000e22 2 3 1.5\n", "bigx.xyzr", ErrorCode::Format,
                        {"out of range", "x coordinate"});
    expect_memory_error("1 2 3 1000000000000000000e22\n", "bigr.xyzr", ErrorCode::Format,
                        {"out of range", "radius"});
    expect_memory_error("ATOM 1 N MET A 1 1000000000000000000e22 2.0 3.0 -0.3 1.8\n", "big.pqr",
                        ErrorCode::Format, {"out of range"});
    expect_memory_error("1 2,5 3 1.5\n", "comma.xyzr", ErrorCode::Format,
                        {"non-numeric y coordinate '2,5' at line 1"});
    expect_memory_error("# only comments\n", "none.xyzr", ErrorCode::Format,
                        {"none.xyzr", "no atoms"});
}

TEST(StructureErrors, LargeXyzrReadInPiecesKeepsOrderAndLineNumbers) {
    // About 3 MiB: read in pieces of 1 MiB on several threads, joined in order. Radius-0 atoms
    // in later pieces, a comment and CRLF lines; then an error far down names its own line.
    std::string text;
    std::vector<float> radii;
    std::size_t zero = 0, first_zero = 0, line = 0;
    for (int i = 0; text.size() < (std::size_t{3} << 20); ++i) {
        ++line;
        if (i % 50000 == 7) {
            text += "# comment\r\n";
            continue;
        }
        const bool empty = i > 40000 && i % 30011 == 0;
        if (empty && zero++ == 0) first_zero = line;
        text += std::to_string(i % 997) + ".125 " + std::to_string(-i % 89) + ".5 " +
                std::to_string(i % 13) + " " + (empty ? "0" : "1.5") + (i % 3 ? "\n" : "\r\n");
        if (!empty) radii.push_back(1.5f);
    }
    ASSERT_GT(zero, 2u);
    const Structure s = read_structure_from_memory(text, "big.xyzr");
    ASSERT_EQ(s.atoms.size(), radii.size());
    EXPECT_EQ(s.info.zero_radius_skipped, zero);
    EXPECT_EQ(s.info.first_zero_radius_line, first_zero);
    EXPECT_EQ(s.atoms.xyz[0], 0.125f);
    const std::size_t last = s.atoms.size() - 1;
    // The last atom is the file's last line that is no comment and not of radius 0.
    std::size_t at = text.rfind('\n', text.size() - 2) + 1;
    EXPECT_EQ(s.atoms.xyz[3 * last], std::stof(text.substr(at)));
    const std::string bad = text + "1 2 3\n" + text;
    expect_memory_error(bad, "bad.xyzr", ErrorCode::Format,
                        {"too few fields for an XYZR atom at line " + std::to_string(line + 1)});
}

TEST(StructureErrors, OnlyModelOneForPqrAndXyzr) {
    ReadOptions second;
    second.model = 2;
    expect_memory_error("1 2 3 1.5\n", "one.xyzr", ErrorCode::InvalidArgument,
                        {"one.xyzr", "model 2", "one model"}, second);
}

// Random damage to real files must end in a result or an fdmsurf::Error, nothing else.
TEST(StructureErrors, DamagedFilesNeverCrash) {
    const std::pair<std::string, std::string> files[] = {
        {"1crn.pdb", test::read_text_file(data_path("1crn.pdb")).substr(0, 12000)},
        {"1crn.cif", test::read_text_file(data_path("1crn.cif")).substr(0, 30000)},
        {"1crn.xyzr", test::read_text_file(data_path("1crn.xyzr")).substr(0, 2000)},
        {"x.pqr", "ATOM 1 N MET A 1 1.0 2.0 3.0 -0.3 1.8\nATOM 2 C MET 1 1 2 3 0 1.9\n"}};
    std::mt19937 rng(12345);
    const char alphabet[] = " \n\t0123456789.-+eEATOMHXYZ_'\";#?loop_data\x01\xff";
    int results = 0, errors = 0;
    for (const auto& [name, original] : files) {
        for (int trial = 0; trial < 150; ++trial) {
            std::string text = original;
            switch (trial % 3) {
                case 0:
                    text.resize(rng() % (text.size() + 1));
                    break;
                case 1:
                    for (int k = 0; k < 5; ++k)
                        text[rng() % text.size()] = alphabet[rng() % (sizeof alphabet - 1)];
                    break;
                default: {
                    std::size_t at = rng() % text.size();
                    text.erase(at, rng() % 200);
                    break;
                }
            }
            try {
                Structure s = read_structure_from_memory(text, name);
                ++results;
                EXPECT_EQ(s.atoms.xyz.size(), 3 * s.atoms.size());
                for (float r : s.atoms.radius) EXPECT_GT(r, 0.0f);
                for (float v : s.atoms.xyz) EXPECT_TRUE(std::isfinite(v));
            } catch (const Error&) {
                ++errors;
            }
        }
    }
    EXPECT_GT(results, 0);
    EXPECT_GT(errors, 0);
}

}  // namespace
}  // namespace fdmsurf
