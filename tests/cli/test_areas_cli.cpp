// The fdmsurf program's --areas, --relative and --buried: parsing, errors found before any
// device work (exit 2, nothing written), areas alone without a device, and with a mesh.
#include <gtest/gtest.h>

#include "cli/cli_program.hpp"
#include "cli/json_check.hpp"
#include "cli/parse_check.hpp"
#include "cli/usage.hpp"

namespace {

using namespace fdmsurf_cli_test;

TEST(CliAreas, OptionsAreParsed) {
    const fdmsurf::cli::CliOptions o =
        parse_with({"--areas", "a.csv", "--relative", "miller1987", "--buried", "A,C:B,D"});
    EXPECT_EQ(o.areas, "a.csv");
    EXPECT_EQ(o.relative, fdmsurf::RelativeTable::Miller1987);
    EXPECT_EQ(o.buried, "A,C:B,D");
    // No -o: the areas alone (vdw and sas).
    const fdmsurf::cli::CliOptions alone =
        fdmsurf::cli::parse_args({"in.pdb", "--surface", "sas", "--areas", "a.json"});
    EXPECT_TRUE(alone.output.empty());
}

TEST(CliAreas, BadOptionsAreUsageErrors) {
    EXPECT_TRUE(contains(parse_error_with({"--areas", "a.txt"}), "unknown extension '.txt'"));
    EXPECT_TRUE(contains(parse_error_with({"--areas", "a.csv", "--relative", "naccess"}),
                         "tien2013, miller1987 or sander1994"));
    EXPECT_TRUE(contains(parse_error_with({"--relative", "tien2013"}), "give --areas too"));
    EXPECT_TRUE(contains(parse_error_with({"--buried", "A:B"}), "give --areas too"));
    EXPECT_TRUE(contains(parse_error_with({"--areas", "a.csv", "--buried", "AB"}), "one ':'"));
    EXPECT_TRUE(contains(parse_error_with({"--areas", "a.csv", "--buried", "A:B", "--patch", "A"}),
                         "--patch"));
    EXPECT_TRUE(
        contains(parse_error_with({"--areas", "a.csv", "--buried", "A:B", "--simplify", "0.5"}),
                 "--simplify"));
    EXPECT_TRUE(contains(parse_error_with({"--areas", "out.ply"}), "unknown extension"));
    try {
        fdmsurf::cli::parse_args({"in.pdb", "--areas", "a.csv"});  // ses needs the mesh
        ADD_FAILURE();
    } catch (const fdmsurf::Error& e) {
        EXPECT_TRUE(contains(e.what(), "give -o OUTPUT, or --surface sas")) << e.what();
    }
    try {
        fdmsurf::cli::parse_args({"a.pdb", "b.pdb", "-o", "out/", "--areas", "a.csv"});
        ADD_FAILURE();
    } catch (const fdmsurf::Error& e) {
        EXPECT_TRUE(contains(e.what(), "one INPUT")) << e.what();
    }
}

TEST(CliAreas, HelpDescribesTheOptions) {
    const std::string help = fdmsurf::cli::usage_text();
    for (const char* text :
         {"--areas FILE", "--relative TABLE", "--buried G1:G2", "tien2013", "docs/areas.md"})
        EXPECT_TRUE(contains(help, text)) << text;
}

class CliAreasRun : public CliProgram {
protected:
    std::string data(const std::string& file) const { return std::string(kDataDir) + "/" + file; }
};

// Errors about the structure come before the device is even looked for: with a device that
// does not exist, they still exit 2 with their own reason.
TEST_F(CliAreasRun, StructureErrorsComeBeforeTheDevice) {
    const std::string mesh = path("m.ply"), areas = path("a.json");
    expect_failure(run({data("4hhb.pdb.gz"), "-o", mesh, "--surface", "sas", "--areas", areas,
                        "--buried", "A:Q", "--device", "no-such-device"}),
                   2,
                   {"--buried", "chain Q is not in the structure", "chains present: A, B, C, D"});
    expect_failure(run({data("4hhb.pdb.gz"), "-o", mesh, "--areas", areas, "--buried", "A,B:B",
                        "--device", "no-such-device"}),
                   2, {"overlap"});
    expect_failure(run({data("4hhb.pdb.gz"), "-o", mesh, "--areas", areas, "--buried",
                        "A:B/2000-3000", "--device", "no-such-device"}),
                   2, {"selects none of the"});
    expect_failure(run({data("1crn.xyzr"), "-o", mesh, "--areas", areas, "--relative", "tien2013",
                        "--device", "no-such-device"}),
                   2, {"--relative needs residues", "xyzr"});
    expect_failure(run({data("1crn.xyzr"), "-o", mesh, "--areas", areas, "--buried", "A:B",
                        "--device", "no-such-device"}),
                   2, {"need chains"});
    expect_failure(run({data("1crn.pdb"), "-o", mesh, "--areas", path("no/a.csv"), "--device",
                        "no-such-device"}),
                   3, {"does not exist"});
    expect_failure(run({data("1crn.pdb"), "-o", mesh, "--areas", path("a.tsv")}), 2,
                   {"unknown extension '.tsv'"});
}

// Two files of one run that reach the same file, by any spelling or through a link, would
// overwrite each other: exit 2 before any work, nothing written.
TEST_F(CliAreasRun, FilesOfOneRunMustBeDistinct) {
    const std::string mesh = path("same.json");
    expect_failure(run({data("1crn.pdb"), "-o", mesh, "--areas", mesh, "--surface", "sas"}), 2,
                   {"--areas and -o name the same file"});
    expect_failure(run({data("1crn.pdb"), "-o", path("./same.json"), "--output-format", "glb",
                        "--areas", mesh, "--surface", "sas", "--device", "no-such-device"}),
                   2, {"-o '", "--areas '", "name the same file"});
    expect_failure(run({data("1crn.pdb"), "-o", path("pic.png"), "--output-format", "ply",
                        "--image", path("pic.png"), "--device", "no-such-device"}),
                   2, {"--image '", "name the same file"});
    fs::create_directory_symlink(path(""), path("link"));
    const CliRun r = run({data("1crn.pdb"), "-o", path("link/m.csv"), "--output-format", "ply",
                          "--surface", "sas", "--areas", path("m.csv"), "--device",
                          "no-such-device"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "name the same file")) << r.err;
    EXPECT_FALSE(fs::exists(path("m.csv")));
    fs::remove(path("link"));
    // A link to a file not made yet is followed as the writer follows it (weakly_canonical
    // alone stops at it): the areas would have replaced the mesh.
    fs::create_symlink("target.glb", path("a.json"));
    CliRun d = run({data("1crn.pdb"), "-o", path("target.glb"), "--areas", path("a.json"),
                    "--surface", "sas", "--device", "no-such-device"});
    EXPECT_EQ(d.exit_code, 2) << d.err;
    EXPECT_TRUE(contains(d.err, "name the same file")) << d.err;
    fs::remove(path("a.json"));
    // And a link into a folder that does not exist is refused before any work.
    fs::create_symlink("nodir/x.ply", path("out.ply"));
    d = run({data("1crn.pdb"), "-o", path("out.ply"), "--device", "no-such-device"});
    EXPECT_EQ(d.exit_code, 3) << d.err;
    EXPECT_TRUE(contains(d.err, "'nodir' does not exist") ||
                contains(d.err, "/nodir' does not exist"))
        << d.err;
    fs::remove(path("out.ply"));
}

TEST_F(CliAreasRun, AreasAloneNeedNoDevice) {
    const std::string areas = path("a.csv");
    const CliRun r = run({data("1crn.pdb"), "--surface", "sas", "--areas", areas, "--relative",
                          "tien2013", "--device", "no-such-device"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "sas areas of")) << r.out;
    EXPECT_TRUE(contains(r.out, "exact sphere patches")) << r.out;
    const std::vector<std::string> lines = lines_of(read_text(areas));
    ASSERT_EQ(lines.size(), 1u + 327u + 46u + 1u);  // header, atoms, residues, total
    EXPECT_TRUE(lines[1].rfind("atom,0,1,A,1,,THR,N,N,", 0) == 0) << lines[1];
    EXPECT_TRUE(lines.back().rfind("total,", 0) == 0);
    // Residue THR 1: its relative area is filled, the mesh area is not (no mesh).
    EXPECT_TRUE(lines[328].rfind("residue,,,A,1,,THR,", 0) == 0) << lines[328];
    EXPECT_TRUE(contains(lines[328], ",,0.")) << lines[328];
    // XYZR: per atom and in total, with a warning.
    const CliRun x =
        run({data("1crn.xyzr"), "--surface", "vdw", "--areas", path("x.json"), "--stats", "json"});
    ASSERT_EQ(x.exit_code, 0) << x.err;
    EXPECT_TRUE(contains(x.err, "per-atom and total areas only")) << x.err;
    const auto summary = parse_json(x.out);
    ASSERT_TRUE(summary.has_value()) << x.out;
    EXPECT_TRUE(summary->find("areas")->find("exact")->boolean);
    EXPECT_EQ(summary->find("areas")->find("residues")->number, 0);
    // Without -o: the structure's members as with a mesh, none of the mesh's.
    for (const char* member : {"status", "models_in_file", "assembly", "waters_skipped",
                               "altlocs_skipped", "warnings"})
        EXPECT_NE(summary->find(member), nullptr) << member;
    EXPECT_EQ(summary->find("vertices"), nullptr);
    const auto file = parse_json(read_text(path("x.json")));
    ASSERT_TRUE(file.has_value());
    EXPECT_EQ(file->find("atoms")->array.size(), 327u);
    EXPECT_TRUE(file->find("residues")->array.empty());
}

// The areas file is valid JSON whatever bytes the input's name holds: a byte that is not UTF-8
// becomes U+FFFD, as in --stats json (the file once carried the raw byte).
// XYZRN names of another form than MSMS's chain_number_icode_residue_atom name no residue: the
// file has per-atom and total areas, as for XYZR (no made-up residue of every atom), and
// --relative is a usage error that says why; with some MSMS names among them, those atoms alone
// make residues.
TEST_F(CliAreasRun, XyzrnWithoutMsmsNamesHasNoResidues) {
    const std::string plain = write_file("plain.xyzrn", "0 0 0 1.7 1 N1\n3 0 0 1.5 1 N2\n");
    expect_failure(run({plain, "--surface", "sas", "--areas", path("p.csv"), "--relative",
                        "tien2013"}),
                   2, {"--relative needs residues", "chain_number_icode_residue_atom"});
    CliRun r = run({plain, "--surface", "sas", "--areas", path("p.csv"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "has no residues")) << r.err;
    std::vector<std::string> lines = lines_of(read_text(path("p.csv")));
    ASSERT_EQ(lines.size(), 4u);  // header, two atoms, total
    EXPECT_TRUE(lines[1].rfind("atom,0,1,,,,,N1,", 0) == 0) << lines[1];
    EXPECT_TRUE(lines[3].rfind("total,", 0) == 0) << lines[3];
    r = run({plain, "--surface", "sas", "--areas", path("p.json"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto json = parse_json(read_text(path("p.json")));
    ASSERT_TRUE(json.has_value());
    EXPECT_TRUE(json->find("residues")->array.empty());
    EXPECT_EQ(json->find("atoms")->array[0].find("chain"), nullptr);
    EXPECT_EQ(json->find("atoms")->array[0].find("name")->string, "N1");

    const std::string mixed =
        write_file("mixed.xyzrn", "0 0 0 1.7 1 A_5_x_GLY_CA\n3 0 0 1.5 1 N2\n");
    r = run({mixed, "--surface", "sas", "--areas", path("m.csv"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(contains(r.err, "has no residues")) << r.err;
    lines = lines_of(read_text(path("m.csv")));
    ASSERT_EQ(lines.size(), 5u);  // header, two atoms, one residue, total
    EXPECT_TRUE(lines[3].rfind("residue,,,A,5,,GLY,", 0) == 0) << lines[3];
}

TEST_F(CliAreasRun, AreasJsonIsValidUtf8ForAnyFileName) {
    const std::string input = path("cr\xffn.pdb");
    fs::copy_file(data("1crn.pdb"), input);
    const CliRun r = run({input, "--surface", "sas", "--areas", path("u.json"), "--quiet",
                          "--device", "no-such-device"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string text = read_text(path("u.json"));
    EXPECT_EQ(text.find('\xff'), std::string::npos);
    const auto file = parse_json(text);
    ASSERT_TRUE(file.has_value());
    const std::string name = file->find("input")->string;
    EXPECT_TRUE(name.ends_with("/cr\xef\xbf\xbdn.pdb")) << name;
}

// The CSV file is UTF-8 as the JSON file (pandas reads it as such): a residue name with a byte
// that is not becomes U+FFFD. Numbers too large for fixed notation (a radius of 1e30 Å) are
// written with an exponent, and the JSON file stays valid.
TEST_F(CliAreasRun, AreasFilesHoldValidTextAndNumbers) {
    const std::string odd = write_file("odd.xyzrn", "0 0 0 1.7 1 A_5_x_GL\xffY_CA\n");
    CliRun r = run({odd, "--surface", "sas", "--areas", path("o.csv"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::vector<std::string> lines = lines_of(read_text(path("o.csv")));
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_TRUE(lines[1].rfind("atom,0,1,A,5,,GL\xef\xbf\xbdY,CA,", 0) == 0) << lines[1];
    EXPECT_TRUE(lines[2].rfind("residue,,,A,5,,GL\xef\xbf\xbdY,", 0) == 0) << lines[2];

    const std::string big = write_file("big.xyzr", "0 0 0 1e30\n");
    r = run({big, "--surface", "sas", "--areas", path("b.json"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto json = parse_json(read_text(path("b.json")));
    ASSERT_TRUE(json.has_value()) << read_text(path("b.json")).substr(0, 400);
    const double area = json->find("atoms")->array[0].find("area")->number;
    EXPECT_NEAR(area / (4.0 * 3.14159265358979 * 1e60), 1.0, 1e-6) << area;
    r = run({big, "--surface", "sas", "--areas", path("b.csv"), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    lines = lines_of(read_text(path("b.csv")));
    ASSERT_GE(lines.size(), 2u);
    EXPECT_TRUE(contains(lines[1], ",1.000000015e+30,,1.2566370")) << lines[1];
}

TEST_F(CliAreasRun, AreasBesideTheMesh) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string mesh = path("m.ply"), areas = path("a.json");
    const CliRun r = run({data("3al1.pdb"), "-o", mesh, "--surface", "sas", "--areas", areas,
                          "--buried", "A:B", "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "atoms in neither group are left out")) << r.err;
    const auto summary = parse_json(r.out);
    ASSERT_TRUE(summary.has_value()) << r.out;
    const JsonValue* buried = summary->find("buried");
    ASSERT_NE(buried, nullptr);
    EXPECT_GT(buried->find("area")->number, 100.0);
    EXPECT_GT(buried->find("mesh_area")->number, 100.0);
    const JsonValue* a = summary->find("areas");
    EXPECT_NEAR(a->find("mesh_total")->number, summary->find("area")->number,
                1e-6 * summary->find("area")->number);
    const auto file = parse_json(read_text(areas));
    ASSERT_TRUE(file.has_value());
    EXPECT_EQ(file->find("mesh")->string, mesh);
    EXPECT_EQ(file->find("atoms")->array.size(), std::size_t(summary->find("atoms_used")->number));
    EXPECT_EQ(file->find("buried")->find("groups")->array.size(), 2u);
    EXPECT_NE(file->find("atoms")->array[0].find("mesh_area")->type, JsonValue::Type::Null);
}

// -o FILE.png with --areas: vdw and sas keep the mesh on the device for the picture and write
// the exact areas with no mesh split (as without -o); ses splits the host mesh it draws.
TEST_F(CliAreasRun, AreasBesideAPicture) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string picture = path("p.png"), areas = path("a.json");
    const CliRun r = run({data("1crn.pdb"), "-o", picture, "--surface", "sas", "--areas", areas,
                          "--relative", "tien2013", "--image-size", "64x48", "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(read_text(picture).empty());
    const auto summary = parse_json(r.out);
    ASSERT_TRUE(summary.has_value()) << r.out;
    EXPECT_FALSE(summary->find("mesh_on_host")->boolean);
    EXPECT_EQ(summary->find("images")->array.size(), 1u);
    const JsonValue* a = summary->find("areas");
    ASSERT_NE(a, nullptr);
    EXPECT_TRUE(a->find("exact")->boolean);
    EXPECT_EQ(a->find("mesh_total")->type, JsonValue::Type::Null);
    EXPECT_EQ(a->find("residues")->number, 46);
    const auto file = parse_json(read_text(areas));
    ASSERT_TRUE(file.has_value());
    EXPECT_EQ(file->find("mesh")->type, JsonValue::Type::Null);
    EXPECT_EQ(file->find("atoms")->array.size(), 327u);
    EXPECT_EQ(file->find("atoms")->array[0].find("mesh_area")->type, JsonValue::Type::Null);
    // The same exact areas as without -o.
    const std::string alone = path("alone.json");
    ASSERT_EQ(run({data("1crn.pdb"), "--surface", "sas", "--areas", alone, "--relative",
                   "tien2013"})
                  .exit_code,
              0);
    const auto file_alone = parse_json(read_text(alone));
    ASSERT_TRUE(file_alone.has_value());
    EXPECT_EQ(file->find("total")->find("area")->number,
              file_alone->find("total")->find("area")->number);

    // ses: the areas come from the mesh, made on the host and drawn.
    const std::string ses_picture = path("q.png"), ses_areas = path("b.json");
    const CliRun s = run({data("1crn.pdb"), "-o", ses_picture, "--areas", ses_areas,
                          "--image-size", "64x48", "--stats", "json"});
    ASSERT_EQ(s.exit_code, 0) << s.err;
    EXPECT_FALSE(read_text(ses_picture).empty());
    const auto ses_summary = parse_json(s.out);
    ASSERT_TRUE(ses_summary.has_value()) << s.out;
    EXPECT_TRUE(ses_summary->find("mesh_on_host")->boolean);
    EXPECT_NEAR(ses_summary->find("areas")->find("total")->number,
                ses_summary->find("area")->number, 1e-6 * ses_summary->find("area")->number);
    // No sphere patches for ses: null, as the file's mesh_area_on_patches.
    EXPECT_EQ(ses_summary->find("areas")->find("mesh_on_patches")->type, JsonValue::Type::Null);
    const auto ses_file = parse_json(read_text(ses_areas));
    ASSERT_TRUE(ses_file.has_value());
    EXPECT_NE(ses_file->find("atoms")->array[0].find("mesh_area")->type, JsonValue::Type::Null);
}

// Without -o no mesh is made: a picture option is refused, not ignored.
TEST(CliAreas, PicturesNeedAMesh) {
    for (const char* option : {"--image", "--view", "--outline"}) {
        std::vector<std::string> args{"in.pdb", "--surface", "sas", "--areas", "a.csv", option};
        if (std::string(option) == "--image") args.push_back("p.png");
        if (std::string(option) == "--view") args.push_back("top");
        try {
            fdmsurf::cli::parse_args(args);
            ADD_FAILURE() << option;
        } catch (const fdmsurf::Error& e) {
            EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
            EXPECT_TRUE(contains(e.what(), "--areas without -o computes none")) << e.what();
            EXPECT_TRUE(contains(e.what(), option)) << e.what();
        }
    }
}

}  // namespace
