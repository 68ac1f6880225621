// `fdmsurf msms` and the program started as `msms`: MSMS's options (abbreviations, values,
// refusals), the density-to-spacing rule, and runs on the xyzrn of 1CRN and 4HHB read back the
// way MaSIF's read_msms reads MSMS's files (fields 0-5, 7 and 9; the area file's 1 and 3).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli/msms_command.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "support/temp_folder.hpp"

namespace {

using namespace fdmsurf;
using namespace fdmsurf::cli;
namespace fs = std::filesystem;

std::string parse_error(const std::vector<std::string>& args) {
    try {
        parse_msms_args(args);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error thrown";
    return {};
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(MsmsOptions, AsMsmsSpellsThemAbbreviationsIncluded) {
    const MsmsOptions o = parse_msms_args({"-if", "a.xyzrn", "-of", "out/a", "-af", "out/b",
                                           "-probe", "1.5", "-density", "3.0", "-hdensity",
                                           "3.0", "-no_header", "-surface", "tses"});
    EXPECT_EQ(o.input, "a.xyzrn");
    EXPECT_EQ(o.output_base, "out/a");
    EXPECT_EQ(o.area_base, "out/b");
    EXPECT_FLOAT_EQ(o.probe, 1.5f);
    EXPECT_FLOAT_EQ(o.density, 3.0f);
    EXPECT_TRUE(o.hdensity_given);
    EXPECT_FALSE(o.header);
    EXPECT_TRUE(o.triangulate);
    EXPECT_EQ(o.method, SesMethod::Edt);
    // MSMS takes the first option an abbreviation starts: -de is -density, -no is -no_area,
    // -no_rest is itself (exact names first), -probe_radius in full.
    const MsmsOptions a = parse_msms_args({"-if", "x", "-de", "2", "-no", "-probe_radius", "1.2",
                                           "-surf", "ases", "-all", "-no_rest"});
    EXPECT_FLOAT_EQ(a.density, 2.0f);
    EXPECT_FALSE(a.areas);
    EXPECT_FLOAT_EQ(a.probe, 1.2f);
    EXPECT_FALSE(a.triangulate);
    EXPECT_TRUE(a.all_components);
    ASSERT_EQ(a.warnings.size(), 1u);
    EXPECT_TRUE(has(a.warnings[0], "-no_rest is ignored")) << a.warnings[0];
    const MsmsOptions c = parse_msms_args({"-if", "x", "-one_cavity", "2", "5", "9", "-noh"});
    EXPECT_EQ(c.warnings.size(), 2u);
    EXPECT_TRUE(parse_msms_args({"-help"}).help);
    // fdmsurf's placements, as the main command's --host-* options.
    const MsmsOptions d = parse_msms_args({"-if", "x"});
    EXPECT_EQ(d.gaussian_filter, StagePlace::Auto);
    EXPECT_EQ(d.ses_distance, StagePlace::Auto);
    const MsmsOptions p = parse_msms_args({"-if", "x", "-host_filter", "on", "-host_mc", "off",
                                           "-host_atoms", "auto", "-host_ses", "off",
                                           "-host_density", "on"});
    EXPECT_EQ(p.gaussian_filter, StagePlace::Host);
    EXPECT_EQ(p.marching_cubes, StagePlace::Device);
    EXPECT_EQ(p.vertex_atoms, StagePlace::Auto);
    EXPECT_EQ(p.ses_distance, StagePlace::Device);
    EXPECT_EQ(p.density_place, StagePlace::Host);
    EXPECT_EQ(d.density_place, StagePlace::Auto);
}

TEST(MsmsOptions, BadValuesNameTheOption) {
    EXPECT_TRUE(has(parse_error({"-if", "x", "-probe_radius"}), "-probe_radius needs a value"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-density", "many"}),
                    "-density needs a number, not 'many'"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-density", "0"}), "-density must be > 0"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-of", "-af", "y"}), "-of needs a value"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-surface", "vdw"}), "tses, ses or ases"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-socket", "s"}), "server mode"));
    const std::string unknown = parse_error({"-if", "x", "-colour"});
    EXPECT_TRUE(has(unknown, "unknown option '-colour'")) << unknown;
    EXPECT_TRUE(has(unknown, "-probe_radius")) << unknown;
    EXPECT_TRUE(has(parse_error({"-of", "y"}), "-if FILE is required"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-host_ses", "gpu"}),
                    "-host_ses takes auto, on or off, not 'gpu'"));
    EXPECT_TRUE(has(parse_error({"-if", "x", "-host_mc"}), "-host_mc needs a value"));
    // A negative coordinate-like value is a value, not an option.
    EXPECT_TRUE(has(parse_error({"-if", "x", "-probe", "-1"}), "-probe_radius must be > 0"));
}

TEST(MsmsOptions, DensityGivesAtLeastThatManyVerticesPerSquareAngstrom) {
    // 1.50 vertices per Å² × 1/h² (measured); h = sqrt(1.4 / D), within 0.2-1 Å.
    EXPECT_NEAR(spacing_for_density(3.0f), std::sqrt(1.4f / 3.0f), 1e-6);
    EXPECT_FLOAT_EQ(spacing_for_density(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(spacing_for_density(100.0f), 0.2f);
    for (float d : {2.0f, 3.0f, 10.0f}) EXPECT_GE(1.50f / std::pow(spacing_for_density(d), 2), d);
}

#if defined(FDMSURF_CLI_PATH) && defined(FDMSURF_TEST_DATA_DIR)

struct MsmsRun {
    int exit_code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> split(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> f;
    for (std::string w; in >> w;) f.push_back(w);
    return f;
}

std::vector<std::string> lines_of(const fs::path& p) {
    std::istringstream in(slurp(p));
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

// MSMS's files read as MaSIF's read_msms reads them: the count from the third line's first
// field, then per line fields 0-2 the position, 3-5 the normal, 7 the atom, 9 the name; face
// fields 0-2 minus 1; the area file from its second line, field 1 the SES area by field 3.
struct MasifRead {
    std::vector<std::array<double, 3>> vertices, normals;
    std::vector<std::string> atom_id, res_id;
    std::vector<std::array<long, 3>> faces;
    std::map<std::string, double> areas;
};

MasifRead masif_read(const std::string& base) {
    MasifRead r;
    const std::vector<std::string> vert = lines_of(base + ".vert");
    const std::size_t nv = std::stoul(split(vert.at(2)).at(0));
    EXPECT_EQ(vert.size() - 3, nv);
    for (std::size_t i = 3; i < vert.size(); ++i) {
        const std::vector<std::string> f = split(vert[i]);
        r.vertices.push_back({std::stod(f.at(0)), std::stod(f.at(1)), std::stod(f.at(2))});
        r.normals.push_back({std::stod(f.at(3)), std::stod(f.at(4)), std::stod(f.at(5))});
        r.atom_id.push_back(f.at(7));
        r.res_id.push_back(f.at(9));
    }
    const std::vector<std::string> face = lines_of(base + ".face");
    const std::size_t nf = std::stoul(split(face.at(2)).at(0));
    EXPECT_EQ(face.size() - 3, nf);
    for (std::size_t i = 3; i < face.size(); ++i) {
        const std::vector<std::string> f = split(face[i]);
        r.faces.push_back({std::stol(f.at(0)) - 1, std::stol(f.at(1)) - 1, std::stol(f.at(2)) - 1});
    }
    const std::vector<std::string> area = lines_of(base + ".area");
    for (std::size_t i = 1; i < area.size(); ++i) {
        const std::vector<std::string> f = split(area[i]);
        r.areas[f.at(3)] = std::stod(f.at(1));
    }
    return r;
}

// A fresh folder per test, its name with the process id: runs of the suite in other checkouts
// at the same time do not share it.
class MsmsRuns : public fdmsurf::test::TempFolderTest {
protected:
    MsmsRuns() : TempFolderTest("fdmsurf-msms-") {}

    // Runs `program args` in the test's folder.
    MsmsRun run(const std::string& program, const std::string& args) {
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const std::string command = "cd " + dir_.string() + " && " + program + " " + args +
                                    " > " + out.string() + " 2> " + err.string();
        const int status = std::system(command.c_str());
        MsmsRun r;
        if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
        r.out = slurp(out);
        r.err = slurp(err);
        fs::remove(out);
        fs::remove(err);
        return r;
    }
    static std::string data(const std::string& file) {
        return std::string(FDMSURF_TEST_DATA_DIR) + "/" + file;
    }
};

TEST_F(MsmsRuns, MasifReadsTheFilesOfCrambinAndHaemoglobinIntoTheRightArrays) {
    for (const std::string name : {"1crn", "4hhb"}) {
        SCOPED_TRACE(name);
        // MaSIF's call: msms -if F.xyzrn -of F -af F -probe_radius 1.5 -density 3.0
        // -hdensity 3.0 (here through `fdmsurf msms`).
        const MsmsRun r = run(std::string(FDMSURF_CLI_PATH) + " msms",
                          "-if " + data(name + ".xyzrn") + " -of " + name + " -af " + name +
                              " -probe_radius 1.5 -density 3.0 -hdensity 3.0");
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(has(r.out, "exact SES")) << r.out;
        const std::string base = (dir_ / name).string();
        const MasifRead m = masif_read(base);
        // The input's names in order: the atom field is the 1-based line, the name its name.
        const Structure s = read_structure(data(name + ".xyzrn"));
        ASSERT_FALSE(m.vertices.empty());
        for (std::size_t v = 0; v < m.vertices.size(); ++v) {
            const long atom = std::stol(m.atom_id[v]);
            ASSERT_GE(atom, 1);
            ASSERT_LE(atom, long(s.atoms.size()));
            ASSERT_EQ(m.res_id[v], s.atoms.meta[std::size_t(atom - 1)].xyzrn_name) << v;
            const auto& n = m.normals[v];
            ASSERT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 0.01) << v;
            // The vertex is near its atom (within its radius + the probe diameter).
            double d2 = 0;
            for (int k = 0; k < 3; ++k)
                d2 += std::pow(m.vertices[v][k] - s.atoms.xyz[3 * (atom - 1) + k], 2);
            ASSERT_LT(std::sqrt(d2), s.atoms.radius[std::size_t(atom - 1)] + 3.0 + 0.01) << v;
        }
        for (const auto& f : m.faces)
            for (long i : f) ASSERT_TRUE(i >= 0 && i < long(m.vertices.size()));
        // Areas by name: one per atom (the names are unique), the SES areas summing to the
        // mesh's area.
        EXPECT_EQ(m.areas.size(), s.atoms.size());
        double total = 0;
        for (const auto& [n, a] : m.areas) total += a;
        const Mesh mesh = read_mesh_any(base + ".vert");
        EXPECT_NEAR(total, compute_stats(mesh).area, 0.002 * total);
        EXPECT_TRUE(compute_stats(mesh).is_closed_manifold());
    }
}

TEST_F(MsmsRuns, TheProgramNamedMsmsIsTheSameCommand) {
    const fs::path msms = fs::path(FDMSURF_CLI_PATH).parent_path() / "msms";
    ASSERT_TRUE(fs::exists(msms)) << "the build makes " << msms;
    const MsmsRun a = run(msms.string(), "-if " + data("1crn.xyzrn") + " -of a -no_area");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const MsmsRun b = run(std::string(FDMSURF_CLI_PATH) + " msms",
                      "-if " + data("1crn.xyzrn") + " -of b -no_area");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    // Same lines apart from the file names in the first header line.
    const std::vector<std::string> va = lines_of(dir_ / "a.vert"), vb = lines_of(dir_ / "b.vert");
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 1; i < va.size(); ++i) ASSERT_EQ(va[i], vb[i]);
    EXPECT_EQ(slurp(dir_ / "a.face"), slurp(dir_ / "b.face"));
    EXPECT_FALSE(fs::exists(dir_ / "a.area"));
    // XYZR (no names) works too, the name field left out; -no_header leaves the counts out.
    const MsmsRun c = run(msms.string(), "-if " + data("1crn.xyzr") + " -of c -no_header");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const std::vector<std::string> vc = lines_of(dir_ / "c.vert");
    EXPECT_EQ(split(vc.at(0)).size(), 9u);
    EXPECT_EQ(vc.size(), va.size() - 3);
}

// The placements change where the stages run, not the surface: every stage on the device gives
// the files of the default (on a CPU device: the host's stages) to the printed digits, but for
// the last digit where a coordinate's rounding falls the other way.
TEST_F(MsmsRuns, PlacementsGiveTheSameFiles) {
    const std::string cli = std::string(FDMSURF_CLI_PATH) + " msms -if " + data("1crn.xyzrn");
    const MsmsRun a = run(cli, "-of a -no_area");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const MsmsRun b =
        run(cli, "-of b -no_area -host_filter off -host_mc off -host_atoms off -host_ses off");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    // The summary says what ran on the host: nothing here; on a CPU device, by default, the
    // exact SES field and marching cubes.
    EXPECT_FALSE(has(b.out, "on the host")) << b.out;
    const MsmsRun c = run(cli, "-of c -no_area -host_ses on -host_mc on");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_TRUE(has(c.out, "; exact SES field and marching cubes on the host")) << c.out;
    const std::vector<std::string> va = lines_of(dir_ / "a.vert"), vb = lines_of(dir_ / "b.vert");
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 3; i < va.size(); ++i) {
        const std::vector<std::string> x = split(va[i]), y = split(vb[i]);
        ASSERT_EQ(x.size(), y.size()) << i;
        for (std::size_t k = 0; k < 6; ++k)
            ASSERT_NEAR(std::stod(x[k]), std::stod(y[k]), 0.0015) << va[i] << " | " << vb[i];
        for (std::size_t k = 6; k < x.size(); ++k) ASSERT_EQ(x[k], y[k]) << i;
    }
    EXPECT_EQ(slurp(dir_ / "a.face"), slurp(dir_ / "b.face"));
}

// An input whose name holds a line break: the headers keep their three lines (the name with
// '?' for it), so MSMS's readers and fdmsurf compare still read the files.
TEST_F(MsmsRuns, NamesWithLineBreaksKeepTheHeaders) {
    fs::copy_file(data("1crn.xyzrn"), dir_ / "x\nyz.xyzrn");
    const MsmsRun r =
        run(std::string(FDMSURF_CLI_PATH) + " msms", "-if 'x\nyz.xyzrn' -of o -af o -density 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.out, "fdmsurf msms: x?yz.xyzrn,")) << r.out;
    for (const char* file : {"o.vert", "o.face"}) {
        std::ifstream in(dir_ / file);
        std::string first, second, third;
        std::getline(in, first), std::getline(in, second), std::getline(in, third);
        EXPECT_TRUE(has(first, "for x?yz.xyzrn (written by fdmsurf)")) << first;
        EXPECT_EQ(second[0], '#') << second;
        EXPECT_NE(third[0], '#') << third;  // the count line
    }
    const fdmsurf::Mesh mesh = fdmsurf::read_mesh_any((dir_ / "o.vert").string());
    EXPECT_GT(mesh.triangle_count(), 1000u);
}

TEST_F(MsmsRuns, BadInputIsAnErrorAndWritesNothing) {
    std::ofstream(dir_ / "short.xyzrn") << "1 2 3 1.5 1 A_1_x_GLY_N\n4 5 6\n";
    MsmsRun r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if short.xyzrn -of s -af s");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "line 2")) << r.err;
    r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if " + data("1crn.xyzrn") + " -probe");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(has(r.err, "-probe_radius needs a value")) << r.err;
    r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if " + data("1crn.xyzrn") + " -of no/s");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "cannot write 'no/s.vert': 'no' does not exist")) << r.err;
    // A name longer than the file system allows, with its extension: before any work.
    r = run(std::string(FDMSURF_CLI_PATH) + " msms",
            "-if " + data("1crn.xyzrn") + " -of " + std::string(251, 's') + " -device nothing");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "its name is 256 bytes long")) << r.err;
    r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if " + data("1crn.xyzrn") +
                                                          " -of s -noh -free_vertices");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(has(r.err, "-noh is ignored")) << r.err;
    fs::remove(dir_ / "s.vert");
    fs::remove(dir_ / "s.face");
    fs::remove(dir_ / "short.xyzrn");
    EXPECT_TRUE(fs::is_empty(dir_));

    // A sphere of radius 0 would be left out and shift every later atom number: refused.
    std::ofstream(dir_ / "zero.xyzrn") << "1 2 3 1.5 1 A_1_x_GLY_N\n# a comment\n"
                                          "4 5 6 0 1 A_1_x_GLY_H\n7 8 9 1.7 1 A_1_x_GLY_CA\n";
    r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if zero.xyzrn -of z -af z");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "line 3") && has(r.err, "radius 0")) << r.err;
    // A sphere line without its name among named ones: refused, naming it.
    std::ofstream(dir_ / "unnamed.xyzrn") << "1 2 3 1.5 1 A_1_x_GLY_N\n4 5 6 1.7\n";
    r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if unnamed.xyzrn -of u -af u");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(has(r.err, "line 2 has 4 fields, line 1 6")) << r.err;
    fs::remove(dir_ / "zero.xyzrn");
    fs::remove(dir_ / "unnamed.xyzrn");
    EXPECT_TRUE(fs::is_empty(dir_));

    // A folder where the .face or the .area would go: refused before any work, nothing written
    // (and were it made during the run, the files appear together or not at all: CommitGroup).
    for (const char* taken : {"t.face", "t.area"}) {
        fs::create_directory(dir_ / taken);
        r = run(std::string(FDMSURF_CLI_PATH) + " msms",
                "-if " + data("1crn.xyzrn") + " -of t -af t");
        EXPECT_EQ(r.exit_code, 3) << r.err;
        EXPECT_TRUE(has(r.err, std::string("cannot write '") + taken + "': it is a folder"))
            << r.err;
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(dir_)) left.push_back(e.path().filename());
        EXPECT_EQ(left, std::vector<std::string>{taken});
        fs::remove(dir_ / taken);
    }
}

TEST_F(MsmsRuns, XyzrnWithTabsCrlfAndOtherFieldCountsIsRead) {
    // Tabs, CRLF line ends, and named lines of five and six fields (issue 33).
    std::ofstream(dir_ / "loose.xyzrn", std::ios::binary)
        << "1\t2\t3\t1.5\t1\tA_1_x_GLY_N\r\n"
           "2.2 2 3 1.7 A_1_x_GLY_CA   \r\n";
    MsmsRun r = run(std::string(FDMSURF_CLI_PATH) + " msms", "-if loose.xyzrn -of l -af l");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::vector<std::string> area = lines_of((dir_ / "l.area").string());
    ASSERT_EQ(area.size(), 3u);
    EXPECT_TRUE(has(area[1], "A_1_x_GLY_N")) << area[1];
    EXPECT_TRUE(has(area[2], "A_1_x_GLY_CA")) << area[2];
}

TEST_F(MsmsRuns, AllComponentsWritesEachCavityApart) {
    // 1AON-like cavities are too slow here; 4HHB's exact SES at probe 1.0 encloses voids.
    const MsmsRun r = run(std::string(FDMSURF_CLI_PATH) + " msms",
                      "-if " + data("4hhb.xyzrn") + " -of h -no_area -probe 1.0 -all_components");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir_ / "h_1.vert")) << r.out;
    const Mesh outer = read_mesh_any((dir_ / "h.vert").string());
    const Mesh cavity = read_mesh_any((dir_ / "h_1.vert").string());
    EXPECT_GT(compute_stats(outer).volume, 0.0);
    EXPECT_LT(compute_stats(cavity).volume, 0.0);
    EXPECT_EQ(compute_stats(outer).pieces, 1u);
}

#endif

}  // namespace
