// The C++ side of the module's Python classes: Structure, Mesh, SurfaceResult and the parsed
// options. Each holds its data through a shared_ptr that the numpy arrays it hands out share.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/simplify.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf::python {

// fdmsurf.Structure: atoms and what the reader said. xyz and radii are handed out as views
// (writable: editing them moves the atoms of later surfaces); the metadata arrays are built on
// first use and kept.
struct PyStructure {
    std::shared_ptr<Structure> data;
    py::dict metadata;  // name -> numpy array, filled lazily
};

// fdmsurf.Mesh: a mesh shared with the arrays over its vectors. `stats` is computed on first
// use (eagerly for surfaces, where make_surface's caller wants it anyway).
struct PyMesh {
    std::shared_ptr<Mesh> mesh;
    std::optional<MeshStats> stats;
    const MeshStats& get_stats();
};

// fdmsurf.SurfaceResult: the mesh of Engine.surface with everything else make_surface says.
struct PySurface : PyMesh {
    GridInfo grid;
    std::vector<StageTime> times;
    std::vector<std::string> warnings;
    std::size_t cavities_removed = 0;
    std::size_t specks_removed = 0;
    // simplify or max_triangles: what simplify_mesh did (the CLI's summary reports the same).
    std::optional<SimplifyOptions> simplify_options;
    SimplifyReport simplify;
    bool optimized = false;
    std::string device;
    double total_ms = 0.0;
    PyStructure structure;
};

// The keywords of Engine.surface and read_structure after the CLI's parser has read them
// (python/src/options.cpp): the library's option structs and the CLI-only --patch, --simplify,
// --max-triangles and --optimize, which act on the mesh after make_surface as in the CLI.
struct PyOptions {
    ReadOptions read;
    SurfaceOptions surface;
    std::string patch;
    SimplifyOptions simplify;         // simplify (ratio) and max_triangles
    bool simplify_requested = false;  // either was given
    bool optimize = false;
};

}  // namespace fdmsurf::python
