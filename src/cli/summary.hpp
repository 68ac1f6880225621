// The run summary of the fdmsurf program, as text or as one JSON object (--stats json).
// Declarations; the definitions are in summary.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/simplify.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf::cli {

// One picture written (src/render/).
struct ImageReport {
    std::string path;  // "-": standard output
    std::string view;  // "front", ...
    std::array<float, 3> rotate{0.0f, 0.0f, 0.0f};
    std::uint32_t width = 0, height = 0;
    float pixel_size = 0.0f;  // Å per pixel
    std::uint32_t supersample = 1;
};

// Everything the summary shows, gathered by main; plain data so that it is testable without a
// device.
struct RunReport {
    std::string version;
    std::string input;          // "-": standard input
    std::string output;         // "-": standard output
    std::string output_format;  // "ply", "obj", "glb", "stl" or "off"
    SurfaceKind surface = SurfaceKind::Ses;
    SesMethod method = SesMethod::Fdm;  // ses only
    int model = 1;
    StructureInfo info;
    std::size_t atoms_used = 0;
    GridInfo grid;
    MeshStats stats;
    bool closed_manifold = false;  // stats.is_closed_manifold()
    std::string device;
    std::vector<StageTime> times;  // in order of execution; repeated names are summed
    double total_ms = 0.0;
    std::vector<std::string> warnings;  // every warning printed to stderr
    std::string patch;                  // --patch EXPR (empty: the whole surface)
    std::size_t patch_atoms = 0;        // atoms EXPR matched
    ColorScheme color = ColorScheme::None;
    std::array<std::uint8_t, 3> color_rgb{200, 200, 200};  // ColorScheme::Uniform's colour
    std::vector<std::string> properties;  // per-vertex scalars written
    bool simplified = false;              // --simplify or --max-triangles
    SimplifyOptions simplify_options;     // what was asked
    SimplifyReport simplify;              // what simplify_mesh did
    bool optimized = false;               // --optimize
    // --areas: the file and its totals (areas_file empty: not asked for).
    std::string areas_file;
    bool areas_exact = false;        // exact sphere patches (vdw, sas) rather than the mesh's
    double areas_total = 0.0;        // Å², sum of the per-atom areas
    double areas_mesh_total = -1.0;  // Å², the mesh's split (< 0: no mesh, areas only)
    double areas_on_patches = 0.0;   // Å² of it split by sphere patch
    std::size_t areas_residues = 0;
    // --buried: the groups, the area the complex buries, and the atoms in neither group.
    std::string buried;                     // "A:B"; empty: not asked for
    std::array<double, 2> buried_groups{};  // Å² buried per group
    double buried_area = 0.0;
    double buried_mesh_area = -1.0;  // < 0: no mesh
    std::size_t atoms_outside_groups = 0;
    // False when the mesh stayed on the device (-o FILE.png): only its vertex and triangle
    // counts are known (stats.vertices, stats.triangles); no pieces, area or volume.
    bool mesh_on_host = true;
    std::vector<ImageReport> images;
};

// Sums the times of stages that share a name (one per slab, say), keeping the first order.
std::vector<StageTime> merge_times(const std::vector<StageTime>& times);

// `value` with `decimals` digits after the point and commas between thousands: 12,345.6.
std::string format_grouped(double value, int decimals);
// A whole number with commas between thousands: 12,345.
std::string format_count(std::uint64_t value);
// `value` with `precision` significant digits (printf's %g).
std::string format_general(double value, int precision = 3);

// The summary's words for a simplification that did not keep the topology: the defects of
// the result (for a closed input, all of them are new); or, with none new, the pieces and the
// Euler characteristic that changed.
std::string simplify_breakage(const SimplifyReport& s);

// The warning for a simplified mesh well above its target, saying why; empty otherwise. With
// fdmsurf's collapses, more than 2% (the cells' last pass's margin) and 4 triangles above:
// every collapse left was refused. With meshoptimizer, which keeps the triangles around its
// collapses that broke the topology and may stop early itself (docs/mesh.md), more than 10%.
std::string simplify_shortfall(const SimplifyReport& q, Simplifier simplifier);

// The stages that ran on the host's threads instead of the device (EngineOptions' places), as
// "exact SES field, Gaussian filter and marching cubes"; empty when none did.
std::string host_stages(const GridInfo& g);

// The colour scheme as --color takes it: the scheme's name, or #RRGGBB for one colour.
std::string color_name(const RunReport& r);

// The text summary of a run: structure, grid, mesh, what was done to it, times and files.
std::string text_summary(const RunReport& r);

// The line --stats json gives an input (or a model, model > 0) that failed among several: one
// line, no trailing newline.
std::string json_failure(const std::string& version, const std::string& input, int model,
                         const std::string& output, const Error& e, int exit_code);

// The summary as one JSON object (--stats json): one line, no trailing newline.
std::string json_summary(const RunReport& r);

// The summary of a run with --areas and no -o: no grid, mesh or device.
std::string areas_only_text(const RunReport& r);
// The same as one JSON object on one line, no trailing newline.
std::string areas_only_json(const RunReport& r);

}  // namespace fdmsurf::cli
