// simplify_mesh and optimize_mesh through meshoptimizer 0.18 (A. Kapoulkine,
// github.com/zeux/meshoptimizer): edge collapses ordered by the quadric error metric (M. Garland
// and P. S. Heckbert, "Surface simplification using quadric error metrics", SIGGRAPH 1997),
// the vertex-cache order of T. Forsyth's "Linear-speed vertex cache optimisation" (2006) as
// meshoptimizer adapts it, and vertices renumbered by first use.
#include "fdmsurf/simplify.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "fdmsurf/error.hpp"
#include "compare/compare_detail.hpp"
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

// Keeps the vertices the indices use, in their old order, and re-points the indices. `kept`
// (may be null): the vertices of `from` kept, in order.
Mesh compact(const Mesh& from, std::vector<std::uint32_t> indices,
             std::vector<std::uint32_t>* kept_out = nullptr) {
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
    if (kept_out) *kept_out = std::move(kept);
    return out;
}

// Items per chunk of the loops over the whole mesh that run on all threads.
constexpr std::size_t kChunk = 65536;

// Whether two vertices have bit-identical positions: one pass over the positions with an
// open-addressing table (cheaper than meshopt_generateVertexRemap, which walks the indices),
// filled by all threads at once: a slot is taken by compare-and-swap, and two vertices at one
// position probe the same slots, so whichever comes second meets the first.
bool has_duplicate_positions(const std::vector<float>& positions) {
    const std::size_t nv = positions.size() / 3;
    // Twice as many slots as vertices, not rounded up to a power of two (which doubles the table,
    // and its page faults, for 1AON's 2.2 M vertices): a hash's high half times the size, over
    // 2^32, is its first slot.
    const std::size_t size = std::max<std::size_t>(2 * nv, 1);
    std::vector<std::uint32_t> table(size, kUnused);
    auto bits = [&positions](std::size_t v, int a) {
        return std::bit_cast<std::uint32_t>(positions[3 * v + a]);
    };
    std::atomic<bool> found{false};
    parallel_chunks((nv + kChunk - 1) / kChunk, thread_count(0), [&](std::size_t chunk) {
        const std::size_t end = std::min(nv, (chunk + 1) * kChunk);
        for (std::size_t v = chunk * kChunk; v < end && !found.load(std::memory_order_relaxed);
             ++v) {
            std::uint64_t h = bits(v, 0) * 0x9e3779b97f4a7c15ull;
            h = (h ^ bits(v, 1)) * 0xc2b2ae3d27d4eb4full;
            h = (h ^ bits(v, 2)) * 0x165667b19e3779f9ull;
            std::size_t slot = size <= (std::size_t{1} << 32) ? ((h >> 32) * size) >> 32 : h % size;
            for (;; slot = slot + 1 == size ? 0 : slot + 1) {
                std::atomic_ref<std::uint32_t> entry(table[slot]);
                std::uint32_t other = kUnused;
                if (entry.compare_exchange_strong(other, static_cast<std::uint32_t>(v),
                                                  std::memory_order_relaxed)) {
                    break;
                }
                if (bits(other, 0) == bits(v, 0) && bits(other, 1) == bits(v, 1) &&
                    bits(other, 2) == bits(v, 2)) {
                    found = true;
                    return;
                }
            }
        }
    });
    return found;
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
    if (triangles == 0) return 0;  // nothing to keep
    if (options.ratio < 1.0) {
        const double kept = std::round(options.ratio * static_cast<double>(triangles));
        target = std::max<std::size_t>(1, static_cast<std::size_t>(kept));
    }
    if (options.max_triangles != 0) target = std::min(target, options.max_triangles);
    return target;
}

bool weld_exact(const Mesh& mesh, Mesh& welded, std::size_t* merged) {
    if (merged) *merged = 0;
    std::atomic<bool> degenerate{false};
    const std::size_t triangles = mesh.triangle_count();
    parallel_chunks((triangles + kChunk - 1) / kChunk, thread_count(0), [&](std::size_t chunk) {
        const std::size_t end = std::min(triangles, (chunk + 1) * kChunk);
        bool found = false;
        for (std::size_t t = chunk * kChunk; t < end; ++t) {
            const std::uint32_t* c = &mesh.indices[3 * t];
            found |= c[0] == c[1] || c[1] == c[2] || c[2] == c[0];
        }
        if (found) degenerate = true;
    });
    if (!degenerate && !has_duplicate_positions(mesh.positions)) return false;

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
    if (merged) *merged = duplicates;
    std::vector<std::uint32_t> indices;
    indices.reserve(mesh.indices.size());
    for (std::size_t c = 0; c < mesh.indices.size(); c += 3) {
        const std::uint32_t a = first[remap[mesh.indices[c]]];
        const std::uint32_t b = first[remap[mesh.indices[c + 1]]];
        const std::uint32_t d = first[remap[mesh.indices[c + 2]]];
        if (a == b || b == d || d == a) continue;  // collapsed by welding, or degenerate
        indices.insert(indices.end(), {a, b, d});
    }
    welded = compact(mesh, std::move(indices));
    return true;
}

bool topology_kept(const MeshStats& in, const MeshStats& out) {
    return out.pieces == in.pieces && out.euler_characteristic == in.euler_characteristic &&
           out.boundary_edges <= in.boundary_edges &&
           out.nonmanifold_edges <= in.nonmanifold_edges &&
           out.nonmanifold_vertices <= in.nonmanifold_vertices &&
           out.inconsistent_edges <= in.inconsistent_edges &&
           out.degenerate_triangles <= in.degenerate_triangles &&
           (!(in.volume > 0.0) || out.volume > 0.0);
}

void measure_distance(const Mesh& full, const Mesh& simplified,
                      const std::vector<std::uint32_t>& kept, double& hausdorff, double& rmsd) {
    // compare_meshes would weld both meshes, build a tree on each and query both ways; the
    // way back is 0 here (the simplified mesh's vertices are vertices of the full one), so
    // only the full mesh's vertices are queried, against a tree of the simplified triangles,
    // and those kept in the simplified mesh are at distance 0 without a query. Vertices no
    // triangle uses are left out, as compare's clean_mesh drops them.
    trace("simplify-compare: start");
    const std::vector<double> weights = vertex_weights(CleanMesh{full.positions, full.indices});
    trace("simplify-compare: weights");
    const std::size_t nv = full.vertex_count();
    std::vector<std::uint8_t> skip(nv, 1);  // unused, or kept: not queried
    for (std::uint32_t v : full.indices) skip[v] = 0;
    double sum_w = 0.0;
    for (std::uint32_t v : kept) {
        if (!skip[v]) sum_w += weights[v];
        skip[v] = 1;
    }
    std::vector<std::uint32_t> queried;
    queried.reserve(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        if (!skip[v]) queried.push_back(static_cast<std::uint32_t>(v));
    }
    if (queried.empty()) {  // every used vertex kept: no tree to build
        hausdorff = 0.0;
        rmsd = sum_w > 0.0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
        return;
    }
    std::vector<float> points(3 * queried.size());
    for (std::size_t i = 0; i < queried.size(); ++i) {
        std::copy_n(&full.positions[3 * std::size_t{queried[i]}], 3, &points[3 * i]);
    }
    trace("simplify-compare: points");
    const std::vector<double> closest =
        closest_distances(CleanMesh{simplified.positions, simplified.indices}, points);
    trace("simplify-compare: closest points");
    double sum_wd2 = 0.0, largest = 0.0;
    for (std::size_t i = 0; i < closest.size(); ++i) {
        const double d = closest[i], w = weights[queried[i]];
        sum_w += w;
        sum_wd2 += w * d * d;
        largest = std::max(largest, d);
    }
    hausdorff = largest;
    rmsd = sum_w > 0.0 ? std::sqrt(sum_wd2 / sum_w) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace detail

const char* to_string(Simplifier simplifier) noexcept {
    return simplifier == Simplifier::kMeshopt ? "meshopt" : "collapse";
}

Mesh simplify_mesh(const Mesh& mesh, const SimplifyOptions& options, SimplifyReport* report) {
    using namespace detail;
    validate_mesh(mesh, "simplify", true);
    validate_attributes(mesh, "simplify");
    simplify_target(mesh.triangle_count(), options);  // the options' checks, before any work
    SimplifyReport r;
    const auto start = Clock::now();
    trace("simplify: start");
    Mesh welded;
    const Mesh& in = weld_exact(mesh, welded, &r.welded) ? welded : mesh;
    trace("simplify: welded");
    r.triangles_in = in.triangle_count();
    r.vertices_in = in.vertex_count();
    r.target_triangles = simplify_target(r.triangles_in, options);

    Mesh out;
    std::vector<std::uint32_t> kept;  // in's vertices that out keeps, in order
    if (r.target_triangles >= r.triangles_in) {
        out = compact(in, in.indices, &kept);
    } else {
        CellPassStats cells;
        out = compact(in,
                      simplify_in_cells(in.positions, in.indices, r.target_triangles,
                                        options.max_error, 0, &cells, options.simplifier),
                      &kept);
        r.regions = cells.regions;
        r.frozen_triangles = cells.frozen;
        r.regions_kept_whole = cells.gave_up;
        r.attempts = cells.attempts;
        r.error = cells.error;
    }
    trace("simplify: compact");
    r.triangles_out = out.triangle_count();
    r.vertices_out = out.vertex_count();
    r.stats_out = compute_stats(out);
    // The input's statistics: to tell what simplification changed where it may have changed
    // anything (SimplifyReport::stats_in).
    if (options.simplifier == Simplifier::kMeshopt || !r.stats_out.is_closed_manifold()) {
        r.stats_in = compute_stats(in);
        r.stats_in_computed = true;
    }
    r.topology_kept = !r.stats_in_computed || topology_kept(r.stats_in, r.stats_out);
    trace("simplify: stats");
    r.times.push_back({"simplify", ms_since(start), false});

    if (options.measure_distance && out.triangle_count() != 0) {
        const auto t = Clock::now();
        measure_distance(in, out, kept, r.hausdorff, r.rmsd);
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
