// The run summary of the fdmsurf program, as text or as one JSON object (--stats json): the
// definitions of summary.hpp, each summary assembled from the lines or members of its parts.
#include "cli/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "cli/json.hpp"
#include "cli/options.hpp"
#include "base/text.hpp"

namespace fdmsurf::cli {
namespace {

// The summary's lines for --areas and --buried (empty when neither was asked for).
std::string areas_lines(const RunReport& r) {
    std::string s;
    if (r.areas_file.empty()) return s;
    s += "  areas        " + format_grouped(r.areas_total, 1) + " Å² (";
    if (r.areas_exact)
        s += "exact sphere patches";
    else
        s += "the mesh split by vertex atom";
    if (r.areas_exact && r.areas_mesh_total >= 0.0) {
        const double share =
            r.areas_mesh_total > 0.0 ? 100.0 * r.areas_on_patches / r.areas_mesh_total : 100.0;
        s += "; the mesh " + format_grouped(r.areas_mesh_total, 1) + " Å², " +
             format_grouped(share, 1) + "% of it split by sphere patch";
    }
    s += ") per atom" +
         std::string(r.areas_residues ? " and residue (" + format_count(r.areas_residues) + ")"
                                      : "") +
         ": " + detail::printable(r.areas_file) + "\n";
    if (!r.buried.empty()) {
        const std::size_t colon = r.buried.find(':');
        s += "  buried       " + format_grouped(r.buried_area, 1) + " Å² between " +
             r.buried.substr(0, colon) + " and " + r.buried.substr(colon + 1) + " (" +
             format_grouped(r.buried_groups[0], 1) + " + " + format_grouped(r.buried_groups[1], 1);
        if (r.buried_mesh_area >= 0.0)
            s += "; mesh " + format_grouped(r.buried_mesh_area, 1) + " Å²";
        s += ")";
        if (r.atoms_outside_groups)
            s += "; " + format_count(r.atoms_outside_groups) + " atoms in neither group left out";
        s += "\n";
    }
    return s;
}

// `key`: `value` where it is known, else null.
template <class T>
void member_or_null(JsonWriter& w, std::string_view key, bool known, const T& value) {
    if (known)
        w.member(key, value);
    else
        w.member(key, nullptr);
}

// `key`: the object that members() writes, or null when there is none.
template <class Members>
void object_or_null(JsonWriter& w, std::string_view key, bool present, Members&& members) {
    if (!present) {
        w.member(key, nullptr);
        return;
    }
    w.key(key).begin_object();
    members();
    w.end_object();
}

void areas_json(JsonWriter& w, const RunReport& r) {
    const bool mesh = r.areas_mesh_total >= 0.0;
    object_or_null(w, "areas", !r.areas_file.empty(), [&] {
        w.member("file", r.areas_file);
        w.member("exact", r.areas_exact);
        w.member("total", r.areas_total);
        member_or_null(w, "mesh_total", mesh, r.areas_mesh_total);
        // Split by sphere patch: vdw and sas (exact areas); null for ses, as in the areas file.
        member_or_null(w, "mesh_on_patches", mesh && r.areas_exact, r.areas_on_patches);
        w.member("residues", r.areas_residues);
    });
    object_or_null(w, "buried", !r.buried.empty(), [&] {
        w.member("groups", r.buried);
        w.member("area", r.buried_area);
        w.key("group_areas").begin_array();
        for (double a : r.buried_groups) w.value(a);
        w.end_array();
        member_or_null(w, "mesh_area", r.buried_mesh_area >= 0.0, r.buried_mesh_area);
        w.member("atoms_outside_groups", r.atoms_outside_groups);
    });
}

// The stage times, the total and the warnings: the last members of both JSON summaries.
void times_json(JsonWriter& w, const RunReport& r) {
    w.key("times").begin_object();
    for (const StageTime& t : merge_times(r.times)) w.member(t.name, t.ms);
    w.end_object();
    w.member("total_ms", r.total_ms);
    w.key("warnings").begin_array();
    for (const std::string& warning : r.warnings) w.value(warning);
    w.end_array();
}

// The structure's members of a summary: the model, the atoms used and what the reader left out.
void structure_json(JsonWriter& w, const RunReport& r) {
    w.member("model", r.model);
    w.member("atoms_used", r.atoms_used);
    w.member("atoms_in_file", r.info.atoms_in_file);
    w.member("models_in_file", r.info.models_in_file);
    w.member("assembly", r.info.assembly);
    w.member("assembly_name", r.info.assembly_name);
    w.member("assemblies_in_file", r.info.assemblies_in_file);
    w.member("assembly_chains", r.info.assembly_chains);
    w.member("waters_skipped", r.info.waters_skipped);
    w.member("hydrogens_skipped", r.info.hydrogens_skipped);
    w.member("altlocs_skipped", r.info.altlocs_skipped);
    w.member("ligands_skipped", r.info.ligands_skipped);
}

// The summary's first line and its atoms line: what was read and what the reader left out.
std::string structure_lines(const RunReport& r) {
    std::string s =
        "fdmsurf " + r.version + ": " + surface_name(r.surface) + " surface " +
        (r.surface == SurfaceKind::Ses && r.method == SesMethod::Edt ? "(exact, edt) " : "") +
        "of " + detail::printable(r.input) + "\n";
    const StructureInfo& info = r.info;
    const std::string source = info.assembly == 0
                                   ? "in file"
                                   : "in assembly " + info.assembly_name + ", " +
                                         format_count(info.assembly_chains) + " chains";
    s += "  atoms        " + format_count(r.atoms_used) + " used (" +
         format_count(info.atoms_in_file) + " " + source + "; " +
         format_count(info.waters_skipped) + " waters, " + format_count(info.hydrogens_skipped) +
         " hydrogens, ";
    if (info.ligands_skipped != 0) s += format_count(info.ligands_skipped) + " ligand atoms, ";
    if (info.zero_radius_skipped != 0)
        s += format_count(info.zero_radius_skipped) + " of radius 0, ";
    s += format_count(info.altlocs_skipped) + " altlocs left out";
    if (info.models_in_file > 1) {
        s += "; model " + std::to_string(r.model) + " of " + format_count(info.models_in_file);
    }
    s += ")\n";
    return s;
}

// The grid line: its size, spacing and filter, the slabs and the stages run on the host.
std::string grid_line(const GridInfo& g) {
    std::string s = "  grid         " + std::to_string(g.dims[0]) + " x " +
                    std::to_string(g.dims[1]) + " x " + std::to_string(g.dims[2]) +
                    " points, spacing " + format_general(g.spacing) + " Å, ";
    s += g.cutoff > 0.0f ? "cut-off " + format_general(g.cutoff) + " 1/Å" : "no filter";
    if (g.slabs > 1) s += ", " + std::to_string(g.slabs) + " slabs";
    const std::string on_host = host_stages(g);
    if (!on_host.empty()) s += " (" + on_host + " on the host)";
    s += "\n";
    return s;
}

// The mesh's closedness, as the mesh line ends: of the patch with --patch, else of the whole.
std::string closedness(const RunReport& r) {
    const MeshStats& m = r.stats;
    if (!r.patch.empty()) {
        // A patch is open unless the selection holds whole pieces of the surface.
        const std::string on = " on the " + format_count(r.patch_atoms) + " atoms of '" +
                               r.patch + "'";
        if (m.triangles == 0) return "no, an empty patch: no triangle has its three vertices" + on;
        if (r.closed_manifold) return "yes, a patch made of whole closed pieces" + on;
        return "no, an open patch (" + format_count(m.boundary_edges) + " boundary edges)" + on;
    }
    if (r.closed_manifold) return "yes";
    return "no (" + format_count(m.boundary_edges) + " boundary edges, " +
           format_count(m.nonmanifold_edges) + " non-manifold edges)";
}

// The mesh's lines: counts, pieces, closedness, area and volume; the counts alone for a mesh
// drawn where it was computed.
std::string mesh_lines(const RunReport& r) {
    const MeshStats& m = r.stats;
    if (!r.mesh_on_host) {
        return "  mesh         " + format_count(m.vertices) + " vertices, " +
               format_count(m.triangles) +
               " triangles, drawn from the device (pieces, area and volume are not computed: "
               "write a mesh with --image for them)\n";
    }
    std::string s = "  mesh         " + format_count(m.vertices) + " vertices, " +
                    format_count(m.triangles) + " triangles, " + format_count(m.pieces) +
                    " piece(s)";
    if (m.closed_pieces != m.pieces) s += " (" + format_count(m.closed_pieces) + " closed)";
    s += ", closed manifold: " + closedness(r) + "\n";
    s += "  area         " + format_grouped(m.area, 1) + " Å²\n";
    s += "  volume       " + format_grouped(m.volume, 1) + " Å³\n";
    return s;
}

// The lines of --simplify or --max-triangles: the triangles kept, the topology, the deviation.
std::string simplify_lines(const RunReport& r) {
    const SimplifyReport& q = r.simplify;
    const double kept = q.triangles_in ? 100.0 * q.triangles_out / q.triangles_in : 0.0;
    std::string s = "  simplified   " + format_count(q.triangles_in) + " -> " +
                    format_count(q.triangles_out) + " triangles (" + format_grouped(kept, 1) +
                    "%; target " + format_count(q.target_triangles) + "), ";
    if (!q.topology_kept) {
        s += simplify_breakage(q);
    } else if (q.frozen_triangles != 0) {
        s += "topology kept (" + format_count(q.frozen_triangles) +
             " triangles left as they were around collapses that would have broken it)";
    } else {
        s += "topology kept";
    }
    s += "\n";
    if (std::isnan(q.hausdorff) || std::isnan(q.rmsd))
        s += "  deviation    not measured (no triangles)\n";
    else
        s += "  deviation    Hausdorff " + format_general(q.hausdorff) + " Å, RMSD " +
             format_general(q.rmsd) + " Å from the full mesh; " +
             (r.simplify_options.simplifier == Simplifier::kMeshopt ? "meshoptimizer's"
                                                                     : "the collapses'") +
             " estimate " + format_general(q.error) + " Å\n";
    return s;
}

// The properties line (none without --color or --properties), the device, the stage times,
// the output and each picture.
std::string closing_lines(const RunReport& r) {
    std::string s;
    if (r.color != ColorScheme::None || !r.properties.empty()) {
        s += "  properties   atom per vertex";
        if (r.color != ColorScheme::None) s += ", coloured by " + color_name(r);
        for (const std::string& p : r.properties) s += ", " + p;
        s += "\n";
    }
    s += "  device       " + r.device + "\n";
    s += "  time (ms)    ";
    for (const StageTime& t : merge_times(r.times)) {
        s += t.name + " " + format_grouped(t.ms, 1) + (t.gpu ? " (gpu)" : "") + " | ";
    }
    s += "total " + format_grouped(r.total_ms, 1) + "\n";
    s += "  output       " + detail::printable(r.output) + "\n";
    for (const ImageReport& im : r.images) {
        s += "  image        " + detail::printable(im.path) + " (" + std::to_string(im.width) +
             " x " + std::to_string(im.height) + ", " + im.view + " view";
        if (im.rotate[0] != 0.0f || im.rotate[1] != 0.0f || im.rotate[2] != 0.0f)
            s += " turned " + format_general(im.rotate[0]) + "," + format_general(im.rotate[1]) +
                 "," + format_general(im.rotate[2]) + "°";
        s += ", " + format_general(im.pixel_size) + " Å/pixel)\n";
    }
    return s;
}

void grid_json(JsonWriter& w, const GridInfo& g) {
    w.key("grid").begin_object();
    w.key("dims").begin_array();
    for (std::uint32_t d : g.dims) w.value(d);
    w.end_array();
    w.member("spacing", g.spacing);
    w.key("origin").begin_array();
    for (float o : g.origin) w.value(o);
    w.end_array();
    w.member("cutoff", g.cutoff);
    w.member("slabs", g.slabs);
    w.member("host_filter", g.host_filter);
    w.member("host_density", g.host_density);
    w.member("host_marching_cubes", g.host_marching_cubes);
    w.member("host_ses_distance", g.host_ses_distance);
    w.end_object();
}

// The mesh's counts and measures (null where the mesh stayed on the device), the patch and
// the per-vertex properties.
void mesh_json(JsonWriter& w, const RunReport& r) {
    const MeshStats& m = r.stats;
    w.member("vertices", m.vertices);
    w.member("triangles", m.triangles);
    w.member("mesh_on_host", r.mesh_on_host);
    member_or_null(w, "pieces", r.mesh_on_host, m.pieces);
    member_or_null(w, "closed_pieces", r.mesh_on_host, m.closed_pieces);
    member_or_null(w, "boundary_edges", r.mesh_on_host, m.boundary_edges);
    member_or_null(w, "nonmanifold_edges", r.mesh_on_host, m.nonmanifold_edges);
    member_or_null(w, "closed_manifold", r.mesh_on_host, r.closed_manifold);
    w.member("patch", r.patch);
    w.member("patch_atoms", r.patch_atoms);
    w.member("color", color_name(r));
    w.key("properties").begin_array();
    for (const std::string& p : r.properties) w.value(p);
    w.end_array();
    member_or_null(w, "area", r.mesh_on_host, m.area);
    member_or_null(w, "volume", r.mesh_on_host, m.volume);
}

// The members of the "simplify" object: what was asked and what simplify_mesh did.
void simplify_json(JsonWriter& w, const RunReport& r) {
    const SimplifyReport& q = r.simplify;
    w.member("ratio", r.simplify_options.ratio);
    w.member("max_triangles", r.simplify_options.max_triangles);
    w.member("simplifier", to_string(r.simplify_options.simplifier));
    w.member("target_triangles", q.target_triangles);
    w.member("triangles_in", q.triangles_in);
    w.member("vertices_in", q.vertices_in);
    w.member("triangles_out", q.triangles_out);
    w.member("vertices_out", q.vertices_out);
    w.member("welded_vertices", q.welded);
    w.member("topology_kept", q.topology_kept);
    w.member("frozen_triangles", q.frozen_triangles);
    w.member("regions", q.regions);
    w.member("regions_kept_whole", q.regions_kept_whole);
    w.member("attempts", q.attempts);
    w.member("error", q.error);
    w.member("hausdorff", q.hausdorff);
    w.member("rmsd", q.rmsd);
}

void images_json(JsonWriter& w, const RunReport& r) {
    w.key("images").begin_array();
    for (const ImageReport& im : r.images) {
        w.begin_object();
        w.member("path", im.path);
        w.member("view", im.view);
        w.key("rotate").begin_array();
        for (float a : im.rotate) w.value(a);
        w.end_array();
        w.member("width", im.width);
        w.member("height", im.height);
        w.member("pixel_size", im.pixel_size);
        w.member("supersample", im.supersample);
        w.end_object();
    }
    w.end_array();
}

}  // namespace

// Sums the times of stages that share a name (one per slab, say), keeping the first order.
std::vector<StageTime> merge_times(const std::vector<StageTime>& times) {
    std::vector<StageTime> merged;
    for (const StageTime& t : times) {
        auto it = merged.begin();
        while (it != merged.end() && it->name != t.name) ++it;
        if (it == merged.end()) {
            merged.push_back(t);
        } else {
            it->ms += t.ms;
            it->gpu = it->gpu || t.gpu;
        }
    }
    return merged;
}

// `value` with `decimals` digits after the point and commas between thousands: 12,345.6.
std::string format_grouped(double value, int decimals) {
    if (!std::isfinite(value)) return value != value ? "nan" : (value > 0 ? "inf" : "-inf");
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, std::fabs(value));
    std::string digits(buffer);
    const std::size_t point = digits.find('.');
    std::string integer = digits.substr(0, point);
    const std::string fraction = point == std::string::npos ? "" : digits.substr(point);
    std::string grouped;
    for (std::size_t i = 0; i < integer.size(); ++i) {
        if (i != 0 && (integer.size() - i) % 3 == 0) grouped += ',';
        grouped += integer[i];
    }
    // No "-0.0": the sign only when a digit shown is not zero.
    const bool negative =
        std::signbit(value) && digits.find_first_not_of("0.") != std::string::npos;
    return (negative ? "-" : "") + grouped + fraction;
}

std::string format_count(std::uint64_t value) {
    return format_grouped(static_cast<double>(value), 0);
}

std::string format_general(double value, int precision) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
    return buffer;
}

std::string simplify_breakage(const SimplifyReport& s) {
    const MeshStats& m = s.stats_out;
    const MeshStats& in = s.stats_in;
    if (s.stats_in_computed && m.boundary_edges <= in.boundary_edges &&
        m.nonmanifold_edges <= in.nonmanifold_edges &&
        m.nonmanifold_vertices <= in.nonmanifold_vertices &&
        m.inconsistent_edges <= in.inconsistent_edges &&
        m.degenerate_triangles <= in.degenerate_triangles &&
        (!(in.volume > 0.0) || m.volume > 0.0))
        return "simplification changed the topology (no new boundary or non-manifold edge): " +
               format_count(in.pieces) + " -> " + format_count(m.pieces) +
               " pieces, Euler characteristic " + std::to_string(in.euler_characteristic) +
               " -> " + std::to_string(m.euler_characteristic);
    std::string text = "simplification broke closedness: " + format_count(m.nonmanifold_edges) +
                       " non-manifold edges, " + format_count(m.boundary_edges) +
                       " boundary edges, " + format_count(m.nonmanifold_vertices) +
                       " non-manifold vertices";
    if (m.inconsistent_edges != 0)
        text += ", " + format_count(m.inconsistent_edges) + " inconsistently oriented edges";
    return text;
}

std::string simplify_shortfall(const SimplifyReport& q, Simplifier simplifier) {
    const bool meshopt = simplifier == Simplifier::kMeshopt;
    const std::size_t margin =
        std::max<std::size_t>(q.target_triangles / (meshopt ? 10 : 50), 4);
    if (q.triangles_out <= q.target_triangles + margin) return {};
    std::string text = "the simplified mesh has " + format_count(q.triangles_out) +
                       " triangles for a target of " + format_count(q.target_triangles) + ": ";
    if (!meshopt)
        return text + "every collapse left would change its topology or turn a triangle over";
    return text + "meshoptimizer's collapses stopped there (" + format_count(q.frozen_triangles) +
           " triangles kept as they were where they broke the topology)";
}

std::string host_stages(const GridInfo& g) {
    std::vector<std::string> on_host;
    if (g.host_ses_distance) on_host.push_back("exact SES field");
    if (g.host_density) on_host.push_back("density");
    if (g.host_filter) on_host.push_back("Gaussian filter");
    if (g.host_marching_cubes) on_host.push_back("marching cubes");
    std::string s;
    for (std::size_t k = 0; k < on_host.size(); ++k)
        s += (k == 0 ? "" : k + 1 == on_host.size() ? " and " : ", ") + on_host[k];
    return s;
}

std::string color_name(const RunReport& r) {
    if (r.color != ColorScheme::Uniform) return to_string(r.color);
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", r.color_rgb[0], r.color_rgb[1],
                  r.color_rgb[2]);
    return hex;
}

std::string text_summary(const RunReport& r) {
    std::string s = structure_lines(r) + grid_line(r.grid) + mesh_lines(r);
    if (r.simplified) s += simplify_lines(r);
    if (r.optimized) s += "  order        optimised for the vertex cache and vertex fetch\n";
    s += areas_lines(r);
    s += closing_lines(r);
    return s;
}

std::string json_failure(const std::string& version, const std::string& input, int model,
                         const std::string& output, const Error& e, int exit_code) {
    JsonWriter w;
    w.begin_object();
    w.member("version", version);
    w.member("input", input);
    if (model > 0) w.member("model", model);
    if (output.empty())
        w.member("output", nullptr);  // none known (report_failure)
    else
        w.member("output", output);
    w.member("status", "failed");
    w.member("error", std::string(e.what()));
    w.member("error_code", to_string(e.code()));
    w.member("exit_code", exit_code);
    w.end_object();
    return w.str();
}

std::string json_summary(const RunReport& r) {
    JsonWriter w;
    w.begin_object();
    w.member("version", r.version);
    w.member("input", r.input);
    w.member("output", r.output);
    w.member("status", "ok");
    w.member("input_format", to_string(r.info.format));
    w.member("output_format", r.output_format);
    w.member("surface", surface_name(r.surface));
    if (r.surface == SurfaceKind::Ses) w.member("method", to_string(r.method));
    structure_json(w, r);
    grid_json(w, r.grid);
    mesh_json(w, r);
    object_or_null(w, "simplify", r.simplified, [&] { simplify_json(w, r); });
    w.member("optimized", r.optimized);
    areas_json(w, r);
    w.member("device", r.device);
    images_json(w, r);
    times_json(w, r);
    w.end_object();
    return w.str();
}

std::string areas_only_text(const RunReport& r) {
    std::string s = "fdmsurf " + r.version + ": " + surface_name(r.surface) + " areas of " +
                    detail::printable(r.input) + " (exact sphere patches, no mesh)\n";
    s += "  atoms        " + format_count(r.atoms_used) + " used (" +
         format_count(r.info.atoms_in_file) + " in file" +
         (r.info.zero_radius_skipped != 0
              ? "; " + format_count(r.info.zero_radius_skipped) + " of radius 0 left out"
              : std::string()) +
         ")\n";
    s += areas_lines(r);
    s += "  time (ms)    ";
    for (const StageTime& t : merge_times(r.times))
        s += t.name + " " + format_grouped(t.ms, 1) + " | ";
    s += "total " + format_grouped(r.total_ms, 1) + "\n";
    return s;
}

std::string areas_only_json(const RunReport& r) {
    JsonWriter w;
    w.begin_object();
    w.member("version", r.version);
    w.member("input", r.input);
    w.member("output", nullptr);
    w.member("status", "ok");
    w.member("input_format", to_string(r.info.format));
    w.member("surface", surface_name(r.surface));
    structure_json(w, r);
    areas_json(w, r);
    times_json(w, r);
    w.end_object();
    return w.str();
}

}  // namespace fdmsurf::cli
