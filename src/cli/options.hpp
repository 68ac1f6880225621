// Command-line options of the fdmsurf program: parsed into the library's option structs.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/render.hpp"
#include "fdmsurf/simplify.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf::cli {

struct CliOptions {
    std::vector<std::string> inputs;  // exactly one unless help, version or list_devices;
                                      // "-": standard input (at most once)
    std::string output;               // "-": the mesh to standard output (one input)
    fdmsurf::MeshFormat output_format = fdmsurf::MeshFormat::Auto;  // --output-format
    fdmsurf::ReadOptions read;
    fdmsurf::SurfaceOptions surface;
    fdmsurf::EngineOptions engine;
    bool list_devices = false;
    bool quiet = false;  // no text summary; warnings still go to stderr
    bool json = false;   // --stats json: the summary as one JSON object on stdout (stderr with
                         // -o -)
    bool help = false;
    bool version = false;
    bool paper = false;  // --paper: the paper's settings where not given explicitly
    bool explicit_filter = false, explicit_level = false, explicit_cavities = false;
    bool explicit_spacing = false;  // --spacing given: no finer spacing for an empty surface
    bool all_models = false;  // --models all: one mesh per model (read.model = kAllModels)
    std::string patch;        // --patch EXPR: keep the triangles on the atoms EXPR selects
    // --simplify RATIO and --max-triangles N (both: the smaller target); `simplify_requested`
    // when either was given.
    fdmsurf::SimplifyOptions simplify;
    bool simplify_requested = false;
    bool simplifier_given = false;  // --simplifier: only with --simplify or --max-triangles
    bool optimize = false;  // --optimize: vertex-cache and vertex-fetch order
    // --areas FILE (.csv or .json): areas per atom, per residue and in total; with no -o, the
    // areas alone (vdw and sas: exact, no mesh, no device).
    std::string areas;
    fdmsurf::RelativeTable relative = fdmsurf::RelativeTable::None;  // --relative TABLE
    std::string buried;  // --buried GROUP1:GROUP2: the buried interface area
    // Pictures (src/render/, docs/rendering.md). `image_output`: OUTPUT is a PNG (its
    // extension, or --output-format png), the picture alone; `image`: --image FILE.png or
    // FOLDER/, a picture beside the mesh. `render` holds --image-size, --rotate,
    // --background, --outline, --occlusion, --depth-cue; `views` --view/--views (one PNG each).
    bool image_output = false;
    std::string image;
    fdmsurf::RenderOptions render;
    std::vector<fdmsurf::View> views{fdmsurf::View::Front};
    std::string render_options_given;  // the last picture option given (for its error)
    bool wants_images() const { return image_output || !image.empty(); }
};

// Parses the arguments after the program name. `--name value` and `--name=value` are both
// accepted; `--` ends the options. Throws Error(InvalidArgument) naming the offending option.
// With --help, --version or --list-devices no INPUT or -o is required; with --areas no -o. Several
// INPUTs need -o to name a folder, and so does --models all.
CliOptions parse_args(const std::vector<std::string>& args);

// The INPUT and OUTPUT that stand for standard input and standard output.
inline constexpr const char* kStdio = "-";

// True when OUTPUT names a folder (ends in '/' or exists as one): one mesh per input goes there.
// Never for "-".
bool output_is_folder(const std::string& output);
// The mesh path for `input`: OUTPUT itself, or OUTPUT/<input name>.ply for a folder (.glb, ...
// with another `format`; "stdin" is the name of input "-").
std::string output_for(const std::string& input, const std::string& output,
                       fdmsurf::MeshFormat format = fdmsurf::MeshFormat::Auto);
// With --models all: OUTPUT/<input name>-m<model>.ply (OUTPUT must be a folder).
std::string output_for(const std::string& input, const std::string& output, int model,
                       fdmsurf::MeshFormat format = fdmsurf::MeshFormat::Auto);

// What the run writes for `input` (model `model` with --models all): the mesh, or the PNG of
// an image output, as output_for names it.
std::string primary_output(const CliOptions& options, const std::string& input, int model);
// The PNG beside the mesh for `input` with --image: the path given, or FOLDER/NAME.png
// (NAME-mN.png with --models all); empty without --image.
std::string image_for(const CliOptions& options, const std::string& input, int model);
// The PNG files for the views of `options` from one base path: the base itself for one view,
// else BASE-VIEW.png for each (1crn.png -> 1crn-front.png, 1crn-left.png).
std::vector<std::string> view_paths(const std::string& base,
                                    const std::vector<fdmsurf::View>& views);
// True when `path` ends in .png (any case).
bool is_png_path(const std::string& path);

// A stage's place as the --host-* options spell it, lower case: "auto", "on" (the host) or
// "off" (the device); nothing for any other text.
std::optional<fdmsurf::StagePlace> stage_place(std::string_view text);

// Process exit codes (documented in --help).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;     // anything else (Internal, unexpected exceptions)
inline constexpr int kExitUsage = 2;       // InvalidArgument
inline constexpr int kExitInput = 3;       // Io, Format, EmptySelection
inline constexpr int kExitDevice = 4;      // NoDevice, DeviceLimit, Vulkan, Fft
inline constexpr int kExitValidation = 5;  // --validation and the layer reported messages
inline constexpr int kExitDeviceLost = 6;  // the Vulkan device was lost (VK_ERROR_DEVICE_LOST)
inline constexpr int kExitOutOfMemory = 7; // an allocation failed: device or host memory

int exit_code_for(fdmsurf::ErrorCode code) noexcept;
// The same for a thrown Error, whose VkResult tells a lost device (6) and an allocation that
// failed (7) from the other device errors (4).
int exit_code_for(const fdmsurf::Error& error) noexcept;

// The name the command line uses for a surface kind ("ses", "vdw", "sas").
const char* surface_name(fdmsurf::SurfaceKind kind) noexcept;

}  // namespace fdmsurf::cli
