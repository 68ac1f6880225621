// `fdmsurf msms`: MSMS's command line (Sanner's man page, v2.6) over fdmsurf's engine.
#include "cli/msms_command.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <new>
#include <string_view>

#include "cli/messages.hpp"
#include "cli/options.hpp"
#include "cli/output_paths.hpp"
#include "cli/summary.hpp"
#include "base/text.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/msms.hpp"
#include "fdmsurf/structure.hpp"
#include "io/atomic_file.hpp"
#include "structure/detail.hpp"

namespace fdmsurf::cli {
namespace {

[[noreturn]] void usage_error(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, "msms: " + message + " (see fdmsurf msms -help)");
}

// MSMS's options in MSMS's order (an abbreviation takes the first that it starts), then
// fdmsurf's own. `values`: how many values follow (-1: -one_cavity's count and atoms).
struct MsmsOption {
    std::string_view name;
    int values;
};
constexpr std::array<MsmsOption, 27> kOptions{{
    {"if", 1},           {"of", 1},           {"af", 1},           {"probe_radius", 1},
    {"density", 1},      {"hdensity", 1},     {"no_area", 0},      {"surface", 1},
    {"socket", 1},       {"sinetd", 0},       {"noh", 0},          {"no_rest_on_pbr", 0},
    {"no_rest", 0},      {"free_vertices", 0}, {"all_components", 0}, {"one_cavity", -1},
    {"no_header", 0},    {"spacing", 1},      {"method", 1},       {"device", 1},
    {"validation", 0},   {"host_filter", 1},  {"host_mc", 1},      {"host_atoms", 1},
    {"host_ses", 1},     {"host_density", 1}, {"help", 0},
}};

const MsmsOption& find_option(const std::string& arg) {
    if (arg.size() < 2 || arg[0] != '-') usage_error("unexpected argument '" + arg + "'");
    const std::string_view name = std::string_view(arg).substr(arg[1] == '-' ? 2 : 1);
    for (const MsmsOption& o : kOptions)  // an exact name first: -no_rest is not -no_rest_on_pbr
        if (o.name == name) return o;
    for (const MsmsOption& o : kOptions)
        if (!name.empty() && o.name.starts_with(name)) return o;
    std::string list;
    for (const MsmsOption& o : kOptions) list += (list.empty() ? "-" : ", -") + std::string(o.name);
    usage_error("unknown option '" + arg + "'; the options are " + list);
}

float number(const std::string& option, const std::string& text, float low, bool low_open) {
    float value = 0.0f;
    const char* first = text.data();
    if (!text.empty() && text.front() == '+') ++first;
    const auto [end, ec] = std::from_chars(first, text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
        !std::isfinite(value))
        usage_error(option + " needs a number, not '" + text + "'");
    if (low_open ? !(value > low) : !(value >= low))
        usage_error(option + " must be " + (low_open ? "> " : ">= ") + format_general(low) +
                    " (got " + text + ")");
    return value;
}

// MSMS's -if file is xyzr ("x y z r") or xyzrn ("x y z r n name") throughout. The structure
// reader takes a line without its name in an xyzrn file (an empty name), which MSMS's files
// would then carry as a vertex line of nine fields and an area line of three: every sphere line
// must have a name if the first one has (five fields or more; tabs and CRLF are white space). Throws Error(Format) naming the line; returns the
// first sphere line's field count (0: none).
std::size_t check_sphere_lines(std::string_view text, const std::string& path) {
    detail::check_text(text, path);  // binary data: the reader's message
    detail::LineReader lines(text);
    std::string_view line;
    std::size_t first_fields = 0, first_line = 0;
    while (lines.next(line)) {
        const std::string_view t = detail::trim(line);
        if (t.empty() || t[0] == '#') continue;
        const std::size_t fields = detail::split_fields(t).size();
        if (first_line == 0) {
            first_fields = fields, first_line = lines.number();
            if (fields < 4) return fields;  // the reader names the line: too few fields
        } else if ((fields >= 5) != (first_fields >= 5)) {  // extra fields after a name: fine
            throw Error(ErrorCode::Format,
                        path + ": line " + std::to_string(lines.number()) + " has " +
                            std::to_string(fields) + " fields, line " +
                            std::to_string(first_line) + " " + std::to_string(first_fields) +
                            (first_fields >= 5 ? " (x y z radius n name)" : " (x y z radius)") +
                            ": every sphere line of an xyzr or xyzrn file has the same fields");
        }
    }
    return first_fields;
}

// The files a run writes: the surface's (-of, not with -surface ases) and the areas' (-af, not
// with -no_area).
struct MsmsFiles {
    bool surface = false;
    bool areas = false;
};

// The warnings for -of and -af that write nothing, then every file's folder and name checked
// before any work.
MsmsFiles check_msms_files(const MsmsOptions& o) {
    MsmsFiles f;
    f.surface = !o.output_base.empty() && o.triangulate;
    f.areas = !o.area_base.empty() && o.areas;
    if (!o.area_base.empty() && !o.areas)
        print_warning("-no_area: no area file is written for -af " + o.area_base);
    if (!o.output_base.empty() && !o.triangulate)
        print_warning("-surface ases: no .vert/.face files are written for -of " + o.output_base);
    // The files' folders and names, before any work.
    std::vector<std::string> paths;
    if (f.surface) {
        paths.insert(paths.end(), {o.output_base + ".vert", o.output_base + ".face"});
        // -all_components: BASE_N.vert for the cavities, N up to 6 digits here.
        if (o.all_components) paths.push_back(o.output_base + "_999999.vert");
    }
    if (f.areas) paths.push_back(o.area_base + ".area");
    for (const std::string& file : paths)
        if (const std::string e = output_path_problem(file); !e.empty())
            throw Error(ErrorCode::Io, e);
    return f;
}

// Every sphere of the file, in order: MSMS's atom numbers count lines (a sphere of radius 0,
// which the reader would leave out, is refused).
Structure read_spheres(const std::string& input) {
    const std::string text = detail::load_file(input);
    const std::size_t fields = check_sphere_lines(text, input);
    ReadOptions read;  // xyzrn when the spheres have names, else xyzr (its messages)
    read.format = fields >= 5 ? StructureFormat::Xyzrn : StructureFormat::Xyzr;
    read.keep_hydrogens = read.keep_waters = read.keep_ligands = true;
    Structure s = read_structure_from_memory(text, input, read);
    if (s.info.zero_radius_skipped != 0)
        throw Error(ErrorCode::Format,
                    input + ": line " + std::to_string(s.info.first_zero_radius_line) +
                        ": a sphere of radius 0 (" + std::to_string(s.info.zero_radius_skipped) +
                        " in the file), which would be left out and shift MSMS's atom "
                        "numbers: give it a radius or remove it");
    return s;
}

// The surface MSMS computes: the SES, every cavity kept (split off later), the spacing from
// the density unless -spacing gives it.
SurfaceOptions msms_surface(const MsmsOptions& o, float density) {
    SurfaceOptions surface;
    surface.surface = SurfaceKind::Ses;
    surface.method = o.method;
    surface.probe = o.probe;
    surface.spacing = o.spacing > 0.0f ? o.spacing : spacing_for_density(density);
    surface.min_cavity_volume = 0.0f;  // cavities split off below
    return surface;
}

EngineOptions msms_engine(const MsmsOptions& o) {
    EngineOptions eo;
    eo.device = o.device;
    eo.validation = o.validation;
    eo.gaussian_filter = o.gaussian_filter;
    eo.density = o.density_place;
    eo.marching_cubes = o.marching_cubes;
    eo.vertex_atoms = o.vertex_atoms;
    eo.ses_distance = o.ses_distance;
    return eo;
}

// -validation: the layer's messages as warnings; true (nothing is written) when there were any.
bool msms_validation_failed(const MsmsOptions& o, Engine& engine) {
    if (!o.validation) return false;
    const std::vector<std::string> messages = engine.take_validation_messages();
    for (const std::string& m : messages) print_warning("validation: " + m);
    if (messages.empty()) return false;
    print_error("the Vulkan validation layer reported messages; no output written");
    return true;
}

// What the summary counts: the components written, their vertices and triangles, and the SES
// and SAS areas in total.
struct MsmsTotals {
    std::size_t components = 0, vertices = 0, triangles = 0;
    double ses = 0.0, sas = 0.0;
};

// Each component's .vert and .face, and the .area file: every file of the run appears
// together or not at all.
MsmsTotals write_msms_files(const MsmsOptions& o, const MsmsFiles& f, const Structure& s,
                            const Mesh& surface_mesh, float spacing, float density) {
    std::vector<Mesh> components = msms_components(surface_mesh);
    if (!o.all_components) components.resize(1);
    const float tolerance = 0.1f * spacing;
    MsmsFileOptions fo;
    fo.header = o.header;
    fo.source = o.input;
    fo.density = density;
    fo.probe = o.probe;
    MsmsTotals totals;
    totals.components = components.size();
    std::vector<double> ses(s.atoms.size(), 0.0);
    detail::CommitGroup files;
    for (std::size_t c = 0; c < components.size(); ++c) {
        const Mesh& mesh = components[c];
        totals.vertices += mesh.vertex_count();
        totals.triangles += mesh.triangle_count();
        const std::vector<double> a = atom_mesh_areas(mesh, s.atoms.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            ses[i] += a[i];
            totals.ses += a[i];
        }
        if (f.surface)
            write_msms_surface(mesh, s.atoms, ses_vertex_parts(mesh, s.atoms, o.probe, tolerance),
                               c == 0 ? o.output_base : o.output_base + "_" + std::to_string(c),
                               fo);
    }
    if (o.areas) {
        const std::vector<double> sas = atom_sas_areas(s.atoms, o.probe);
        for (double a : sas) totals.sas += a;
        if (f.areas) write_msms_areas(s.atoms, ses, sas, o.area_base + ".area", fo);
    }
    files.commit();
    return totals;
}

// The summary: the spheres and settings, the surface, the areas, the time and the device.
void print_msms_summary(const MsmsOptions& o, const MsmsFiles& f, const MsmsTotals& t,
                        std::size_t spheres, float spacing, double ms, const std::string& device,
                        const GridInfo& grid) {
    std::printf("fdmsurf msms: %s, %s spheres, probe %s Å, spacing %s Å (%s)\n",
                detail::printable(o.input).c_str(), format_count(spheres).c_str(),
                format_general(o.probe).c_str(), format_general(spacing).c_str(),
                o.method == SesMethod::Edt ? "exact SES" : "fdm");
    std::printf("  surface    %s vertices, %s triangles, %zu component(s)%s\n",
                format_count(t.vertices).c_str(), format_count(t.triangles).c_str(), t.components,
                f.surface
                    ? (", written to " + detail::printable(o.output_base) + ".vert/.face").c_str()
                    : "");
    if (o.areas)
        std::printf(
            "  areas      SES %s Å², SAS %s Å²%s\n", format_grouped(t.ses, 1).c_str(),
            format_grouped(t.sas, 1).c_str(),
            f.areas ? (", per atom in " + detail::printable(o.area_base) + ".area").c_str() : "");
    const std::string on_host = host_stages(grid);
    std::printf("  time       %s ms on %s%s\n", format_grouped(ms, 0).c_str(), device.c_str(),
                on_host.empty() ? "" : ("; " + on_host + " on the host").c_str());
}

}  // namespace

float spacing_for_density(float density) {
    // Marching cubes on fdmsurf's grids puts 1.50 ± 0.01 vertices per Å² times 1/h² on a
    // protein's SES (1CRN, probe 1.5, h from 0.3 to 1 Å): h = sqrt(1.4 / D) gives at least D.
    // Kept between 0.2 Å (finer costs memory, not accuracy) and 1 Å (coarser loses detail).
    return std::clamp(std::sqrt(1.4f / density), 0.2f, 1.0f);
}

MsmsOptions parse_msms_args(const std::vector<std::string>& args) {
    MsmsOptions o;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "-h" || arg == "--help" || arg == "-help") {
            o.help = true;
            continue;
        }
        const MsmsOption& opt = find_option(arg);
        std::string name(1, '-');  // (not "-" + name: GCC 12's false -Wrestrict)
        name += opt.name;
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size() || (args[i + 1].size() > 1 && args[i + 1][0] == '-' &&
                                         !std::isdigit(static_cast<unsigned char>(args[i + 1][1])) &&
                                         args[i + 1][1] != '.'))
                usage_error(name + " needs a value");
            return args[++i];
        };
        if (opt.name == "if") {
            o.input = value();
        } else if (opt.name == "of") {
            o.output_base = value();
        } else if (opt.name == "af") {
            o.area_base = value();
        } else if (opt.name == "probe_radius") {
            o.probe = number(name, value(), 0.0f, true);
        } else if (opt.name == "density") {
            o.density = number(name, value(), 0.0f, true);
            o.density_given = true;
        } else if (opt.name == "hdensity") {
            o.hdensity = number(name, value(), 0.0f, true);
            o.hdensity_given = true;
        } else if (opt.name == "no_area") {
            o.areas = false;
        } else if (opt.name == "surface") {
            const std::string& kind = value();
            if (kind == "tses" || kind == "ses")
                o.triangulate = true;
            else if (kind == "ases")
                o.triangulate = false;
            else
                usage_error("-surface takes tses, ses or ases, not '" + kind + "'");
        } else if (opt.name == "socket" || opt.name == "sinetd") {
            usage_error(name + ": MSMS's server mode is not supported; give -if FILE");
        } else if (opt.name == "one_cavity") {
            const std::string count = value();
            const float n = number(name, count, 1.0f, false);
            for (int k = 0; k < int(n); ++k) value();
            o.warnings.push_back("-one_cavity is ignored: fdmsurf writes every cavity with "
                                 "-all_components, or none");
        } else if (opt.name == "noh" || opt.name == "no_rest_on_pbr" || opt.name == "no_rest" ||
                   opt.name == "free_vertices") {
            o.warnings.push_back(name + " is ignored: it has no meaning for fdmsurf's grid "
                                        "surface");
        } else if (opt.name == "all_components") {
            o.all_components = true;
        } else if (opt.name == "no_header") {
            o.header = false;
        } else if (opt.name == "spacing") {
            o.spacing = number(name, value(), 0.0f, true);
        } else if (opt.name == "method") {
            const std::string& m = value();
            if (m == "edt")
                o.method = SesMethod::Edt;
            else if (m == "fdm")
                o.method = SesMethod::Fdm;
            else
                usage_error("-method takes edt or fdm, not '" + m + "'");
        } else if (opt.name == "device") {
            o.device = value();
        } else if (opt.name == "validation") {
            o.validation = true;
        } else if (opt.name.starts_with("host_")) {
            const std::string& text = value();
            const std::optional<StagePlace> place = stage_place(text);
            if (!place) usage_error(name + " takes auto, on or off, not '" + text + "'");
            (opt.name == "host_filter"    ? o.gaussian_filter
             : opt.name == "host_density" ? o.density_place
             : opt.name == "host_mc"   ? o.marching_cubes
             : opt.name == "host_atoms" ? o.vertex_atoms
                                        : o.ses_distance) = *place;
        } else if (opt.name == "help") {
            o.help = true;
        }
    }
    if (!o.help && o.input.empty()) usage_error("-if FILE is required (xyzr or xyzrn spheres)");
    return o;
}

std::string msms_usage_text() {
    return R"(usage: fdmsurf msms -if FILE [-of BASE] [-af BASE] [-probe_radius R] [-density D]
                    [-hdensity D] [-no_area] [-surface tses|ses|ases] [-all_components]
                    [-no_header] [-spacing H] [-method edt|fdm] [-device D] [-validation]
                    [-host_filter P] [-host_density P] [-host_mc P] [-host_atoms P]
                    [-host_ses P]
       (also as a program named msms: a symlink to fdmsurf)

MSMS's command line over fdmsurf: the solvent-excluded surface of the spheres of FILE (xyzr:
"x y z r" per line; xyzrn: "x y z r n name"), written in MSMS's files. Options may be
abbreviated as MSMS allows (-probe for -probe_radius, -de for -density).

  -if FILE            spheres, xyzr or xyzrn (names kept and written back)
  -of BASE            BASE.vert and BASE.face (none without -of); with -all_components each
                      cavity k in BASE_k.vert and BASE_k.face
  -af BASE            BASE.area: per atom, SES area (from the mesh) and SAS area (Shrake-Rupley)
  -probe_radius R     probe radius, Å (default 1.5, as MSMS)
  -density D          vertices per Å² (default 1): the grid spacing is sqrt(1.4 / D) Å, kept
  -hdensity D         within 0.2-1 Å; the larger of the two densities given counts
  -no_area            no areas (no .area file)
  -surface KIND       tses or ses (default): triangulated; ases: areas only, no .vert/.face
  -all_components     the cavities too (default: the outer surface only, as MSMS)
  -no_header          no header lines in the files
fdmsurf's own:
  -spacing H          grid spacing, Å (overrides the densities)
  -method M           edt (default): the exact SES, as MSMS; fdm: fdmsurf's filtered density
  -device D           Vulkan device index or name part; -validation: the validation layer
  -host_filter P, -host_density P, -host_mc P, -host_atoms P, -host_ses P
                      auto (default), on or off: the Gaussian filter, the density, marching
                      cubes, the vertex atoms and the exact SES field on the host's threads
                      (on), on the device (off), or the host on a CPU device only (auto);
                      fdmsurf --help
Ignored with a warning: -noh, -no_rest_on_pbr, -no_rest, -free_vertices, -one_cavity.
Refused: -socket, -sinetd (server mode).

Vertex lines: x y z nx ny nz 0 ATOM T NAME (ATOM 1-based; T 1 contact, 2 toric, 3 re-entrant);
face lines: v1 v2 v3 T 0 (1-based). See docs/formats.md.
)";
}

int msms_command(const std::vector<std::string>& args) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    return report_errors([&] {
        const MsmsOptions o = parse_msms_args(args);
        if (o.help) {
            std::fputs(msms_usage_text().c_str(), stdout);
            return kExitOk;
        }
        for (const std::string& w : o.warnings) print_warning(w);
        const MsmsFiles f = check_msms_files(o);
        const Structure s = read_spheres(o.input);
        float density = o.density;
        if (o.hdensity_given) density = o.density_given ? std::max(o.density, o.hdensity)
                                                         : o.hdensity;
        const SurfaceOptions surface = msms_surface(o, density);
        Engine engine(msms_engine(o));
        SurfaceResult result = engine.make_surface(s.atoms, surface);
        for (const std::string& w : result.warnings) print_warning(w);
        if (msms_validation_failed(o, engine)) return kExitValidation;
        const MsmsTotals totals =
            write_msms_files(o, f, s, result.mesh, surface.spacing, density);
        const double ms =
            std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        print_msms_summary(o, f, totals, s.atoms.size(), surface.spacing, ms,
                           engine.device().name, result.grid);
        return kExitOk;
    });
}

}  // namespace fdmsurf::cli
