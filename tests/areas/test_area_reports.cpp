// Residues, relative-area tables, buried groups and the areas files (CSV and JSON), on the host.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

#include "cli/json_check.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "support/test_data.hpp"

namespace {

using namespace fdmsurf;
namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return {};
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

fs::path scratch() {
    const fs::path dir = fs::temp_directory_path() /
                         ("fdmsurf-area-reports-" + std::to_string(::getpid()) + "-" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(RelativeTables, PublishedMaxima) {
    EXPECT_EQ(residue_max_area("ALA", RelativeTable::Tien2013), 129.0);
    EXPECT_EQ(residue_max_area("TRP", RelativeTable::Tien2013), 285.0);
    EXPECT_EQ(residue_max_area("GLY", RelativeTable::Miller1987), 85.0);
    EXPECT_EQ(residue_max_area("ARG", RelativeTable::Miller1987), 241.0);
    EXPECT_EQ(residue_max_area("VAL", RelativeTable::Sander1994), 142.0);
    EXPECT_EQ(residue_max_area("TYR", RelativeTable::Sander1994), 222.0);
    EXPECT_LT(residue_max_area("HEM", RelativeTable::Tien2013), 0.0);
    EXPECT_LT(residue_max_area("ALA", RelativeTable::None), 0.0);
    EXPECT_STREQ(to_string(RelativeTable::Tien2013), "tien2013");
    EXPECT_STREQ(to_string(RelativeTable::Sander1994), "sander1994");
}

TEST(ResidueAreas, CrambinResiduesInOrder) {
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    SurfaceOptions options;
    options.surface = SurfaceKind::Sas;
    const AtomAreas a = surface_atom_areas(atoms, options);
    const std::vector<ResidueArea> r = residue_areas(atoms, a, RelativeTable::Tien2013);
    ASSERT_EQ(r.size(), 46u);
    EXPECT_EQ(r[0].name, "THR");
    EXPECT_EQ(r[0].number, 1);
    EXPECT_EQ(r[0].chain, "A");
    EXPECT_EQ(r[45].number, 46);
    double total = 0.0;
    std::size_t atoms_seen = 0;
    for (const ResidueArea& res : r) {
        total += res.area;
        atoms_seen += res.atoms.size();
        EXPECT_NEAR(res.relative, res.area / res.max_area, 1e-12);
    }
    EXPECT_EQ(atoms_seen, atoms.size());
    EXPECT_NEAR(total, std::accumulate(a.area.begin(), a.area.end(), 0.0), 1e-9);
    // XYZR input has no residues.
    const Atoms xyzr = read_structure(test::data_path("1crn.xyzr")).atoms;
    const AtomAreas b = surface_atom_areas(xyzr, options);
    EXPECT_TRUE(has(error_of([&] { residue_areas(xyzr, b); }), "XYZR"));
}

TEST(BuriedGroups, ChainListsSelectionsAndErrors) {
    const Atoms atoms = read_structure(test::data_path("4hhb.pdb.gz")).atoms;
    std::array<std::string, 2> names;
    const std::vector<std::uint8_t> g = match_buried_groups(atoms, "A,C:B,D", names);
    EXPECT_EQ(names[0], "A,C");
    EXPECT_EQ(names[1], "B,D");
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const std::string& c = atoms.meta[i].chain;
        EXPECT_EQ(g[i], c == "A" || c == "C" ? 1 : c == "B" || c == "D" ? 2 : 0);
    }
    // A gemmi selection: residues 1-40 of chain A against chain B.
    const std::vector<std::uint8_t> s = match_buried_groups(atoms, "A/1-40:B", names);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const AtomMeta& m = atoms.meta[i];
        EXPECT_EQ(s[i], m.chain == "A" && m.residue_number <= 40 ? 1 : m.chain == "B" ? 2 : 0);
    }
    const std::string missing = error_of([&] { match_buried_groups(atoms, "A:Q", names); });
    EXPECT_TRUE(has(missing, "chain Q is not in the structure; chains present: A, B, C, D"))
        << missing;
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "A:A,B", names); }), "overlap"));
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "A:B/999", names); }),
                    "selects none of the"));
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "AB", names); }), "one ':'"));
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "A:B:C", names); }), "one ':'"));
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "A:", names); }), "empty"));
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(atoms, "A:B[", names); }), "B["));
    const Atoms xyzr = read_structure(test::data_path("1crn.xyzr")).atoms;
    EXPECT_TRUE(has(error_of([&] { match_buried_groups(xyzr, "A:B", names); }), "need chains"));
}

TEST(AreasFile, CsvAndJsonLayouts) {
    const Atoms atoms = read_structure(test::data_path("4hhb.pdb.gz")).atoms;
    std::array<std::string, 2> names;
    const std::vector<std::uint8_t> g = match_buried_groups(atoms, "A:B", names);
    SurfaceOptions options;
    options.surface = SurfaceKind::Sas;
    const BuriedAreas b = buried_areas(nullptr, atoms, g, names, options);
    const std::vector<ResidueArea> residues =
        residue_areas(b.complex, b.in_complex, RelativeTable::Miller1987);
    AreasReport report;
    report.input = "4hhb.pdb.gz";
    report.surface = options;
    report.relative = RelativeTable::Miller1987;
    report.atoms = &b.complex;
    report.areas = &b.in_complex;
    report.residues = &residues;
    report.buried = &b;
    const fs::path dir = scratch();

    write_areas(report, (dir / "a.csv").string());
    std::istringstream csv(slurp(dir / "a.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line,
              "record,atom,serial,chain,residue_number,insertion_code,residue_name,atom_name,"
              "element,x,y,z,radius,group,area,mesh_area,relative_area,area_alone,buried_area");
    std::size_t rows[4] = {0, 0, 0, 0};
    std::string total;
    while (std::getline(csv, line)) {
        // Every row has the header's 19 fields (none here needs quoting).
        EXPECT_EQ(std::count(line.begin(), line.end(), ','), 18) << line;
        const std::string record = line.substr(0, line.find(','));
        rows[record == "atom" ? 0 : record == "residue" ? 1 : record == "group" ? 2 : 3]++;
        if (record == "total") total = line;
    }
    EXPECT_EQ(rows[0], b.complex.size());
    EXPECT_EQ(rows[1], residues.size());
    EXPECT_EQ(rows[2], 2u);
    EXPECT_EQ(rows[3], 1u);
    char buried[32];
    std::snprintf(buried, sizeof buried, ",%.4f", b.buried());
    EXPECT_TRUE(has(total, buried)) << total << " " << buried;

    write_areas(report, (dir / "a.JSON").string());
    const auto json = fdmsurf_cli_test::parse_json(slurp(dir / "a.JSON"));
    ASSERT_TRUE(json.has_value());
    EXPECT_EQ(json->find("surface")->string, "sas");
    EXPECT_EQ(json->find("relative_table")->string, "miller1987");
    EXPECT_EQ(json->find("area_method")->string, "exact sphere patches");
    EXPECT_EQ(json->find("mesh")->type, fdmsurf_cli_test::JsonValue::Type::Null);
    EXPECT_EQ(json->find("atoms")->array.size(), b.complex.size());
    EXPECT_EQ(json->find("residues")->array.size(), residues.size());
    const auto& res0 = json->find("residues")->array[0];
    EXPECT_EQ(res0.find("name")->string, "VAL");
    EXPECT_EQ(res0.find("max_area")->number, 160.0);
    EXPECT_NEAR(json->find("buried")->find("buried_area")->number, b.buried(), 1e-3);
    const auto& atom0 = json->find("atoms")->array[0];
    for (const char* key :
         {"index", "serial", "name", "chain", "residue_number", "insertion_code", "residue_name",
          "element", "xyz", "radius", "area", "mesh_area", "group", "area_alone", "buried_area"})
        EXPECT_NE(atom0.find(key), nullptr) << key;
}

TEST(AreasFile, BadExtensionAndUnwritableFolderLeaveNothing) {
    const Atoms atoms = read_structure(test::data_path("1crn.pdb")).atoms;
    SurfaceOptions options;
    options.surface = SurfaceKind::Sas;
    const AtomAreas a = surface_atom_areas(atoms, options);
    AreasReport report;
    report.atoms = &atoms;
    report.areas = &a;
    const fs::path dir = scratch();
    EXPECT_TRUE(has(error_of([&] { write_areas(report, (dir / "a.txt").string()); }),
                    "unknown extension '.txt'"));
    EXPECT_TRUE(has(error_of([&] { areas_format_for_path("areas"); }), "no extension"));
    try {
        write_areas(report, (dir / "missing" / "a.csv").string());
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::Io);
    }
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}
