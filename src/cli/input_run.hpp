// One input's run in the fdmsurf program (input_run.cpp, input_areas.cpp): the job that
// describes it, its output files checked before any work, what --areas needs from its
// structure, and the run itself: the surface computed, drawn and written with its summary.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cli/models_table.hpp"
#include "cli/options.hpp"
#include "cli/progress.hpp"
#include "cli/summary.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace fdmsurf::cli {

using Clock = std::chrono::steady_clock;

// Milliseconds since `start`.
inline double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What --areas, --relative and --buried need from the structure, checked before any device
// work: residues for --relative, the two groups of --buried (exit 2 with the reason).
struct AreasPlan {
    bool wanted = false;
    std::vector<std::uint8_t> groups;  // --buried: 1 or 2 per atom, 0 in neither
    std::array<std::string, 2> names;
    std::size_t outside = 0;  // atoms in neither group
};

// One structure's job (a model of a file read once, with --models all), run on an engine that
// stays up for every input of the run.
struct InputJob {
    const CliOptions& options;  // the run's (the grid raised to the largest of a file's models)
    Engine& engine;
    Renderer* renderer;  // set when the run writes pictures
    Progress& progress;
    std::string input;   // as given; "-": standard input
    std::string output;  // the mesh or picture written for it (primary_output)
    std::string image;   // --image's PNG for it (image_for); empty without --image
    const Structure& structure;
    double parse_ms;  // its parse time; < 0: no parse stage (the second and later models)
    double init_ms;   // the engine's start-up, reported with the first structure (0: none)
    // >= 0: the wall time before run_one when parse and init overlapped (the total then counts
    // it instead of their sum).
    double before_ms;
    const AreasPlan* areas_plan;  // --areas, --relative and --buried as checked (null: none)
    // --models all --areas: the model's row of the table, whose mesh fields the run fills
    // (null: no table).
    ModelRow* model_row = nullptr;
};

// The surface of the job's structure: computed, cut (--patch), simplified and reordered as
// asked, drawn, written with the pictures and the areas file (all of them or none), and its
// summary printed. Returns the exit code (kExitValidation when the validation layer spoke);
// throws Error for everything else.
int run_one(const InputJob& job);

// That a file can be created at `output` (output_path_problem), else Error(Io).
void check_path(const std::string& output);
// Checks every file a run for an input will write (`output`, and `image` with --image),
// before any work; two of them that reach one file (by any spelling or link) would overwrite
// each other: Error(InvalidArgument).
void check_outputs(const CliOptions& options, const std::string& output,
                   const std::string& image);

// --areas, --relative and --buried checked against `structure` (read from `input`); throws
// Error(InvalidArgument) with the reason. Nothing wanted without --areas.
AreasPlan plan_areas(const CliOptions& options, const Structure& structure,
                     const std::string& input);
// --areas with no -o: the exact vdw or sas areas, no mesh and no device; the summary printed.
int areas_only(const CliOptions& options, const Structure& structure, double parse_ms,
               const AreasPlan& plan);
// The --areas file and the report's lines for it (`buried`: --buried's areas, else null;
// `mesh_area` and `has_mesh`: the mesh's, when there is one).
void write_areas_file(const CliOptions& options, const std::string& input,
                      const std::string& output, const Atoms& atoms, const AtomAreas& areas,
                      const BuriedAreas* buried, double mesh_area, bool has_mesh,
                      RunReport& report);
// The warning for --areas on a structure without residues (XYZR, or XYZRN whose names are not
// MSMS's): per-atom and total areas only.
std::string no_residues_warning(const std::string& input, const Structure& structure);

}  // namespace fdmsurf::cli
