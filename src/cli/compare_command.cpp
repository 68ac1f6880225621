// `fdmsurf compare`: reads two meshes, runs compare_meshes, prints text or one JSON object.
#include "cli/compare_command.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "cli/json.hpp"
#include "cli/messages.hpp"
#include "cli/options.hpp"
#include "cli/summary.hpp"
#include "base/text.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::cli {
namespace {

[[noreturn]] void usage_error(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument,
                "compare: " + message + " (see fdmsurf compare --help)");
}

double parse_number(const std::string& option, std::string_view text) {
    double value = 0;
    const char* first = text.data();
    if (!text.empty() && text.front() == '+') ++first;
    const auto [end, ec] = std::from_chars(first, text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
        !std::isfinite(value)) {
        usage_error(option + " needs a number, not '" + std::string(text) + "'");
    }
    return value;
}

std::string fixed(double value, int decimals) { return format_grouped(value, decimals); }

std::string signed_fixed(double value, int decimals) {
    const std::string text = format_grouped(value, decimals);
    return (text.front() == '-' || text.front() == 'n') ? text : "+" + text;
}

std::string percent(double fraction, int decimals) {
    // No reference volume (an open or flat mesh): no relative error.
    if (!std::isfinite(fraction)) return "n/a";
    return signed_fixed(100.0 * fraction, decimals) + " %";
}

double ms_between(std::chrono::steady_clock::time_point a,
                  std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

CompareCliOptions parse_compare_args(const std::vector<std::string>& args) {
    CompareCliOptions options;
    std::vector<std::string> positional;
    bool spacing_given = false;
    bool options_ended = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (options_ended || arg.size() < 2 || arg[0] != '-') {
            positional.push_back(arg);
            continue;
        }
        if (arg == "--") {
            options_ended = true;
            continue;
        }
        if (arg == "-h" || arg == "--help") {
            options.help = true;
            continue;
        }
        std::string name = arg, value;
        bool has_value = false;
        if (const std::size_t eq = arg.find('=');
            eq != std::string::npos && arg.starts_with("--")) {
            name = arg.substr(0, eq);
            value = arg.substr(eq + 1);
            has_value = true;
        }
        auto take_value = [&]() -> std::string {
            if (has_value) return value;
            if (i + 1 >= args.size()) usage_error(name + " needs a value");
            return args[++i];
        };
        if (name == "--spacing") {
            options.compare.spacing = parse_number(name, take_value());
            if (!(options.compare.spacing > 0)) usage_error("--spacing must be > 0 Å");
            spacing_given = true;
        } else if (name == "--stats") {
            const std::string kind = take_value();
            if (kind != "json") usage_error("--stats takes 'json', not '" + kind + "'");
            options.json = true;
        } else if (name == "--outer" && !has_value) {
            options.compare.outer_only = true;
        } else if (name == "--weld-tol") {
            options.compare.weld_tolerance = parse_number(name, take_value());
        } else {
            usage_error("unknown option " + arg);
        }
    }
    if (options.help) return options;
    if (positional.size() < 2) usage_error("missing REFERENCE or TESTED mesh");
    if (positional.size() > 2) usage_error("unexpected argument '" + positional[2] + "'");
    if (!spacing_given) usage_error("missing --spacing H");
    options.reference = positional[0];
    options.tested = positional[1];
    return options;
}

std::string compare_usage_text() {
    return R"(Usage: fdmsurf compare REFERENCE TESTED --spacing H [--stats json] [--outer]

Accuracy of the TESTED mesh against the REFERENCE mesh (Giard & Macq 2010): for every
reference vertex v, d(v) is the exact distance to the closest point of TESTED, and
w(v) the mean area of the triangles around v. Prints the weighted RMSD
sqrt(sum w d^2 / sum w), the weighted mean unsigned and signed distance (positive:
reference outside TESTED), the share of reference area with d > H, the RMSD the
other way round, the vertex-sampled Hausdorff distance, and both areas and volumes
with the relative errors (TESTED - REFERENCE) / REFERENCE. Same definitions as
shared/tools/meshstat.py compare.

Meshes: PLY, OBJ, GLB, STL, OFF (incl. NanoShaper's OFF+N), MSMS .vert/.face
(either name), each optionally gzip-compressed (.ply.gz). Vertices closer than
1e-5 Å are welded.

Options:
  --spacing H        H, Å (> 0; required): report the area share with d > H
  --stats json       print one JSON object instead of text
  --outer            compare only the largest-area piece of each mesh (outer
                     surface; cavities and detached pieces left out)
  --weld-tol T       weld vertices closer than T Å (default 1e-5; 0: exact
                     duplicates only; < 0: no welding)
  -h, --help         this text

Exit codes: 0 success, 2 usage error, 3 unreadable or unusable mesh, 1 other.
)";
}

std::string compare_text(const CompareReport& report) {
    const CompareResult& r = report.result;
    const double h = report.options.spacing;
    std::string s = "fdmsurf compare: " + detail::printable(report.tested) + " against " +
                    detail::printable(report.reference) +
                    (report.options.outer_only ? " (largest pieces only)" : "") + "\n";
    s += "  vertices        " + format_count(r.ref_vertices) + " reference, " +
         format_count(r.test_vertices) + " tested (after welding)\n";
    s += "  RMSD_w          " + fixed(r.rmsd_weighted, 4) + " Å (reference vertices to tested)\n";
    s += "  mean |d|        " + fixed(r.mean_unsigned, 4) + " Å\n";
    s += "  mean signed d   " + signed_fixed(r.mean_signed, 4) +
         " Å (positive: reference outside tested)\n";
    s += "  beyond H        " + fixed(100.0 * r.share_beyond_spacing, 2) +
         " % of reference area has d > " + format_general(h, 4) + " Å\n";
    s += "  Hausdorff       " + fixed(r.hausdorff, 4) + " Å (max reference to tested " +
         fixed(r.max_ref_to_test, 4) + ", tested to reference " + fixed(r.max_test_to_ref, 4) +
         ")\n";
    s += "  RMSD_w reverse  " + fixed(r.rmsd_tested_to_reference, 4) +
         " Å (tested vertices to reference)\n";
    s += "  area            " + fixed(r.area_ref, 1) + " Å² reference, " + fixed(r.area_test, 1) +
         " Å² tested, " + percent(r.area_rel_error, 2) + "\n";
    s += "  volume          " + fixed(r.volume_ref, 1) + " Å³ reference, " +
         fixed(r.volume_test, 1) + " Å³ tested, " + percent(r.volume_rel_error, 2) + "\n";
    s += "  time (ms)       read " + fixed(report.read_ms, 1) + " | compare " +
         fixed(report.compare_ms, 1) + "\n";
    return s;
}

std::string compare_json(const CompareReport& report) {
    const CompareResult& r = report.result;
    JsonWriter j;
    j.begin_object();
    // Key names follow meshstat.py's --json output, so that the two can be diffed.
    j.member("reference", report.reference).member("test", report.tested);
    j.member("spacing", report.options.spacing).member("outer", report.options.outer_only);
    j.member("ref_vertices", r.ref_vertices).member("test_vertices", r.test_vertices);
    j.member("ref_triangles", r.ref_triangles).member("test_triangles", r.test_triangles);
    j.member("ref_area", r.area_ref).member("test_area", r.area_test);
    j.member("area_rel_err", r.area_rel_error);
    j.member("ref_volume", r.volume_ref).member("test_volume", r.volume_test);
    j.member("volume_rel_err", r.volume_rel_error);
    j.member("rmsd", r.rmsd_weighted).member("mean_unsigned", r.mean_unsigned);
    j.member("mean_signed", r.mean_signed);
    j.member("pct_area_beyond_spacing", 100.0 * r.share_beyond_spacing);
    j.member("max_ref_to_test", r.max_ref_to_test).member("max_test_to_ref", r.max_test_to_ref);
    j.member("hausdorff", r.hausdorff).member("rmsd_test_to_ref", r.rmsd_tested_to_reference);
    j.member("read_ms", report.read_ms).member("compare_ms", report.compare_ms);
    j.end_object();
    return j.str();
}

int compare_command(const std::vector<std::string>& args) {
    return report_errors([&] {
        const CompareCliOptions options = parse_compare_args(args);
        if (options.help) {
            std::fputs(compare_usage_text().c_str(), stdout);
            return kExitOk;
        }
        using Clock = std::chrono::steady_clock;
        CompareReport report;
        report.reference = options.reference;
        report.tested = options.tested;
        report.options = options.compare;
        const auto t0 = Clock::now();
        const Mesh reference = read_mesh_any(options.reference);
        const Mesh tested = read_mesh_any(options.tested);
        const auto t1 = Clock::now();
        report.result = compare_meshes(reference, tested, options.compare);
        const auto t2 = Clock::now();
        report.read_ms = ms_between(t0, t1);
        report.compare_ms = ms_between(t1, t2);
        if (options.json) {
            std::printf("%s\n", compare_json(report).c_str());
        } else {
            std::fputs(compare_text(report).c_str(), stdout);
        }
        return kExitOk;
    });
}

}  // namespace fdmsurf::cli
