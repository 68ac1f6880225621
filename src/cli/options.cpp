// Hand-written argument parser of the fdmsurf program: each argument read and its value checked
// (the options against each other in options_check.cpp), the output paths named from the
// options, and the exit codes. The --help text is in usage.cpp.
#include "cli/options.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <system_error>

#include <vulkan/vulkan_core.h>

#include "cli/models_table.hpp"
#include "cli/options_check.hpp"
#include "refine/refine.hpp"

namespace fdmsurf::cli {
namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;

enum class Opt {
    Output,
    OutputFormat,
    Surface,
    Spacing,
    Probe,
    Cutoff,
    Sigma,
    Level,
    Filter,
    Padding,
    Model,
    Models,
    Assembly,
    Waters,
    Hydrogens,
    NoLigands,
    Format,
    Chains,
    Select,
    Color,
    Properties,
    Patch,
    Device,
    ListDevices,
    Stats,
    Quiet,
    Validation,
    Help,
    Version,
    Paper,
    NoCavities,
    MinCavity,
    Refine,
    NoSnap,
    NaturalGrid,
    ChordTolerance,
    Method,
    Simplify,
    MaxTriangles,
    Simplifier,
    HostFilter,
    HostDensity,
    HostMc,
    HostAtoms,
    HostSes,
    Optimize,
    Areas,
    Relative,
    Buried,
    Image,
    ImageSize,
    View,
    Rotate,
    Background,
    Outline,
    Occlusion,
    DepthCue,
};

struct OptionSpec {
    std::string_view name;   // long form, with the dashes
    std::string_view alias;  // short form or empty
    Opt id;
    bool takes_value;
    bool numeric;  // a value that may start with '-' (a negative number, rejected later)
};

constexpr std::array<OptionSpec, 59> kOptions{{
    {"--output", "-o", Opt::Output, true, false},
    {"--output-format", "", Opt::OutputFormat, true, false},
    {"--surface", "", Opt::Surface, true, false},
    {"--spacing", "", Opt::Spacing, true, true},
    {"--probe", "", Opt::Probe, true, true},
    {"--cutoff", "", Opt::Cutoff, true, true},
    {"--sigma", "", Opt::Sigma, true, true},
    {"--level", "", Opt::Level, true, true},
    {"--filter", "", Opt::Filter, true, false},
    {"--padding", "", Opt::Padding, true, true},
    {"--model", "", Opt::Model, true, true},
    {"--models", "", Opt::Models, true, false},
    {"--assembly", "", Opt::Assembly, true, true},
    {"--waters", "", Opt::Waters, false, false},
    {"--hydrogens", "", Opt::Hydrogens, false, false},
    {"--no-ligands", "", Opt::NoLigands, false, false},
    {"--format", "", Opt::Format, true, false},
    {"--chains", "", Opt::Chains, true, false},
    {"--select", "", Opt::Select, true, false},
    {"--device", "", Opt::Device, true, false},
    {"--list-devices", "", Opt::ListDevices, false, false},
    {"--stats", "", Opt::Stats, true, false},
    {"--quiet", "", Opt::Quiet, false, false},
    {"--validation", "", Opt::Validation, false, false},
    {"--help", "-h", Opt::Help, false, false},
    {"--version", "", Opt::Version, false, false},
    {"--paper", "", Opt::Paper, false, false},
    {"--no-cavities", "", Opt::NoCavities, false, false},
    {"--min-cavity-volume", "", Opt::MinCavity, true, true},
    {"--refine", "", Opt::Refine, true, true},
    {"--no-snap", "", Opt::NoSnap, false, false},
    {"--natural-grid", "", Opt::NaturalGrid, false, false},
    {"--chord-tolerance", "", Opt::ChordTolerance, true, true},
    {"--method", "", Opt::Method, true, false},
    {"--color", "", Opt::Color, true, false},
    {"--colour", "", Opt::Color, true, false},
    {"--properties", "", Opt::Properties, true, false},
    {"--patch", "", Opt::Patch, true, false},
    {"--simplify", "", Opt::Simplify, true, true},
    {"--max-triangles", "", Opt::MaxTriangles, true, true},
    {"--simplifier", "", Opt::Simplifier, true, false},
    {"--host-filter", "", Opt::HostFilter, true, false},
    {"--host-density", "", Opt::HostDensity, true, false},
    {"--host-mc", "", Opt::HostMc, true, false},
    {"--host-atoms", "", Opt::HostAtoms, true, false},
    {"--host-ses", "", Opt::HostSes, true, false},
    {"--optimize", "", Opt::Optimize, false, false},
    {"--areas", "", Opt::Areas, true, false},
    {"--relative", "", Opt::Relative, true, false},
    {"--buried", "", Opt::Buried, true, false},
    {"--image", "", Opt::Image, true, false},
    {"--image-size", "", Opt::ImageSize, true, true},
    {"--view", "", Opt::View, true, false},
    {"--views", "", Opt::View, true, false},
    {"--rotate", "", Opt::Rotate, true, true},
    {"--background", "", Opt::Background, true, false},
    {"--outline", "", Opt::Outline, false, false},
    {"--occlusion", "", Opt::Occlusion, true, true},
    {"--depth-cue", "", Opt::DepthCue, true, true},
}};

[[noreturn]] void fail(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, message);
}

const OptionSpec* find_option(std::string_view name) {
    for (const OptionSpec& spec : kOptions) {
        if (name == spec.name || (!spec.alias.empty() && name == spec.alias)) return &spec;
    }
    return nullptr;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] =
                std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

[[noreturn]] void fail_unknown_option(std::string_view name) {
    const OptionSpec* closest = nullptr;
    std::size_t best = 3;  // suggest only near misses (typos), not unrelated options
    for (const OptionSpec& spec : kOptions) {
        const std::size_t d = edit_distance(name, spec.name);
        if (d < best) {
            best = d;
            closest = &spec;
        }
    }
    std::string message = "unknown option '" + std::string(name) + "'";
    if (closest != nullptr) message += " (did you mean " + std::string(closest->name) + "?)";
    fail(message + "; see fdmsurf --help");
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// A number in plain decimal or exponent notation, finite, nothing after it.
template <class Real = float>
Real parse_float(std::string_view option, const std::string& text) {
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    Real value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::result_out_of_range) {
        fail("option " + std::string(option) + ": '" + text + "' is out of range");
    }
    if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
        fail("option " + std::string(option) + ": '" + text + "' is not a number");
    }
    if (!std::isfinite(value)) {
        fail("option " + std::string(option) + ": '" + text + "' is not a finite number");
    }
    return value;
}

int parse_int(std::string_view option, const std::string& text) {
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    int value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::result_out_of_range) {
        fail("option " + std::string(option) + ": '" + text + "' is out of range");
    }
    if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
        fail("option " + std::string(option) + ": '" + text + "' is not a whole number");
    }
    return value;
}

// Range checks name the option and echo the value as the user typed it.
void require(bool ok, std::string_view option, std::string_view condition,
             const std::string& text) {
    if (!ok) {
        fail("option " + std::string(option) + " must be " + std::string(condition) + " (got " +
             text + ")");
    }
}

template <class Enum, std::size_t N>
Enum parse_choice(std::string_view option, const std::string& text,
                  const std::array<std::pair<std::string_view, Enum>, N>& choices,
                  std::string_view what, std::string_view expected) {
    const std::string key = lower(text);
    for (const auto& [name, value] : choices) {
        if (key == name) return value;
    }
    fail("unknown " + std::string(what) + " '" + text + "' for " + std::string(option) +
         " (expected " + std::string(expected) + ")");
}

constexpr std::array<std::pair<std::string_view, SurfaceKind>, 3> kSurfaces{
    {{"ses", SurfaceKind::Ses}, {"vdw", SurfaceKind::Vdw}, {"sas", SurfaceKind::Sas}}};
constexpr std::array<std::pair<std::string_view, FilterShape>, 2> kFilters{
    {{"ideal", FilterShape::Ideal}, {"gaussian", FilterShape::Gaussian}}};
constexpr std::array<std::pair<std::string_view, StagePlace>, 3> kStagePlaces{
    {{"auto", StagePlace::Auto}, {"off", StagePlace::Device}, {"on", StagePlace::Host}}};
constexpr std::array<std::pair<std::string_view, Simplifier>, 2> kSimplifiers{
    {{"collapse", Simplifier::kCollapse}, {"meshopt", Simplifier::kMeshopt}}};

constexpr std::array<std::pair<std::string_view, SesMethod>, 2> kMethods{
    {{"fdm", SesMethod::Fdm}, {"edt", SesMethod::Edt}}};
constexpr std::array<std::pair<std::string_view, StructureFormat>, 6> kFormats{
    {{"pdb", StructureFormat::Pdb},
     {"cif", StructureFormat::Mmcif},
     {"mmcif", StructureFormat::Mmcif},
     {"pqr", StructureFormat::Pqr},
     {"xyzr", StructureFormat::Xyzr},
     {"xyzrn", StructureFormat::Xyzrn}}};
constexpr std::array<std::pair<std::string_view, ColorScheme>, 7> kColors{
    {{"none", ColorScheme::None},
     {"chain", ColorScheme::Chain},
     {"element", ColorScheme::Element},
     {"residue", ColorScheme::Residue},
     {"hydrophobicity", ColorScheme::Hydrophobicity},
     {"bfactor", ColorScheme::BFactor},
     {"coulombic", ColorScheme::Coulombic}}};
constexpr std::array<std::pair<std::string_view, VertexProperty>, 6> kProperties{
    {{"coulombic", VertexProperty::Coulombic},
     {"hydrophobicity", VertexProperty::Hydrophobicity},
     {"bfactor", VertexProperty::BFactor},
     {"mean_curvature", VertexProperty::MeanCurvature},
     {"gaussian_curvature", VertexProperty::GaussianCurvature},
     {"shape_index", VertexProperty::ShapeIndex}}};

// --color SCHEME or #RRGGBB.
void parse_color(std::string_view option, const std::string& text, PropertyOptions& p) {
    if (text.size() == 7 && text[0] == '#' &&
        text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        p.color = ColorScheme::Uniform;
        for (int k = 0; k < 3; ++k)
            p.rgb[k] = static_cast<std::uint8_t>(std::stoi(text.substr(1 + 2 * k, 2), nullptr, 16));
        return;
    }
    p.color = parse_choice(option, text, kColors, "colour scheme",
                           "chain, element, residue, hydrophobicity, bfactor, coulombic, none "
                           "or #RRGGBB");
}

// The items of a comma-separated list, empty ones included ("a,,b" has three).
std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> items;
    for (std::size_t start = 0;;) {
        const std::size_t comma = text.find(',', start);
        items.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
        if (comma == std::string::npos) return items;
        start = comma + 1;
    }
}

// --properties a,b: each once, in the order given.
std::vector<VertexProperty> parse_properties(std::string_view option, const std::string& text) {
    std::vector<VertexProperty> out;
    for (const std::string& name : split_commas(text)) {
        const VertexProperty p = parse_choice(
            option, name, kProperties, "vertex property",
            "a comma-separated list of coulombic, hydrophobicity, bfactor, mean_curvature, "
            "gaussian_curvature, shape_index");
        if (std::find(out.begin(), out.end(), p) != out.end())
            fail("option " + std::string(option) + ": '" + name + "' is listed twice");
        out.push_back(p);
    }
    return out;
}

// Auto stands for png: a picture, not a mesh format.
constexpr std::array<std::pair<std::string_view, MeshFormat>, 6> kOutputFormats{
    {{"ply", MeshFormat::Ply},
     {"obj", MeshFormat::Obj},
     {"glb", MeshFormat::Glb},
     {"stl", MeshFormat::Stl},
     {"off", MeshFormat::Off},
     {"png", MeshFormat::Auto}}};

constexpr std::array<std::pair<std::string_view, fdmsurf::View>, 6> kViews{
    {{"front", fdmsurf::View::Front},
     {"back", fdmsurf::View::Back},
     {"left", fdmsurf::View::Left},
     {"right", fdmsurf::View::Right},
     {"top", fdmsurf::View::Top},
     {"bottom", fdmsurf::View::Bottom}}};

// --image-size WxH: two whole numbers >= 1 (the device's maxImageDimension2D is checked once
// the device is up).
void parse_image_size(std::string_view option, const std::string& text, RenderOptions& r) {
    const std::string what = "option " + std::string(option) +
                             " must be WIDTHxHEIGHT in pixels, each a whole number >= 1 (got " +
                             text + ")";
    const std::size_t x = lower(text).find('x');
    if (x == std::string::npos) fail(what);
    std::uint32_t size[2] = {0, 0};
    const std::string parts[2] = {text.substr(0, x), text.substr(x + 1)};
    for (int k = 0; k < 2; ++k) {
        const std::string& p = parts[k];
        const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), size[k]);
        if (p.empty() || ec != std::errc() || end != p.data() + p.size() || size[k] == 0)
            fail(what);
    }
    r.width = size[0];
    r.height = size[1];
}

// --background #RRGGBB, white, black or transparent.
void parse_background(std::string_view option, const std::string& text, RenderOptions& r) {
    const std::string key = lower(text);
    if (key == "transparent") {
        r.background = {0, 0, 0, 0};
    } else if (key == "white") {
        r.background = {255, 255, 255, 255};
    } else if (key == "black") {
        r.background = {0, 0, 0, 255};
    } else if (text.size() == 7 && text[0] == '#' &&
               text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        for (int k = 0; k < 3; ++k)
            r.background[k] =
                static_cast<std::uint8_t>(std::stoi(text.substr(1 + 2 * k, 2), nullptr, 16));
        r.background[3] = 255;
    } else {
        fail("unknown background '" + text + "' for " + std::string(option) +
             " (expected #RRGGBB, white, black or transparent)");
    }
}

constexpr std::array<std::pair<std::string_view, RelativeTable>, 3> kRelativeTables{
    {{"tien2013", RelativeTable::Tien2013},
     {"miller1987", RelativeTable::Miller1987},
     {"sander1994", RelativeTable::Sander1994}}};

constexpr std::array<std::pair<std::string_view, bool>, 2> kStats{
    {{"json", true}, {"text", false}}};

// --chains A,B: author chain ids, case-sensitive, none empty.
std::vector<std::string> parse_chains(std::string_view option, const std::string& text) {
    std::vector<std::string> chains;
    for (std::string& chain : split_commas(text)) {
        if (chain.empty() || chain.find_first_of(" \t") != std::string::npos)
            fail("option " + std::string(option) + ": '" + text +
                 "' is not a comma-separated list of chain ids (e.g. A or A,B)");
        if (std::find(chains.begin(), chains.end(), chain) == chains.end())
            chains.push_back(std::move(chain));
    }
    return chains;
}

// --view a,b: each view once, in the order given.
std::vector<fdmsurf::View> parse_views(std::string_view option, const std::string& text) {
    std::vector<fdmsurf::View> views;
    for (const std::string& item : split_commas(text)) {
        const fdmsurf::View v =
            parse_choice(option, item, kViews, "view",
                         "front, back, left, right, top or bottom, or a comma-separated list");
        if (std::find(views.begin(), views.end(), v) != views.end())
            fail("option " + std::string(option) + ": '" + item + "' is listed twice");
        views.push_back(v);
    }
    return views;
}

// --rotate X,Y,Z: three angles in degrees.
void parse_rotate(std::string_view option, const std::string& text, RenderOptions& r) {
    const std::vector<std::string> items = split_commas(text);
    if (items.size() != 3)
        fail("option " + std::string(option) + " must be three angles in degrees, X,Y,Z (got " +
             text + ")");
    for (int k = 0; k < 3; ++k) r.rotate[k] = parse_float(option, items[k]);
}

// --max-triangles N: an upper bound, any whole number >= 1, however large (beyond 2^64: no
// bound).
std::size_t parse_max_triangles(std::string_view option, const std::string& text) {
    std::string_view digits = text;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    if (!digits.empty() && digits.front() == '-') {
        // "-5" or "-99999999999" is below 1; "-x" or "-" is not a whole number.
        const std::string_view magnitude = digits.substr(1);
        const bool whole = !magnitude.empty() &&
                           std::all_of(magnitude.begin(), magnitude.end(),
                                       [](char c) { return c >= '0' && c <= '9'; });
        if (!whole) fail("option " + std::string(option) + ": '" + text + "' is not a whole number");
        require(false, option, "a whole number of triangles >= 1", text);
    }
    std::uint64_t count = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
    if (digits.empty() || end != digits.data() + digits.size() ||
        (ec != std::errc() && ec != std::errc::result_out_of_range))
        fail("option " + std::string(option) + ": '" + text + "' is not a whole number");
    if (ec == std::errc::result_out_of_range) count = std::numeric_limits<std::uint64_t>::max();
    require(count >= 1, option, "a whole number of triangles >= 1", text);
    return static_cast<std::size_t>(
        std::min<std::uint64_t>(count, std::numeric_limits<std::size_t>::max()));
}

// --buried GROUP1:GROUP2: two groups, neither empty (matched against the atoms later).
void check_buried_groups(std::string_view option, const std::string& text) {
    if (std::count(text.begin(), text.end(), ':') != 1 || text.front() == ':' ||
        text.back() == ':')
        fail("option " + std::string(option) + " '" + text +
             "': give two groups separated by one ':' (chain ids, e.g. A:B or A,C:B,D, "
             "or gemmi selections, e.g. 'A/1-50:B')");
}

// The apply_*_value functions below set the value of an option of their group and return
// true, or return false for an option of another group.

// The files written, their format, the device, the stage places and --stats.
bool apply_run_value(CliOptions& o, Opt id, std::string_view name, const std::string& text) {
    switch (id) {
        case Opt::Output:
            // Standard output by another name: the same as '-' (the summary then goes to
            // stderr rather than into the mesh).
            o.output = text == "/dev/stdout" || text == "/dev/fd/1" || text == "/proc/self/fd/1"
                           ? std::string(kStdio)
                           : text;
            return true;
        case Opt::OutputFormat:
            o.output_format = parse_choice(name, text, kOutputFormats, "output format",
                                           "ply, obj, glb, stl, off or png");
            o.image_output = lower(text) == "png";
            return true;
        case Opt::Device:
            o.engine.device = text;
            return true;
        case Opt::Stats:
            o.json = parse_choice(name, text, kStats, "--stats format", "json or text");
            return true;
        case Opt::HostFilter:
            o.engine.gaussian_filter =
                parse_choice(name, text, kStagePlaces, "host filter setting", "auto, on or off");
            return true;
        case Opt::HostDensity:
            o.engine.density = parse_choice(name, text, kStagePlaces, "host density setting",
                                            "auto, on or off");
            return true;
        case Opt::HostMc:
            o.engine.marching_cubes = parse_choice(name, text, kStagePlaces,
                                                   "host marching cubes setting", "auto, on or off");
            return true;
        case Opt::HostAtoms:
            o.engine.vertex_atoms = parse_choice(name, text, kStagePlaces,
                                                 "host vertex atoms setting", "auto, on or off");
            return true;
        case Opt::HostSes:
            o.engine.ses_distance = parse_choice(name, text, kStagePlaces,
                                                 "host SES field setting", "auto, on or off");
            return true;
        default:
            return false;
    }
}

// The pictures: --image and the render options (the last one given is kept for its error).
bool apply_picture_value(CliOptions& o, Opt id, std::string_view name, const std::string& text) {
    switch (id) {
        case Opt::Image:
            o.image = text;
            return true;
        case Opt::ImageSize:
            parse_image_size(name, text, o.render);
            break;
        case Opt::View:
            o.views = parse_views(name, text);
            break;
        case Opt::Rotate:
            parse_rotate(name, text, o.render);
            break;
        case Opt::Background:
            parse_background(name, text, o.render);
            break;
        case Opt::Occlusion:
            o.render.ambient_occlusion = parse_float(name, text);
            require(o.render.ambient_occlusion >= 0.0f && o.render.ambient_occlusion <= 1.0f,
                    name, "within [0, 1]", text);
            break;
        case Opt::DepthCue:
            o.render.depth_cue = parse_float(name, text);
            require(o.render.depth_cue >= 0.0f && o.render.depth_cue <= 1.0f, name,
                    "within [0, 1]", text);
            break;
        default:
            return false;
    }
    o.render_options_given = std::string(name);
    return true;
}

// The surface: its kind, method, grid, filter, level, cavities and refinement.
bool apply_surface_value(SurfaceOptions& s, bool& explicit_cavities, Opt id,
                         std::string_view name, const std::string& text) {
    switch (id) {
        case Opt::Surface:
            s.surface = parse_choice(name, text, kSurfaces, "surface kind", "ses, vdw or sas");
            return true;
        case Opt::Spacing:
            s.spacing = parse_float(name, text);
            require(s.spacing > 0.0f, name, "> 0 Å", text);
            return true;
        case Opt::Probe:
            s.probe = parse_float(name, text);
            require(s.probe >= 0.0f, name, ">= 0 Å", text);
            return true;
        case Opt::Cutoff:
            s.cutoff = parse_float(name, text);
            require(s.cutoff >= 0.0f, name, ">= 0 1/Å", text);
            return true;
        case Opt::Sigma:
            s.sigma = parse_float(name, text);
            require(s.sigma > 0.0f, name, "> 0 Å", text);
            return true;
        case Opt::Level:
            s.level = parse_float(name, text);
            require(s.level > 0.0f, name, "> 0", text);
            return true;
        case Opt::Filter:
            s.filter = parse_choice(name, text, kFilters, "filter", "ideal or gaussian");
            return true;
        case Opt::Method:
            s.method = parse_choice(name, text, kMethods, "ses method", "fdm or edt");
            return true;
        case Opt::MinCavity:
            s.min_cavity_volume = parse_float(name, text);
            require(s.min_cavity_volume >= 0.0f, name, ">= 0 Å³", text);
            explicit_cavities = true;
            return true;
        case Opt::Refine:
            s.refine = parse_int(name, text);
            require(s.refine >= 0 && s.refine <= detail::kMaxRefineLevels, name,
                    "a whole number of levels from 0 to " +
                        std::to_string(detail::kMaxRefineLevels) +
                        " (each multiplies the triangles by 4)",
                    text);
            return true;
        case Opt::ChordTolerance:
            s.chord_tolerance = parse_float(name, text);
            require(s.chord_tolerance >= 0.0f, name, ">= 0 Å", text);
            return true;
        case Opt::Padding:
            s.padding = parse_float(name, text);
            require(s.padding >= 0.0f, name, ">= 0 Å", text);
            return true;
        default:
            return false;
    }
}

// The structure read: its model or models, assembly, format, chains and selection.
bool apply_input_value(CliOptions& o, Opt id, std::string_view name, const std::string& text) {
    switch (id) {
        case Opt::Model:
            o.read.model = parse_int(name, text);
            require(o.read.model >= 1, name, ">= 1", text);
            return true;
        case Opt::Models:
            if (lower(text) != "all")
                fail("unknown value '" + text + "' for " + std::string(name) +
                     " (expected all; --model N reads one model)");
            o.all_models = true;
            return true;
        case Opt::Assembly:
            o.read.assembly = parse_int(name, text);
            require(o.read.assembly >= 0, name, ">= 0 (0: the model as deposited)", text);
            return true;
        case Opt::Format:
            o.read.format =
                parse_choice(name, text, kFormats, "input format", "pdb, cif, pqr, xyzr or xyzrn");
            return true;
        case Opt::Chains:
            o.read.chains = parse_chains(name, text);
            return true;
        case Opt::Select:
            o.read.select = text;
            return true;
        default:
            return false;
    }
}

// What is done with the mesh: colours and properties, --patch, simplification, areas.
bool apply_mesh_value(CliOptions& o, Opt id, std::string_view name, const std::string& text) {
    switch (id) {
        case Opt::Color:
            parse_color(name, text, o.surface.properties);
            return true;
        case Opt::Properties:
            o.surface.properties.scalars = parse_properties(name, text);
            return true;
        case Opt::Patch:
            if (text.empty()) fail("option " + std::string(name) + " needs a selection");
            o.patch = text;
            return true;
        case Opt::Simplify: {
            const double ratio = parse_float<double>(name, text);
            require(ratio > 0.0 && ratio <= 1.0, name,
                    "the fraction of the triangles to keep, in (0, 1]", text);
            o.simplify.ratio = ratio;
            o.simplify_requested = true;
            return true;
        }
        case Opt::MaxTriangles:
            o.simplify.max_triangles = parse_max_triangles(name, text);
            o.simplify_requested = true;
            return true;
        case Opt::Simplifier:
            o.simplify.simplifier =
                parse_choice(name, text, kSimplifiers, "simplifier", "collapse or meshopt");
            o.simplifier_given = true;
            return true;
        case Opt::Areas:
            // .csv or .json, before any work (.jsonl: the table of --models all)
            if (!is_jsonl_path(text)) areas_format_for_path(text);
            o.areas = text;
            return true;
        case Opt::Relative:
            o.relative = parse_choice(name, text, kRelativeTables, "relative-area table",
                                      "tien2013, miller1987 or sander1994");
            return true;
        case Opt::Buried:
            check_buried_groups(name, text);
            o.buried = text;
            return true;
        default:
            return false;
    }
}

// The value `text` of the option `spec` (spelt `name`), read into `o` and range-checked.
void apply_value(CliOptions& o, const OptionSpec& spec, std::string_view name,
                 const std::string& text) {
    if (apply_run_value(o, spec.id, name, text) || apply_picture_value(o, spec.id, name, text) ||
        apply_surface_value(o.surface, o.explicit_cavities, spec.id, name, text) ||
        apply_input_value(o, spec.id, name, text) || apply_mesh_value(o, spec.id, name, text))
        return;
    fail("internal: option " + std::string(name) + " takes no value");
}

void apply_flag(CliOptions& o, const OptionSpec& spec) {
    switch (spec.id) {
        case Opt::Waters:
            o.read.keep_waters = true;
            break;
        case Opt::Hydrogens:
            o.read.keep_hydrogens = true;
            break;
        case Opt::NoLigands:
            o.read.keep_ligands = false;
            break;
        case Opt::ListDevices:
            o.list_devices = true;
            break;
        case Opt::Quiet:
            o.quiet = true;
            break;
        case Opt::Validation:
            o.engine.validation = true;
            break;
        case Opt::Help:
            o.help = true;
            break;
        case Opt::Version:
            o.version = true;
            break;
        case Opt::Paper:
            o.paper = true;
            break;
        case Opt::Optimize:
            o.optimize = true;
            break;
        case Opt::Outline:
            o.render.outline = true;
            o.render_options_given = "--outline";
            break;
        case Opt::NoSnap:
            o.surface.snap = false;
            break;
        case Opt::NaturalGrid:
            o.surface.canonical_grid = false;
            break;
        case Opt::NoCavities:
            o.surface.min_cavity_volume = std::numeric_limits<float>::infinity();
            o.explicit_cavities = true;
            break;
        default:
            fail("internal: option " + std::string(spec.name) + " needs a value");
    }
}

// Whether the argument after a value-taking option is another option rather than its value
// (`-o --quiet`). Numeric options accept "-1" as a value so that the range check can name it.
bool looks_like_option(const std::string& arg, bool numeric) {
    if (arg.size() < 2 || arg[0] != '-') return false;
    if (arg[1] == '-') return true;
    return !numeric;
}

// OUTPUT itself, or OUTPUT/<input name><extension> for a folder.
std::string output_with_extension(const std::string& input, const std::string& output,
                                  const char* extension) {
    if (!output_is_folder(output)) return output;
    std::filesystem::path name =
        input == kStdio ? std::filesystem::path("stdin") : std::filesystem::path(input).filename();
    // 1crn.pdb.gz -> 1crn.ply
    if (lower(name.extension().string()) == ".gz") name = name.stem();
    name.replace_extension(extension);
    return (std::filesystem::path(output) / name).string();
}

std::string with_model(const std::string& file, int model) {
    std::filesystem::path path = file;
    path.replace_filename(path.stem().string() + "-m" + std::to_string(model) +
                          path.extension().string());
    return path.string();
}

}  // namespace

bool output_is_folder(const std::string& output) {
    std::error_code ec;
    return !output.empty() && output != kStdio &&
           (output.back() == '/' || std::filesystem::is_directory(output, ec));
}

std::string output_for(const std::string& input, const std::string& output, MeshFormat format) {
    return output_with_extension(
        input, output, format == MeshFormat::Auto ? ".ply" : mesh_format_extension(format));
}

std::string output_for(const std::string& input, const std::string& output, int model,
                       MeshFormat format) {
    return with_model(output_for(input, output, format), model);
}

std::string primary_output(const CliOptions& options, const std::string& input, int model) {
    const std::string file =
        options.image_output ? output_with_extension(input, options.output, ".png")
                             : output_for(input, options.output, options.output_format);
    return options.all_models ? with_model(file, model) : file;
}

std::string image_for(const CliOptions& options, const std::string& input, int model) {
    if (options.image.empty()) return "";
    const std::string file = output_with_extension(input, options.image, ".png");
    return options.all_models ? with_model(file, model) : file;
}

std::vector<std::string> view_paths(const std::string& base,
                                    const std::vector<fdmsurf::View>& views) {
    if (views.size() <= 1 || base == kStdio) return {base};
    std::vector<std::string> out;
    for (fdmsurf::View v : views) {
        std::filesystem::path path = base;
        std::string ext = path.extension().string();
        if (ext.empty()) ext = ".png";
        path.replace_filename(path.stem().string() + "-" + fdmsurf::to_string(v) + ext);
        out.push_back(path.string());
    }
    return out;
}

bool is_png_path(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".png";
}

std::optional<StagePlace> stage_place(std::string_view text) {
    for (const auto& [name, place] : kStagePlaces) {
        if (text == name) return place;
    }
    return std::nullopt;
}

CliOptions parse_args(const std::vector<std::string>& args) {
    CliOptions o;
    ArgumentsSeen seen;
    bool options_done = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (options_done || arg.size() < 2 || arg[0] != '-') {
            o.inputs.push_back(arg);
            continue;
        }
        if (arg == "--") {
            options_done = true;
            continue;
        }
        std::string name = arg;
        std::optional<std::string> inline_value;
        if (arg.starts_with("--")) {
            if (const auto eq = arg.find('='); eq != std::string::npos) {
                name = arg.substr(0, eq);
                inline_value = arg.substr(eq + 1);
            }
        }
        const OptionSpec* spec = find_option(name);
        if (spec == nullptr) fail_unknown_option(name);
        if (!spec->takes_value) {
            if (inline_value) fail("option " + name + " takes no value");
            apply_flag(o, *spec);
            continue;
        }
        std::string value;
        if (inline_value) {
            value = *inline_value;
        } else if (i + 1 < args.size() && !looks_like_option(args[i + 1], spec->numeric)) {
            value = args[++i];
        }
        if (value.empty()) fail("option " + name + " needs a value");
        apply_value(o, *spec, name, value);
        if (spec->id == Opt::Filter) o.explicit_filter = true;
        if (spec->id == Opt::Filter || spec->id == Opt::Cutoff || spec->id == Opt::Sigma ||
            spec->id == Opt::Level)
            seen.fdm_only = std::string(spec->name);
        if (spec->id == Opt::Level) o.explicit_level = true;
        if (spec->id == Opt::Spacing) o.explicit_spacing = true;
        if (spec->id == Opt::Model) seen.explicit_model = true;
    }
    check_combinations(o, seen);
    return o;
}

int exit_code_for(ErrorCode code) noexcept {
    switch (code) {
        case ErrorCode::InvalidArgument:
            return kExitUsage;
        case ErrorCode::Io:
        case ErrorCode::Format:
        case ErrorCode::EmptySelection:
            return kExitInput;
        case ErrorCode::NoDevice:
        case ErrorCode::DeviceLimit:
        case ErrorCode::Vulkan:
        case ErrorCode::Fft:
            return kExitDevice;
        case ErrorCode::Internal:
            return kExitFailure;
    }
    return kExitFailure;
}

int exit_code_for(const Error& error) noexcept {
    const int vk = error.vk_result();
    if ((error.code() == ErrorCode::Vulkan || error.code() == ErrorCode::DeviceLimit ||
         error.code() == ErrorCode::Fft) &&
        vk != 0) {
        if (error.code() != ErrorCode::Fft && vk == VK_ERROR_DEVICE_LOST) return kExitDeviceLost;
        if (error.code() != ErrorCode::Fft &&
            (vk == VK_ERROR_OUT_OF_DEVICE_MEMORY || vk == VK_ERROR_OUT_OF_HOST_MEMORY)) {
            return kExitOutOfMemory;
        }
    }
    return exit_code_for(error.code());
}

const char* surface_name(SurfaceKind kind) noexcept {
    for (const auto& [name, value] : kSurfaces) {
        if (value == kind) return name.data();
    }
    return "unknown";
}

}  // namespace fdmsurf::cli
