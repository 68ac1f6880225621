// fdmsurf.Engine's compiled half (_Engine), Mesh and SurfaceResult, compare, read_mesh and
// list_devices. Device work runs with the GIL released; each engine serialises its own calls.
#include <algorithm>
#include <array>
#include <chrono>
#include <mutex>

#include "cli/summary.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "fdmsurf/simplify.hpp"
#include "objects.hpp"

namespace fdmsurf::python {

const MeshStats& PyMesh::get_stats() {
    if (!stats) {
        MeshStats computed;
        {
            py::gil_scoped_release release;
            computed = compute_stats(*mesh);
        }
        if (!stats) stats = computed;
    }
    return *stats;
}

namespace {

// The grid of a run; `planned` (plan_grid, no device): the grid alone, without what only the
// engine decides when it runs (slabs, the stages' places), which would all read as defaults.
py::dict grid_dict(const GridInfo& g, bool planned = false) {
    py::dict d;
    d["dims"] = py::make_tuple(g.dims[0], g.dims[1], g.dims[2]);
    d["spacing"] = g.spacing;
    d["origin"] = py::make_tuple(g.origin[0], g.origin[1], g.origin[2]);
    d["cutoff"] = g.cutoff;
    if (planned) return d;
    d["slabs"] = g.slabs;
    d["host_filter"] = g.host_filter;
    d["host_density"] = g.host_density;
    d["host_marching_cubes"] = g.host_marching_cubes;
    d["host_ses_distance"] = g.host_ses_distance;
    return d;
}

py::dict device_dict(const DeviceInfo& d) {
    py::dict out;
    out["index"] = d.index;
    out["name"] = d.name;
    out["type"] = d.type;
    out["driver"] = d.driver;
    out["api_version"] = d.api_version;
    out["usable"] = d.usable;
    out["reason"] = d.reason;
    out["max_storage_buffer_range"] = d.max_storage_buffer_range;
    out["device_memory"] = d.device_memory;
    return out;
}

py::dict stats_dict(const MeshStats& s) {
    py::dict d;
    d["vertices"] = s.vertices;
    d["triangles"] = s.triangles;
    d["area"] = s.area;
    d["volume"] = s.volume;
    d["pieces"] = s.pieces;
    d["closed_pieces"] = s.closed_pieces;
    d["boundary_edges"] = s.boundary_edges;
    d["nonmanifold_edges"] = s.nonmanifold_edges;
    d["nonmanifold_vertices"] = s.nonmanifold_vertices;
    d["inconsistent_edges"] = s.inconsistent_edges;
    d["degenerate_triangles"] = s.degenerate_triangles;
    d["euler_characteristic"] = s.euler_characteristic;
    d["closed_manifold"] = s.is_closed_manifold();
    return d;
}

// Stage times in order, stages that ran more than once (one per slab) summed, as the CLI shows.
py::dict times_dict(const std::vector<StageTime>& times) {
    py::dict d;
    for (const StageTime& t : times) {
        const py::str key(t.name);
        d[key] = d.contains(key) ? d[key].cast<double>() + t.ms : t.ms;
    }
    return d;
}

// write()'s format=: the names of the CLI's --output-format.
MeshFormat format_named(const py::object& format, const std::string& path) {
    if (format.is_none()) return mesh_format_for_path(path);
    if (!py::isinstance<py::str>(format))
        throw py::type_error("format must be a str ('ply', 'obj', 'glb', 'stl' or 'off') or "
                             "None, not " + type_name(format));
    const std::string name = format.cast<std::string>();
    for (MeshFormat f :
         {MeshFormat::Ply, MeshFormat::Obj, MeshFormat::Glb, MeshFormat::Stl, MeshFormat::Off})
        if (name == mesh_format_extension(f) + 1) return f;  // ".ply" without its dot
    throw Error(ErrorCode::InvalidArgument, "unknown mesh format '" + name +
                                                "' (expected 'ply', 'obj', 'glb', 'stl' or 'off')");
}

// SurfaceResult.simplify: the CLI's `--stats json` "simplify" object.
py::object simplify_dict(const PySurface& s) {
    if (!s.simplify_options) return py::none();
    const SimplifyReport& q = s.simplify;
    py::dict d;
    d["ratio"] = s.simplify_options->ratio;
    d["max_triangles"] = s.simplify_options->max_triangles;
    d["simplifier"] = to_string(s.simplify_options->simplifier);
    d["target_triangles"] = q.target_triangles;
    d["triangles_in"] = q.triangles_in;
    d["vertices_in"] = q.vertices_in;
    d["triangles_out"] = q.triangles_out;
    d["vertices_out"] = q.vertices_out;
    d["welded_vertices"] = q.welded;
    d["topology_kept"] = q.topology_kept;
    d["frozen_triangles"] = q.frozen_triangles;
    d["regions"] = q.regions;
    d["regions_kept_whole"] = q.regions_kept_whole;
    d["attempts"] = q.attempts;
    d["error"] = q.error;
    d["hausdorff"] = q.hausdorff;
    d["rmsd"] = q.rmsd;
    return d;
}


std::shared_ptr<Mesh> read_mesh_at(const std::string& path) {
    auto mesh = std::make_shared<Mesh>();
    py::gil_scoped_release release;
    *mesh = read_mesh_any(path);
    return mesh;
}

std::shared_ptr<Mesh> mesh_of(py::handle source) {
    if (py::isinstance<PyMesh>(source)) return source.cast<PyMesh&>().mesh;
    return read_mesh_at(path_argument(source));
}

std::string mesh_repr(PyMesh& m, const char* type) {
    const MeshStats& s = m.get_stats();
    char text[256];
    std::snprintf(text, sizeof text,
                  "<fdmsurf.%s: %zu vertices, %zu triangles, %zu piece(s), area %.1f Å², volume "
                  "%.1f Å³, closed manifold: %s>",
                  type, s.vertices, s.triangles, s.pieces, s.area, s.volume,
                  s.is_closed_manifold() ? "yes" : "no");
    return text;
}

using Clock = std::chrono::steady_clock;

// fdmsurf.Engine's compiled half: the library's Engine behind a mutex, so that threads sharing
// one engine take turns (the GIL is released while they compute), and two engines in two
// threads compute at the same time.
class PyEngine {
public:
    // places: where the Gaussian filter, marching cubes, the vertex atoms, the exact SES's
    // field and the density run (EngineOptions; 0 auto, 1 the device, 2 the host).
    PyEngine(const std::string& device, bool validation, const std::array<int, 5>& places)
        : validation_(validation) {
        EngineOptions options;
        options.device = device;
        options.validation = validation;
        auto place = [](int p) {
            return p == 1 ? StagePlace::Device : p == 2 ? StagePlace::Host : StagePlace::Auto;
        };
        options.gaussian_filter = place(places[0]);
        options.marching_cubes = place(places[1]);
        options.vertex_atoms = place(places[2]);
        options.ses_distance = place(places[3]);
        options.density = place(places[4]);
        py::gil_scoped_release release;
        engine_ = std::make_unique<Engine>(options);
        info_ = engine_->device();
    }

    PySurface surface(const PyStructure& structure, const PyOptions& options) {
        const auto start = Clock::now();
        PySurface out;
        out.structure = structure;
        std::shared_ptr<const Structure> input = structure.data;  // alive while we compute
        SurfaceResult result;
        MeshStats stats;
        {
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> lock(mutex_);
            Engine& engine = get();
            // patch: the selection is checked before the surface is computed (as the CLI does).
            std::vector<std::uint8_t> patch;
            std::size_t patch_atoms = 0;
            if (!options.patch.empty()) {
                patch = match_selection(input->atoms, options.patch, input->info.model);
                patch_atoms = std::size_t(std::count(patch.begin(), patch.end(), 1));
                if (patch_atoms == 0)
                    throw Error(ErrorCode::EmptySelection,
                                "patch '" + options.patch + "' matches none of the " +
                                    std::to_string(input->atoms.size()) + " atoms");
            }
            // The statistics from the engine, with the cavity removal's pieces, when the mesh
            // is kept as the engine gives it (no patch, simplification or reordering after).
            SurfaceOptions surface = options.surface;
            surface.mesh_stats =
                options.patch.empty() && !options.simplify_requested && !options.optimize;
            result = engine.make_surface(input->atoms, surface);
            if (validation_)
                for (std::string& m : engine.take_validation_messages())
                    result.warnings.push_back("validation: " + m);
            if (!patch.empty()) {
                result.mesh = extract_patch(result.mesh, patch);
                if (result.mesh.triangle_count() == 0)
                    result.warnings.push_back(
                        "patch '" + options.patch + "': its " + std::to_string(patch_atoms) +
                        " atoms own no whole triangle of the surface (buried, or too few): "
                        "the patch is empty");
            }
            // Simplification and reordering come last, on the mesh as it will be written: the
            // CLI's order and calls (src/cli/main.cpp), its warning when topology was lost.
            if (options.simplify_requested) {
                result.mesh = simplify_mesh(result.mesh, options.simplify, &out.simplify);
                result.times.insert(result.times.end(), out.simplify.times.begin(),
                                    out.simplify.times.end());
                out.simplify_options = options.simplify;
                if (!out.simplify.topology_kept)
                    result.warnings.push_back(cli::simplify_breakage(out.simplify));
                if (const std::string why =
                        cli::simplify_shortfall(out.simplify, options.simplify.simplifier);
                    !why.empty())
                    result.warnings.push_back(why);
            }
            if (options.optimize) {
                const auto t = Clock::now();
                optimize_mesh(result.mesh);
                result.times.push_back(
                    {"optimize",
                     std::chrono::duration<double, std::milli>(Clock::now() - t).count(), false});
                out.optimized = true;
            }
            stats = result.stats ? *result.stats : compute_stats(result.mesh);
        }
        out.mesh = std::make_shared<Mesh>(std::move(result.mesh));
        out.stats = stats;
        out.grid = result.grid;
        out.times = std::move(result.times);
        out.warnings = std::move(result.warnings);
        out.cavities_removed = result.cavities_removed;
        out.specks_removed = result.specks_removed;
        out.device = info_.name;
        out.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        return out;
    }

    py::dict device() const { return device_dict(info_); }

    std::vector<std::string> take_validation_messages() {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex_);
        return get().take_validation_messages();
    }

    void close() {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex_);
        engine_.reset();
    }

    bool closed() const { return engine_ == nullptr; }

private:
    Engine& get() {
        if (!engine_)
            throw Error(ErrorCode::InvalidArgument, "this Engine was closed; make a new one");
        return *engine_;
    }

    std::unique_ptr<Engine> engine_;
    std::mutex mutex_;
    bool validation_;
    DeviceInfo info_;
};

py::dict compare_dict(const CompareResult& r) {
    py::dict d;
    d["rmsd_weighted"] = r.rmsd_weighted;
    d["mean_unsigned"] = r.mean_unsigned;
    d["mean_signed"] = r.mean_signed;
    d["share_beyond_spacing"] = r.share_beyond_spacing;
    d["hausdorff"] = r.hausdorff;
    d["rmsd_tested_to_reference"] = r.rmsd_tested_to_reference;
    d["area_ref"] = r.area_ref;
    d["area_test"] = r.area_test;
    d["volume_ref"] = r.volume_ref;
    d["volume_test"] = r.volume_test;
    d["area_rel_error"] = r.area_rel_error;
    d["volume_rel_error"] = r.volume_rel_error;
    d["ref_vertices"] = r.ref_vertices;
    d["test_vertices"] = r.test_vertices;
    d["ref_triangles"] = r.ref_triangles;
    d["test_triangles"] = r.test_triangles;
    d["max_ref_to_test"] = r.max_ref_to_test;
    d["max_test_to_ref"] = r.max_test_to_ref;
    return d;
}

}  // namespace

void bind_surface(py::module_& m) {
    py::class_<PyMesh>(m, "Mesh", R"(A triangle mesh as numpy arrays.

vertices (V, 3) float32 (Å), normals (V, 3) float32 (unit, pointing out of the molecule),
faces (F, 3) uint32 (counter-clockwise seen from outside), atoms (V,) uint32 (the index of the
atom each vertex belongs to), colors (V, 3) uint8 and properties {name: (V,) float32}. The
arrays share the mesh's own memory (no copy is made, and they stay valid after the mesh object
is gone); write() writes them as they are, so edit them in place to write an edited mesh.
area, volume, pieces, closed_manifold and stats describe the mesh as it was made.)")
        .def_property_readonly(
            "vertices",
            [](PyMesh& s) {
                auto& v = s.mesh->positions;
                return share(s.mesh, v.data(), {py::ssize_t(v.size() / 3), 3});
            },
            "Vertex positions, (V, 3) float32, Å.")
        .def_property_readonly(
            "normals",
            [](PyMesh& s) -> py::object {
                auto& v = s.mesh->normals;
                if (v.empty() && !s.mesh->positions.empty()) return py::none();
                return share(s.mesh, v.data(), {py::ssize_t(v.size() / 3), 3});
            },
            "Unit vertex normals pointing outwards, (V, 3) float32; None for a mesh read "
            "without normals.")
        .def_property_readonly(
            "faces",
            [](PyMesh& s) {
                auto& v = s.mesh->indices;
                return share(s.mesh, v.data(), {py::ssize_t(v.size() / 3), 3});
            },
            "Triangles as vertex indices, (F, 3) uint32, counter-clockwise seen from outside.")
        .def_property_readonly(
            "atoms",
            [](PyMesh& s) -> py::object {
                auto& v = s.mesh->atoms;
                if (v.empty() && !s.mesh->positions.empty()) return py::none();
                return share(s.mesh, v.data(), {py::ssize_t(v.size())});
            },
            "Per vertex, the index (into the structure's atoms) of the atom it belongs to, (V,) "
            "uint32; None when unknown (a mesh read from a file without it).")
        .def_property_readonly(
            "colors",
            [](PyMesh& s) -> py::object {
                auto& v = s.mesh->colors;
                if (v.empty()) return py::none();
                return share(s.mesh, v.data(), {py::ssize_t(v.size() / 3), 3});
            },
            "Vertex colours (sRGB red, green, blue), (V, 3) uint8; None when uncoloured.")
        .def_property_readonly(
            "properties",
            [](PyMesh& s) {
                py::dict d;
                for (VertexScalars& p : s.mesh->scalars)
                    d[py::str(p.name)] =
                        share(s.mesh, p.values.data(), {py::ssize_t(p.values.size())});
                return d;
            },
            "Per-vertex scalars asked for with `properties`, {name: (V,) float32}.")
        .def_property_readonly("vertex_count",
                               [](const PyMesh& s) { return s.mesh->vertex_count(); })
        .def_property_readonly("triangle_count",
                               [](const PyMesh& s) { return s.mesh->triangle_count(); })
        .def_property_readonly(
            "area", [](PyMesh& s) { return s.get_stats().area; }, "Surface area, Å².")
        .def_property_readonly(
            "volume", [](PyMesh& s) { return s.get_stats().volume; },
            "Enclosed volume, Å³ (signed: cavities count negative).")
        .def_property_readonly(
            "pieces", [](PyMesh& s) { return s.get_stats().pieces; },
            "Connected pieces (the outer surface, cavities, separate molecules).")
        .def_property_readonly(
            "closed_manifold", [](PyMesh& s) { return s.get_stats().is_closed_manifold(); },
            "Every edge in exactly two consistently oriented triangles, positive volume.")
        .def_property_readonly(
            "stats", [](PyMesh& s) { return stats_dict(s.get_stats()); },
            "Every mesh statistic of fdmsurf's summary: vertices, triangles, area, volume, "
            "pieces, closed_pieces, boundary_edges, nonmanifold_edges, nonmanifold_vertices, "
            "inconsistent_edges, degenerate_triangles, euler_characteristic, closed_manifold.")
        .def(
            "piece_stats",
            [](PyMesh& s) {
                std::vector<MeshStats> pieces;
                {
                    py::gil_scoped_release release;
                    pieces = piece_stats(*s.mesh);
                }
                py::list out;
                for (const MeshStats& piece : pieces) out.append(stats_dict(piece));
                return out;
            },
            "The statistics of each connected piece (dicts as `stats`), largest area first: "
            "the outer surface, then separate molecules (positive volume) and cavities "
            "(negative volume, Å³).")
        .def(
            "write",
            [](PyMesh& s, py::handle path_object, py::object format) {
                const std::string path = path_argument(path_object);
                const MeshFormat f = format_named(format, path);
                py::gil_scoped_release release;
                write_mesh(*s.mesh, path, f);
            },
            py::arg("path"), py::arg("format") = py::none(),
            R"(Writes the mesh to `path` as the CLI does: binary PLY (positions, normals, `uint
atom`, colours, one float per property), OBJ (v x y z [r g b], vn, f), GLB (glTF 2.0 binary:
POSITION, NORMAL, COLOR_0, _ATOM, one _NAME per property), binary STL (positions only) or OFF
(COFF when coloured), by the extension (.ply, .obj, .glb, .stl, .off) unless format= names one
('ply', 'obj', 'glb', 'stl', 'off': the CLI's --output-format). Written under a temporary name
and renamed: a failure leaves no file at `path`. Raises InvalidArgumentError for an unknown
extension or format, or a mesh the format cannot hold; FileError when the file cannot be
written.)")
        .def("__len__", [](const PyMesh& s) { return s.mesh->triangle_count(); })
        .def("__repr__", [](PyMesh& s) { return mesh_repr(s, "Mesh"); });

    py::class_<PySurface, PyMesh>(m, "SurfaceResult",
                                  R"(The surface Engine.surface made: a Mesh, and
what the engine says of it: grid, times, warnings, device, structure (the atoms it was made
from; `atoms` indexes them), cavities_removed, specks_removed, simplify (what simplify= and
max_triangles= did), optimized, total_ms.)")
        .def_property_readonly(
            "grid", [](const PySurface& s) { return grid_dict(s.grid); },
            "The grid: dims (points along x, y, z), spacing (Å), origin (Å), cutoff (1/Å, 0 for "
            "vdw, sas and edt), slabs (> 1 when processed in parts), host_filter (the Gaussian "
            "filter ran on the host), host_density (the density was computed on the host), "
            "host_marching_cubes (marching cubes ran on the host), "
            "host_ses_distance (the exact SES field was computed on the host).")
        .def_property_readonly(
            "times", [](const PySurface& s) { return times_dict(s.times); },
            "Milliseconds per stage ('density', 'fft-forward', ...), in order of execution.")
        .def_property_readonly(
            "stages",
            [](const PySurface& s) {
                py::list out;
                for (const StageTime& t : s.times) out.append(py::make_tuple(t.name, t.ms, t.gpu));
                return out;
            },
            "Every stage as it ran, (name, ms, gpu) in order (a stage per slab repeats): gpu is "
            "True where the time comes from GPU timestamps, False for host work.")
        .def_property_readonly(
            "warnings", [](const PySurface& s) { return text_list(s.warnings); },
            "The engine's warnings (the CLI prints them as `fdmsurf: warning:` lines), and the "
            "validation layer's messages with Engine(validation=True).")
        .def_property_readonly(
            "device", [](const PySurface& s) { return s.device; }, "The Vulkan device's name.")
        .def_property_readonly(
            "structure", [](const PySurface& s) { return s.structure; },
            "The Structure the surface was made from.")
        .def(
            "atom_areas",
            [](PySurface& s) {
                std::vector<double> areas;
                {
                    py::gil_scoped_release release;
                    areas = atom_mesh_areas(*s.mesh, s.structure.data->atoms.size());
                }
                return py::array_t<double>(py::ssize_t(areas.size()), areas.data());
            },
            R"(The surface's area shared out to the structure's atoms, (N,) float64, Å²: each
triangle gives a third of its area to the atom of each of its vertices (docs/areas.md); the sum
is the area. Atoms that own no vertex get 0.)")
        .def_property_readonly(
            "simplify", &simplify_dict,
            "With simplify or max_triangles, what the simplification did, as the CLI's `--stats "
            "json` reports it (ratio, max_triangles, target_triangles, triangles_in, "
            "vertices_in, triangles_out, vertices_out, welded_vertices, topology_kept, "
            "frozen_triangles, regions, regions_kept_whole, attempts, error, hausdorff and rmsd "
            "to the full mesh, Å); None without.")
        .def_property_readonly(
            "optimized", [](const PySurface& s) { return s.optimized; },
            "True when the mesh was reordered for the vertex cache and fetch (optimize=True).")
        .def_property_readonly("cavities_removed",
                               [](const PySurface& s) { return s.cavities_removed; })
        .def_property_readonly("specks_removed",
                               [](const PySurface& s) { return s.specks_removed; })
        .def_property_readonly(
            "total_ms", [](const PySurface& s) { return s.total_ms; },
            "Wall time of the call, milliseconds.")
        .def("__repr__", [](PySurface& s) { return mesh_repr(s, "SurfaceResult"); });

    py::class_<PyEngine>(m, "_Engine")
        .def(py::init<const std::string&, bool, const std::array<int, 5>&>(), py::arg("device"),
             py::arg("validation"), py::arg("places"))
        .def("surface", &PyEngine::surface, py::arg("structure"), py::arg("options"))
        .def_property_readonly("device", &PyEngine::device)
        .def("take_validation_messages", &PyEngine::take_validation_messages)
        .def("close", &PyEngine::close)
        .def_property_readonly("closed", &PyEngine::closed);

    m.def(
        "_plan_grid",
        [](const PyStructure& structure, const PyOptions& options) {
            GridInfo grid;
            {
                py::gil_scoped_release release;
                grid = plan_surface_grid(structure.data->atoms, options.surface);
            }
            return grid_dict(grid, true);
        },
        py::arg("structure"), py::arg("options"));

    m.def(
        "list_devices",
        []() {
            std::vector<DeviceInfo> devices;
            {
                py::gil_scoped_release release;
                devices = list_devices();
            }
            py::list out;
            for (const DeviceInfo& d : devices) out.append(device_dict(d));
            return out;
        },
        R"(The Vulkan devices, each a dict: index, name, type ('discrete GPU', 'CPU', ...),
driver, api_version, usable, reason (why not usable), max_storage_buffer_range and
device_memory (bytes). Raises NoDeviceError when the Vulkan loader or every driver is
missing (install mesa-vulkan-drivers for lavapipe, the CPU device).)");

    m.def(
        "sas_areas",
        [](const PyStructure& structure, float probe, int points) {
            std::vector<double> areas;
            {
                py::gil_scoped_release release;
                areas = atom_sas_areas(structure.data->atoms, probe, points);
            }
            return py::array_t<double>(py::ssize_t(areas.size()), areas.data());
        },
        py::arg("structure"), py::arg("probe") = 1.4f, py::arg("points") = 1000,
        R"(The solvent-accessible area of every atom of `structure`, (N,) float64, Å², by
Shrake & Rupley's test points (`points` per atom; probe 0 gives the van der Waals area), on
the host with every thread (docs/areas.md).)");

    m.def(
        "exact_areas",
        [](const PyStructure& structure, float probe) {
            std::vector<double> areas;
            {
                py::gil_scoped_release release;
                areas = atom_exact_areas(structure.data->atoms, probe);
            }
            return py::array_t<double>(py::ssize_t(areas.size()), areas.data());
        },
        py::arg("structure"), py::arg("probe") = 1.4f,
        R"(The solvent-accessible area of every atom of `structure`, (N,) float64, Å², exactly:
each atom's patch of the union of the balls of radius r + probe, by the Gauss-Bonnet theorem
on the arcs where the spheres meet (no sampling; probe 0 gives the van der Waals area), on the
host with every thread (docs/areas.md).)");

    m.def(
        "read_mesh",
        [](py::handle path) {
            PyMesh out;
            out.mesh = read_mesh_at(path_argument(path));
            return out;
        },
        py::arg("path"),
        R"(Reads a mesh: PLY (ASCII or binary), OBJ, GLB, STL (binary or ASCII), OFF
(NanoShaper's too) and MSMS .vert/.face, each optionally gzipped, as `fdmsurf compare` reads
them. Raises FileError or FormatError.)");

    m.def(
        "compare",
        [](py::handle reference, py::handle tested, double spacing, bool outer,
           double weld_tolerance) {
            const auto ref = mesh_of(reference);
            const auto test = mesh_of(tested);
            CompareOptions options;
            options.spacing = spacing;
            options.outer_only = outer;
            options.weld_tolerance = weld_tolerance;
            CompareResult r;
            {
                py::gil_scoped_release release;
                r = compare_meshes(*ref, *test, options);
            }
            return compare_dict(r);
        },
        py::arg("reference"), py::arg("tested"), py::arg("spacing"), py::kw_only(),
        py::arg("outer") = false, py::arg("weld_tolerance") = 1e-5,
        R"(`fdmsurf compare`: the tested mesh against the reference (each a Mesh, a
SurfaceResult or a path read as read_mesh reads it) with the weighted RMSD of Giard & Macq
(2010) and its companions (docs/compare.md). spacing: H in Å (share_beyond_spacing counts
distances above it); outer: only the largest piece of each mesh. Returns a dict:
rmsd_weighted, mean_unsigned, mean_signed, share_beyond_spacing, hausdorff,
rmsd_tested_to_reference, area_ref, area_test, volume_ref, volume_test, area_rel_error,
volume_rel_error, ref_vertices, test_vertices, ref_triangles, test_triangles,
max_ref_to_test, max_test_to_ref (Å, Å², Å³).)");
}

}  // namespace fdmsurf::python
