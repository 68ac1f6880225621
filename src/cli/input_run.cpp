// One input's run in the fdmsurf program: the files it writes checked before any work, its
// surface computed on the engine of the run, drawn where it was computed (-o FILE.png alone) or
// brought to the host, cut (--patch), simplified and reordered, its areas, pictures and mesh
// written together or not at all, and its summary printed.
#include "cli/input_run.hpp"

#include <algorithm>
#include <cstdio>
#include <future>
#include <ostream>
#include <utility>

#include "cli/messages.hpp"
#include "cli/output_paths.hpp"
#include "cli/standard_output.hpp"
#include "base/trace.hpp"
#include "io/atomic_file.hpp"

namespace fdmsurf::cli {
namespace {

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


// The PNG files of one input: OUTPUT's views with -o FILE.png, else --image's (none without).
std::vector<std::string> picture_paths(const CliOptions& options, const std::string& output,
                                       const std::string& image) {
    if (options.image_output) return view_paths(output, options.views);
    if (image.empty()) return {};
    return view_paths(image, options.views);
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

// The run of one InputJob, in its steps: the files checked, the structure's stages and
// warnings, the --patch selection, then the surface drawn where it was computed (-o FILE.png
// alone) or brought to the host, finished, drawn and written.
class InputRun {
public:
    explicit InputRun(const InputJob& job) : job_(job), options_(job.options) {}
    int run();

private:
    void warn(const std::string& message);
    void check_files();
    void report_structure();
    void match_patch();
    void warn_areas();
    int run_on_device();
    int run_on_host();
    SurfaceResult compute_surface();
    SurfaceResult buried_surface();
    SurfaceResult surface_at_a_spacing_that_finds_it();
    void finish_mesh(Mesh& mesh);
    AtomAreas mesh_areas(const Mesh& mesh);
    std::vector<Picture> draw_mesh(const Mesh& mesh);
    void write_mesh_file(const Mesh& mesh);
    void write_outputs(const SurfaceResult& result, const AtomAreas& areas,
                       const std::vector<Picture>& pictures);
    bool areas_wanted() const { return job_.areas_plan != nullptr && job_.areas_plan->wanted; }
    void fill_report(const GridInfo& grid);
    void print_summary();
    void show_validation();
    bool validation_failed();

    const InputJob& job_;
    const CliOptions& options_;
    const Clock::time_point start_ = Clock::now();
    RunReport report_;
    std::vector<std::string> picture_files_;
    MeshFormat format_ = MeshFormat::Auto;
    bool to_stdout_ = false;
    std::vector<std::uint8_t> patch_;  // --patch: 1 per atom selected
    // --buried: the complex (the atoms of both groups) is the surface written; each group's own
    // surface is computed on the same engine.
    bool buried_ = false;
    bool exact_fallback_ = false;  // the exact SES computed for atoms too small for fdm
    BuriedAreas buried_result_;
};

int InputRun::run() {
    job_.progress.begin(job_.input);
    check_files();
    report_structure();
    match_patch();
    warn_areas();
    if (!needs_host_mesh(options_)) return run_on_device();
    return run_on_host();
}

void InputRun::warn(const std::string& message) {
    job_.progress.clear();
    print_warning(message);
    report_.warnings.push_back(message);
}

// The files this input writes, before any work, and the warnings for what OUTPUT's format
// cannot hold.
void InputRun::check_files() {
    const std::string& output = job_.output;
    check_outputs(options_, output, job_.image);
    picture_files_ = picture_paths(options_, output, job_.image);
    format_ = options_.image_output ? MeshFormat::Auto : check_output(output, options_.output_format);
    to_stdout_ = output == kStdio;
    if (!options_.image_output && format_ != MeshFormat::Ply && format_ != MeshFormat::Glb &&
        !options_.surface.properties.scalars.empty())
        warn(std::string(format_ == MeshFormat::Obj   ? "OBJ"
                         : format_ == MeshFormat::Stl ? "STL"
                                                      : "OFF") +
             " has no place for per-vertex atoms or --properties values: '" + output +
             "' is written without them (PLY and GLB keep them all)");
    if (!options_.image_output && format_ == MeshFormat::Stl &&
        options_.surface.properties.color != ColorScheme::None)
        warn("STL has no place for colours: '" + output + "' is written without --color's (PLY, "
             "OBJ, OFF and GLB keep them)");
}

// The parse and init stages (read and started before this run) and the reader's warnings.
void InputRun::report_structure() {
    if (job_.parse_ms >= 0) report_.times.push_back({"parse", job_.parse_ms, false});
    job_.progress.stage("parse");
    for (const std::string& message : job_.structure.info.warnings) warn(message);
    if (job_.init_ms > 0) report_.times.push_back({"init", job_.init_ms, false});
    job_.progress.stage("init");
}

// --patch: the selection is checked before the surface is computed.
void InputRun::match_patch() {
    if (options_.patch.empty()) return;
    const Structure& structure = job_.structure;
    patch_ = match_selection(structure.atoms, options_.patch, structure.info.model);
    report_.patch_atoms = static_cast<std::size_t>(std::count(patch_.begin(), patch_.end(), 1));
    if (report_.patch_atoms == 0)
        throw Error(ErrorCode::EmptySelection,
                    job_.input + ": --patch '" + options_.patch + "' matches none of the " +
                        std::to_string(structure.atoms.size()) + " atoms read");
}

// --areas on a structure without residues, and --buried's atoms in neither group.
void InputRun::warn_areas() {
    const AreasPlan* plan = job_.areas_plan;
    buried_ = plan != nullptr && !plan->groups.empty();
    if (areas_wanted() && !job_.structure.atoms.has_residues())
        warn(no_residues_warning(job_.input, job_.structure));
    if (buried_ && plan->outside != 0)
        warn("--buried " + options_.buried + ": the " + format_count(plan->outside) +
             " atoms in neither group are left out of the surface and the areas");
}

// -o FILE.png: the surface stays on the device where it is drawn.
int InputRun::run_on_device() {
    const Atoms& atoms = job_.structure.atoms;
    DeviceSurfaceResult dev;
    std::vector<Picture> pictures;
    try {
        dev = job_.engine.make_device_surface(atoms, options_.surface);
        for (const std::string& message : dev.warnings) warn(message);
        report_.times.insert(report_.times.end(), dev.times.begin(), dev.times.end());
        pictures = render_views(options_, *job_.renderer, dev.mesh, picture_files_, report_,
                                job_.progress);
    } catch (...) {
        show_validation();
        throw;
    }
    if (validation_failed()) return kExitValidation;
    // The pictures and the areas file appear together or not at all.
    detail::CommitGroup files;
    write_pictures(pictures, report_, job_.progress);
    report_.mesh_on_host = false;
    report_.stats.vertices = dev.mesh.vertex_count();
    report_.stats.triangles = dev.mesh.triangle_count();
    if (areas_wanted()) {
        // vdw or sas (needs_host_mesh): the exact areas; no mesh was written to split.
        const auto t = Clock::now();
        const AtomAreas areas = surface_atom_areas(atoms, options_.surface, nullptr);
        report_.times.push_back({"areas", ms_since(t), false});
        write_areas_file(options_, job_.input, job_.output, atoms, areas, nullptr, 0.0, false,
                         report_);
        job_.progress.stage("write-areas");
    }
    files.commit();
    fill_report(dev.grid);
    print_summary();
    return kExitOk;
}

// The mesh brought to the host: finished as asked, its areas, its pictures, all written.
int InputRun::run_on_host() {
    SurfaceResult result = compute_surface();
    // A run the validation layer complained about writes nothing: its output is suspect.
    if (validation_failed()) return kExitValidation;
    finish_mesh(result.mesh);
    // Areas of the mesh as it will be written (after --patch and --simplify).
    const AtomAreas areas = mesh_areas(result.mesh);
    // The pictures of the mesh as written: uploaded, drawn, kept until the mesh is written.
    std::vector<Picture> pictures;
    if (!picture_files_.empty()) {
        pictures = draw_mesh(result.mesh);
        if (validation_failed()) return kExitValidation;
    }
    write_outputs(result, areas, pictures);
    return kExitOk;
}

// The surface (of the complex, with --buried), its warnings and stage times.
SurfaceResult InputRun::compute_surface() {
    SurfaceResult result;
    try {
        if (buried_)
            result = buried_surface();
        else
            result = surface_at_a_spacing_that_finds_it();
    } catch (...) {
        show_validation();
        throw;
    }
    for (const std::string& message : result.warnings) warn(message);
    report_.times.insert(report_.times.end(), result.times.begin(), result.times.end());
    return result;
}

// The surface as asked, or, when no grid point lies inside it at the default spacing and none
// was given (ions and coarse-grained beads written with tiny radii), at the spacing that puts
// four grid points across the largest sphere: for the SES, as the exact SES (the FDM filter,
// whose length is the probe's, smooths atoms this small away at any spacing). A warning says so.
SurfaceResult InputRun::surface_at_a_spacing_that_finds_it() {
    const Atoms& atoms = job_.structure.atoms;
    // The statistics from the engine, with the cavity removal's pieces, when the mesh is written
    // as the engine gives it (no --patch, --simplify or --optimize after).
    SurfaceOptions surface = options_.surface;
    surface.mesh_stats = patch_.empty() && !options_.simplify_requested && !options_.optimize;
    SurfaceResult result = job_.engine.make_surface(atoms, surface);
    if (options_.explicit_spacing || result.mesh.triangle_count() > 0 || atoms.size() == 0 ||
        options_.surface.level > 0.0f)
        return result;
    const float add = options_.surface.surface == SurfaceKind::Sas ? options_.surface.probe : 0.0f;
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r + add);
    SurfaceOptions finer = surface;
    finer.spacing = std::clamp(r_max / 2.0f, 0.05f, options_.surface.spacing);
    const bool exact = finer.surface == SurfaceKind::Ses && finer.method == SesMethod::Fdm;
    if (exact) finer.method = SesMethod::Edt;
    if (!exact && !(finer.spacing < options_.surface.spacing)) return result;
    SurfaceResult retried = job_.engine.make_surface(atoms, finer);
    if (retried.mesh.triangle_count() == 0) return result;
    exact_fallback_ = exact;
    char note[320];
    std::snprintf(note, sizeof note,
                  "no grid point lay inside the surface of atoms of radius %.3g Å at most "
                  "(default spacing %.3g Å); computed at spacing %.3g Å%s (--spacing and "
                  "--method set them)",
                  double(r_max), double(options_.surface.spacing), double(finer.spacing),
                  exact ? " as the exact SES, --method edt, since the FDM filter smooths atoms "
                          "this small away"
                        : "");
    retried.warnings.insert(retried.warnings.begin(), note);
    return retried;
}

// --buried: the complex's surface, the two groups' own and the areas, on the same engine.
SurfaceResult InputRun::buried_surface() {
    const AreasPlan& plan = *job_.areas_plan;
    const auto t = Clock::now();
    buried_result_ = buried_areas(&job_.engine, job_.structure.atoms, plan.groups, plan.names,
                                  options_.surface);
    const double all_ms = ms_since(t);
    SurfaceResult result = std::move(buried_result_.complex_surface);
    double complex_ms = 0.0;
    for (const StageTime& s : result.times) complex_ms += s.ms;
    // The two groups alone and the areas, as one host-timed stage.
    result.times.push_back({"buried-groups", std::max(0.0, all_ms - complex_ms), false});
    return result;
}

// --patch, then simplification and reordering, which come last, on the mesh as it will be
// written.
void InputRun::finish_mesh(Mesh& mesh) {
    if (!patch_.empty()) {
        const auto t = Clock::now();
        mesh = extract_patch(mesh, patch_);
        report_.times.push_back({"patch", ms_since(t), false});
        if (mesh.triangle_count() == 0)
            warn("--patch '" + options_.patch + "': its " + std::to_string(report_.patch_atoms) +
                 " atoms own no whole triangle of the surface (buried, or too few): the patch "
                 "is empty");
    }
    if (options_.simplify_requested) {
        mesh = simplify_mesh(mesh, options_.simplify, &report_.simplify);
        report_.times.insert(report_.times.end(), report_.simplify.times.begin(),
                             report_.simplify.times.end());
        report_.simplified = true;
        report_.simplify_options = options_.simplify;
        if (!report_.simplify.topology_kept) warn(simplify_breakage(report_.simplify));
        if (const std::string why =
                simplify_shortfall(report_.simplify, options_.simplify.simplifier);
            !why.empty())
            warn(why);
    }
    if (options_.optimize) {
        const auto t = Clock::now();
        optimize_mesh(mesh);
        report_.times.push_back({"optimize", ms_since(t), false});
        report_.optimized = true;
    }
}

// The per-atom areas split from the mesh (none without --areas; --buried has its own).
AtomAreas InputRun::mesh_areas(const Mesh& mesh) {
    AtomAreas areas;
    if (areas_wanted() && !buried_) {
        const auto t = Clock::now();
        areas = surface_atom_areas(job_.structure.atoms, options_.surface, &mesh);
        report_.times.push_back({"areas", ms_since(t), false});
        job_.progress.stage("areas");
    }
    return areas;
}

// The mesh uploaded and drawn in every view.
std::vector<Picture> InputRun::draw_mesh(const Mesh& mesh) {
    try {
        const auto t = Clock::now();
        const DeviceMesh uploaded = job_.engine.upload_mesh(mesh);
        report_.times.push_back({"upload-mesh", ms_since(t), false});
        return render_views(options_, *job_.renderer, uploaded, picture_files_, report_,
                            job_.progress);
    } catch (...) {
        show_validation();
        throw;
    }
}

void InputRun::write_mesh_file(const Mesh& mesh) {
    const auto t = Clock::now();
    if (to_stdout_) {
        StdoutBuffer buffer;
        std::ostream out(&buffer);
        out.exceptions(std::ios::badbit);
        write_mesh(mesh, out, format_, kStdoutName);
    } else {
        write_mesh(mesh, job_.output, format_);
    }
    report_.times.push_back({"write", ms_since(t), false});
    job_.progress.stage("write");
    detail::trace("cli: mesh written");
}

// The mesh, the pictures and the areas file, then the summary.
void InputRun::write_outputs(const SurfaceResult& result, const AtomAreas& areas,
                             const std::vector<Picture>& pictures) {
    // The statistics, unless the engine gave them (SurfaceOptions::mesh_stats, asked for only
    // when the mesh is written as it came), read the mesh while it is written: on a thread of
    // their own, overlapped.
    std::future<std::pair<MeshStats, double>> stats_job;
    if (!result.stats)
        stats_job = std::async(std::launch::async, [&mesh = result.mesh] {
            const auto t0 = Clock::now();
            MeshStats stats = compute_stats(mesh);
            return std::make_pair(stats, ms_since(t0));
        });
    // The mesh, the pictures and the areas file appear together or not at all (a mesh on
    // standard output goes as it is written).
    detail::CommitGroup files;
    if (!options_.image_output) write_mesh_file(result.mesh);
    write_pictures(pictures, report_, job_.progress);

    if (result.stats) {
        report_.stats = *result.stats;
    } else {
        const auto [stats, stats_ms] = stats_job.get();
        detail::trace("cli: statistics");
        report_.stats = stats;
        report_.times.push_back({"mesh-stats", stats_ms, false});
    }
    report_.closed_manifold = report_.stats.is_closed_manifold();
    if (job_.model_row != nullptr) add_mesh(*job_.model_row, result.mesh, report_.stats);
    if (areas_wanted()) {
        const Atoms& atoms = job_.structure.atoms;
        if (buried_)
            write_areas_file(options_, job_.input, job_.output, buried_result_.complex,
                             buried_result_.in_complex, &buried_result_, report_.stats.area,
                             true, report_);
        else
            write_areas_file(options_, job_.input, job_.output, atoms, areas, nullptr,
                             report_.stats.area, true, report_);
        report_.atoms_outside_groups = buried_ ? job_.areas_plan->outside : 0;
        job_.progress.stage("write-areas");
    }
    files.commit();
    fill_report(result.grid);
    if (buried_) report_.atoms_used = buried_result_.complex.size();
    print_summary();
}

// The report's fields that do not depend on the path taken.
void InputRun::fill_report(const GridInfo& grid) {
    const PropertyOptions& properties = options_.surface.properties;
    const Structure& structure = job_.structure;
    report_.patch = options_.patch;
    report_.color = properties.color;
    report_.color_rgb = properties.rgb;
    for (VertexProperty p : properties.scalars) report_.properties.push_back(to_string(p));
    report_.version = version();
    report_.input = job_.input;
    report_.output = job_.output;
    report_.output_format =
        options_.image_output ? "png" : mesh_format_extension(format_) + 1;
    report_.surface = options_.surface.surface;
    report_.method = exact_fallback_ ? SesMethod::Edt : options_.surface.method;
    report_.model = structure.info.model;
    report_.info = structure.info;
    report_.atoms_used = structure.atoms.size();
    report_.grid = grid;
    report_.device = job_.engine.device().name;
}

void InputRun::print_summary() {
    // A structure read before this run: its parse time counts in the total all the same.
    report_.total_ms =
        ms_since(start_) + (job_.before_ms >= 0.0
                                ? job_.before_ms
                                : job_.init_ms + (job_.parse_ms > 0 ? job_.parse_ms : 0.0));
    job_.progress.end();
    // With the mesh or picture on standard output, the summary goes to stderr.
    std::FILE* const summary = to_stdout_ ? stderr : stdout;
    if (options_.json) {
        put_noting_errors(json_summary(report_) + "\n", summary);
    } else if (!options_.quiet) {
        put_noting_errors(text_summary(report_), summary);
    }
    flush_noting_errors(summary);
}

// Validation messages, shown before a failure they may explain (the layer's messages often
// explain a Vulkan failure).
void InputRun::show_validation() {
    if (options_.engine.validation) {
        try {
            report_validation(job_.engine);
        } catch (...) {
        }
    }
}

// A run the validation layer complained about writes nothing: its output is suspect.
bool InputRun::validation_failed() {
    if (!options_.engine.validation) return false;
    const std::size_t count = report_validation(job_.engine);
    if (count == 0) return false;
    print_error("the Vulkan validation layer reported " + std::to_string(count) +
                " message(s); no output written");
    return true;
}

}  // namespace

// That a file can be created at `output` (output_path_problem), else Error(Io).
void check_path(const std::string& output) {
    const std::string problem = output_path_problem(output);
    if (!problem.empty()) throw Error(ErrorCode::Io, problem);
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

int run_one(const InputJob& job) {
    InputRun run(job);
    return run.run();
}

}  // namespace fdmsurf::cli
