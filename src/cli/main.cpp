// The fdmsurf program: a structure file in, its molecular-surface mesh out (see --help). Here
// the commands are told apart and the inputs of a run are read and handed, one structure at a
// time, to run_one (input_run.cpp) on one engine.
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <future>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "cli/compare_command.hpp"
#include "cli/huge_pages.hpp"
#include "cli/input_run.hpp"
#include "cli/interrupts.hpp"
#include "cli/messages.hpp"
#include "cli/models_table.hpp"
#include "cli/msms_command.hpp"
#include "cli/options.hpp"
#include "cli/prepare_command.hpp"
#include "cli/progress.hpp"
#include "cli/standard_output.hpp"
#include "cli/summary.hpp"
#include "cli/usage.hpp"
#include "cli/version.hpp"
#include "base/trace.hpp"
#include "io/atomic_file.hpp"
#include "vulkan/context.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

using namespace fdmsurf;
using namespace fdmsurf::cli;

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

// Option checks that need neither the structure nor the device come first. The warning for a
// spacing too coarse for the filter comes from the engine, with result.warnings.
void check_before_work(const CliOptions& options) {
    if (!options.output.empty()) {  // --areas without -o writes no mesh
        make_output_folder(options.output);
        if (!options.image.empty()) make_output_folder(options.image);
        for (const std::string& input : options.inputs)
            check_outputs(options, output_of(options, input, 1), image_for(options, input, 1));
    }
    effective_cutoff(options.surface);
    if (!options.patch.empty()) check_selection(options.patch, "--patch");
    if (!options.areas.empty()) check_path(options.areas);  // its extension: with the options
}

// --areas without -o: no mesh and no device; the structure alone.
int run_areas_only(const CliOptions& options) {
    const auto t0 = Clock::now();
    const Structure structure = std::move(read_input(options, options.inputs.front()).front());
    const double parse_ms = ms_since(t0);
    const AreasPlan areas_plan = plan_areas(options, structure, options.inputs.front());
    return areas_only(options, structure, parse_ms, areas_plan);
}

// One input, one model. The structure is read while the device starts; a bad input is
// reported before any device error, as if it had been read first.
int run_single(const CliOptions& options, const EngineOptions& engine_options,
               Progress& progress) {
    const std::string& input = options.inputs.front();
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
    const AreasPlan areas_plan = plan_areas(options, structure, input);
    if (engine_error) {
        renderer.reset();  // before the engine
        std::rethrow_exception(engine_error);
    }
    const int code = run_one({.options = options,
                              .engine = *engine,
                              .renderer = renderer ? &*renderer : nullptr,
                              .progress = progress,
                              .input = input,
                              .output = output_of(options, input, 1),
                              .image = image_for(options, input, 1),
                              .structure = structure,
                              .parse_ms = parse_ms,
                              .init_ms = init_ms,
                              .before_ms = ms_since(t),
                              .areas_plan = &areas_plan});
    renderer.reset();  // before the engine
    return code;
}

// The structures of input `i` of a batch into `structures`, with their parse time; false when
// it cannot be read (reported, its exit code kept in `status` when the first failure).
bool read_batch_input(const CliOptions& options, const std::string& input, Progress& progress,
                      std::vector<Structure>& structures, double& parse_ms, int& status) {
    try {
        const auto t = Clock::now();
        structures = read_input(options, input);
        parse_ms = ms_since(t);
        return true;
    } catch (const Error& e) {
        progress.end();
        print_error(naming(input, e.what()));
        report_failure(options, input, -1, e);
        if (status == kExitOk) status = exit_code_for(e);
        return false;
    }
}

// The models of one file get the largest of their grids: similar sizes, one FFT plan (and one
// set of compiled kernels) for all instead of one per size.
CliOptions batch_options(const CliOptions& options, const std::vector<Structure>& structures) {
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
    return batch;
}

// A failed device (lost, out of memory) would fail every later input too: the inputs after
// input `i` get a failure line each, and `done` counts them.
void stop_after_device_failure(const CliOptions& options, std::size_t i, std::size_t& done) {
    print_error(
        "stopping: the Vulkan device failed; the remaining inputs were "
        "not processed");
    done = i + 1;
    const Error skipped(ErrorCode::Vulkan,
                        "not processed: the Vulkan device failed on " + options.inputs[i]);
    for (std::size_t j = i + 1; j < options.inputs.size(); ++j) {
        report_failure(options, options.inputs[j], -1, skipped);
        done = j + 1;
    }
}

// Several inputs or models: one engine for all, so that its pipelines and FFT plans are made
// once. The first input is read before the device starts, so that bad input fails fast; a
// single input that cannot be read fails the run as above. Each input, and each model, is
// reported on its own; a failed one does not stop the others (but a failed device does), and
// the exit code is that of the first failure.
int run_batch(const CliOptions& options, const EngineOptions& engine_options, Progress& progress,
              std::size_t& done) {
    const bool table = options.all_models && !options.areas.empty();
    std::vector<ModelRow> rows;
    std::vector<Structure> first;
    auto t = Clock::now();
    if (options.inputs.size() == 1) first = read_input(options, options.inputs.front());
    const double first_parse_ms = ms_since(t);
    t = Clock::now();
    Engine engine(engine_options);
    std::optional<Renderer> renderer = make_renderer(options, engine);
    double init_ms = ms_since(t);
    int status = kExitOk;
    for (std::size_t i = 0; i < options.inputs.size(); ++i) {
        const std::string& input = options.inputs[i];
        std::vector<Structure> structures;
        double parse_ms = first_parse_ms;
        if (i == 0 && options.inputs.size() == 1) {
            structures = std::move(first);
        } else if (!read_batch_input(options, input, progress, structures, parse_ms, status)) {
            done = i + 1;
            continue;
        }
        const CliOptions batch = batch_options(options, structures);
        for (std::size_t k = 0; k < structures.size(); ++k) {
            int code = kExitOk;
            const int model = structures[k].info.model;
            ModelRow* row = nullptr;
            if (table) {
                rows.push_back({.model = model});
                row = &rows.back();
            }
            try {
                if (row != nullptr) add_sasa(*row, structures[k], options.surface.probe);
                code = run_one({.options = batch,
                                .engine = engine,
                                .renderer = renderer ? &*renderer : nullptr,
                                .progress = progress,
                                .input = input,
                                .output = output_of(options, input, model),
                                .image = image_for(options, input, model),
                                .structure = structures[k],
                                .parse_ms = k == 0 ? parse_ms : -1.0,
                                .init_ms = init_ms,
                                .before_ms = -1.0,
                                .areas_plan = nullptr,
                                .model_row = row});
            } catch (const Error& e) {
                if (row != nullptr) {
                    row->ok = false;
                    row->error = one_line(e.what());
                }
                progress.end();
                print_error(naming(input, e.what()) +
                            (options.all_models ? " (model " + std::to_string(model) + ")" : ""));
                report_failure(options, input, model, e);
                code = exit_code_for(e);
                if (e.code() == ErrorCode::Vulkan) {
                    stop_after_device_failure(options, i, done);
                    if (table) write_models_table(rows, options.areas);
                    return status == kExitOk ? code : status;
                }
            }
            init_ms = 0.0;
            if (status == kExitOk) status = code;
        }
        done = i + 1;
    }
    if (table) write_models_table(rows, options.areas);
    return status;
}

// --models all --areas without -o: the table of every model's exact SASA, no mesh and no
// device; with --stats json its rows also go to standard output.
int run_models_areas_only(const CliOptions& options) {
    const std::vector<Structure> structures = read_input(options, options.inputs.front());
    std::vector<ModelRow> rows;
    for (const Structure& s : structures) {
        rows.push_back({.model = s.info.model});
        add_sasa(rows.back(), s, options.surface.probe);
    }
    write_models_table(rows, options.areas);
    if (options.json) {
        std::string lines;
        for (const ModelRow& r : rows) lines += model_row_json(r) + "\n";
        put_noting_errors(lines, stdout);
    } else if (!options.quiet) {
        std::string text;
        for (const ModelRow& r : rows) {
            char sasa[64];
            std::snprintf(sasa, sizeof sasa, "%.1f", r.sasa);
            text += "model " + std::to_string(r.model) + ": " + std::to_string(r.atoms) +
                    " atoms, SASA " + sasa + " Å²\n";
        }
        put_noting_errors(text + "table of " + std::to_string(rows.size()) + " models: " +
                              options.areas + "\n",
                          stdout);
    }
    return kExitOk;
}

// The run of every input; `done` counts the inputs whose summary or failure line is out (for
// run's lines of the others when an error ends it).
int run_inputs(const CliOptions& options, std::size_t& done) {
    detail::trace("cli: start");
    check_before_work(options);
    // Progress on stderr (a terminal, not --quiet): the engine reports its stages to it. Not
    // when --stats json goes to stderr itself (the mesh on standard output): the JSON keeps a
    // line of its own, after any warning's.
    const bool json_on_stderr = options.json && options.output == kStdio;
    Progress progress(!json_on_stderr && progress_wanted(options.quiet));
    EngineOptions engine_options = options.engine;
    engine_options.progress = [&progress](std::string_view stage) { progress.stage(stage); };
    if (options.all_models && !options.areas.empty() && options.output.empty()) {
        done = 1;
        return run_models_areas_only(options);
    }
    if (options.inputs.size() == 1 && !options.all_models) {
        const int code = options.output.empty() ? run_areas_only(options)
                                                : run_single(options, engine_options, progress);
        done = 1;
        return code;
    }
    return run_batch(options, engine_options, progress, done);
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
