// The fdmsurf program: a structure file in, its molecular-surface mesh out (see --help).
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <future>
#include <iostream>
#include <new>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>
#include <system_error>
#include <vector>

#include "cli/compare_command.hpp"
#include "cli/prepare_command.hpp"
#include "cli/huge_pages.hpp"
#include "cli/interrupts.hpp"
#include "cli/messages.hpp"
#include "cli/msms_command.hpp"
#include "cli/options.hpp"
#include "cli/output_paths.hpp"
#include "cli/progress.hpp"
#include "cli/summary.hpp"
#include "cli/version.hpp"
#include "base/trace.hpp"
#include "io/atomic_file.hpp"
#include "vulkan/context.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

// errno of the first failed flush of stdout (0: none): by the time check_stdout flushes the
// stream again, the error flag is all that is left of it.
int stdout_errno = 0;

void note_error(std::FILE* stream) {
    if (stream == stdout && stdout_errno == 0) stdout_errno = errno != 0 ? errno : EIO;
}

void flush_noting_errors(std::FILE* stream) {
    errno = 0;
    if (std::fflush(stream) != 0) note_error(stream);
}

// `text` written to `stream`, the reason of a failed write kept as a flush's is: a text longer
// than the stream's buffer fails inside the write, and the later flush knows only that it did.
void put_noting_errors(const std::string& text, std::FILE* stream) {
    errno = 0;
    if (std::fwrite(text.data(), 1, text.size(), stream) != text.size()) note_error(stream);
}

using namespace fdmsurf;
using namespace fdmsurf::cli;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string format_bytes(std::uint64_t bytes) {
    char text[64];
    std::snprintf(text, sizeof text, " (%.2f GiB)", static_cast<double>(bytes) / (1 << 30));
    return format_count(bytes) + " bytes" + text;
}

int list_devices_command() {
    std::vector<DeviceInfo> devices;
    try {
        devices = list_devices();
    } catch (const Error& e) {
        if (e.code() != ErrorCode::NoDevice) throw;
        std::printf("%s\n", one_line(e.what()).c_str());  // says what to install
        return kExitOk;
    }
    bool any_usable = false;
    for (const DeviceInfo& d : devices) {
        any_usable = any_usable || d.usable;
        std::printf("device %u: %s\n", d.index, d.name.c_str());
        std::printf("  type                   %s\n", d.type.c_str());
        std::printf("  driver                 %s\n", d.driver.c_str());
        std::printf("  vulkan                 %s\n", d.api_version.c_str());
        std::printf("  usable                 %s\n",
                    d.usable ? "yes" : ("no: " + one_line(d.reason)).c_str());
        std::printf("  maxStorageBufferRange  %s\n",
                    format_bytes(d.max_storage_buffer_range).c_str());
        std::printf("  memory                 %s\n", format_bytes(d.device_memory).c_str());
    }
    if (!any_usable) std::printf("%s\n", detail::no_device_help().c_str());
    return kExitOk;
}

// Adds the path to a message that does not name it already.
std::string naming(const std::string& path, const std::string& message) {
    if (message.find(path) != std::string::npos) return message;
    return "'" + path + "': " + message;
}

const char* const kStdoutName = "standard output";

// Standard output as a stream for write_mesh, straight to descriptor 1 (stdio is not used for
// it): a failed write, a closed pipe among them (SIGPIPE is ignored), throws the Error that
// names its reason, and the stream passes it on (badbit is in its exception mask).
class StdoutBuffer final : public std::streambuf {
protected:
    std::streamsize xsputn(const char* data, std::streamsize size) override {
        std::streamsize done = 0;
        while (done < size) {
            const ssize_t n = ::write(STDOUT_FILENO, data + done, std::size_t(size - done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int error_number = n < 0 ? errno : EIO;
                throw Error(ErrorCode::Io, std::string("cannot write ") + kStdoutName + ": " +
                                               std::strerror(error_number) +
                                               (error_number == EPIPE
                                                    ? " (the reading end of the pipe was closed; "
                                                      "the output is incomplete)"
                                                    : ""));
            }
            done += n;
        }
        return size;
    }
    int_type overflow(int_type c) override {
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            const char byte = traits_type::to_char_type(c);
            xsputn(&byte, 1);
        }
        return traits_type::not_eof(c);
    }
};

// The structures of INPUT, or of standard input for "-": every model with --models all (the
// file parsed once), else the one model asked for.
std::vector<Structure> read_input(const CliOptions& options, const std::string& input) {
    if (input == kStdio) {
        std::vector<Structure> models = read_models(std::cin, "standard input", options.read);
        if (!options.all_models) models.resize(std::min<std::size_t>(models.size(), 1));
        return models;
    }
    if (options.all_models) return read_models(input, options.read);
    std::vector<Structure> one;
    one.push_back(read_structure(input, options.read));
    return one;
}

// That a file can be created at `output` (output_path_problem), else Error(Io).
void check_path(const std::string& output) {
    const std::string problem = output_path_problem(output);
    if (!problem.empty()) throw Error(ErrorCode::Io, problem);
}

// Everything about OUTPUT that can be known before any work: its format, and that its folder
// exists, so that a typo costs no GPU time.
MeshFormat check_output(const std::string& output, MeshFormat format) {
    if (output == kStdio) return format == MeshFormat::Auto ? MeshFormat::Ply : format;
    if (format == MeshFormat::Auto) {
        try {
            format = mesh_format_for_path(output);
        } catch (const Error& e) {
            throw Error(e.code(), naming(output, e.what()) +
                                      "; .png draws a picture; or name the format with "
                                      "--output-format");
        }
    }
    check_path(output);
    return format;
}

// What --areas, --relative and --buried need from the structure, checked before any device
// work: residues for --relative, the two groups of --buried (exit 2 with the reason).
struct AreasPlan {
    bool wanted = false;
    std::vector<std::uint8_t> groups;  // --buried: 1 or 2 per atom, 0 in neither
    std::array<std::string, 2> names;
    std::size_t outside = 0;  // atoms in neither group
};

AreasPlan plan_areas(const CliOptions& options, const Structure& structure,
                     const std::string& input) {
    AreasPlan plan;
    if (options.areas.empty()) return plan;
    plan.wanted = true;
    const Atoms& atoms = structure.atoms;
    const bool residues = atoms.has_residues();
    if (options.relative != RelativeTable::None && !residues)
        throw Error(ErrorCode::InvalidArgument,
                    input + ": --relative needs residues, and " + to_string(structure.info.format) +
                        (structure.info.format == StructureFormat::Xyzrn
                             ? " input names none: give names in MSMS's "
                               "chain_number_icode_residue_atom form, or PDB, mmCIF or PQR"
                             : " input has none (only coordinates and radii): give PDB, mmCIF, "
                               "PQR or XYZRN"));
    if (!options.buried.empty()) {
        try {
            plan.groups =
                match_buried_groups(atoms, options.buried, plan.names, structure.info.model);
        } catch (const Error& e) {
            throw Error(ErrorCode::InvalidArgument, input + ": --buried: " + e.what());
        }
        plan.outside = std::size_t(std::count(plan.groups.begin(), plan.groups.end(), 0));
    }
    return plan;
}

// The --areas file and the report's lines for it.
void write_areas_file(const CliOptions& options, const std::string& input,
                      const std::string& output, const Atoms& atoms, const AtomAreas& areas,
                      const BuriedAreas* buried, double mesh_area, bool has_mesh,
                      RunReport& report) {
    auto t = Clock::now();
    std::vector<ResidueArea> residues;
    if (atoms.has_residues()) residues = residue_areas(atoms, areas, options.relative);
    AreasReport file;
    file.input = input;
    file.output = output;
    file.surface = options.surface;
    file.has_mesh = has_mesh;
    file.mesh_area = mesh_area;
    file.relative = options.relative;
    file.atoms = &atoms;
    file.areas = &areas;
    file.residues = &residues;
    file.buried = buried;
    write_areas(file, options.areas);
    report.times.push_back({"write-areas", ms_since(t), false});
    report.areas_file = options.areas;
    report.areas_exact = areas.exact;
    report.areas_total = 0.0;
    for (double a : areas.area) report.areas_total += a;
    report.areas_mesh_total = -1.0;
    if (!areas.mesh_area.empty()) {
        report.areas_mesh_total = 0.0;
        for (double a : areas.mesh_area) report.areas_mesh_total += a;
        report.areas_on_patches = areas.exact ? areas.mesh_on_patches : 0.0;
    }
    report.areas_residues = residues.size();
    if (buried) {
        report.buried = options.buried;
        report.buried_area = buried->buried();
        for (int g = 0; g < 2; ++g)
            report.buried_groups[g] = buried->area_alone[g] - buried->area_in_complex[g];
        report.buried_mesh_area = has_mesh ? buried->mesh_buried() : -1.0;
    }
}

// The warning for --areas on a structure without residues (XYZR, or XYZRN whose names are not
// MSMS's): per-atom and total areas only.
std::string no_residues_warning(const std::string& input, const Structure& structure) {
    return "--areas: " + input + " has no residues (" + to_string(structure.info.format) +
           " input): the file has per-atom and total areas only";
}

// --areas with no -o: the exact vdw or sas areas, no mesh and no device.
int areas_only(const CliOptions& options, const Structure& structure, double parse_ms,
               const AreasPlan& plan) {
    const auto start = Clock::now();
    RunReport report;
    report.times.push_back({"parse", parse_ms, false});
    for (const std::string& message : structure.info.warnings) {
        print_warning(message);
        report.warnings.push_back(message);
    }
    const std::string& input = options.inputs.front();
    if (!structure.atoms.has_residues()) {
        const std::string message = no_residues_warning(input, structure);
        print_warning(message);
        report.warnings.push_back(message);
    }
    auto t = Clock::now();
    if (!plan.groups.empty()) {
        const BuriedAreas buried =
            buried_areas(nullptr, structure.atoms, plan.groups, plan.names, options.surface);
        report.times.push_back({"areas", ms_since(t), false});
        write_areas_file(options, input, "", buried.complex, buried.in_complex, &buried, 0.0, false,
                         report);
        report.atoms_outside_groups = plan.outside;
        report.atoms_used = buried.complex.size();
    } else {
        const AtomAreas areas = surface_atom_areas(structure.atoms, options.surface, nullptr);
        report.times.push_back({"areas", ms_since(t), false});
        write_areas_file(options, input, "", structure.atoms, areas, nullptr, 0.0, false, report);
        report.atoms_used = structure.atoms.size();
    }
    report.version = version();
    report.input = input;
    report.surface = options.surface.surface;
    report.model = structure.info.model;
    report.info = structure.info;
    report.total_ms = ms_since(start) + parse_ms;
    if (options.json)
        put_noting_errors(areas_only_json(report) + "\n", stdout);
    else if (!options.quiet)
        put_noting_errors(areas_only_text(report), stdout);
    flush_noting_errors(stdout);
    return kExitOk;
}
// The PNG files of one input: OUTPUT's views with -o FILE.png, else --image's (none without).
std::vector<std::string> picture_paths(const CliOptions& options, const std::string& output,
                                       const std::string& image) {
    if (options.image_output) return view_paths(output, options.views);
    if (image.empty()) return {};
    return view_paths(image, options.views);
}

// Checks every file a run for `input` will write, before any work; two of them that reach one
// file (by any spelling or link) would overwrite each other: Error(InvalidArgument).
void check_outputs(const CliOptions& options, const std::string& output,
                   const std::string& image) {
    std::vector<std::pair<const char*, std::string>> files;  // option, path
    if (!options.image_output) {
        check_output(output, options.output_format);
        if (output != kStdio) files.emplace_back("-o", output);
    }
    for (const std::string& path : picture_paths(options, output, image)) {
        if (path == kStdio) continue;
        check_path(path);
        files.emplace_back(options.image_output ? "-o" : "--image", path);
    }
    if (!options.areas.empty()) files.emplace_back("--areas", options.areas);
    // Files written through (/dev/null twice, say) are not replaced: any number may share one.
    std::vector<std::string> ids;
    for (const auto& file : files) ids.push_back(output_identity(file.second));
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (written_through(ids[i])) continue;
        for (std::size_t j = i + 1; j < files.size(); ++j) {
            if (ids[i] != ids[j]) continue;
            throw Error(ErrorCode::InvalidArgument,
                        std::string(files[i].first) + " '" + files[i].second + "' and " +
                            files[j].first + " '" + files[j].second +
                            "' name the same file; each would overwrite the other");
        }
    }
}

// Whether -o FILE.png can draw the surface where it was computed (make_device_surface), or
// needs the mesh on the host first: for what only the host does to it. --areas with vdw or
// sas keeps the mesh on the device (the exact areas need none; no mesh is written to split);
// the ses areas come from the mesh, and --buried computes its three surfaces on the host.
bool needs_host_mesh(const CliOptions& options) {
    const PropertyOptions& p = options.surface.properties;
    const bool areas_need_mesh =
        !options.areas.empty() &&
        (options.surface.surface == SurfaceKind::Ses || !options.buried.empty());
    return !options.image_output || options.simplify_requested || options.optimize ||
           !options.patch.empty() || !p.scalars.empty() || p.color == ColorScheme::Coulombic ||
           areas_need_mesh;
}

// A picture rendered and not yet written.
struct Picture {
    std::string path;
    Image image;
};

// Every view of `mesh`, framed alike (the first view finds the mesh's bounding sphere, the
// others reuse it), into `report`; nothing is written here.
std::vector<Picture> render_views(const CliOptions& options, Renderer& renderer,
                                  const DeviceMesh& mesh, const std::vector<std::string>& paths,
                                  RunReport& report, Progress& progress) {
    RenderOptions ro = options.render;
    ro.double_sided = !options.patch.empty();  // a patch is open: its inside shows
    std::vector<Picture> pictures;
    for (std::size_t k = 0; k < options.views.size(); ++k) {
        ro.view = options.views[k];
        RenderResult r = renderer.render(mesh, ro);
        ro.frame = r.frame;
        report.times.insert(report.times.end(), r.times.begin(), r.times.end());
        ImageReport im;
        im.path = paths[k];
        im.view = to_string(ro.view);
        im.rotate = ro.rotate;
        im.width = r.image.width;
        im.height = r.image.height;
        im.pixel_size = r.pixel_size;
        im.supersample = r.supersample;
        report.images.push_back(im);
        pictures.push_back({paths[k], std::move(r.image)});
        progress.stage("render");
    }
    return pictures;
}

// Writes the pictures (each PNG atomically), timed as "png".
void write_pictures(const std::vector<Picture>& pictures, RunReport& report, Progress& progress) {
    const auto t = Clock::now();
    for (const Picture& p : pictures) {
        if (p.path == kStdio) {
            StdoutBuffer buffer;
            std::ostream out(&buffer);
            out.exceptions(std::ios::badbit);
            write_png(p.image, out, kStdoutName);
        } else {
            write_png(p.image, p.path);
        }
    }
    if (!pictures.empty()) {
        report.times.push_back({"png", ms_since(t), false});
        progress.stage("png");
    }
}


// Prints the validation layer's messages; returns how many there were.
std::size_t report_validation(Engine& engine) {
    const std::vector<std::string> messages = engine.take_validation_messages();
    for (const std::string& m : messages) {
        std::fprintf(stderr, "fdmsurf: validation: %s\n", one_line(m).c_str());
    }
    return messages.size();
}

// One structure through an engine that stays up for every input of the run.
// `read`: the structure when it was read already, with its parse time (< 0: report no parse
// stage, for the second and later models of a file read once), else null.
// `before_ms` >= 0: the wall time before this call when parse and init overlapped (the total
// then counts it instead of their sum).
// `renderer`: set when the run writes pictures (`image`: --image's path for this input).
// `areas_plan`: --areas, --relative and --buried as checked against the structure (null: none).
int run_one(const CliOptions& options, Engine& engine, Renderer* renderer, Progress& progress,
            double init_ms, const std::string& input, const std::string& output,
            const std::string& image, const Structure* read = nullptr, double parse_ms = 0.0,
            double before_ms = -1.0, const AreasPlan* areas_plan = nullptr) {
    const auto start = Clock::now();
    RunReport report;
    auto warn = [&report, &progress](const std::string& message) {
        progress.clear();
        print_warning(message);
        report.warnings.push_back(message);
    };
    progress.begin(input);
    check_outputs(options, output, image);
    const std::vector<std::string> picture_files = picture_paths(options, output, image);
    const MeshFormat format =
        options.image_output ? MeshFormat::Auto : check_output(output, options.output_format);
    const bool to_stdout = output == kStdio;
    if (!options.image_output && format != MeshFormat::Ply && format != MeshFormat::Glb &&
        !options.surface.properties.scalars.empty())
        warn(std::string(format == MeshFormat::Obj ? "OBJ" : format == MeshFormat::Stl ? "STL" : "OFF") +
             " has no place for per-vertex atoms or --properties values: '" + output +
             "' is written without them (PLY and GLB keep them all)");
    if (!options.image_output && format == MeshFormat::Stl &&
        options.surface.properties.color != ColorScheme::None)
        warn("STL has no place for colours: '" + output + "' is written without --color's (PLY, "
             "OBJ, OFF and GLB keep them)");

    auto t = Clock::now();
    const Structure structure = read ? *read : std::move(read_input(options, input).front());
    if (!read) parse_ms = ms_since(t);
    if (parse_ms >= 0) report.times.push_back({"parse", parse_ms, false});
    progress.stage("parse");
    for (const std::string& message : structure.info.warnings) warn(message);
    if (init_ms > 0) report.times.push_back({"init", init_ms, false});
    progress.stage("init");

    // --patch: the selection is checked before the surface is computed.
    std::vector<std::uint8_t> patch;
    if (!options.patch.empty()) {
        patch = match_selection(structure.atoms, options.patch, structure.info.model);
        report.patch_atoms = static_cast<std::size_t>(std::count(patch.begin(), patch.end(), 1));
        if (report.patch_atoms == 0)
            throw Error(ErrorCode::EmptySelection,
                        input + ": --patch '" + options.patch + "' matches none of the " +
                            std::to_string(structure.atoms.size()) + " atoms read");
    }

    // --buried: the complex (the atoms of both groups) is the surface written; each group's own
    // surface is computed on the same engine.
    const bool buried = areas_plan != nullptr && !areas_plan->groups.empty();
    BuriedAreas buried_result;
    if (areas_plan != nullptr && areas_plan->wanted && !structure.atoms.has_residues())
        warn(no_residues_warning(input, structure));
    if (buried && areas_plan->outside != 0)
        warn("--buried " + options.buried + ": the " + format_count(areas_plan->outside) +
             " atoms in neither group are left out of the surface and the areas");

    // The report's fields that do not depend on the path taken.
    auto fill_report = [&](const GridInfo& grid) {
        report.patch = options.patch;
        report.color = options.surface.properties.color;
        report.color_rgb = options.surface.properties.rgb;
        for (VertexProperty p : options.surface.properties.scalars)
            report.properties.push_back(to_string(p));
        report.version = version();
        report.input = input;
        report.output = output;
        report.output_format = options.image_output ? "png" : mesh_format_extension(format) + 1;
        report.surface = options.surface.surface;
        report.method = options.surface.method;
        report.model = structure.info.model;
        report.info = structure.info;
        report.atoms_used = structure.atoms.size();
        report.grid = grid;
        report.device = engine.device().name;
    };
    auto print_summary = [&]() {
        // A structure read before this call: its parse time counts in the total all the same.
        report.total_ms =
            ms_since(start) +
            (before_ms >= 0.0 ? before_ms : init_ms + (read && parse_ms > 0 ? parse_ms : 0.0));
        progress.end();
        // With the mesh or picture on standard output, the summary goes to stderr.
        std::FILE* const summary = to_stdout ? stderr : stdout;
        if (options.json) {
            put_noting_errors(json_summary(report) + "\n", summary);
        } else if (!options.quiet) {
            put_noting_errors(text_summary(report), summary);
        }
        flush_noting_errors(summary);
    };
    // Validation messages, shown before a failure they may explain.
    auto show_validation = [&]() {
        if (options.engine.validation) {
            try {
                report_validation(engine);
            } catch (...) {
            }
        }
    };
    // A run the validation layer complained about writes nothing: its output is suspect.
    auto validation_failed = [&]() {
        if (!options.engine.validation) return false;
        const std::size_t count = report_validation(engine);
        if (count == 0) return false;
        print_error("the Vulkan validation layer reported " + std::to_string(count) +
                    " message(s); no output written");
        return true;
    };

    if (!needs_host_mesh(options)) {
        // -o FILE.png: the surface stays on the device where it is drawn.
        DeviceSurfaceResult dev;
        std::vector<Picture> pictures;
        try {
            dev = engine.make_device_surface(structure.atoms, options.surface);
            for (const std::string& message : dev.warnings) warn(message);
            report.times.insert(report.times.end(), dev.times.begin(), dev.times.end());
            pictures = render_views(options, *renderer, dev.mesh, picture_files, report, progress);
        } catch (...) {
            show_validation();
            throw;
        }
        if (validation_failed()) return kExitValidation;
        // The pictures and the areas file appear together or not at all.
        detail::CommitGroup files;
        write_pictures(pictures, report, progress);
        report.mesh_on_host = false;
        report.stats.vertices = dev.mesh.vertex_count();
        report.stats.triangles = dev.mesh.triangle_count();
        if (areas_plan != nullptr && areas_plan->wanted) {
            // vdw or sas (needs_host_mesh): the exact areas; no mesh was written to split.
            t = Clock::now();
            const AtomAreas areas = surface_atom_areas(structure.atoms, options.surface, nullptr);
            report.times.push_back({"areas", ms_since(t), false});
            write_areas_file(options, input, output, structure.atoms, areas, nullptr, 0.0, false,
                             report);
            progress.stage("write-areas");
        }
        files.commit();
        fill_report(dev.grid);
        print_summary();
        return kExitOk;
    }

    SurfaceResult result;
    try {
        if (buried) {
            t = Clock::now();
            buried_result = buried_areas(&engine, structure.atoms, areas_plan->groups,
                                         areas_plan->names, options.surface);
            const double all_ms = ms_since(t);
            result = std::move(buried_result.complex_surface);
            double complex_ms = 0.0;
            for (const StageTime& s : result.times) complex_ms += s.ms;
            // The two groups alone and the areas, as one host-timed stage.
            result.times.push_back({"buried-groups", std::max(0.0, all_ms - complex_ms), false});
        } else {
            result = engine.make_surface(structure.atoms, options.surface);
        }
    } catch (...) {
        // The layer's messages often explain a Vulkan failure: show them before the error.
        if (options.engine.validation) {
            try {
                report_validation(engine);
            } catch (...) {
            }
        }
        throw;
    }
    for (const std::string& message : result.warnings) warn(message);
    report.times.insert(report.times.end(), result.times.begin(), result.times.end());

    // A run the validation layer complained about writes nothing: its output is suspect.
    if (options.engine.validation) {
        if (const std::size_t count = report_validation(engine); count != 0) {
            print_error("the Vulkan validation layer reported " + std::to_string(count) +
                        " message(s); no output written");
            return kExitValidation;
        }
    }

    if (!patch.empty()) {
        t = Clock::now();
        result.mesh = extract_patch(result.mesh, patch);
        report.times.push_back({"patch", ms_since(t), false});
        if (result.mesh.triangle_count() == 0)
            warn("--patch '" + options.patch + "': its " + std::to_string(report.patch_atoms) +
                 " atoms own no whole triangle of the surface (buried, or too few): the patch "
                 "is empty");
    }

    // Simplification and reordering come last, on the mesh as it will be written.
    if (options.simplify_requested) {
        result.mesh = simplify_mesh(result.mesh, options.simplify, &report.simplify);
        report.times.insert(report.times.end(), report.simplify.times.begin(),
                            report.simplify.times.end());
        report.simplified = true;
        report.simplify_options = options.simplify;
        if (!report.simplify.topology_kept) warn(simplify_breakage(report.simplify));
        if (const std::string why = simplify_shortfall(report.simplify, options.simplify.simplifier);
            !why.empty())
            warn(why);
    }
    if (options.optimize) {
        t = Clock::now();
        optimize_mesh(result.mesh);
        report.times.push_back({"optimize", ms_since(t), false});
        report.optimized = true;
    }

    // Areas of the mesh as it will be written (after --patch and --simplify).
    AtomAreas areas;
    if (areas_plan != nullptr && areas_plan->wanted && !buried) {
        t = Clock::now();
        areas = surface_atom_areas(structure.atoms, options.surface, &result.mesh);
        report.times.push_back({"areas", ms_since(t), false});
        progress.stage("areas");
    }

    // The pictures of the mesh as written: uploaded, drawn, kept until the mesh is written.
    std::vector<Picture> pictures;
    if (!picture_files.empty()) {
        try {
            t = Clock::now();
            const DeviceMesh uploaded = engine.upload_mesh(result.mesh);
            report.times.push_back({"upload-mesh", ms_since(t), false});
            pictures = render_views(options, *renderer, uploaded, picture_files, report, progress);
        } catch (...) {
            show_validation();
            throw;
        }
        if (validation_failed()) return kExitValidation;
    }

    // The statistics read the mesh while it is written: on a thread of their own, overlapped.
    auto stats_job = std::async(std::launch::async, [&mesh = result.mesh] {
        const auto t0 = Clock::now();
        MeshStats stats = compute_stats(mesh);
        return std::make_pair(stats, ms_since(t0));
    });
    // The mesh, the pictures and the areas file appear together or not at all (a mesh on
    // standard output goes as it is written).
    detail::CommitGroup files;
    if (!options.image_output) {
        t = Clock::now();
        if (to_stdout) {
            StdoutBuffer buffer;
            std::ostream out(&buffer);
            out.exceptions(std::ios::badbit);
            write_mesh(result.mesh, out, format, kStdoutName);
        } else {
            write_mesh(result.mesh, output, format);
        }
        report.times.push_back({"write", ms_since(t), false});
        progress.stage("write");
        detail::trace("cli: mesh written");
    }
    write_pictures(pictures, report, progress);

    const auto [stats, stats_ms] = stats_job.get();
    detail::trace("cli: statistics");
    report.stats = stats;
    report.times.push_back({"mesh-stats", stats_ms, false});
    report.closed_manifold = report.stats.is_closed_manifold();
    if (areas_plan != nullptr && areas_plan->wanted) {
        if (buried)
            write_areas_file(options, input, output, buried_result.complex,
                             buried_result.in_complex, &buried_result, report.stats.area, true,
                             report);
        else
            write_areas_file(options, input, output, structure.atoms, areas, nullptr,
                             report.stats.area, true, report);
        report.atoms_outside_groups = buried ? areas_plan->outside : 0;
        progress.stage("write-areas");
    }
    files.commit();
    fill_report(result.grid);
    if (buried) report.atoms_used = buried_result.complex.size();
    print_summary();
    return kExitOk;
}

std::string output_of(const CliOptions& options, const std::string& input, int model) {
    return primary_output(options, input, model);
}

// `-o FOLDER/` that does not exist yet is created (not its parents: a typo in a parent folder
// is an error, as for a file).
void make_output_folder(const std::string& output) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!output_is_folder(output) || fs::is_directory(output, ec)) return;
    const fs::path folder = fs::path(output).parent_path();  // "out/" -> "out"
    const fs::path parent = folder.parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
        throw Error(ErrorCode::Io, "cannot create the output folder '" + output + "': '" +
                                       parent.string() + "' does not exist");
    }
    if (!fs::create_directory(folder, ec) && !fs::is_directory(folder)) {
        throw Error(ErrorCode::Io, "cannot create the output folder '" + output +
                                       "': " + (ec ? ec.message() : std::string("it is a file")));
    }
}

// The renderer of a run that writes pictures, its options checked against the device (a size
// above maxImageDimension2D fails here, before any surface is computed).
std::optional<Renderer> make_renderer(const CliOptions& options, Engine& engine) {
    std::optional<Renderer> renderer;
    if (!options.wants_images()) return renderer;
    renderer.emplace(engine);
    renderer->check(options.render);
    return renderer;
}

// --stats json: a line for an input (or a model of it, model > 0) that failed, where its
// summary would have gone, so that the lines stand for every input (JSON Lines). Its output is
// named where one is known: not for the models of a file that could not be read, nor without -o.
void report_failure(const CliOptions& options, const std::string& input, int model,
                    const Error& e) {
    if (!options.json) return;
    const bool named = !options.output.empty() && (model > 0 || !options.all_models);
    const std::string output = named ? output_of(options, input, std::max(model, 1)) : "";
    std::FILE* const stream = options.output == kStdio ? stderr : stdout;
    put_noting_errors(json_failure(version(), input, options.all_models ? model : -1, output, e,
                                   exit_code_for(e)) +
                          "\n",
                      stream);
    flush_noting_errors(stream);
}

// The run of every input; `done` counts the inputs whose summary or failure line is out (for
// run's lines of the others when an error ends it).
int run_inputs(const CliOptions& options, std::size_t& done) {
    detail::trace("cli: start");
    // Option checks that need neither the structure nor the device come first. The warning
    // for a spacing too coarse for the filter comes from the engine, with result.warnings.
    if (!options.output.empty()) {  // --areas without -o writes no mesh
        make_output_folder(options.output);
        if (!options.image.empty()) make_output_folder(options.image);
        for (const std::string& input : options.inputs)
            check_outputs(options, output_of(options, input, 1), image_for(options, input, 1));
    }
    effective_cutoff(options.surface);
    if (!options.patch.empty()) check_selection(options.patch, "--patch");
    if (!options.areas.empty()) check_path(options.areas);  // its extension: with the options
    // Progress on stderr (a terminal, not --quiet): the engine reports its stages to it. Not
    // when --stats json goes to stderr itself (the mesh on standard output): the JSON keeps a
    // line of its own, after any warning's.
    const bool json_on_stderr = options.json && options.output == kStdio;
    Progress progress(!json_on_stderr && progress_wanted(options.quiet));
    EngineOptions engine_options = options.engine;
    engine_options.progress = [&progress](std::string_view stage) { progress.stage(stage); };
    if (options.inputs.size() == 1 && !options.all_models) {
        // --areas without -o: no mesh and no device; the structure alone.
        if (options.output.empty()) {
            const auto t0 = Clock::now();
            const Structure structure =
                std::move(read_input(options, options.inputs.front()).front());
            const double parse_ms = ms_since(t0);
            const AreasPlan areas_plan = plan_areas(options, structure, options.inputs.front());
            const int code = areas_only(options, structure, parse_ms, areas_plan);
            done = 1;
            return code;
        }
        // The structure is read while the device starts; a bad input is reported before any
        // device error, as if it had been read first.
        const auto t = Clock::now();
        auto read_job = std::async(std::launch::async, [&options] {
            const auto t0 = Clock::now();
            Structure s = std::move(read_input(options, options.inputs.front()).front());
            return std::make_pair(std::move(s), ms_since(t0));
        });
        std::optional<Engine> engine;
        std::optional<Renderer> renderer;
        std::exception_ptr engine_error;
        const auto t_init = Clock::now();
        try {
            engine.emplace(engine_options);
            renderer = make_renderer(options, *engine);
        } catch (...) {
            engine_error = std::current_exception();
        }
        const double init_ms = ms_since(t_init);
        const auto [structure, parse_ms] = read_job.get();
        detail::trace("cli: structure read, engine up");
        // --areas, --relative and --buried are checked against the atoms before any surface is
        // computed, and reported before a device error as a bad input is.
        const AreasPlan areas_plan = plan_areas(options, structure, options.inputs.front());
        if (engine_error) {
            renderer.reset();  // before the engine
            std::rethrow_exception(engine_error);
        }
        const int code = run_one(options, *engine, renderer ? &*renderer : nullptr, progress,
                                 init_ms, options.inputs.front(),
                                 output_of(options, options.inputs.front(), 1),
                                 image_for(options, options.inputs.front(), 1), &structure,
                                 parse_ms, ms_since(t), &areas_plan);
        renderer.reset();  // before the engine
        done = 1;
        return code;
    }

    // Several inputs or models: one engine for all, so that its pipelines and FFT plans are
    // made once. The first input is read before the device starts, so that bad input fails
    // fast; a single input that cannot be read fails the run as above.
    std::vector<Structure> first;
    auto t = Clock::now();
    if (options.inputs.size() == 1) first = read_input(options, options.inputs.front());
    const double first_parse_ms = ms_since(t);
    t = Clock::now();
    Engine engine(engine_options);
    std::optional<Renderer> renderer = make_renderer(options, engine);
    double init_ms = ms_since(t);
    // Each input, and each model, is reported on its own; a failed one does not stop the
    // others, and the exit code is that of the first failure.
    int status = kExitOk;
    for (std::size_t i = 0; i < options.inputs.size(); ++i) {
        const std::string& input = options.inputs[i];
        std::vector<Structure> structures;
        double parse_ms = first_parse_ms;
        if (i == 0 && options.inputs.size() == 1) {
            structures = std::move(first);
        } else {
            try {
                t = Clock::now();
                structures = read_input(options, input);
                parse_ms = ms_since(t);
            } catch (const Error& e) {
                progress.end();
                print_error(naming(input, e.what()));
                report_failure(options, input, -1, e);
                if (status == kExitOk) status = exit_code_for(e);
                done = i + 1;
                continue;
            }
        }
        // The models of one file get the largest of their grids: similar sizes, one FFT plan
        // (and one set of compiled kernels) for all instead of one per size.
        CliOptions batch = options;
        if (structures.size() > 1) {
            for (const Structure& s : structures) {
                try {
                    const GridInfo g = plan_surface_grid(s.atoms, options.surface);
                    for (int a = 0; a < 3; ++a)
                        batch.surface.min_grid[a] = std::max(batch.surface.min_grid[a], g.dims[a]);
                } catch (const Error&) {
                    // reported by its own run below
                }
            }
        }
        for (std::size_t k = 0; k < structures.size(); ++k) {
            int code = kExitOk;
            const int model = structures[k].info.model;
            try {
                code = run_one(batch, engine, renderer ? &*renderer : nullptr, progress,
                               init_ms, input, output_of(options, input, model),
                               image_for(options, input, model), &structures[k],
                               k == 0 ? parse_ms : -1.0);
            } catch (const Error& e) {
                progress.end();
                print_error(naming(input, e.what()) +
                            (options.all_models ? " (model " + std::to_string(model) + ")" : ""));
                report_failure(options, input, model, e);
                code = exit_code_for(e);
                // A failed device (lost, out of memory) would fail every later input too.
                if (e.code() == ErrorCode::Vulkan) {
                    print_error(
                        "stopping: the Vulkan device failed; the remaining inputs were "
                        "not processed");
                    done = i + 1;
                    const Error skipped(ErrorCode::Vulkan,
                                        "not processed: the Vulkan device failed on " + input);
                    for (std::size_t j = i + 1; j < options.inputs.size(); ++j) {
                        report_failure(options, options.inputs[j], -1, skipped);
                        done = j + 1;
                    }
                    return status == kExitOk ? code : status;
                }
            }
            init_ms = 0.0;
            if (status == kExitOk) status = code;
        }
        done = i + 1;
    }
    return status;
}

// run_inputs, and with --stats json a failure line for each input left without one when an
// error ends the run (a single input that cannot be read, no device): a line per input.
int run(const CliOptions& options) {
    std::size_t done = 0;
    try {
        return run_inputs(options, done);
    } catch (const Error& e) {
        for (std::size_t i = done; options.json && i < options.inputs.size(); ++i)
            report_failure(options, options.inputs[i], -1, e);
        throw;
    }
}

// A summary that could not be printed (stdout a closed pipe) fails the run, as in coreutils.
int check_stdout(int code) {
    errno = 0;
    const bool flushed = std::fflush(stdout) == 0;
    // The reason of the first failed flush (a summary flushed earlier), else of this one.
    const int error_number = stdout_errno != 0 ? stdout_errno : errno != 0 ? errno : EIO;
    if (flushed && !std::ferror(stdout)) return code;
    if (code == kExitOk) {
        print_error(std::string("cannot write ") + kStdoutName + ": " +
                    std::strerror(error_number));
        return kExitInput;
    }
    return code;
}

int run_command(int argc, char** argv) {
    // Started as `msms` (a symlink): MSMS's command line.
    if (argc >= 1 && std::filesystem::path(argv[0]).filename() == "msms")
        return msms_command(std::vector<std::string>(argv + 1, argv + argc));
    if (argc >= 2 && std::string(argv[1]) == "msms")
        return msms_command(std::vector<std::string>(argv + 2, argv + argc));
    if (argc >= 2 && std::string(argv[1]) == "compare") {
        return compare_command(std::vector<std::string>(argv + 2, argv + argc));
    }
    if (argc >= 2 && std::string(argv[1]) == "prepare")
        return prepare_command(std::vector<std::string>(argv + 2, argv + argc));
    return report_errors([&] {
        const CliOptions options = parse_args(std::vector<std::string>(argv + 1, argv + argc));
        if (options.help) {
            put_noting_errors(usage_text(), stdout);
            return kExitOk;
        }
        if (options.version) {
            put_noting_errors(version_text(), stdout);
            return kExitOk;
        }
        if (options.list_devices) return list_devices_command();
        return run(options);
    });
}

}  // namespace

int main(int argc, char** argv) {
    // Before anything is allocated: glibc reads its tunables at start-up (cli/huge_pages.hpp).
    fdmsurf::cli::restart_with_huge_pages(argv);
    // A closed pipe on stdout is an error to report (EPIPE), not a signal that kills silently.
    std::signal(SIGPIPE, SIG_IGN);
    // So is a file grown past the size limit (ulimit -f): write() fails with EFBIG and the
    // temporary file is removed, rather than the process killed with it left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    // Ctrl-C and SIGTERM: stop at once, remove the output being written (cli/interrupts.hpp).
    install_interrupt_handlers();
    return check_stdout(run_command(argc, argv));
}
