// compare_meshes: weighted RMSD of a mesh against a reference (Giard & Macq, "Molecular surface
// mesh generation by filtering electron density map", Int. J. Biomed. Imaging 2010, sec. 4.3),
// with the definitions of shared/tools/meshstat.py compare, and exact closest points through a
// bounding-volume hierarchy.
#include "fdmsurf/compare.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
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

#include "fdmsurf/error.hpp"
#include "compare/compare_detail.hpp"
#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "base/vec3.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {
namespace detail {
namespace {

template <class T>
Vec3 at(const std::vector<T>& p, std::size_t i) {
    return {double(p[3 * i]), double(p[3 * i + 1]), double(p[3 * i + 2])};
}
double squared_distance(const Vec3& a, const Vec3& b) {
    const Vec3 d = sub(a, b);
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}
// The triangle's vertices a, b, c.
std::array<Vec3, 3> corners(const CleanMesh& mesh, std::size_t t) {
    return {at(mesh.positions, mesh.indices[3 * t]), at(mesh.positions, mesh.indices[3 * t + 1]),
            at(mesh.positions, mesh.indices[3 * t + 2])};
}
double triangle_area(const std::array<Vec3, 3>& v) {
    const Vec3 x = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    return 0.5 * std::sqrt(dot(x, x));
}

// Runs a() here and b() on another thread when `parallel`; rethrows a's exception, else b's.
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

// Sorts keys (value << 32 | index) whose indices are 0, 1, 2, ... in order: a stable radix
// sort on the values alone (11, 11 and 10 bits) then gives what std::sort gives, in linear time.
void sort_indexed_keys(std::vector<std::uint64_t>& keys) {
    std::vector<std::uint64_t> buffer(keys.size());
    for (const int shift : {32, 43, 54}) {
        std::size_t count[2048] = {};
        for (std::uint64_t k : keys) ++count[(k >> shift) & 0x7ff];
        std::size_t sum = 0;
        for (std::size_t& c : count) sum += std::exchange(c, sum);
        for (std::uint64_t k : keys) buffer[count[(k >> shift) & 0x7ff]++] = k;
        keys.swap(buffer);
    }
}

// ---------------------------------------------------------------------------------------------
// Welding

std::uint64_t mix64(std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
}

// A 32-bit hash of an integer cell: equal cells, equal hashes (unequal ones may collide).
std::uint64_t cell_hash(std::int64_t x, std::int64_t y, std::int64_t z) {
    return mix64(mix64(mix64(std::uint64_t(x)) ^ std::uint64_t(y)) ^ std::uint64_t(z)) >> 32;
}

std::int64_t cell_of(double coordinate, double cell) {
    constexpr double kLimit = 4.0e18;
    return std::int64_t(std::clamp(std::floor(coordinate / cell), -kLimit, kLimit));
}

// Unites the vertices closer than `tolerance` (<=, as scipy's query_pairs). Vertices are
// bucketed in cells at least `tolerance` wide, sorted by the cell's hash: a close pair lies in
// one cell or, for a vertex near a cell face, in the neighbouring cell across that face. A hash
// collision only puts more pairs to the distance test.
void unite_close_vertices(const std::vector<float>& p, double tolerance, DisjointSets& sets) {
    const std::size_t n = p.size() / 3;
    if (n == 0) return;
    double lo[3], hi[3];
    for (std::size_t k = 0; k < 3; ++k) lo[k] = hi[k] = p[k];
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(p[3 * i + k]));
            hi[k] = std::max(hi[k], double(p[3 * i + k]));
        }
    }
    // Cells much wider than the tolerance, so that few vertices lie near a face, but not so
    // wide that many vertices share one (the pairs inside a cell are all tested).
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double typical = extent / std::cbrt(double(n));
    double cell = tolerance > 0 ? std::max(tolerance, std::min(256 * tolerance, typical)) : 1.0;
    if (!(cell > 0) || !std::isfinite(cell)) cell = 1.0;
    const double margin = 2 * tolerance;  // generous: floor() may round either way

    auto cell_at = [&](std::size_t i, std::size_t k) { return cell_of(p[3 * i + k], cell); };
    std::vector<std::uint64_t> entries(n);  // hash << 32 | vertex
    for (std::size_t i = 0; i < n; ++i) {
        entries[i] = cell_hash(cell_at(i, 0), cell_at(i, 1), cell_at(i, 2)) << 32 | i;
    }
    sort_indexed_keys(entries);
    const double limit = tolerance * tolerance;
    auto try_pair = [&](std::uint32_t a, std::uint32_t b) {
        if (a != b && squared_distance(at(p, a), at(p, b)) <= limit) sets.unite(a, b);
    };
    for (std::size_t begin = 0, end; begin < n; begin = end) {
        end = begin + 1;
        while (end < n && entries[end] >> 32 == entries[begin] >> 32) ++end;
        for (std::size_t i = begin; i < end; ++i) {
            for (std::size_t j = i + 1; j < end; ++j) {
                try_pair(std::uint32_t(entries[i]), std::uint32_t(entries[j]));
            }
        }
    }
    if (tolerance <= 0) return;  // exact duplicates share a cell
    for (std::size_t i = 0; i < n; ++i) {
        int from[3], to[3];
        bool near = false;
        std::int64_t c[3];
        for (std::size_t k = 0; k < 3; ++k) {
            c[k] = cell_at(i, k);
            const double base = double(c[k]) * cell;
            from[k] = p[3 * i + k] - base <= margin ? -1 : 0;
            to[k] = base + cell - p[3 * i + k] <= margin ? 1 : 0;
            near = near || from[k] != 0 || to[k] != 0;
        }
        if (!near) continue;
        for (int dx = from[0]; dx <= to[0]; ++dx) {
            for (int dy = from[1]; dy <= to[1]; ++dy) {
                for (int dz = from[2]; dz <= to[2]; ++dz) {
                    if (dx == 0 && dy == 0 && dz == 0) continue;
                    const std::uint64_t hash = cell_hash(c[0] + dx, c[1] + dy, c[2] + dz);
                    auto it = std::lower_bound(entries.begin(), entries.end(), hash << 32);
                    for (; it != entries.end() && *it >> 32 == hash; ++it) {
                        try_pair(std::uint32_t(i), std::uint32_t(*it));
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
            for (std::size_t k = 0; k < 3; ++k)
                mesh.positions[3 * next + k] = mesh.positions[3 * v + k];
            index[v] = next++;
        }
    }
    mesh.unreferenced = n - next;
    mesh.positions.resize(3 * std::size_t(next));
    for (std::uint32_t& v : mesh.indices) v = index[v];
}

// ---------------------------------------------------------------------------------------------
// Bounding-volume hierarchy over triangles, for exact closest-point queries.

// Morton codes of points quantised in their bounding box (11, 11 and 10 bits): sorting by code
// puts nearby points next to each other. Packed with an index below it into one 64-bit key.
class MortonKeys {
public:
    template <class T>
    explicit MortonKeys(const std::vector<T>& points) {
        const std::size_t n = points.size() / 3;
        double hi[3] = {0, 0, 0};
        for (std::size_t k = 0; k < 3; ++k) lo_[k] = hi[k] = n > 0 ? double(points[k]) : 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t k = 0; k < 3; ++k) {
                lo_[k] = std::min(lo_[k], double(points[3 * i + k]));
                hi[k] = std::max(hi[k], double(points[3 * i + k]));
            }
        }
        for (std::size_t k = 0; k < 3; ++k) {
            scale_[k] = hi[k] > lo_[k] ? kMax[k] / (hi[k] - lo_[k]) : 0.0;
        }
    }
    std::uint64_t operator()(const Vec3& p, std::uint32_t index) const {
        std::uint64_t code = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto q = std::uint64_t(std::clamp((p[k] - lo_[k]) * scale_[k], 0.0, kMax[k]));
            code |= spread(q) << k;
        }
        return code << 32 | index;
    }

private:
    static constexpr double kMax[3] = {2047.0, 2047.0, 1023.0};
    static std::uint64_t spread(std::uint64_t x) {  // bit i to bit 3 i
        x &= 0x7ff;
        x = (x | x << 16) & 0x70000ffull;
        x = (x | x << 8) & 0x700f00full;
        x = (x | x << 4) & 0x430c30c3ull;
        x = (x | x << 2) & 0x49249249ull;
        return x;
    }
    double lo_[3], scale_[3];
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

class TriangleTree {
public:
    explicit TriangleTree(const CleanMesh& mesh);
    // The closest point of the mesh to p; `hint` is a slot to try first (or kNone), and on
    // return the slot of the answer.
    ClosestPoint closest(const Vec3& p, std::uint32_t& hint) const;
    static constexpr std::uint32_t kNone = 0xffffffffu;

private:
    struct Node {
        float lo[3], hi[3];   // rounded outwards: never closer than the triangles inside
        std::uint32_t first;  // leaf: first slot; inner node: index of the first child
        std::uint32_t count;  // leaf: triangles; 0 for an inner node
    };
    static constexpr std::uint32_t kLeafSize = 4;
    static constexpr int kMaxDepth = 96;  // 32 code bits, then halving runs of equal codes

    std::array<double, 6> build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                                const std::vector<std::uint64_t>& keys, int depth);
    static double box_distance(const Node& node, const Vec3& p) {
        double d2 = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const double d = std::max({double(node.lo[k]) - p[k], p[k] - double(node.hi[k]), 0.0});
            d2 += d * d;
        }
        return d2;
    }
    Vec3 vertex(std::uint32_t slot, std::size_t v) const {
        const float* x = &triangles_[9 * std::size_t(slot) + 3 * v];
        return {x[0], x[1], x[2]};
    }
    Vec3 centroid(std::uint32_t slot) const {  // as meshstat and the brute force compute it
        const Vec3 a = vertex(slot, 0), b = vertex(slot, 1), c = vertex(slot, 2);
        return {(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, (a[2] + b[2] + c[2]) / 3.0};
    }

    std::vector<Node> nodes_;
    std::vector<float> triangles_;         // 9 per slot: a, b, c; slots in Morton order
    std::vector<float> spheres_;  // 4 per slot: a centre and a radius holding the triangle
    std::vector<std::uint32_t> original_;  // slot -> triangle of the mesh
    std::vector<std::uint32_t> parent_;    // per node (the root's: 0)
    std::vector<std::uint32_t> leaf_;      // slot -> its leaf
};

TriangleTree::TriangleTree(const CleanMesh& mesh) {
    const std::size_t n = mesh.triangle_count();
    const MortonKeys morton(mesh.positions);
    std::vector<std::uint64_t> keys(n);  // Morton code of the centroid << 32 | triangle
    for (std::size_t t = 0; t < n; ++t) {
        const auto v = corners(mesh, t);
        keys[t] = morton({(v[0][0] + v[1][0] + v[2][0]) / 3, (v[0][1] + v[1][1] + v[2][1]) / 3,
                          (v[0][2] + v[1][2] + v[2][2]) / 3},
                         std::uint32_t(t));
    }
    sort_indexed_keys(keys);
    original_.resize(n);
    triangles_.resize(9 * n);
    for (std::size_t s = 0; s < n; ++s) {
        const auto t = std::uint32_t(keys[s]);
        original_[s] = t;
        for (std::size_t v = 0; v < 3; ++v) {
            for (std::size_t k = 0; k < 3; ++k) {
                triangles_[9 * s + 3 * v + k] = mesh.positions[3 * mesh.indices[3 * t + v] + k];
            }
        }
    }
    spheres_.resize(4 * n);
    for (std::size_t s = 0; s < n; ++s) {
        const Vec3 a = vertex(std::uint32_t(s), 0), b = vertex(std::uint32_t(s), 1),
                   c = vertex(std::uint32_t(s), 2);
        float* sphere = &spheres_[4 * s];
        for (std::size_t k = 0; k < 3; ++k) sphere[k] = float((a[k] + b[k] + c[k]) / 3.0);
        // The radius from the stored (rounded) centre, rounded up: every point of the triangle
        // (a convex combination of its corners) lies within it.
        const Vec3 centre = {sphere[0], sphere[1], sphere[2]};
        const double r2 = std::max({squared_distance(a, centre), squared_distance(b, centre),
                                    squared_distance(c, centre)});
        sphere[3] = round_up(std::sqrt(r2) * (1 + 1e-9));
    }
    nodes_.reserve(2 * n);  // an upper bound (leaves of one triangle); untouched pages cost nothing
    nodes_.push_back(Node{});
    parent_.reserve(2 * n);
    parent_.push_back(0);
    leaf_.resize(n);
    if (n > 0) build(0, 0, std::uint32_t(n), keys, 0);
}

// Splits a run of slots at the highest bit where its Morton codes differ (a spatial split along
// an octree plane, as in Karras 2012), or in the middle where they all agree. Returns the box.
std::array<double, 6> TriangleTree::build(std::uint32_t node, std::uint32_t begin,
                                          std::uint32_t end, const std::vector<std::uint64_t>& keys,
                                          int depth) {
    std::array<double, 6> box;
    if (end - begin <= kLeafSize || depth >= kMaxDepth) {
        for (std::size_t k = 0; k < 3; ++k) {
            box[k] = std::numeric_limits<double>::infinity();
            box[k + 3] = -std::numeric_limits<double>::infinity();
        }
        for (std::uint32_t s = begin; s < end; ++s) {
            for (std::size_t v = 0; v < 3; ++v) {
                const Vec3 x = vertex(s, v);
                for (std::size_t k = 0; k < 3; ++k) {
                    box[k] = std::min(box[k], x[k]);
                    box[k + 3] = std::max(box[k + 3], x[k]);
                }
            }
        }
        nodes_[node].first = begin;
        nodes_[node].count = end - begin;
        for (std::uint32_t s = begin; s < end; ++s) leaf_[s] = node;
    } else {
        std::uint32_t middle = begin + (end - begin) / 2;
        const std::uint64_t differ = (keys[begin] ^ keys[end - 1]) >> 32;
        if (differ != 0) {
            const std::uint64_t bit = std::uint64_t{1} << (95 - std::countl_zero(differ));
            middle = std::uint32_t(
                std::partition_point(keys.begin() + begin, keys.begin() + end,
                                     [bit](std::uint64_t key) { return (key & bit) == 0; }) -
                keys.begin());
        }
        const auto child = std::uint32_t(nodes_.size());
        nodes_[node].first = child;
        nodes_[node].count = 0;
        nodes_.push_back(Node{});
        nodes_.push_back(Node{});
        parent_.push_back(node);
        parent_.push_back(node);
        const std::array<double, 6> left = build(child, begin, middle, keys, depth + 1);
        const std::array<double, 6> right = build(child + 1, middle, end, keys, depth + 1);
        for (std::size_t k = 0; k < 3; ++k) {
            box[k] = std::min(left[k], right[k]);
            box[k + 3] = std::max(left[k + 3], right[k + 3]);
        }
    }
    for (std::size_t k = 0; k < 3; ++k) {
        nodes_[node].lo[k] = round_down(box[k]);
        nodes_[node].hi[k] = round_up(box[k + 3]);
    }
    return box;
}

ClosestPoint TriangleTree::closest(const Vec3& p, std::uint32_t& hint) const {
    ClosestPoint best;
    double best_d2 = std::numeric_limits<double>::infinity();
    double limit = best_d2;        // boxes farther than this (squared) cannot hold a closer point
    double best_centroid_d2 = -1;  // computed on the first tie only
    std::uint32_t best_slot = kNone;
    auto consider = [&](std::uint32_t slot) {
        // A triangle whose bounding sphere is out of reach cannot be closer (nor tie).
        const float* sphere = &spheres_[4 * std::size_t(slot)];
        const double sx = p[0] - sphere[0], sy = p[1] - sphere[1], sz = p[2] - sphere[2];
        const double gap = std::sqrt(sx * sx + sy * sy + sz * sz) - sphere[3];
        if (gap > 0 && gap * gap > limit) return;
        const Vec3 q =
            closest_point_on_triangle(p, vertex(slot, 0), vertex(slot, 1), vertex(slot, 2));
        const double d2 = squared_distance(p, q);
        if (d2 > best_d2) return;
        if (d2 == best_d2) {
            // Equally close (a shared edge or vertex): the nearest centroid wins, as in meshstat,
            // and between centroids as near, the lowest-numbered triangle (as in the brute
            // force): the answer does not depend on the order the triangles are visited in.
            if (slot == best_slot) return;
            if (best_centroid_d2 < 0) best_centroid_d2 = squared_distance(p, centroid(best_slot));
            const double c2 = squared_distance(p, centroid(slot));
            if (c2 > best_centroid_d2 ||
                (c2 == best_centroid_d2 && original_[slot] > original_[best_slot]))
                return;
            best_centroid_d2 = c2;
        } else {
            best_centroid_d2 = -1;
            best_d2 = d2;
            limit = d2 * (1 + 1e-12);  // margin for rounding in the box distances
        }
        best.point = q;
        best_slot = slot;
    };
    if (triangles_.empty()) return best;
    // Depth first from `start`, nearer child first; a box is left out only when it is farther
    // than the best triangle so far.
    std::uint32_t stack[kMaxDepth + 2];
    double stack_d2[kMaxDepth + 2];
    auto descend = [&](std::uint32_t start) {
        int top = 0;
        std::uint32_t current = start;
        while (true) {
            const Node& node = nodes_[current];
            if (node.count != 0) {
                for (std::uint32_t s = node.first; s < node.first + node.count; ++s) consider(s);
            } else {
                const double d_left = box_distance(nodes_[node.first], p);
                const double d_right = box_distance(nodes_[node.first + 1], p);
                const bool left_first = d_left <= d_right;
                const double d_near = left_first ? d_left : d_right;
                const double d_far = left_first ? d_right : d_left;
                if (d_near <= limit) {
                    if (d_far <= limit) {
                        stack[top] = node.first + (left_first ? 1u : 0u);
                        stack_d2[top++] = d_far;
                    }
                    current = node.first + (left_first ? 0u : 1u);
                    continue;
                }
            }
            // Next: the most recently deferred box still in reach.
            while (top > 0 && stack_d2[top - 1] > limit) --top;
            if (top == 0) break;
            current = stack[--top];
        }
    };
    if (hint == kNone) {
        descend(0);
    } else {
        // From the leaf of the hint up to the root: that leaf, then at each level the other
        // child's subtree when its box is in reach. Every leaf is in exactly one of them, so the
        // answer is certified as from the root, with the tight bounds of the nearby leaves
        // found first.
        std::uint32_t node = leaf_[hint];
        descend(node);
        while (node != 0) {
            const std::uint32_t parent = parent_[node];
            const std::uint32_t other = nodes_[parent].first + (nodes_[parent].first == node);
            if (box_distance(nodes_[other], p) <= limit) descend(other);
            node = parent;
        }
    }
    best.distance = std::sqrt(best_d2);
    best.triangle = original_[best_slot];
    hint = best_slot;
    return best;
}

// Calls sink(i, closest point) for every point i, on `threads` threads. Queries run in Morton
// order, each starting from the previous answer: its distance bounds the search from the start,
// so that few boxes are opened.
template <class T, class Sink>
void query(const TriangleTree& tree, const std::vector<T>& points, unsigned threads, Sink&& sink) {
    const std::size_t n = points.size() / 3;
    const MortonKeys morton(points);
    std::vector<std::uint64_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = morton(at(points, i), std::uint32_t(i));
    sort_indexed_keys(order);
    trace("closest points: queries sorted");
    constexpr std::size_t kChunk = 4096;
    parallel_chunks((n + kChunk - 1) / kChunk, threads, [&](std::size_t chunk) {
        std::uint32_t hint = TriangleTree::kNone;
        const std::size_t end = std::min(n, (chunk + 1) * kChunk);
        for (std::size_t k = chunk * kChunk; k < end; ++k) {
            const auto i = std::uint32_t(order[k]);
            sink(i, tree.closest(at(points, i), hint));
        }
    });
}

// sink(i, closest point) for every point i, through a tree of `mesh`.
template <class T, class Sink>
void closest_of(const CleanMesh& mesh, const std::vector<T>& points, unsigned threads,
                Sink&& sink) {
    if (mesh.triangle_count() == 0) throw Error(ErrorCode::InvalidArgument, "compare: empty mesh");
    const TriangleTree tree(mesh);
    trace("closest points: tree built");
    query(tree, points, thread_count(threads), sink);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

CleanMesh clean_mesh(const Mesh& mesh, double tolerance) {
    if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0) {
        throw Error(ErrorCode::InvalidArgument,
                    "compare: positions or indices not a multiple of 3");
    }
    const std::size_t n = mesh.vertex_count();
    if (n >= std::size_t{UINT32_MAX}) {
        throw Error(ErrorCode::InvalidArgument, "compare: too many vertices");
    }
    for (std::uint32_t v : mesh.indices) {
        if (v >= n) {
            throw Error(ErrorCode::InvalidArgument,
                        "compare: vertex index " + std::to_string(v) + " out of range");
        }
    }
    for (float x : mesh.positions) {
        if (!std::isfinite(x))
            throw Error(ErrorCode::Format, "compare: a vertex position is not finite");
    }
    CleanMesh out;
    out.positions = mesh.positions;
    std::vector<std::uint32_t> index(n);
    if (tolerance >= 0 && n > 0) {
        DisjointSets sets(n);  // the root of a class is its lowest index
        unite_close_vertices(out.positions, tolerance, sets);
        std::uint32_t next = 0;
        for (std::size_t v = 0; v < n; ++v) {
            const std::uint32_t root = sets.find(std::uint32_t(v));
            if (root == v) {
                for (std::size_t k = 0; k < 3; ++k)
                    out.positions[3 * next + k] = out.positions[3 * v + k];
                index[v] = next++;
            } else {
                index[v] = index[root];  // root < v: numbered already
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
        piece[t] = sets.find(mesh.indices[3 * t]);
        area[piece[t]] += triangle_area(corners(mesh, t));
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
        const double area = triangle_area(corners(mesh, t));
        for (std::size_t k = 0; k < 3; ++k) {
            sum[mesh.indices[3 * t + k]] += area;
            ++count[mesh.indices[3 * t + k]];
        }
    }
    for (std::size_t v = 0; v < n; ++v) sum[v] = count[v] > 0 ? sum[v] / count[v] : 0.0;
    return sum;
}

double mesh_area(const CleanMesh& mesh) {
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        total += triangle_area(corners(mesh, t));
    return total;
}

double mesh_volume(const CleanMesh& mesh) {
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const auto v = corners(mesh, t);
        total += dot(v[0], cross(v[1], v[2])) / 6.0;
    }
    return total;
}

// The branch order follows Ericson's, and each branch computes its point with the operations
// meshstat.py uses, so that the two agree to the last bit on most points.
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
    std::vector<ClosestPoint> out(points.size() / 3);
    closest_of(mesh, points, threads, [&out](std::size_t i, const ClosestPoint& c) { out[i] = c; });
    return out;
}

std::vector<double> closest_distances(const CleanMesh& mesh, const std::vector<float>& points,
                                      unsigned threads) {
    std::vector<double> out(points.size() / 3);
    closest_of(mesh, points, threads,
               [&out](std::size_t i, const ClosestPoint& c) { out[i] = c.distance; });
    return out;
}

std::vector<ClosestPoint> closest_points_brute_force(const CleanMesh& mesh,
                                                     const std::vector<double>& points) {
    std::vector<ClosestPoint> out(points.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const Vec3 p = at(points, i);
        double best_d2 = std::numeric_limits<double>::infinity(), best_c2 = 0;
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const auto [a, b, c] = corners(mesh, t);
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

CompareResult compare_meshes(const Mesh& reference, const Mesh& tested,
                             const CompareOptions& options) {
    using namespace detail;
    if (!(options.spacing > 0) || !std::isfinite(options.spacing)) {
        throw Error(ErrorCode::InvalidArgument,
                    "compare: spacing must be a positive number of Å, not " +
                        std::to_string(options.spacing));
    }
    if (std::isnan(options.weld_tolerance)) {
        throw Error(ErrorCode::InvalidArgument, "compare: the weld tolerance is not a number");
    }
    const unsigned threads = thread_count(0);
    struct Side {
        CleanMesh mesh;
        std::vector<double> weights;
        std::unique_ptr<TriangleTree> tree;
    };
    Side ref, test;
    // The two meshes are independent until the queries: each is prepared on its own thread.
    auto prepare = [&options](const Mesh& input, const char* name, Side& side) {
        side.mesh = clean_mesh(input, options.weld_tolerance);
        if (options.outer_only) side.mesh = largest_piece(side.mesh);
        side.weights = vertex_weights(side.mesh);
        double total = 0;
        for (double w : side.weights) total += w;
        if (!(total > 0)) {
            throw Error(ErrorCode::Format, std::string("compare: the ") + name +
                                               " mesh has no triangle of non-zero area");
        }
        side.tree = std::make_unique<TriangleTree>(side.mesh);
    };
    run_both([&] { prepare(reference, "reference", ref); },
             [&] { prepare(tested, "tested", test); }, threads > 1);

    // Distances, and for reference vertices the side of the tested mesh they lie on: the sign
    // of (v - closest point) . (b - a) x (c - a) of the closest triangle, as meshstat.py takes it.
    std::vector<double> d_ref(ref.mesh.vertex_count()), d_test(test.mesh.vertex_count());
    std::vector<signed char> side_ref(ref.mesh.vertex_count());
    query(*test.tree, ref.mesh.positions, threads, [&](std::size_t v, const ClosestPoint& cp) {
        const auto [a, b, c] = corners(test.mesh, cp.triangle);
        const double side =
            dot(sub(at(ref.mesh.positions, v), cp.point), cross(sub(b, a), sub(c, a)));
        d_ref[v] = cp.distance;
        side_ref[v] = side > 0 ? 1 : (side < 0 ? -1 : 0);
    });
    query(*ref.tree, test.mesh.positions, threads,
          [&](std::size_t v, const ClosestPoint& cp) { d_test[v] = cp.distance; });

    double sum_w = 0, sum_wd = 0, sum_wd2 = 0, sum_wsd = 0, sum_w_beyond = 0, max_ref = 0;
    for (std::size_t v = 0; v < d_ref.size(); ++v) {
        const double w = ref.weights[v], d = d_ref[v];
        sum_w += w;
        sum_wd += w * d;
        sum_wd2 += w * d * d;
        sum_wsd += w * side_ref[v] * d;
        if (d > options.spacing) sum_w_beyond += w;
        max_ref = std::max(max_ref, d);
    }
    double back_w = 0, back_wd2 = 0, max_test = 0;
    for (std::size_t v = 0; v < d_test.size(); ++v) {
        const double w = test.weights[v], d = d_test[v];
        back_w += w;
        back_wd2 += w * d * d;
        max_test = std::max(max_test, d);
    }

    CompareResult r;
    r.rmsd_weighted = std::sqrt(sum_wd2 / sum_w);
    r.mean_unsigned = sum_wd / sum_w;
    r.mean_signed = sum_wsd / sum_w;
    r.share_beyond_spacing = sum_w_beyond / sum_w;
    r.max_ref_to_test = max_ref;
    r.max_test_to_ref = max_test;
    r.hausdorff = std::max(max_ref, max_test);
    r.rmsd_tested_to_reference = std::sqrt(back_wd2 / back_w);
    r.area_ref = mesh_area(ref.mesh);
    r.area_test = mesh_area(test.mesh);
    r.volume_ref = mesh_volume(ref.mesh);
    r.volume_test = mesh_volume(test.mesh);
    r.area_rel_error = (r.area_test - r.area_ref) / r.area_ref;
    r.volume_rel_error = r.volume_ref != 0 ? (r.volume_test - r.volume_ref) / r.volume_ref
                                           : std::numeric_limits<double>::quiet_NaN();
    r.ref_vertices = ref.mesh.vertex_count();
    r.test_vertices = test.mesh.vertex_count();
    r.ref_triangles = ref.mesh.triangle_count();
    r.test_triangles = test.mesh.triangle_count();
    return r;
}

}  // namespace fdmsurf
