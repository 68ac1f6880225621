// simplify_mesh and optimize_mesh through meshoptimizer 0.18 (A. Kapoulkine,
// github.com/zeux/meshoptimizer): edge collapses ordered by the quadric error metric (M. Garland
// and P. S. Heckbert, "Surface simplification using quadric error metrics", SIGGRAPH 1997),
// the vertex-cache order of T. Forsyth's "Linear-speed vertex cache optimisation" (2006) as
// meshoptimizer adapts it, and vertices renumbered by first use.
#include "fdmsurf/simplify.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_validate.hpp"
#include "simplify/simplify_detail.hpp"

namespace fdmsurf {
namespace detail {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();

// Keeps the vertices the indices use, in their old order, and re-points the indices.
Mesh compact(const Mesh& from, std::vector<std::uint32_t> indices) {
    std::vector<std::uint32_t> remap(from.vertex_count(), kUnused);
    for (std::uint32_t i : indices) remap[i] = 0;
    std::vector<std::uint32_t> kept;
    for (std::size_t v = 0; v < remap.size(); ++v) {
        if (remap[v] == kUnused) continue;
        remap[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(static_cast<std::uint32_t>(v));
    }
    Mesh out;
    for (std::uint32_t& i : indices) i = remap[i];
    out.indices = std::move(indices);
    copy_vertices(from, out, kept);
    return out;
}

}  // namespace

std::size_t simplify_target(std::size_t triangles, const SimplifyOptions& options) {
    if (!(options.ratio > 0.0 && options.ratio <= 1.0)) {
        throw Error(ErrorCode::InvalidArgument,
                    "simplify: the ratio of triangles to keep must be in (0, 1], not " +
                        std::to_string(options.ratio));
    }
    if (!(options.max_error >= 0.0)) {
        throw Error(ErrorCode::InvalidArgument,
                    "simplify: max_error must be >= 0 Å, not " + std::to_string(options.max_error));
    }
    std::size_t target = triangles;
    if (options.ratio < 1.0) {
        const double kept = std::round(options.ratio * static_cast<double>(triangles));
        target = std::max<std::size_t>(1, static_cast<std::size_t>(kept));
    }
    if (options.max_triangles != 0) target = std::min(target, options.max_triangles);
    return target;
}

Mesh weld_exact(const Mesh& mesh, std::size_t* welded) {
    const std::size_t nv = mesh.vertex_count();
    // meshoptimizer numbers the distinct positions by first use; each class is represented
    // by its lowest-numbered vertex, so that the welded mesh keeps the input's vertex order.
    std::vector<std::uint32_t> remap(nv);
    meshopt_generateVertexRemap(remap.data(), mesh.indices.data(), mesh.indices.size(),
                                mesh.positions.data(), nv, 3 * sizeof(float));
    std::vector<std::uint32_t> first(nv, kUnused);
    std::size_t duplicates = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (remap[v] == kUnused) continue;
        if (first[remap[v]] == kUnused) {
            first[remap[v]] = static_cast<std::uint32_t>(v);
        } else {
            ++duplicates;
        }
    }
    if (welded) *welded = duplicates;
    std::vector<std::uint32_t> indices;
    indices.reserve(mesh.indices.size());
    for (std::size_t c = 0; c < mesh.indices.size(); c += 3) {
        const std::uint32_t a = first[remap[mesh.indices[c]]];
        const std::uint32_t b = first[remap[mesh.indices[c + 1]]];
        const std::uint32_t d = first[remap[mesh.indices[c + 2]]];
        if (a == b || b == d || d == a) continue;  // collapsed by welding
        indices.insert(indices.end(), {a, b, d});
    }
    return compact(mesh, std::move(indices));
}

bool topology_kept(const MeshStats& in, const MeshStats& out) {
    return out.boundary_edges <= in.boundary_edges &&
           out.nonmanifold_edges <= in.nonmanifold_edges &&
           out.nonmanifold_vertices <= in.nonmanifold_vertices &&
           out.inconsistent_edges <= in.inconsistent_edges &&
           out.degenerate_triangles <= in.degenerate_triangles &&
           (!(in.volume > 0.0) || out.volume > 0.0);
}

}  // namespace detail

Mesh simplify_mesh(const Mesh& mesh, const SimplifyOptions& options, SimplifyReport* report) {
    using namespace detail;
    validate_mesh(mesh, "simplify", true);
    validate_attributes(mesh, "simplify");
    SimplifyReport r;
    const auto start = Clock::now();
    Mesh in = weld_exact(mesh, &r.welded);
    r.triangles_in = in.triangle_count();
    r.vertices_in = in.vertex_count();
    r.target_triangles = simplify_target(r.triangles_in, options);
    r.stats_in = compute_stats(in);

    Mesh out;
    if (r.target_triangles >= r.triangles_in) {
        out = in;
    } else {
        const std::size_t nv = in.vertex_count();
        const float scale = meshopt_simplifyScale(in.positions.data(), nv, 3 * sizeof(float));
        const float max_error = std::isinf(options.max_error) || scale <= 0.0f
                                    ? std::numeric_limits<float>::max()
                                    : static_cast<float>(options.max_error / scale);
        std::vector<std::uint32_t> indices(in.indices.size());
        float error = 0.0f;
        const std::size_t count = meshopt_simplify(
            indices.data(), in.indices.data(), in.indices.size(), in.positions.data(), nv,
            3 * sizeof(float), 3 * r.target_triangles, max_error, meshopt_SimplifyLockBorder,
            &error);
        indices.resize(count);
        r.attempts = 1;
        r.error = static_cast<double>(error) * scale;
        out = compact(in, std::move(indices));
    }
    r.triangles_out = out.triangle_count();
    r.vertices_out = out.vertex_count();
    r.stats_out = compute_stats(out);
    r.topology_kept = topology_kept(r.stats_in, r.stats_out);
    r.times.push_back({"simplify", ms_since(start), false});

    if (options.measure_distance && out.triangle_count() != 0) {
        const auto t = Clock::now();
        CompareOptions compare;
        compare.weld_tolerance = 0.0;  // welded already
        const CompareResult c = compare_meshes(in, out, compare);
        r.hausdorff = c.hausdorff;
        r.rmsd = c.rmsd_weighted;
        r.times.push_back({"simplify-compare", ms_since(t), false});
    }
    if (report) *report = std::move(r);
    return out;
}

void optimize_mesh(Mesh& mesh) {
    using namespace detail;
    validate_mesh(mesh, "optimize", true);
    validate_attributes(mesh, "optimize");
    const std::size_t nv = mesh.vertex_count();
    std::vector<std::uint32_t> indices(mesh.indices.size());
    meshopt_optimizeVertexCache(indices.data(), mesh.indices.data(), mesh.indices.size(), nv);
    // remap[old] = new, by first use in the new triangle order; kUnused for unused vertices.
    std::vector<std::uint32_t> remap(nv);
    const std::size_t used =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), nv);
    std::vector<std::uint32_t> kept(used);
    for (std::size_t v = 0; v < nv; ++v) {
        if (remap[v] != kUnused) kept[remap[v]] = static_cast<std::uint32_t>(v);
    }
    for (std::uint32_t& i : indices) i = remap[i];
    Mesh out;
    out.indices = std::move(indices);
    copy_vertices(mesh, out, kept);
    mesh = std::move(out);
}

}  // namespace fdmsurf
