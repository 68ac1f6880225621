// Removing cavities: closed pieces with negative signed volume (inward-facing shells inside
// another piece): all of them, those below a volume, or those no solvent probe fits in.
#include "mesh/cavities.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include "base/parallel.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_validate.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {

namespace detail {

namespace {

using P3 = std::array<double, 3>;

// Does the ray from p along a fixed, generic direction cross the piece an odd number of times?
// (Möller-Trumbore; the direction avoids the grid's axes and planes.)
bool inside_piece(const P3& p, const std::vector<std::array<P3, 3>>& tris) {
    constexpr P3 d{0.5773502691896258, 0.5773502691896257 + 1.1e-3, 0.5773502691896259 - 2.3e-3};
    int crossings = 0;
    for (const auto& t : tris) {
        const P3 e1{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
        const P3 e2{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
        const P3 q{d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
        const double det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
        if (std::abs(det) < 1e-14) continue;
        const P3 s{p[0] - t[0][0], p[1] - t[0][1], p[2] - t[0][2]};
        const double u = (s[0] * q[0] + s[1] * q[1] + s[2] * q[2]) / det;
        if (u < 0.0 || u > 1.0) continue;
        const P3 r{s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                   s[0] * e1[1] - s[1] * e1[0]};
        const double v = (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        if ((e2[0] * r[0] + e2[1] * r[1] + e2[2] * r[2]) / det > 0.0) ++crossings;
    }
    return crossings % 2 == 1;
}

}  // namespace

AtomsByX::AtomsByX(const Atoms& atoms) : order(atoms.size()), x(atoms.size()) {
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return atoms.xyz[3 * std::size_t{a}] < atoms.xyz[3 * std::size_t{b}];
    });
    for (std::size_t k = 0; k < order.size(); ++k) x[k] = atoms.xyz[3 * std::size_t{order[k]}];
}

double cavity_clearance(const std::vector<std::array<P3, 3>>& tris, const Atoms& atoms, double step,
                        double cap, const AtomsByX* by_x) {
    P3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& t : tris)
        for (const auto& v : t)
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    // At most about 20,000 samples, whatever the void's size.
    const double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    step = std::max(step, std::cbrt(box / 20000.0));
    // The atoms that can be nearest to a point of the box: within the largest radius plus the
    // box's diagonal of it, or, with a cap, within cap + the largest radius (an atom farther from
    // every point of the box cannot bring the clearance under the cap).
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r);
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const double margin = std::isfinite(cap) ? cap + r_max + 1e-3 : diagonal + 2.0 * r_max;
    std::vector<std::array<double, 4>> near;
    auto consider = [&](std::size_t i) {
        const P3 ci{atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
        bool close = true;
        for (int a = 0; a < 3; ++a)
            close = close && ci[a] > lo[a] - margin && ci[a] < hi[a] + margin;
        if (close) near.push_back({ci[0], ci[1], ci[2], double(atoms.radius[i])});
    };
    if (by_x) {
        // Only the atoms of the box's x range (the min below does not depend on their order).
        const auto first = std::upper_bound(by_x->x.begin(), by_x->x.end(), lo[0] - margin);
        const auto last = std::lower_bound(first, by_x->x.end(), hi[0] + margin);
        for (auto it = first; it != last; ++it) consider(by_x->order[it - by_x->x.begin()]);
    } else {
        for (std::size_t i = 0; i < atoms.size(); ++i) consider(i);
    }
    auto clearance = [&](const P3& p) {
        double best = cap;
        for (const auto& a : near)
            best = std::min(best, std::hypot(p[0] - a[0], p[1] - a[1], p[2] - a[2]) - a[3]);
        return best;
    };
    // Samples on a grid inside the piece (ending at the first that reaches the cap), keeping
    // the best four inside; the inside test (a ray against every triangle) is the dear part, so
    // it is asked only of samples that would enter the four. Then a pattern search from those.
    constexpr std::size_t kSeeds = 4;
    std::vector<std::pair<double, P3>> samples;  // best first
    for (double z = lo[2] + 0.5 * step; z < hi[2]; z += step)
        for (double y = lo[1] + 0.5 * step; y < hi[1]; y += step)
            for (double x = lo[0] + 0.5 * step; x < hi[0]; x += step) {
                const P3 p{x, y, z};
                const double c = clearance(p);
                if (samples.size() == kSeeds && c <= samples.back().first) continue;
                if (!inside_piece(p, tris)) continue;
                if (c >= cap) return cap;
                auto at = std::find_if(samples.begin(), samples.end(),
                                       [&](const auto& e) { return c > e.first; });
                samples.insert(at, {c, p});
                if (samples.size() > kSeeds) samples.pop_back();
            }
    if (samples.empty()) return -std::numeric_limits<double>::infinity();
    const std::size_t keep = samples.size();
    double best = samples.front().first;
    for (std::size_t k = 0; k < keep && best < cap; ++k) {
        auto [value, p] = samples[k];
        // All 26 directions of a cube's neighbours: at a point where several atoms are equally
        // near (a kink of the min), only a diagonal move raises all their distances at once.
        for (double h = 0.5 * step; h > 1e-3 && value < cap; h *= 0.5) {
            bool moved = true;
            while (moved && value < cap) {
                moved = false;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            if (dx == 0 && dy == 0 && dz == 0) continue;
                            const double len = std::sqrt(double(dx * dx + dy * dy + dz * dz));
                            const P3 q{p[0] + h * dx / len, p[1] + h * dy / len,
                                       p[2] + h * dz / len};
                            const double c = clearance(q);
                            if (c > value && inside_piece(q, tris)) value = c, p = q, moved = true;
                        }
            }
        }
        best = std::max(best, value);
    }
    return best;
}

std::size_t remove_pieces_if(Mesh& mesh, const std::function<bool(double)>& candidate,
                             const std::function<bool(const MeshPiece&)>& remove,
                             bool concurrent) {
    validate_mesh(mesh, "remove_cavities", true);
    validate_attributes(mesh, "remove_cavities");
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    if (nt == 0) return 0;
    const VertexPieces parts = vertex_pieces(mesh);
    // Signed volume per piece (divergence theorem), summed chunk by chunk in a fixed order.
    const float* p = mesh.positions.data();
    std::vector<double> volume(parts.count, 0.0);
    sum_by_piece<double>(
        chunk_count(nt, kTriangleChunk), thread_count(),
        [&](std::size_t k, PieceRuns<double>& runs) {
            for (std::size_t t = k * kTriangleChunk; t < std::min(nt, (k + 1) * kTriangleChunk);
                 ++t) {
                const float* a = p + 3 * mesh.indices[3 * t];
                const float* b = p + 3 * mesh.indices[3 * t + 1];
                const float* c = p + 3 * mesh.indices[3 * t + 2];
                const double det = double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
                                   double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
                                   double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0]);
                piece_sum(runs, parts.of_vertex[mesh.indices[3 * t]]) += det / 6.0;
            }
        },
        [&](std::uint32_t piece, double v) { volume[piece] += v; });
    // The triangles of each candidate piece, for the predicate.
    std::vector<std::uint32_t> candidate_of(parts.count, UINT32_MAX);
    std::vector<MeshPiece> pieces;
    for (std::size_t q = 0; q < parts.count; ++q) {
        if (!candidate(volume[q])) continue;
        candidate_of[q] = static_cast<std::uint32_t>(pieces.size());
        pieces.push_back(MeshPiece{volume[q], {}});
    }
    if (pieces.empty()) return 0;
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t c = candidate_of[parts.of_vertex[mesh.indices[3 * t]]];
        if (c == UINT32_MAX) continue;
        std::array<P3, 3> tri;
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) tri[k][a] = p[3 * mesh.indices[3 * t + k] + a];
        pieces[c].triangles.push_back(tri);
    }
    // The verdicts, in piece order, on all threads when `remove` allows it.
    std::vector<char> verdict(pieces.size(), 0);
    parallel_chunks(pieces.size(), concurrent ? thread_count() : 1,
                    [&](std::size_t i) { verdict[i] = remove(pieces[i]) ? 1 : 0; });
    std::vector<char> drop(parts.count, 0);
    std::size_t removed = 0;
    for (std::size_t q = 0; q < parts.count; ++q) {
        if (candidate_of[q] == UINT32_MAX || !verdict[candidate_of[q]]) continue;
        drop[q] = 1;
        ++removed;
    }
    if (removed == 0) return 0;
    // Every per-vertex array (positions, normals, atoms, colours, scalars) follows the vertices;
    // unreferenced vertices are kept, as before.
    const auto dropped = [&](std::uint32_t v) {
        return parts.of_vertex[v] != kNoPiece && drop[parts.of_vertex[v]];
    };
    std::vector<std::uint32_t> remap(nv, UINT32_MAX);
    std::vector<std::uint32_t> kept;
    for (std::size_t v = 0; v < nv; ++v) {
        if (dropped(static_cast<std::uint32_t>(v))) continue;
        remap[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(static_cast<std::uint32_t>(v));
    }
    keep_vertices(mesh, kept);
    std::size_t out = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        if (dropped(mesh.indices[3 * t])) continue;
        for (int k = 0; k < 3; ++k) mesh.indices[3 * out + k] = remap[mesh.indices[3 * t + k]];
        ++out;
    }
    mesh.indices.resize(3 * out);
    return removed;
}

std::size_t remove_cavities_if(Mesh& mesh, const std::function<bool(const MeshPiece&)>& remove,
                               bool concurrent) {
    return remove_pieces_if(
        mesh, [](double volume) { return volume < 0.0; }, remove, concurrent);
}

std::size_t remove_cavities_without_probe(Mesh& mesh, const Atoms& atoms, double probe,
                                          double step) {
    // A void that holds a probe ball encloses at least the ball's volume; below half of it
    // (room for the approximate surface's own error) no search is needed.
    const double half_ball = 0.5 * 4.0 / 3.0 * 3.14159265358979 * probe * probe * probe;
    std::optional<AtomsByX> by_x;  // built at the first void that needs a search
    std::once_flag built;
    return remove_cavities_if(
        mesh,
        [&](const MeshPiece& c) {
            if (-c.volume < half_ball) return true;
            std::call_once(built, [&] { by_x.emplace(atoms); });
            return cavity_clearance(c.triangles, atoms, step, probe, &*by_x) < probe;
        },
        true);
}

std::size_t remove_specks(Mesh& mesh, double max_volume) {
    return remove_pieces_if(
        mesh, [&](double volume) { return std::abs(volume) < max_volume; },
        [](const MeshPiece&) { return true; });
}

}  // namespace detail

std::size_t remove_cavities(Mesh& mesh, double max_volume) {
    return detail::remove_cavities_if(
        mesh, [&](const detail::MeshPiece& c) { return -c.volume < max_volume; });
}

}  // namespace fdmsurf
