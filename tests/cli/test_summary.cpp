// Tests of the run summary (text and --stats json) on a made-up report: no device needed.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "cli/json_check.hpp"
#include "cli/summary.hpp"

namespace {

using fdmsurf::Simplifier;
using fdmsurf::StageTime;
using fdmsurf::cli::format_grouped;
using fdmsurf::cli::RunReport;
using fdmsurf_cli_test::JsonValue;
using fdmsurf_cli_test::parse_json;

RunReport example_report() {
    RunReport r;
    r.version = "0.1.0";
    r.input = "data/1crn.pdb";
    r.output = "out \"1\".ply";
    r.info.atoms_in_file = 327;
    r.info.models_in_file = 1;
    r.atoms_used = 327;
    r.grid.dims = {96, 90, 84};
    r.grid.spacing = 0.5f;
    r.grid.origin = {-1.5f, 2.0f, 3.25f};
    r.grid.cutoff = 0.178571f;
    r.stats.vertices = 41234;
    r.stats.triangles = 82464;
    r.stats.pieces = 1;
    r.stats.closed_pieces = 1;
    r.stats.area = 2312.44;
    r.stats.volume = 4650.06;
    r.closed_manifold = true;
    r.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
    r.times = {{"parse", 3.1, false},
               {"density", 60.0, true},
               {"fft-forward", 20.0, true},
               {"density", 60.4, true},
               {"write", 12.0, false}};
    r.total_ms = 812.3;
    r.warnings = {"unknown element 'Xx' at line 7\tgiven 1.8 Å"};
    return r;
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(CliSummary, GroupsThousands) {
    EXPECT_EQ(format_grouped(0.0, 0), "0");
    EXPECT_EQ(format_grouped(999.0, 0), "999");
    EXPECT_EQ(format_grouped(1000.0, 0), "1,000");
    EXPECT_EQ(format_grouped(1234567.0, 0), "1,234,567");
    EXPECT_EQ(format_grouped(2312.44, 1), "2,312.4");
    EXPECT_EQ(format_grouped(-4650.06, 1), "-4,650.1");
    EXPECT_EQ(format_grouped(-0.01, 1), "0.0");
    EXPECT_EQ(format_grouped(-0.5, 1), "-0.5");
    EXPECT_EQ(format_grouped(999999.96, 1), "1,000,000.0");
}

TEST(CliSummary, MergesRepeatedStages) {
    const auto merged = fdmsurf::cli::merge_times(example_report().times);
    ASSERT_EQ(merged.size(), 4u);
    EXPECT_EQ(merged[1].name, "density");
    EXPECT_DOUBLE_EQ(merged[1].ms, 120.4);
    EXPECT_TRUE(merged[1].gpu);
    EXPECT_EQ(merged[3].name, "write");
}

TEST(CliSummary, TextShowsEveryLine) {
    const std::string text = fdmsurf::cli::text_summary(example_report());
    for (const char* line :
         {"fdmsurf 0.1.0: ses surface of data/1crn.pdb\n",
          "  atoms        327 used (327 in file; 0 waters, 0 hydrogens, 0 altlocs left out)\n",
          "  grid         96 x 90 x 84 points, spacing 0.5 Å, cut-off 0.179 1/Å\n",
          "  mesh         41,234 vertices, 82,464 triangles, 1 piece(s), closed manifold: yes\n",
          "  area         2,312.4 Å²\n", "  volume       4,650.1 Å³\n",
          "  device       llvmpipe (LLVM 15.0.6, 256 bits)\n",
          "  time (ms)    parse 3.1 | density 120.4 (gpu) | fft-forward 20.0 (gpu) | write 12.0 | "
          "total 812.3\n",
          "  output       out \"1\".ply\n"}) {
        EXPECT_TRUE(contains(text, line)) << line << "\nin:\n" << text;
    }
}

TEST(CliSummary, TextShowsWhatIsMissingFromAnOpenMesh) {
    RunReport r = example_report();
    r.surface = fdmsurf::SurfaceKind::Vdw;
    r.grid.cutoff = 0.0f;
    r.grid.slabs = 3;
    r.stats.pieces = 3;
    r.stats.closed_pieces = 2;
    r.stats.boundary_edges = 12;
    r.closed_manifold = false;
    r.info.ligands_skipped = 5;
    r.info.models_in_file = 20;
    r.model = 2;
    const std::string text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text, "vdw surface of")) << text;
    EXPECT_TRUE(contains(text, "no filter, 3 slabs\n")) << text;
    // The default Gaussian filter of slabs run on the host says so.
    RunReport g = example_report();
    g.grid.slabs = 2;
    g.grid.host_filter = true;
    const std::string on_host = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(on_host, ", 2 slabs (Gaussian filter on the host)\n")) << on_host;
    g.grid.host_marching_cubes = true;
    const std::string both = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(both, ", 2 slabs (Gaussian filter and marching cubes on the host)\n"))
        << both;
    g.grid.host_filter = false;
    const std::string mc = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(mc, ", 2 slabs (marching cubes on the host)\n")) << mc;
    g.grid.host_ses_distance = true;
    const std::string ses = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(ses, ", 2 slabs (exact SES field and marching cubes on the host)\n"))
        << ses;
    g.grid.host_filter = true;  // not together with the exact SES, but three names read so
    const std::string three = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(
        three, ", 2 slabs (exact SES field, Gaussian filter and marching cubes on the host)\n"))
        << three;
    // The FDM surface's field on the host: the density named before the filter.
    g.grid.host_ses_distance = false;
    g.grid.host_density = true;
    const std::string fdm = fdmsurf::cli::text_summary(g);
    EXPECT_TRUE(contains(
        fdm, ", 2 slabs (density, Gaussian filter and marching cubes on the host)\n"))
        << fdm;
    EXPECT_TRUE(contains(text,
                         "3 piece(s) (2 closed), closed manifold: no (12 boundary edges, "
                         "0 non-manifold edges)"))
        << text;
    EXPECT_TRUE(contains(text, "5 ligand atoms")) << text;
    EXPECT_TRUE(contains(text, "model 2 of 20")) << text;
}

TEST(CliSummary, AssemblyIsNamedInTextAndJson) {
    RunReport r = example_report();
    r.info.assembly = 1;
    r.info.assembly_name = "1";
    r.info.assemblies_in_file = 1;
    r.info.assembly_chains = 180;
    r.info.atoms_in_file = 317160;
    const std::string text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text, "317,160 in assembly 1, 180 chains;")) << text;
    const auto value = parse_json(fdmsurf::cli::json_summary(r));
    ASSERT_TRUE(value);
    EXPECT_EQ(value->find("assembly")->number, 1);
    EXPECT_EQ(value->find("assembly_name")->string, "1");
    EXPECT_EQ(value->find("assemblies_in_file")->number, 1);
    EXPECT_EQ(value->find("assembly_chains")->number, 180);
    EXPECT_EQ(value->find("model")->number, 1);
    // The model as deposited: "in file", assembly 0.
    const std::string plain = fdmsurf::cli::text_summary(example_report());
    EXPECT_TRUE(contains(plain, " in file;")) << plain;
    EXPECT_EQ(parse_json(fdmsurf::cli::json_summary(example_report()))->find("assembly")->number,
              0);
}

TEST(CliSummary, SimplificationIsReportedInTextAndJson) {
    RunReport r = example_report();
    EXPECT_FALSE(contains(fdmsurf::cli::text_summary(r), "simplified"));
    EXPECT_EQ(parse_json(fdmsurf::cli::json_summary(r))->find("simplify")->type,
              JsonValue::Type::Null);
    r.simplified = true;
    r.simplify_options.ratio = 0.1;
    r.simplify_options.simplifier = Simplifier::kMeshopt;
    r.simplify.triangles_in = 824640;
    r.simplify.target_triangles = 82464;
    r.simplify.triangles_out = 82500;
    r.simplify.frozen_triangles = 120;
    r.simplify.hausdorff = 0.5;
    r.simplify.rmsd = 0.0625;
    r.simplify.error = 0.25;
    r.optimized = true;
    std::string text = fdmsurf::cli::text_summary(r);
    for (const char* line :
         {"  simplified   824,640 -> 82,500 triangles (10.0%; target 82,464), topology kept "
          "(120 triangles left as they were around collapses that would have broken it)\n",
          "  deviation    Hausdorff 0.5 Å, RMSD 0.0625 Å from the full mesh; meshoptimizer's "
          "estimate 0.25 Å\n",
          "  order        optimised for the vertex cache and vertex fetch\n"}) {
        EXPECT_TRUE(contains(text, line)) << line << "\nin:\n" << text;
    }
    const auto value = parse_json(fdmsurf::cli::json_summary(r));
    ASSERT_TRUE(value);
    const JsonValue& s = *value->find("simplify");
    EXPECT_EQ(s.find("ratio")->number, 0.1);
    EXPECT_EQ(s.find("max_triangles")->number, 0);
    EXPECT_EQ(s.find("target_triangles")->number, 82464);
    EXPECT_EQ(s.find("triangles_out")->number, 82500);
    EXPECT_EQ(s.find("topology_kept")->boolean, true);
    EXPECT_EQ(s.find("hausdorff")->number, 0.5);
    EXPECT_EQ(s.find("rmsd")->number, 0.0625);
    EXPECT_EQ(s.find("error")->number, 0.25);
    EXPECT_EQ(s.find("simplifier")->string, "meshopt");
    EXPECT_EQ(value->find("optimized")->boolean, true);
    // fdmsurf's own collapses (the default): their estimate, no frozen triangles.
    r.simplify_options.simplifier = Simplifier::kCollapse;
    r.simplify.frozen_triangles = 0;
    text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text, "(10.0%; target 82,464), topology kept\n")) << text;
    EXPECT_TRUE(contains(text, "from the full mesh; the collapses' estimate 0.25 Å\n")) << text;
    EXPECT_EQ(
        parse_json(fdmsurf::cli::json_summary(r))->find("simplify")->find("simplifier")->string,
        "collapse");
    // A result that lost its closedness says so, with the counts.
    r.simplify.topology_kept = false;
    r.simplify.stats_out.nonmanifold_edges = 3;
    r.simplify.stats_out.nonmanifold_vertices = 1;
    text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text,
                         "target 82,464), simplification broke closedness: 3 non-manifold "
                         "edges, 0 boundary edges, 1 non-manifold vertices\n"))
        << text;
    EXPECT_EQ(
        parse_json(fdmsurf::cli::json_summary(r))->find("simplify")->find("topology_kept")->boolean,
        false);
    // Still closed, but a neck pinched (meshoptimizer's collapses): the pieces and the Euler
    // characteristic that changed.
    r.simplify.stats_out.nonmanifold_edges = r.simplify.stats_out.nonmanifold_vertices = 0;
    r.simplify.stats_in_computed = true;
    r.simplify.stats_in.pieces = 4;
    r.simplify.stats_in.euler_characteristic = -88;
    r.simplify.stats_out.pieces = 6;
    r.simplify.stats_out.euler_characteristic = -82;
    text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text,
                         "target 82,464), simplification changed the topology (no new boundary "
                         "or non-manifold edge): 4 -> 6 pieces, Euler characteristic -88 -> -82\n"))
        << text;
    // Well above the target: why, by simplifier.
    r.simplify.target_triangles = 1000;
    r.simplify.triangles_out = 1010;  // within fdmsurf's 2%
    EXPECT_EQ(fdmsurf::cli::simplify_shortfall(r.simplify, Simplifier::kCollapse), "");
    r.simplify.triangles_out = 1030;
    EXPECT_EQ(fdmsurf::cli::simplify_shortfall(r.simplify, Simplifier::kCollapse),
              "the simplified mesh has 1,030 triangles for a target of 1,000: every collapse "
              "left would change its topology or turn a triangle over");
    EXPECT_EQ(fdmsurf::cli::simplify_shortfall(r.simplify, Simplifier::kMeshopt), "");  // < 10%
    r.simplify.triangles_out = 1200;
    r.simplify.frozen_triangles = 150;
    EXPECT_EQ(fdmsurf::cli::simplify_shortfall(r.simplify, Simplifier::kMeshopt),
              "the simplified mesh has 1,200 triangles for a target of 1,000: meshoptimizer's "
              "collapses stopped there (150 triangles kept as they were where they broke the "
              "topology)");
    // An empty mesh (a --patch of nothing): no distances, said so rather than "nan".
    r.simplify.hausdorff = r.simplify.rmsd = std::numeric_limits<double>::quiet_NaN();
    text = fdmsurf::cli::text_summary(r);
    EXPECT_TRUE(contains(text, "  deviation    not measured (no triangles)\n")) << text;
    EXPECT_FALSE(contains(text, "nan")) << text;
}

TEST(CliSummary, JsonIsOneValidObjectWithEveryKey) {
    const std::string json = fdmsurf::cli::json_summary(example_report());
    EXPECT_EQ(json.find('\n'), std::string::npos);
    const auto value = parse_json(json);
    ASSERT_TRUE(value) << json;
    ASSERT_EQ(value->type, JsonValue::Type::Object);
    for (const char* key : {"input",
                            "output",
                            "input_format",
                            "output_format",
                            "surface",
                            "atoms_used",
                            "atoms_in_file",
                            "waters_skipped",
                            "hydrogens_skipped",
                            "altlocs_skipped",
                            "ligands_skipped",
                            "grid",
                            "vertices",
                            "triangles",
                            "pieces",
                            "closed_pieces",
                            "boundary_edges",
                            "nonmanifold_edges",
                            "area",
                            "volume",
                            "device",
                            "times",
                            "total_ms",
                            "warnings"}) {
        EXPECT_NE(value->find(key), nullptr) << key;
    }
    EXPECT_EQ(value->find("output")->string, "out \"1\".ply");
    EXPECT_EQ(value->find("surface")->string, "ses");
    EXPECT_EQ(value->find("vertices")->number, 41234);
    EXPECT_EQ(value->find("closed_pieces")->number, 1);
    EXPECT_EQ(value->find("closed_manifold")->boolean, true);
    EXPECT_DOUBLE_EQ(value->find("area")->number, 2312.44);

    const JsonValue& grid = *value->find("grid");
    for (const char* key :
         {"dims", "spacing", "origin", "cutoff", "slabs", "host_filter", "host_density",
          "host_marching_cubes", "host_ses_distance"}) {
        EXPECT_NE(grid.find(key), nullptr) << key;
    }
    EXPECT_EQ(grid.find("host_filter")->boolean, false);
    EXPECT_EQ(grid.find("host_density")->boolean, false);
    EXPECT_EQ(grid.find("host_marching_cubes")->boolean, false);
    EXPECT_EQ(grid.find("host_ses_distance")->boolean, false);
    ASSERT_EQ(grid.find("dims")->array.size(), 3u);
    EXPECT_EQ(grid.find("dims")->array[2].number, 84);
    EXPECT_EQ(grid.find("origin")->array[2].number, 3.25);
    EXPECT_EQ(grid.find("spacing")->number, 0.5);

    const JsonValue& times = *value->find("times");
    ASSERT_EQ(times.object.size(), 4u);  // no duplicate keys: repeated stages are summed
    EXPECT_DOUBLE_EQ(times.find("density")->number, 120.4);
    EXPECT_DOUBLE_EQ(value->find("total_ms")->number, 812.3);

    ASSERT_EQ(value->find("warnings")->array.size(), 1u);
    EXPECT_EQ(value->find("warnings")->array[0].string, example_report().warnings[0]);
}

}  // namespace
