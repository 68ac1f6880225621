// The keywords of Engine.surface and read_structure, read by the CLI's own option parser.
//
// fdmsurf/_options.py turns each keyword the caller gave into its command-line option
// (`spacing=1.0` -> `--spacing=1.0`, `no_cavities=True` -> `--no-cavities`) and cli::parse_args
// applies the CLI's defaults, ranges, interplay (--paper against explicit --filter/--level,
// --method edt against the FDM options) and messages: one parser for both, so that the API
// cannot drift from the command line.
#include "cli/options.hpp"

#include <cmath>
#include <cstdio>

#include "objects.hpp"

namespace fdmsurf::python {
namespace {

PyOptions parse(const std::vector<std::string>& args) {
    // parse_args wants an input and an output (a folder, which --models all needs); these
    // placeholders are never opened.
    std::vector<std::string> argv{"structure", "-o", "surfaces/"};
    argv.insert(argv.end(), args.begin(), args.end());
    const cli::CliOptions cli = cli::parse_args(argv);
    if (cli.inputs.size() != 1 || cli.help || cli.version || cli.list_devices)
        throw Error(ErrorCode::Internal, "keywords parsed into something other than options");
    effective_cutoff(cli.surface);  // the checks the CLI makes before any work
    if (!cli.patch.empty()) check_selection(cli.patch, "--patch");
    PyOptions out;
    out.read = cli.read;
    out.surface = cli.surface;
    out.patch = cli.patch;
    out.simplify = cli.simplify;
    out.simplify_requested = cli.simplify_requested;
    out.optimize = cli.optimize;
    return out;
}

const char* filter_name(FilterShape shape) {
    return shape == FilterShape::Ideal ? "ideal" : "gaussian";
}

std::string color_name(const PropertyOptions& p) {
    if (p.color != ColorScheme::Uniform) return to_string(p.color);
    char text[8];
    std::snprintf(text, sizeof text, "#%02x%02x%02x", p.rgb[0], p.rgb[1], p.rgb[2]);
    return text;
}

// None for a negative value (the library's "not given"), else the value.
py::object none_if_negative(double value) {
    return value < 0 ? py::object(py::none()) : py::object(py::float_(value));
}

// Every effective setting, defaults resolved as the library resolves them where that needs no
// atoms: the options hash of fdmsurf.batch and the repr of the options.
py::dict describe(const PyOptions& o) {
    const SurfaceOptions& s = o.surface;
    py::dict d;
    d["surface"] = to_string(s.surface);
    d["method"] = to_string(s.method);
    d["spacing"] = s.spacing;
    d["probe"] = s.probe;
    d["cutoff"] = effective_cutoff(s);  // 0 for vdw, sas and edt
    d["sigma"] = s.sigma;
    d["level"] = effective_level(s);
    d["filter"] = filter_name(s.filter);
    d["padding"] = none_if_negative(s.padding);
    d["density_cut"] = s.density_cut;
    d["min_cavity_volume"] = none_if_negative(s.min_cavity_volume);
    d["refine"] = s.refine;
    d["snap"] = s.snap;
    d["canonical_grid"] = s.canonical_grid;
    // None: the library's spacing / 50
    d["chord_tolerance"] = none_if_negative(s.chord_tolerance);
    d["min_grid"] = py::make_tuple(s.min_grid[0], s.min_grid[1], s.min_grid[2]);
    d["color"] = color_name(s.properties);
    py::list properties;
    for (VertexProperty p : s.properties.scalars) properties.append(to_string(p));
    d["properties"] = properties;
    d["patch"] = o.patch;
    // None: no simplification (1.0 with max_triangles alone: the CLI's ratio, no cap of its own)
    d["simplify"] =
        o.simplify_requested ? py::object(py::float_(o.simplify.ratio)) : py::object(py::none());
    d["max_triangles"] = o.simplify.max_triangles == 0
                             ? py::object(py::none())
                             : py::object(py::int_(o.simplify.max_triangles));
    d["simplifier"] = to_string(o.simplify.simplifier);
    d["optimize"] = o.optimize;
    d["format"] = to_string(o.read.format);
    d["model"] = o.read.model == kAllModels ? py::object(py::str("all"))
                                            : py::object(py::int_(o.read.model));
    d["assembly"] = o.read.assembly;
    d["chains"] = o.read.chains;
    d["select"] = o.read.select;
    d["waters"] = o.read.keep_waters;
    d["hydrogens"] = o.read.keep_hydrogens;
    d["ligands"] = o.read.keep_ligands;
    return d;
}

}  // namespace

void bind_options(py::module_& m) {
    py::class_<PyOptions>(m, "_Options",
                          "Options parsed from command-line arguments (internal: use the "
                          "keywords of Engine.surface).")
        .def(py::init(&parse), py::arg("args"))
        .def_property(
            "density_cut", [](const PyOptions& o) { return o.surface.density_cut; },
            [](PyOptions& o, float value) {
                if (!(value > 0.0f && value < 1.0f))
                    throw Error(ErrorCode::InvalidArgument,
                                "density_cut must be in (0, 1), a fraction of T (got " +
                                    std::to_string(value) + ")");
                o.surface.density_cut = value;
            })
        .def_property(
            "min_grid", [](const PyOptions& o) { return o.surface.min_grid; },
            [](PyOptions& o, const std::array<std::uint32_t, 3>& value) {
                o.surface.min_grid = value;
            })
        .def("describe", &describe);
}

}  // namespace fdmsurf::python
