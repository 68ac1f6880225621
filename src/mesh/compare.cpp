// compare_meshes: weighted RMSD of a mesh against a reference (Giard & Macq, "Molecular surface
// mesh generation by filtering electron density map", Int. J. Biomed. Imaging 2010, sec. 4.3),
// with the same definitions as shared/tools/meshstat.py compare.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/compare_detail.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {
namespace detail {
namespace {

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 at(const std::vector<double>& p, std::size_t i) { return {p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
double squared_distance(const Vec3& a, const Vec3& b) {
    const Vec3 d = sub(a, b);
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

unsigned thread_count(unsigned requested) {
    if (requested != 0) return requested;
    return std::clamp(std::thread::hardware_concurrency(), 1u, 64u);
}

// Runs body(i) for i in [0, count) on `threads` threads, in chunks taken in order; rethrows the
// first exception.
void parallel_chunks(std::size_t count, unsigned threads,
                     const std::function<void(std::size_t)>& body) {
    threads = unsigned(std::min<std::size_t>(threads, count));
    if (threads <= 1) {
        for (std::size_t i = 0; i < count; ++i) body(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto work = [&] {
        try {
            for (std::size_t i; !failed && (i = next++) < count;) body(i);
        } catch (...) {
            if (!failed.exchange(true)) error = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

// Runs a() here and b() on another thread; rethrows the first exception.
void run_both(const std::function<void()>& a, const std::function<void()>& b, bool parallel) {
    if (!parallel) {
        a();
        b();
        return;
    }
    std::exception_ptr error_b;
    std::thread other([&] {
        try {
            b();
        } catch (...) {
            error_b = std::current_exception();
        }
    });
    std::exception_ptr error_a;
    try {
        a();
    } catch (...) {
        error_a = std::current_exception();
    }
    other.join();
    if (error_a) std::rethrow_exception(error_a);
    if (error_b) std::rethrow_exception(error_b);
}

// Open-addressing map from an integer cell (x, y, z) to a run of the sorted vertex order.
class CellTable {
public:
    struct Cell {
        std::int64_t x, y, z;
    };
    explicit CellTable(std::size_t cells) {
        std::size_t capacity = 16;
        while (capacity < 2 * cells) capacity *= 2;
        slots_.assign(capacity, Slot{});
        mask_ = capacity - 1;
    }
    void insert(const Cell& c, std::uint32_t run) {
        for (std::size_t i = hash(c) & mask_;; i = (i + 1) & mask_) {
            if (slots_[i].run == kEmpty) {
                slots_[i] = {c, run};
                return;
            }
        }
    }
    std::uint32_t find(const Cell& c) const {
        for (std::size_t i = hash(c) & mask_;; i = (i + 1) & mask_) {
            const Slot& s = slots_[i];
            if (s.run == kEmpty) return kEmpty;
            if (s.cell.x == c.x && s.cell.y == c.y && s.cell.z == c.z) return s.run;
        }
    }
    static constexpr std::uint32_t kEmpty = 0xffffffffu;

private:
    struct Slot {
        Cell cell{};
        std::uint32_t run = kEmpty;
    };
    static std::size_t hash(const Cell& c) {
        std::uint64_t h = std::uint64_t(c.x) * 0x9e3779b97f4a7c15ull;
        h ^= std::uint64_t(c.y) * 0xc2b2ae3d27d4eb4full + (h >> 29);
        h ^= std::uint64_t(c.z) * 0x165667b19e3779f9ull + (h >> 32);
        return std::size_t(h ^ (h >> 31));
    }
    std::vector<Slot> slots_;
    std::size_t mask_ = 0;
};

std::int64_t cell_of(double coordinate, double cell) {
    constexpr double kLimit = 4.0e18;
    return std::int64_t(std::clamp(std::floor(coordinate / cell), -kLimit, kLimit));
}

// Unites the vertices closer than `tolerance` (<=, as scipy's query_pairs) through a hash grid
// of cells `tolerance` wide: close pairs lie in the same or adjacent cells.
void unite_close_vertices(const std::vector<double>& p, double tolerance, DisjointSets& sets) {
    const std::size_t n = p.size() / 3;
    const double cell = tolerance > 0 ? tolerance : 1.0;
    const double limit = tolerance * tolerance;
    std::vector<CellTable::Cell> cells(n);
    for (std::size_t i = 0; i < n; ++i) {
        cells[i] = {cell_of(p[3 * i], cell), cell_of(p[3 * i + 1], cell), cell_of(p[3 * i + 2], cell)};
    }
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&cells](std::uint32_t a, std::uint32_t b) {
        const auto &ca = cells[a], &cb = cells[b];
        if (ca.x != cb.x) return ca.x < cb.x;
        if (ca.y != cb.y) return ca.y < cb.y;
        if (ca.z != cb.z) return ca.z < cb.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> run_start;  // runs of equal cells in `order`
    for (std::size_t k = 0; k < n; ++k) {
        const auto& c = cells[order[k]];
        if (k == 0 || c.x != cells[order[k - 1]].x || c.y != cells[order[k - 1]].y ||
            c.z != cells[order[k - 1]].z) {
            run_start.push_back(std::uint32_t(k));
        }
    }
    const std::size_t runs = run_start.size();
    run_start.push_back(std::uint32_t(n));
    CellTable table(runs);
    for (std::size_t r = 0; r < runs; ++r) table.insert(cells[order[run_start[r]]], std::uint32_t(r));

    auto close = [&](std::uint32_t a, std::uint32_t b) {
        return squared_distance(at(p, a), at(p, b)) <= limit;
    };
    for (std::size_t r = 0; r < runs; ++r) {
        const std::uint32_t begin = run_start[r], end = run_start[r + 1];
        for (std::uint32_t i = begin; i < end; ++i) {
            for (std::uint32_t j = i + 1; j < end; ++j) {
                if (close(order[i], order[j])) sets.unite(order[i], order[j]);
            }
        }
        if (tolerance <= 0) continue;  // exact duplicates share a cell
        const CellTable::Cell c = cells[order[begin]];
        // The 13 neighbouring cells after this one in (x, y, z) order: each pair once.
        for (int dx = 0; dx <= 1; ++dx) {
            for (int dy = dx == 0 ? 0 : -1; dy <= 1; ++dy) {
                for (int dz = (dx == 0 && dy == 0) ? 1 : -1; dz <= 1; ++dz) {
                    const std::uint32_t other = table.find({c.x + dx, c.y + dy, c.z + dz});
                    if (other == CellTable::kEmpty) continue;
                    for (std::uint32_t i = begin; i < end; ++i) {
                        for (std::uint32_t j = run_start[other]; j < run_start[other + 1]; ++j) {
                            if (close(order[i], order[j])) sets.unite(order[i], order[j]);
                        }
                    }
                }
            }
        }
    }
}

// Drops vertices no triangle uses, keeping the order of the others.
void drop_unreferenced(CleanMesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    std::vector<std::uint32_t> index(n, 0);
    for (std::uint32_t v : mesh.indices) index[v] = 1;
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (index[v] != 0) {
            for (int k = 0; k < 3; ++k) mesh.positions[3 * next + k] = mesh.positions[3 * v + k];
            index[v] = next++;
        }
    }
    mesh.unreferenced = n - next;
    mesh.positions.resize(3 * std::size_t(next));
    for (std::uint32_t& v : mesh.indices) v = index[v];
}

// ---------------------------------------------------------------------------------------------
// Bounding-volume hierarchy over triangles, for exact closest-point queries.

class TriangleTree {
public:
    explicit TriangleTree(const CleanMesh& mesh);
    // The closest point of the mesh to p; `hint` is a slot to try first (or kNone), and on
    // return the slot of the answer.
    ClosestPoint closest(const Vec3& p, std::uint32_t& hint) const;
    static constexpr std::uint32_t kNone = 0xffffffffu;

private:
    struct Node {
        float lo[3], hi[3];
        std::uint32_t first;  // leaf: first slot; inner node: index of the first child
        std::uint32_t count;  // leaf: triangles; 0 for an inner node
    };
    static constexpr std::uint32_t kLeafSize = 4;

    void build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
               std::vector<std::uint32_t>& order, const std::vector<double>& box,
               const std::vector<double>& centroid);
    Vec3 vertex(std::uint32_t slot, int k) const {
        const double* t = &triangles_[9 * std::size_t(slot) + 3 * std::size_t(k)];
        return {t[0], t[1], t[2]};
    }
    double box_distance(const Node& node, const Vec3& p) const {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double below = double(node.lo[k]) - p[std::size_t(k)];
            const double above = p[std::size_t(k)] - double(node.hi[k]);
            const double d = std::max({below, above, 0.0});
            d2 += d * d;
        }
        return d2;
    }

    std::vector<Node> nodes_;
    std::vector<double> triangles_;   // 9 per slot: a, b, c in leaf order
    std::vector<double> centroids_;   // 3 per slot
    std::vector<std::uint32_t> original_;  // slot -> triangle of the mesh
};

float round_down(double x) {
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
float round_up(double x) {
    float f = float(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

TriangleTree::TriangleTree(const CleanMesh& mesh) {
    const std::size_t n = mesh.triangle_count();
    std::vector<double> box(6 * n), centroid(3 * n);
    for (std::size_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) {
            const double a = mesh.positions[3 * mesh.indices[3 * t] + k];
            const double b = mesh.positions[3 * mesh.indices[3 * t + 1] + k];
            const double c = mesh.positions[3 * mesh.indices[3 * t + 2] + k];
            box[6 * t + k] = std::min({a, b, c});
            box[6 * t + 3 + k] = std::max({a, b, c});
            centroid[3 * t + k] = (a + b + c) / 3.0;
        }
    }
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    nodes_.reserve(n == 0 ? 1 : 2 * ((n + kLeafSize - 1) / kLeafSize) * 2);
    nodes_.push_back(Node{});
    build(0, 0, std::uint32_t(n), order, box, centroid);
    original_ = std::move(order);
    triangles_.resize(9 * n);
    centroids_.resize(3 * n);
    for (std::size_t s = 0; s < n; ++s) {
        const std::uint32_t t = original_[s];
        for (int v = 0; v < 3; ++v) {
            for (int k = 0; k < 3; ++k) {
                triangles_[9 * s + 3 * v + k] = mesh.positions[3 * mesh.indices[3 * t + v] + k];
            }
        }
        for (int k = 0; k < 3; ++k) centroids_[3 * s + k] = centroid[3 * t + k];
    }
}

// Median split along the longest axis of the centroids' bounds.
void TriangleTree::build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                         std::vector<std::uint32_t>& order, const std::vector<double>& box,
                         const std::vector<double>& centroid) {
    double lo[3], hi[3], clo[3], chi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = clo[k] = std::numeric_limits<double>::infinity();
        hi[k] = chi[k] = -std::numeric_limits<double>::infinity();
    }
    for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = order[i];
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], box[6 * t + k]);
            hi[k] = std::max(hi[k], box[6 * t + 3 + k]);
            clo[k] = std::min(clo[k], centroid[3 * t + k]);
            chi[k] = std::max(chi[k], centroid[3 * t + k]);
        }
    }
    Node& here = nodes_[node];
    for (int k = 0; k < 3; ++k) {
        here.lo[k] = round_down(lo[k]);
        here.hi[k] = round_up(hi[k]);
    }
    if (end - begin <= kLeafSize) {
        here.first = begin;
        here.count = end - begin;
        return;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k) {
        if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    }
    const std::uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                     [&centroid, axis](std::uint32_t a, std::uint32_t b) {
                         return centroid[3 * a + std::size_t(axis)] <
                                centroid[3 * b + std::size_t(axis)];
                     });
    const auto child = std::uint32_t(nodes_.size());
    here.first = child;  // `here` is not used after the push_back below
    here.count = 0;
    nodes_.push_back(Node{});
    nodes_.push_back(Node{});
    build(child, begin, middle, order, box, centroid);
    build(child + 1, middle, end, order, box, centroid);
}

ClosestPoint TriangleTree::closest(const Vec3& p, std::uint32_t& hint) const {
    ClosestPoint best;
    double best_d2 = std::numeric_limits<double>::infinity();
    double best_centroid_d2 = -1;  // computed on the first tie only
    std::uint32_t best_slot = kNone;
    auto consider = [&](std::uint32_t slot) {
        const Vec3 q = closest_point_on_triangle(p, vertex(slot, 0), vertex(slot, 1), vertex(slot, 2));
        const double d2 = squared_distance(p, q);
        if (d2 > best_d2) return;
        if (d2 == best_d2) {
            const Vec3 c = {centroids_[3 * slot], centroids_[3 * slot + 1], centroids_[3 * slot + 2]};
            if (slot == best_slot) return;
            if (best_centroid_d2 < 0) {
                best_centroid_d2 = squared_distance(
                    p, {centroids_[3 * best_slot], centroids_[3 * best_slot + 1],
                        centroids_[3 * best_slot + 2]});
            }
            const double c2 = squared_distance(p, c);
            if (!(c2 < best_centroid_d2)) return;
            best_centroid_d2 = c2;
        } else {
            best_centroid_d2 = -1;
        }
        best_d2 = d2;
        best.point = q;
        best_slot = slot;
    };
    if (nodes_.empty() || triangles_.empty()) return best;
    if (hint != kNone) consider(hint);

    // Depth first, nearer child first; a node is skipped only when its box is farther than the
    // best triangle so far (with a margin for rounding), which certifies the answer.
    struct Entry {
        std::uint32_t node;
        double d2;
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0, box_distance(nodes_[0], p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > best_d2 * (1 + 1e-12)) continue;
        const Node& node = nodes_[e.node];
        if (node.count != 0) {
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s) consider(s);
            continue;
        }
        const double d_left = box_distance(nodes_[node.first], p);
        const double d_right = box_distance(nodes_[node.first + 1], p);
        const double limit = best_d2 * (1 + 1e-12);
        if (d_left <= d_right) {
            if (d_right <= limit) stack[top++] = {node.first + 1, d_right};
            if (d_left <= limit) stack[top++] = {node.first, d_left};
        } else {
            if (d_left <= limit) stack[top++] = {node.first, d_left};
            if (d_right <= limit) stack[top++] = {node.first + 1, d_right};
        }
    }
    best.distance = std::sqrt(best_d2);
    best.triangle = original_[best_slot];
    hint = best_slot;
    return best;
}

std::vector<ClosestPoint> query(const TriangleTree& tree, const std::vector<double>& points,
                                unsigned threads) {
    const std::size_t n = points.size() / 3;
    std::vector<ClosestPoint> out(n);
    constexpr std::size_t kChunk = 2048;
    parallel_chunks((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk) {
        std::uint32_t hint = TriangleTree::kNone;  // neighbouring vertices: nearby triangles
        const std::size_t end = std::min(n, (chunk + 1) * kChunk);
        for (std::size_t i = chunk * kChunk; i < end; ++i) out[i] = tree.closest(at(points, i), hint);
    });
    return out;
}

struct Weighted {
    double sum_w = 0, sum_wd = 0, sum_wd2 = 0, sum_wsd = 0, sum_w_beyond = 0, max_d = 0;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

CleanMesh clean_mesh(const Mesh& mesh, double tolerance) {
    if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0) {
        throw Error(ErrorCode::InvalidArgument, "compare: positions or indices not a multiple of 3");
    }
    const std::size_t n = mesh.vertex_count();
    if (n > std::size_t{UINT32_MAX}) throw Error(ErrorCode::InvalidArgument, "compare: too many vertices");
    for (std::uint32_t v : mesh.indices) {
        if (v >= n) {
            throw Error(ErrorCode::InvalidArgument,
                        "compare: vertex index " + std::to_string(v) + " out of range");
        }
    }
    CleanMesh out;
    out.positions.assign(mesh.positions.begin(), mesh.positions.end());
    for (double x : out.positions) {
        if (!std::isfinite(x)) throw Error(ErrorCode::Format, "compare: a vertex position is not finite");
    }
    std::vector<std::uint32_t> index(n);
    if (tolerance >= 0 && n > 0) {
        DisjointSets sets(n);  // the root of a class is its lowest index
        unite_close_vertices(out.positions, tolerance, sets);
        std::uint32_t next = 0;
        for (std::size_t v = 0; v < n; ++v) {
            const std::uint32_t root = sets.find(std::uint32_t(v));
            if (root == v) {
                for (int k = 0; k < 3; ++k) out.positions[3 * next + k] = out.positions[3 * v + k];
                index[v] = next++;
            } else {
                index[v] = index[root];  // root < v: already numbered
            }
        }
        out.welded = n - next;
        out.positions.resize(3 * std::size_t(next));
    } else {
        std::iota(index.begin(), index.end(), 0u);
    }
    out.indices.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t a = index[mesh.indices[3 * t]], b = index[mesh.indices[3 * t + 1]],
                            c = index[mesh.indices[3 * t + 2]];
        if (a == b || b == c || a == c) {
            ++out.collapsed;
            continue;
        }
        out.indices.insert(out.indices.end(), {a, b, c});
    }
    drop_unreferenced(out);
    return out;
}

CleanMesh largest_piece(const CleanMesh& mesh) {
    const std::size_t n = mesh.vertex_count(), m = mesh.triangle_count();
    DisjointSets sets(n);
    for (std::size_t t = 0; t < m; ++t) {
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 1]);
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 2]);
    }
    std::vector<double> area(n, 0.0);
    std::vector<std::uint32_t> piece(m);
    for (std::size_t t = 0; t < m; ++t) {
        const Vec3 a = at(mesh.positions, mesh.indices[3 * t]);
        const Vec3 b = at(mesh.positions, mesh.indices[3 * t + 1]);
        const Vec3 c = at(mesh.positions, mesh.indices[3 * t + 2]);
        const Vec3 x = cross(sub(b, a), sub(c, a));
        piece[t] = sets.find(mesh.indices[3 * t]);
        area[piece[t]] += 0.5 * std::sqrt(dot(x, x));
    }
    // Ties go to the piece of the earliest triangle.
    std::uint32_t best = 0;
    double best_area = -1;
    for (std::size_t t = 0; t < m; ++t) {
        if (area[piece[t]] > best_area) {
            best_area = area[piece[t]];
            best = piece[t];
        }
    }
    CleanMesh out;
    out.positions = mesh.positions;
    out.welded = mesh.welded;
    out.collapsed = mesh.collapsed;
    for (std::size_t t = 0; t < m; ++t) {
        if (piece[t] == best) {
            out.indices.insert(out.indices.end(), mesh.indices.begin() + std::ptrdiff_t(3 * t),
                               mesh.indices.begin() + std::ptrdiff_t(3 * t + 3));
        }
    }
    drop_unreferenced(out);
    return out;
}

std::vector<double> vertex_weights(const CleanMesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    std::vector<double> sum(n, 0.0);
    std::vector<std::uint32_t> count(n, 0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* f = &mesh.indices[3 * t];
        const Vec3 a = at(mesh.positions, f[0]), b = at(mesh.positions, f[1]),
                   c = at(mesh.positions, f[2]);
        const Vec3 x = cross(sub(b, a), sub(c, a));
        const double area = 0.5 * std::sqrt(dot(x, x));
        for (int k = 0; k < 3; ++k) {
            sum[f[k]] += area;
            ++count[f[k]];
        }
    }
    for (std::size_t v = 0; v < n; ++v) sum[v] = count[v] > 0 ? sum[v] / count[v] : 0.0;
    return sum;
}

double mesh_area(const CleanMesh& mesh) {
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec3 a = at(mesh.positions, mesh.indices[3 * t]);
        const Vec3 b = at(mesh.positions, mesh.indices[3 * t + 1]);
        const Vec3 c = at(mesh.positions, mesh.indices[3 * t + 2]);
        const Vec3 x = cross(sub(b, a), sub(c, a));
        total += 0.5 * std::sqrt(dot(x, x));
    }
    return total;
}

double mesh_volume(const CleanMesh& mesh) {
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec3 a = at(mesh.positions, mesh.indices[3 * t]);
        const Vec3 b = at(mesh.positions, mesh.indices[3 * t + 1]);
        const Vec3 c = at(mesh.positions, mesh.indices[3 * t + 2]);
        total += dot(a, cross(b, c)) / 6.0;
    }
    return total;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    const double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    auto along = [](const Vec3& o, const Vec3& dir, double s) {
        return Vec3{o[0] + dir[0] * s, o[1] + dir[1] * s, o[2] + dir[2] * s};
    };
    Vec3 r;
    if (d1 <= 0 && d2 <= 0) {
        return a;
    } else if (d3 >= 0 && d4 <= d3) {
        return b;
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        r = along(a, ab, d1 / (d1 - d3));
    } else if (d6 >= 0 && d5 <= d6) {
        return c;
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        r = along(a, ac, d2 / (d2 - d6));
    } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        r = along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    } else {
        const double denom = va + vb + vc;
        r = along(along(a, ab, vb / denom), ac, vc / denom);
    }
    if (std::isfinite(r[0]) && std::isfinite(r[1]) && std::isfinite(r[2])) return r;
    // A degenerate triangle (zero area): the closest point of its three edges.
    Vec3 best{};
    double best_d2 = std::numeric_limits<double>::infinity();
    const Vec3* ends[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
    for (const auto& e : ends) {
        const Vec3 st = sub(*e[1], *e[0]);
        const double ll = dot(st, st);
        const double u = ll > 0 ? std::clamp(dot(sub(p, *e[0]), st) / ll, 0.0, 1.0) : 0.0;
        const Vec3 q = along(*e[0], st, u);
        if (const double e2 = squared_distance(p, q); e2 < best_d2) {
            best_d2 = e2;
            best = q;
        }
    }
    return best;
}

std::vector<ClosestPoint> closest_points(const CleanMesh& mesh, const std::vector<double>& points,
                                         unsigned threads) {
    if (mesh.triangle_count() == 0) throw Error(ErrorCode::InvalidArgument, "compare: empty mesh");
    const TriangleTree tree(mesh);
    return query(tree, points, thread_count(threads));
}

std::vector<ClosestPoint> closest_points_brute_force(const CleanMesh& mesh,
                                                     const std::vector<double>& points) {
    std::vector<ClosestPoint> out(points.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const Vec3 p = at(points, i);
        double best_d2 = std::numeric_limits<double>::infinity(), best_c2 = 0;
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const Vec3 a = at(mesh.positions, mesh.indices[3 * t]);
            const Vec3 b = at(mesh.positions, mesh.indices[3 * t + 1]);
            const Vec3 c = at(mesh.positions, mesh.indices[3 * t + 2]);
            const Vec3 q = closest_point_on_triangle(p, a, b, c);
            const double d2 = squared_distance(p, q);
            const Vec3 centroid = {(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0,
                                   (a[2] + b[2] + c[2]) / 3.0};
            const double c2 = squared_distance(p, centroid);
            if (d2 < best_d2 || (d2 == best_d2 && c2 < best_c2)) {
                best_d2 = d2;
                best_c2 = c2;
                out[i] = {std::sqrt(d2), q, std::uint32_t(t)};
            }
        }
    }
    return out;
}

}  // namespace detail

CompareResult compare_meshes(const Mesh& reference, const Mesh& tested, const CompareOptions& options) {
    using namespace detail;
    if (!(options.spacing > 0) || !std::isfinite(options.spacing)) {
        throw Error(ErrorCode::InvalidArgument,
                    "compare: spacing must be a positive number of Å, not " +
                        std::to_string(options.spacing));
    }
    if (std::isnan(options.weld_tolerance)) {
        throw Error(ErrorCode::InvalidArgument, "compare: weld tolerance is not a number");
    }
    const unsigned threads = thread_count(0);
    CleanMesh ref, test;
    std::vector<double> w_ref, w_test;
    std::unique_ptr<TriangleTree> ref_tree, test_tree;
    // The two meshes are independent until the queries: prepare each on its own thread.
    auto prepare = [&options](const Mesh& input, const char* name, CleanMesh& mesh,
                              std::vector<double>& weights, std::unique_ptr<TriangleTree>& tree) {
        mesh = clean_mesh(input, options.weld_tolerance);
        if (options.outer_only) mesh = largest_piece(mesh);
        weights = vertex_weights(mesh);
        double total = 0;
        for (double w : weights) total += w;
        if (mesh.triangle_count() == 0 || !(total > 0)) {
            throw Error(ErrorCode::Format,
                        std::string("compare: the ") + name + " mesh has no triangle of non-zero area");
        }
        tree = std::make_unique<TriangleTree>(mesh);
    };
    run_both([&] { prepare(reference, "reference", ref, w_ref, ref_tree); },
             [&] { prepare(tested, "tested", test, w_test, test_tree); }, threads > 1);

    const std::vector<ClosestPoint> ref_to_test = query(*test_tree, ref.positions, threads);
    const std::vector<ClosestPoint> test_to_ref = query(*ref_tree, test.positions, threads);

    Weighted f;  // reference vertices against the tested mesh
    for (std::size_t v = 0; v < ref.vertex_count(); ++v) {
        const ClosestPoint& cp = ref_to_test[v];
        const double w = w_ref[v], d = cp.distance;
        const std::uint32_t* t = &test.indices[3 * std::size_t(cp.triangle)];
        const Vec3 a = at(test.positions, t[0]);
        const Vec3 normal = cross(sub(at(test.positions, t[1]), a), sub(at(test.positions, t[2]), a));
        const double side = dot(sub(at(ref.positions, v), cp.point), normal);
        const double sign = side > 0 ? 1.0 : (side < 0 ? -1.0 : 0.0);
        f.sum_w += w;
        f.sum_wd += w * d;
        f.sum_wd2 += w * d * d;
        f.sum_wsd += w * sign * d;
        if (d > options.spacing) f.sum_w_beyond += w;
        f.max_d = std::max(f.max_d, d);
    }
    Weighted b;  // tested vertices against the reference
    for (std::size_t v = 0; v < test.vertex_count(); ++v) {
        const double w = w_test[v], d = test_to_ref[v].distance;
        b.sum_w += w;
        b.sum_wd2 += w * d * d;
        b.max_d = std::max(b.max_d, d);
    }

    CompareResult r;
    r.rmsd_weighted = std::sqrt(f.sum_wd2 / f.sum_w);
    r.mean_unsigned = f.sum_wd / f.sum_w;
    r.mean_signed = f.sum_wsd / f.sum_w;
    r.share_beyond_spacing = f.sum_w_beyond / f.sum_w;
    r.max_ref_to_test = f.max_d;
    r.max_test_to_ref = b.max_d;
    r.hausdorff = std::max(f.max_d, b.max_d);
    r.rmsd_tested_to_reference = std::sqrt(b.sum_wd2 / b.sum_w);
    r.area_ref = mesh_area(ref);
    r.area_test = mesh_area(test);
    r.volume_ref = mesh_volume(ref);
    r.volume_test = mesh_volume(test);
    r.area_rel_error = (r.area_test - r.area_ref) / r.area_ref;
    r.volume_rel_error = r.volume_ref != 0 ? (r.volume_test - r.volume_ref) / r.volume_ref
                                           : std::numeric_limits<double>::quiet_NaN();
    r.ref_vertices = ref.vertex_count();
    r.test_vertices = test.vertex_count();
    r.ref_triangles = ref.triangle_count();
    r.test_triangles = test.triangle_count();
    return r;
}

}  // namespace fdmsurf
