// Mesh statistics: area, signed volume, connected pieces, and the edge and vertex topology checks,
// on all of the machine's threads (the sums are exact integer sums, base/fixed_sum.hpp: the same
// figures for any number of threads and any order of the triangles), piece by piece: the
// analysis the cavity removal shares, and its update when pieces are removed.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <numeric>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

#include "base/cpu_features.hpp"
#include "base/fixed_sum.hpp"
#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {
namespace detail {
namespace {

using Index = std::uint32_t;

bool is_degenerate(const Index* t) { return (t[0] == t[1]) | (t[1] == t[2]) | (t[2] == t[0]); }

// The corners at each vertex of the triangles that are not degenerate, each as the corner's
// next and previous vertex (the triangle runs v -> next -> prev), so that the edges around a
// vertex are read in one run, not gathered from the triangles.
// Vertices are taken in blocks of 2^12 to 2^16 (at least four per thread where the mesh allows):
// the corners of a block's vertices, from the triangles that hold them, fit in the cache, where
// its vertices are then read, and nothing as large as every corner of the mesh is written to
// memory and read back.
int block_shift(std::size_t vertices, unsigned threads) {
    int shift = 16;
    while (shift > 12 && (vertices >> shift) < 4 * std::size_t{threads}) --shift;
    return shift;
}

// The corners of the vertices [lo, hi): next[i] and prev[i] for i in [begin(v), end(v)), placed
// from the triangles [first, last) (all those with a corner in the block); one per thread, its
// memory kept from block to block. 16 more entries than corners, so that 16 can be read from
// any vertex's first.
class BlockCorners {
public:
    void build(const std::vector<Index>& idx, Index lo, Index hi, std::size_t first,
               std::size_t last) {
        lo_ = lo;
        const Index size = hi - lo;
        start_.assign(std::size_t{size} + 1, 0);
        Index* count = start_.data() + 1;
        for (std::size_t t = first; t < last; ++t) {
            const Index* tri = &idx[3 * t];
            if (is_degenerate(tri)) continue;
            for (int k = 0; k < 3; ++k)
                if (tri[k] - lo < size) ++count[tri[k] - lo];
        }
        for (Index v = 0; v < size; ++v) start_[v + 1] += start_[v];
        if (std::size_t{start_[size]} + 16 > capacity_) {
            capacity_ = std::size_t{start_[size]} + 16;
            // Filled below, so not zeroed first; the 16 past the end are never compared.
            next_.reset(new Index[capacity_]);
            prev_.reset(new Index[capacity_]());
        }
        cursor_.assign(start_.begin(), start_.end() - 1);
        for (std::size_t t = first; t < last; ++t) {
            const Index* tri = &idx[3 * t];
            if (is_degenerate(tri)) continue;
            for (int k = 0; k < 3; ++k) {
                if (tri[k] - lo >= size) continue;
                const Index at = cursor_[tri[k] - lo]++;
                next_[at] = tri[(k + 1) % 3];
                prev_[at] = tri[(k + 2) % 3];
            }
        }
    }
    Index begin(Index v) const { return start_[v - lo_]; }
    Index end(Index v) const { return start_[v - lo_ + 1]; }
    Index next(Index i) const { return next_[i]; }
    Index prev(Index i) const { return prev_[i]; }
    const Index* prevs(Index v) const { return &prev_[begin(v)]; }

private:
    Index lo_ = 0;
    std::vector<Index> start_, cursor_;
    std::unique_ptr<Index[]> next_, prev_;
    std::size_t capacity_ = 0;
};

// Where the corners of each block lie: every block's range of triangles, found in one pass
// over them (a mesh whose triangles come in the order of their vertices, as a surface from a
// grid does, gives short ranges). When the ranges together exceed three times the triangles,
// the blocks are the parts' vertex ranges instead, each read from all triangles. The vertices
// are split into `parts` runs of whole blocks, one per thread.
struct CornerPlan {
    std::size_t parts = 1;
    std::vector<Index> block_start;        // the blocks' first vertices, and n at the end
    std::vector<std::size_t> first, last;  // each block's triangles [first, last)
    std::vector<std::size_t> part_block;   // each part's first block, and the block count
    std::vector<Index> degenerate;         // the degenerate triangles, in order
};

// Throws as validate_mesh does when an index is out of range (found in the same pass).
CornerPlan plan_corners(const Mesh& mesh, const char* who, unsigned threads) {
    const std::vector<Index>& idx = mesh.indices;
    const std::size_t n = mesh.vertex_count(), nt = mesh.triangle_count();
    const int shift = block_shift(n, threads);
    const std::size_t blocks = (n + (std::size_t{1} << shift) - 1) >> shift;
    CornerPlan plan;
    plan.parts = std::max<std::size_t>(1, std::min<std::size_t>(threads, blocks));
    // Each part of the triangles on a thread, with ranges of its own.
    struct Seen {
        std::vector<std::size_t> first, last;
        std::vector<Index> degenerate;
        Index largest = 0;
    };
    std::vector<Seen> seen(plan.parts);
    parallel_chunks(plan.parts, threads, [&](std::size_t part) {
        Seen& own = seen[part];
        own.first.assign(blocks, nt);
        own.last.assign(blocks, 0);
        std::size_t* first = own.first.data();
        std::size_t* last = own.last.data();
        Index largest = 0;
        for (std::size_t t = part * nt / plan.parts; t < (part + 1) * nt / plan.parts; ++t) {
            const Index* tri = &idx[3 * t];
            largest = std::max({largest, tri[0], tri[1], tri[2]});
            if (largest >= n) break;  // checked below
            if (is_degenerate(tri)) own.degenerate.push_back(Index(t));
            // Mostly all three in one block.
            const std::size_t b0 = tri[0] >> shift, b1 = tri[1] >> shift, b2 = tri[2] >> shift;
            first[b0] = std::min(first[b0], t);
            last[b0] = t + 1;
            if (b1 != b0) first[b1] = std::min(first[b1], t), last[b1] = t + 1;
            if (b2 != b0 && b2 != b1) first[b2] = std::min(first[b2], t), last[b2] = t + 1;
        }
        own.largest = largest;
    });
    std::size_t spanned = 0;
    plan.first.assign(blocks, nt);
    plan.last.assign(blocks, 0);
    for (const Seen& own : seen) {
        if (own.largest >= n) validate_mesh(mesh, who, false);  // throws
        plan.degenerate.insert(plan.degenerate.end(), own.degenerate.begin(), own.degenerate.end());
        for (std::size_t b = 0; b < blocks; ++b) {
            plan.first[b] = std::min(plan.first[b], own.first[b]);
            plan.last[b] = std::max(plan.last[b], own.last[b]);
        }
    }
    for (std::size_t b = 0; b < blocks; ++b)
        spanned += plan.last[b] > plan.first[b] ? plan.last[b] - plan.first[b] : 0;
    if (spanned <= 3 * nt) {
        for (std::size_t b = 0; b <= blocks; ++b)
            plan.block_start.push_back(Index(std::min(n, b << shift)));
        for (std::size_t part = 0; part <= plan.parts; ++part)
            plan.part_block.push_back(part * blocks / plan.parts);
    } else {
        plan.first.assign(plan.parts, 0);
        plan.last.assign(plan.parts, nt);
        for (std::size_t part = 0; part <= plan.parts; ++part) {
            plan.block_start.push_back(Index(std::min(n, part * blocks / plan.parts << shift)));
            plan.part_block.push_back(part);
        }
    }
    return plan;
}

using Pieces = VertexPieces;
constexpr Index no_piece = kNoPiece;

// One chunk's contribution to one piece (sum_by_piece adds them up): its counts, and its area
// and volume as sums that any order of the triangles gives alike.
struct Partial {
    MeshStats stats;  // the counts
    FixedSum area, volume;
    long faces = 0;  // non-degenerate triangles
};
using Runs = PieceRuns<Partial>;
// A chunk of triangles: its sums per piece (in any order) and its runs of one piece's
// triangles, in order (MeshAnalysis::runs, which the cavity removal moves by).
struct TriangleChunk {
    Runs sums;
    std::vector<TriangleRun> runs;
};

// The signed volume (divergence theorem) and the area of triangle (a, b, d).
double triangle_volume(const std::array<double, 3>& a, const std::array<double, 3>& b,
                       const std::array<double, 3>& d) {
    return (a[0] * (b[1] * d[2] - b[2] * d[1]) + a[1] * (b[2] * d[0] - b[0] * d[2]) +
            a[2] * (b[0] * d[1] - b[1] * d[0])) /
           6.0;
}
double triangle_area(const std::array<double, 3>& a, const std::array<double, 3>& b,
                     const std::array<double, 3>& d) {
    const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const std::array<double, 3> w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const std::array<double, 3> cr{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                   u[0] * w[1] - u[1] * w[0]};
    return 0.5 * std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
}

// The corners of up to kBatch triangles, coordinate by coordinate (row 3 k + a: corner k, axis
// a), and their signed volumes and areas: computed for a batch at once, four at a time where
// the CPU has AVX2, then added to the sums as a batch (FixedSum: in any order, the same sum).
constexpr std::size_t kBatch = 64;
struct TriangleBatch {
    alignas(32) float corners[9][kBatch] = {};
    alignas(32) double volume[kBatch] = {};
    alignas(32) double area[kBatch] = {};
};

// triangle_volume and (with `area`) triangle_area of the batch's first n triangles, into its
// `volume` and `area`.
void batch_terms_plain(TriangleBatch& b, std::size_t n, bool area) {
    for (std::size_t i = 0; i < n; ++i) {
        std::array<double, 3> p[3];
        for (int k = 0; k < 3; ++k)
            for (int x = 0; x < 3; ++x) p[k][x] = b.corners[3 * k + x][i];
        b.volume[i] = triangle_volume(p[0], p[1], p[2]);
        if (area) b.area[i] = triangle_area(p[0], p[1], p[2]);
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same on four triangles at a time: the same operations in the same order, each lane
// rounded as the plain code rounds (no fused multiply-add: the target is AVX2 alone), so the
// same bits. Lanes past n compute on stale corners and are not read.
__attribute__((target("avx2"))) void batch_terms_avx2(TriangleBatch& b, std::size_t n,
                                                      bool area) {
#define FDMSURF_CORNER(row) _mm256_cvtps_pd(_mm_load_ps(&b.corners[row][i]))
    const __m256d six = _mm256_set1_pd(6.0), half = _mm256_set1_pd(0.5);
    for (std::size_t i = 0; i < n; i += 4) {
        const __m256d ax = FDMSURF_CORNER(0), ay = FDMSURF_CORNER(1), az = FDMSURF_CORNER(2);
        const __m256d bx = FDMSURF_CORNER(3), by = FDMSURF_CORNER(4), bz = FDMSURF_CORNER(5);
        const __m256d dx = FDMSURF_CORNER(6), dy = FDMSURF_CORNER(7), dz = FDMSURF_CORNER(8);
        const __m256d t0 =
            _mm256_mul_pd(ax, _mm256_sub_pd(_mm256_mul_pd(by, dz), _mm256_mul_pd(bz, dy)));
        const __m256d t1 =
            _mm256_mul_pd(ay, _mm256_sub_pd(_mm256_mul_pd(bz, dx), _mm256_mul_pd(bx, dz)));
        const __m256d t2 =
            _mm256_mul_pd(az, _mm256_sub_pd(_mm256_mul_pd(bx, dy), _mm256_mul_pd(by, dx)));
        _mm256_store_pd(&b.volume[i], _mm256_div_pd(_mm256_add_pd(_mm256_add_pd(t0, t1), t2), six));
        if (!area) continue;
        const __m256d ux = _mm256_sub_pd(bx, ax), uy = _mm256_sub_pd(by, ay),
                      uz = _mm256_sub_pd(bz, az);
        const __m256d wx = _mm256_sub_pd(dx, ax), wy = _mm256_sub_pd(dy, ay),
                      wz = _mm256_sub_pd(dz, az);
        const __m256d c0 = _mm256_sub_pd(_mm256_mul_pd(uy, wz), _mm256_mul_pd(uz, wy));
        const __m256d c1 = _mm256_sub_pd(_mm256_mul_pd(uz, wx), _mm256_mul_pd(ux, wz));
        const __m256d c2 = _mm256_sub_pd(_mm256_mul_pd(ux, wy), _mm256_mul_pd(uy, wx));
        const __m256d squares = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(c0, c0), _mm256_mul_pd(c1, c1)), _mm256_mul_pd(c2, c2));
        _mm256_store_pd(&b.area[i], _mm256_mul_pd(half, _mm256_sqrt_pd(squares)));
    }
#undef FDMSURF_CORNER
}
#endif

void batch_terms(TriangleBatch& b, std::size_t n, bool area) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (has_avx2()) return batch_terms_avx2(b, n, area);
#endif
    batch_terms_plain(b, n, area);
}

// Signed volume and triangle counts of the triangles in chunk k, and (kStats, for the
// statistics) their area and the degenerate ones; the cavity removal alone needs the volumes.
// A run of one piece's triangles a batch at a time: corners gathered, terms computed together,
// added to the piece's sums; the run itself kept in order.
template <bool kStats>
void triangle_chunk(const Mesh& mesh, const Pieces& pieces, std::size_t k, TriangleChunk& out) {
    const Index* idx = mesh.indices.data();
    const float* positions = mesh.positions.data();
    const std::size_t first = k * kTriangleChunk;
    const std::size_t end = std::min(mesh.triangle_count(), first + kTriangleChunk);
    TriangleBatch batch;
    for (std::size_t t = first; t < end;) {
        const Index piece = pieces.of_vertex[idx[3 * t]];
        Partial& part = piece_sum_any_order(out.sums, piece);
        if (out.runs.empty() || out.runs.back().piece != piece) out.runs.push_back({piece, 0});
        std::size_t n = 0;
        while (t + n < end && n < kBatch && pieces.of_vertex[idx[3 * (t + n)]] == piece) {
            const Index* tri = idx + 3 * (t + n);
            for (int c = 0; c < 3; ++c) {
                const float* p = positions + 3 * std::size_t{tri[c]};
                for (int x = 0; x < 3; ++x) batch.corners[3 * c + x][n] = p[x];
            }
            if constexpr (kStats) {
                const bool degenerate = is_degenerate(tri);
                part.stats.degenerate_triangles += degenerate;
                part.faces += !degenerate;
            }
            ++n;
        }
        batch_terms(batch, n, kStats);
        part.stats.triangles += n;
        out.runs.back().triangles += std::uint32_t(n);
        part.volume.add(batch.volume, n);
        if constexpr (kStats) part.area.add(batch.area, n);
        t += n;
    }
}

// One use of an edge {v, other} by the triangle whose corner at v is `corner` (local number).
struct LocalUse {
    Index other;
    Index corner;
    bool forward;  // the triangle runs v -> other
};

// Which of the 16 entries from `slots` on hold x: bit j for slots[j] (SSE2 compares four at once).
std::uint32_t slots_holding(const Index* slots, Index x) {
#if defined(__SSE2__)
    const __m128i key = _mm_set1_epi32(int(x));
    const auto equal = [&](int j) {
        return _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(slots + j)), key);
    };
    const __m128i low = _mm_packs_epi32(equal(0), equal(4));
    const __m128i high = _mm_packs_epi32(equal(8), equal(12));
    return std::uint32_t(_mm_movemask_epi8(_mm_packs_epi16(low, high)));
#else
    std::uint32_t holding = 0;
    for (int j = 0; j < 16; ++j) holding |= std::uint32_t(slots[j] == x) << j;
    return holding;
#endif
}

// Whether the corners at v form one closed fan: each corner's next vertex is the previous
// vertex of exactly one other corner, and following that link from the first corner visits
// every corner once and comes back. Then each edge at v is used by two triangles in opposite
// directions and the corners make one fan, which is what the general count below would find.
// At most 16 corners; otherwise false.
bool closed_fan(const BlockCorners& corners, Index v) {
    const Index first = corners.begin(v), count = corners.end(v) - first;
    if (count < 3 || count > 16) return false;
    // The corners a corner links to, found by one comparison of 16 previous vertices from v's
    // first on, without branches; those past v's own are masked off.
    const Index* prev = corners.prevs(v);
    const std::uint32_t own = (std::uint32_t{1} << count) - 1;
    // Each step finds the corner linked to `at`: exactly one, not visited yet, so after
    // `count` steps every corner was visited once, each link read once, and the last step
    // must come back to the first corner.
    std::uint32_t visited = 0;
    Index at = 0;
    for (Index step = 0; step < count; ++step) {
        const std::uint32_t link = slots_holding(prev, corners.next(first + at)) & own;
        if (link == 0 || (link & (link - 1)) != 0 || (visited & link) != 0) return false;
        visited |= link;
        at = Index(std::countr_zero(link));
    }
    return at == 0;
}

// What a vertex whose corners do not close one fan adds to its piece: the edges counted at
// it (their smaller end) that one triangle uses (boundary), that two use the same way
// (inconsistent), that more use (non-manifold; `excess`: their uses beyond two), and whether
// its corners make more than one fan.
struct OddVertex {
    Index vertex;
    Index boundary = 0, inconsistent = 0, nonmanifold = 0, excess = 0;
    bool nonmanifold_vertex = false;
};

// One part's labels: provisional pieces, each first met at a vertex that no smaller vertex of
// the part joins; two labels found to meet are united (the smaller number becomes the root, so
// a root is its set's first label, met at its smallest vertex).
struct PartLabels {
    std::vector<Index> parent;
    std::vector<OddVertex> odd;
    std::vector<std::pair<Index, Index>> across;  // edges to a smaller part's vertex
    Index find(Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    Index unite(Index a, Index b) {
        a = find(a), b = find(b);
        if (a < b) return parent[b] = a;
        if (b < a) return parent[a] = b;
        return a;
    }
};

// The vertices of one part, in order: the edges and fans around each (each edge {v, w} is seen
// from both ends and counted at its smaller end v; the corners at v that share an edge form
// one fan, and more than one fan makes v a non-manifold vertex), and the pieces, swept: each
// vertex takes the label of its smaller neighbours in the part (uniting theirs when they
// differ), or a new one; label[v] is that label, or kNoPiece for an unreferenced vertex.
// Linear in the corners, and the labels a vertex reads are of vertices just before it.
void vertex_part(const Mesh& mesh, const CornerPlan& plan,
                 const std::vector<Index>& degenerate_vertices, std::size_t part, Index* label,
                 PartLabels& out) {
    const Index lo = plan.block_start[plan.part_block[part]];
    BlockCorners corners;
    std::vector<LocalUse> uses;
    std::vector<Index> parent;
    const auto find = [&](Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    auto degenerate = std::lower_bound(degenerate_vertices.begin(), degenerate_vertices.end(), lo);
    for (std::size_t block = plan.part_block[part]; block < plan.part_block[part + 1]; ++block) {
        corners.build(mesh.indices, plan.block_start[block], plan.block_start[block + 1],
                      plan.first[block], plan.last[block]);
        for (Index v = plan.block_start[block]; v < plan.block_start[block + 1]; ++v) {
            Index at = no_piece;  // v's label
            const auto meet = [&](Index w) {
                if (w >= v) return;
                if (w < lo) {
                    out.across.push_back({v, w});
                } else if (label[w] != at) {  // mostly equal: v's neighbours share one label
                    at = at == no_piece ? out.find(label[w]) : out.unite(at, label[w]);
                }
            };
            const bool in_degenerate = degenerate != degenerate_vertices.end() && *degenerate == v;
            if (in_degenerate) ++degenerate;
            if (corners.begin(v) == corners.end(v) && !in_degenerate) {
                label[v] = no_piece;
                continue;
            }
            if (closed_fan(corners, v)) {  // the usual vertex: every edge used twice, one way each
                for (Index i = corners.begin(v); i < corners.end(v); ++i) meet(corners.next(i));
            } else {
                uses.clear();
                Index local = 0;
                for (Index i = corners.begin(v); i < corners.end(v); ++i) {
                    uses.push_back({corners.next(i), local, true});
                    uses.push_back({corners.prev(i), local, false});
                    ++local;
                }
                // By the other end (a dozen uses at a vertex of a closed mesh: an insertion sort,
                // a full sort for a crowded vertex; the order within a group does not matter).
                if (uses.size() > 32)
                    std::sort(uses.begin(), uses.end(), [](const LocalUse& x, const LocalUse& y) {
                        return x.other < y.other;
                    });
                for (std::size_t i = 1; i < uses.size(); ++i) {
                    const LocalUse u = uses[i];
                    std::size_t j = i;
                    for (; j > 0 && uses[j - 1].other > u.other; --j) uses[j] = uses[j - 1];
                    uses[j] = u;
                }
                parent.resize(local);
                std::iota(parent.begin(), parent.end(), Index{0});
                Index fans = local;
                OddVertex odd{v};
                for (std::size_t g = 0; g < uses.size();) {
                    std::size_t e = g + 1;
                    while (e < uses.size() && uses[e].other == uses[g].other) ++e;
                    meet(uses[g].other);
                    if (uses[g].other > v) {
                        if (e - g == 1) {
                            ++odd.boundary;
                        } else if (e - g == 2) {
                            if (uses[g].forward == uses[g + 1].forward) ++odd.inconsistent;
                        } else {
                            ++odd.nonmanifold;
                            odd.excess += Index(e - g - 2);
                        }
                    }
                    for (std::size_t u = g + 1; u < e; ++u) {
                        const Index a = find(uses[g].corner), b = find(uses[u].corner);
                        if (a != b) {
                            parent[std::max(a, b)] = std::min(a, b);
                            --fans;
                        }
                    }
                    g = e;
                }
                odd.nonmanifold_vertex = fans > 1;
                if (odd.boundary || odd.inconsistent || odd.nonmanifold || odd.nonmanifold_vertex)
                    out.odd.push_back(odd);
            }
            if (at == no_piece) {
                at = Index(out.parent.size());
                out.parent.push_back(at);
            }
            label[v] = at;
        }
    }
}

// The pieces from the corners (vertex_part on each part, then the labels that meet across parts
// or through degenerate triangles united), numbered in the order of their smallest vertex; and
// the odd vertices.
VertexPieces swept_pieces(const Mesh& mesh, const CornerPlan& plan, unsigned threads,
                          std::vector<OddVertex>& odd) {
    const auto& idx = mesh.indices;
    std::vector<Index> degenerate_vertices;
    for (Index t : plan.degenerate)
        degenerate_vertices.insert(degenerate_vertices.end(), &idx[3 * t], &idx[3 * t + 3]);
    std::sort(degenerate_vertices.begin(), degenerate_vertices.end());
    degenerate_vertices.erase(std::unique(degenerate_vertices.begin(), degenerate_vertices.end()),
                              degenerate_vertices.end());
    VertexPieces pieces;
    std::vector<Index>& label = pieces.of_vertex;
    label.resize(mesh.vertex_count());
    std::vector<PartLabels> parts(plan.parts);
    parallel_chunks(plan.parts, threads, [&](std::size_t part) {
        vertex_part(mesh, plan, degenerate_vertices, part, label.data(), parts[part]);
    });
    const auto range = [&](std::size_t part) { return plan.block_start[plan.part_block[part]]; };
    // All parts' labels in one table (a part's labels after the smaller parts'), so that a
    // root is still its set's label met first, at its smallest vertex.
    PartLabels all;
    std::vector<Index> first_label(plan.parts + 1, 0);
    for (std::size_t part = 0; part < plan.parts; ++part) {
        first_label[part + 1] = first_label[part] + Index(parts[part].parent.size());
        for (Index p : parts[part].parent) all.parent.push_back(p + first_label[part]);
        odd.insert(odd.end(), parts[part].odd.begin(), parts[part].odd.end());
    }
    const auto part_of = [&](Index v) {
        std::size_t part = 0;
        while (v >= range(part + 1)) ++part;
        return part;
    };
    const auto global = [&](Index v) { return label[v] + first_label[part_of(v)]; };
    for (const PartLabels& part : parts)
        for (const auto& [v, w] : part.across) all.unite(global(v), global(w));
    for (Index t : plan.degenerate)
        for (int k = 1; k < 3; ++k) all.unite(global(idx[3 * t]), global(idx[3 * t + k]));
    std::vector<Index> piece_of(all.parent.size());
    for (Index l = 0; l < piece_of.size(); ++l)
        piece_of[l] = all.find(l) == l ? Index(pieces.count++) : piece_of[all.find(l)];
    parallel_chunks(plan.parts, threads, [&](std::size_t part) {
        for (Index v = range(part); v < range(part + 1); ++v)
            if (label[v] != no_piece) label[v] = piece_of[label[v] + first_label[part]];
    });
    return pieces;
}

}  // namespace

MeshAnalysis analyse_mesh(const Mesh& mesh, bool topology, const char* who,
                          unsigned requested_threads) {
    const unsigned threads = thread_count(requested_threads);
    MeshAnalysis a;
    a.topology = topology;
    std::vector<OddVertex> odd;
    if (topology) {
        // Normals play no part in the statistics, so they are not checked; the indices are,
        // while the corners are counted.
        validate_mesh_arrays(mesh, who, false);
        const CornerPlan plan = plan_corners(mesh, who, threads);
        trace("mesh analysis: corners planned");
        a.pieces = swept_pieces(mesh, plan, threads, odd);
        trace("mesh analysis: vertices and pieces");
    } else {
        validate_mesh(mesh, who, false);
        a.pieces = vertex_pieces(mesh, threads);
        trace("mesh analysis: pieces");
    }
    const Pieces& pieces = a.pieces;
    std::vector<MeshStats>& stats = a.stats;
    stats.resize(pieces.count);
    std::vector<long> face_count(pieces.count, 0);
    std::vector<FixedSum> area(pieces.count), volume(pieces.count);
    // The triangles' sums, chunk after chunk, and their runs in order.
    {
        std::vector<TriangleChunk> chunks(chunk_count(mesh.triangle_count(), kTriangleChunk));
        parallel_chunks(chunks.size(), threads, [&](std::size_t k) {
            if (topology) {
                triangle_chunk<true>(mesh, pieces, k, chunks[k]);
            } else {
                triangle_chunk<false>(mesh, pieces, k, chunks[k]);
            }
        });
        std::size_t runs = 0;
        for (const TriangleChunk& chunk : chunks) runs += chunk.runs.size();
        a.runs.reserve(runs);
        for (const TriangleChunk& chunk : chunks) {
            for (const PieceRun<Partial>& run : chunk.sums) {
                const Index piece = run.piece;
                const Partial& part = run.sum;
                MeshStats& s = stats[piece];
                s.triangles += part.stats.triangles;
                area[piece] += part.area;
                volume[piece] += part.volume;
                s.degenerate_triangles += part.stats.degenerate_triangles;
                face_count[piece] += part.faces;
            }
            a.runs.insert(a.runs.end(), chunk.runs.begin(), chunk.runs.end());
        }
    }
    trace("mesh analysis: triangles");
    // The referenced vertices (integers: in any order), for the statistics.
    if (topology)
        sum_by_piece<std::size_t>(
            chunk_count(mesh.vertex_count(), kVertexChunk), threads,
            [&](std::size_t k, PieceRuns<std::size_t>& runs) {
                for (std::size_t v = k * kVertexChunk;
                     v < std::min(mesh.vertex_count(), (k + 1) * kVertexChunk); ++v)
                    if (pieces.of_vertex[v] != no_piece)
                        ++piece_sum_any_order(runs, pieces.of_vertex[v]);
            },
            [&](Index piece, std::size_t vertices) { stats[piece].vertices += vertices; });
    // Each piece's edges: every edge at a vertex whose corners close one fan is used twice, so
    // 3 faces = 2 edges - boundary + excess over the piece, the odd vertices' edges counted.
    std::vector<long> excess(pieces.count, 0);
    for (const OddVertex& o : odd) {
        const Index piece = pieces.of_vertex[o.vertex];
        MeshStats& s = stats[piece];
        s.boundary_edges += o.boundary;
        s.inconsistent_edges += o.inconsistent;
        s.nonmanifold_edges += o.nonmanifold;
        s.nonmanifold_vertices += o.nonmanifold_vertex ? 1 : 0;
        excess[piece] += o.excess;
    }
    for (std::size_t p = 0; p < stats.size(); ++p) {
        MeshStats& s = stats[p];
        s.area = area[p].value();
        s.volume = volume[p].value();
        s.pieces = 1;
        if (!topology) continue;
        s.closed_pieces = s.boundary_edges == 0 && s.nonmanifold_edges == 0 ? 1 : 0;
        const long edges = (3 * face_count[p] + long(s.boundary_edges) - excess[p]) / 2;
        s.euler_characteristic = long(s.vertices) - edges + face_count[p];
    }
    return a;
}

namespace {

// The vertices a removal keeps (unreferenced ones too), one bit each, with the kept ones before
// each 64-bit word: a vertex's new number is the kept ones before it. Two bits a vertex in all
// (an array of new numbers took four bytes a vertex of fresh memory).
// A word of kept vertices only, the common case, has `full` = `before` (one read, no count: the
// baseline x86-64 the library is built for has no popcnt instruction); others kNotFull (never
// a full word's: its 64 new numbers from there on would pass 2^32 - 1).
constexpr Index kNotFull = ~Index{0};

struct KeptVertices {
    std::vector<std::uint64_t> bits;
    std::vector<Index> before;            // kept vertices before each word
    std::vector<Index> full;              // before, or kNotFull where the word drops any
    std::vector<std::size_t> first_kept;  // kept vertices before each vertex chunk; all at the end

    bool kept(std::size_t v) const { return (bits[v / 64] >> (v % 64) & 1) != 0; }
    Index remap(Index v) const {
        const Index base = full[v / 64];
        if (base != kNotFull) return base + v % 64;
        const std::uint64_t below = bits[v / 64] & ((std::uint64_t{1} << (v % 64)) - 1);
        return Index(before[v / 64] + Index(std::popcount(below)));
    }
};

KeptVertices kept_vertices(const MeshAnalysis& a, const std::vector<char>& drop, std::size_t nv,
                           unsigned threads) {
    // Whether each piece is kept, at piece + 1 (kNoPiece + 1 = 0: unreferenced, kept).
    std::vector<std::uint8_t> keep(a.pieces.count + 1, 1);
    for (std::size_t q = 0; q < a.pieces.count; ++q) keep[q + 1] = drop[q] ? 0 : 1;
    const Index* of_vertex = a.pieces.of_vertex.data();
    const std::size_t chunks = chunk_count(nv, kVertexChunk);
    KeptVertices kept;
    kept.bits.resize((nv + 63) / 64);
    kept.before.resize(kept.bits.size());
    kept.full.resize(kept.bits.size());
    kept.first_kept.assign(chunks + 1, 0);
    parallel_chunks(chunks, threads, [&](std::size_t k) {
        std::size_t count = 0;
        const std::size_t end = std::min(nv, (k + 1) * kVertexChunk);
        for (std::size_t w = k * kVertexChunk / 64; w < (end + 63) / 64; ++w) {
            std::uint64_t word = 0;
            for (std::size_t v = 64 * w; v < std::min(end, 64 * w + 64); ++v)
                word |= std::uint64_t{keep[Index(of_vertex[v] + 1)]} << (v % 64);
            kept.bits[w] = word;
            kept.before[w] = Index(count);
            count += std::size_t(std::popcount(word));
        }
        kept.first_kept[k + 1] = count;
    });
    for (std::size_t k = 0; k < chunks; ++k) kept.first_kept[k + 1] += kept.first_kept[k];
    parallel_chunks(chunks, threads, [&](std::size_t k) {
        const std::size_t end = std::min(nv, (k + 1) * kVertexChunk);
        for (std::size_t w = k * kVertexChunk / 64; w < (end + 63) / 64; ++w) {
            kept.before[w] += Index(kept.first_kept[k]);
            kept.full[w] = kept.bits[w] == ~std::uint64_t{0} ? kept.before[w] : kNotFull;
        }
    });
    return kept;
}

// Calls run(first, count) for each maximal run of kept vertices in [begin, end), in order.
template <class Run>
void for_kept_runs(const KeptVertices& kept, std::size_t begin, std::size_t end, Run&& run) {
    std::size_t open = end;  // the first vertex of the run being extended, or end: none
    for (std::size_t w = begin / 64; 64 * w < end; ++w) {
        std::uint64_t word = kept.bits[w];
        if (64 * w < begin) word &= ~std::uint64_t{0} << (begin % 64);
        if (end - 64 * w < 64) word &= (std::uint64_t{1} << (end % 64)) - 1;
        if (word == ~std::uint64_t{0}) {
            if (open == end) open = 64 * w;
            continue;
        }
        // Each change between kept and dropped within the word.
        std::size_t at = 0;
        while (at < 64) {
            const std::uint64_t rest = (open == end ? word : ~word) >> at;
            if (rest == 0) break;
            at += std::size_t(std::countr_zero(rest));
            if (open == end) {
                open = 64 * w + at;
            } else {
                run(open, 64 * w + at - open);
                open = end;
            }
        }
    }
    if (open != end) run(open, end - open);
}

// Every per-vertex array moved in place, in one run of vertex chunks a thread, run of kept
// vertices by run; with `renumber` (the kept pieces' new numbers) the vertices' pieces follow.
// A thread's first new places that lie before its own old vertices (those of the threads
// before it, maybe not yet read: as many as the vertices dropped before it, few) wait in a
// buffer until every thread is done.
void move_vertices(Mesh& mesh, std::vector<Index>* of_vertex, const std::vector<Index>& renumber,
                   const KeptVertices& kept, unsigned threads) {
    const std::size_t nv = mesh.vertex_count();
    const std::size_t chunks = chunk_count(nv, kVertexChunk);
    const std::size_t parts = std::min<std::size_t>(threads, chunks);
    const bool normals = !mesh.normals.empty();
    float* positions = mesh.positions.data();
    float* normal = mesh.normals.data();
    Index* piece = of_vertex ? of_vertex->data() : nullptr;
    struct Held {
        std::vector<float> positions, normals;
        std::vector<Index> pieces;
    };
    std::vector<Held> held(parts);
    const auto part_start = [&](std::size_t r) { return r * chunks / parts; };
    parallel_chunks(parts, threads, [&](std::size_t r) {
        const std::size_t k0 = part_start(r), k1 = part_start(r + 1);
        const std::size_t begin = k0 * kVertexChunk, end = std::min(nv, k1 * kVertexChunk);
        const std::size_t first = kept.first_kept[k0];
        const std::size_t hold = std::min(kept.first_kept[k1], begin);
        Held& h = held[r];
        h.positions.resize(3 * (std::max(hold, first) - first));
        if (normals) h.normals.resize(h.positions.size());
        if (piece) h.pieces.resize(std::max(hold, first) - first);
        std::size_t o = first;
        // count vertices from `from` to new places from o on, those before `hold` held.
        const auto place = [&](std::size_t from, std::size_t count, std::size_t to, bool in_held) {
            const std::size_t at = in_held ? to - first : to;
            float* p = in_held ? h.positions.data() : positions;
            // (Those before the first dropped vertex stay where they are.)
            if (in_held || at != from) {
                std::memmove(p + 3 * at, positions + 3 * from, 12 * count);
                if (normals)
                    std::memmove((in_held ? h.normals.data() : normal) + 3 * at,
                                 normal + 3 * from, 12 * count);
            }
            if (piece) {
                Index* q = in_held ? h.pieces.data() : piece;
                for (std::size_t i = 0; i < count; ++i) {
                    const Index old = piece[from + i];
                    q[at + i] = old == no_piece ? no_piece : renumber[old];
                }
            }
        };
        for_kept_runs(kept, begin, end, [&](std::size_t from, std::size_t count) {
            const std::size_t held_count = o < hold ? std::min(count, hold - o) : 0;
            if (held_count > 0) place(from, held_count, o, true);
            if (count > held_count)
                place(from + held_count, count - held_count, o + held_count, false);
            o += count;
        });
    });
    for (std::size_t r = 0; r < parts; ++r) {
        const std::size_t first = kept.first_kept[part_start(r)];
        std::copy(held[r].positions.begin(), held[r].positions.end(), positions + 3 * first);
        std::copy(held[r].normals.begin(), held[r].normals.end(), normal + 3 * first);
        if (piece) std::copy(held[r].pieces.begin(), held[r].pieces.end(), piece + first);
    }
}

// Where a new chunk of triangles starts among the old ones: the old triangle, its run and its
// place in the run (a run is of one piece, so wholly kept or wholly dropped).
struct ChunkStart {
    std::size_t triangle;
    std::size_t run;
    Index offset;
};

std::vector<ChunkStart> new_chunks(const MeshAnalysis& a, const std::vector<char>& drop,
                                   std::size_t& kept_triangles) {
    std::vector<ChunkStart> starts;
    std::size_t in = 0, out = 0;
    for (std::size_t r = 0; r < a.runs.size(); ++r) {
        const TriangleRun& run = a.runs[r];
        if (!drop[run.piece]) {
            for (std::size_t b = starts.size() * kTriangleChunk; b < out + run.triangles;
                 b += kTriangleChunk)
                starts.push_back({in + (b - out), r, Index(b - out)});
            out += run.triangles;
        }
        in += run.triangles;
    }
    kept_triangles = out;
    return starts;
}

// The runs of the kept triangles as analyse_mesh finds them on the mesh after (pieces
// renumbered): runs of one piece made adjacent by a dropped one joined, and every run cut at the
// new chunks' bounds.
std::vector<TriangleRun> kept_runs(const MeshAnalysis& a, const std::vector<char>& drop,
                                   const std::vector<Index>& renumber) {
    std::vector<TriangleRun> runs;
    std::size_t out = 0;       // kept triangles so far
    std::size_t chunk_at = 0;  // the first run of the chunk `out` is in
    for (const TriangleRun& run : a.runs) {
        if (drop[run.piece]) continue;
        const Index piece = renumber[run.piece];
        for (std::size_t left = run.triangles; left > 0;) {
            if (out % kTriangleChunk == 0) chunk_at = runs.size();
            const std::size_t room = kTriangleChunk - out % kTriangleChunk;
            const std::size_t n = std::min(left, room);
            if (runs.size() > chunk_at && runs.back().piece == piece)
                runs.back().triangles += Index(n);
            else
                runs.push_back({piece, Index(n)});
            out += n, left -= n;
        }
    }
    return runs;
}

// The new numbers of the n (kept) vertices `from` into `to`, which may lie at or before `from`
// (each read before its place is written).
void remap_plain(const Index* from, std::size_t n, const KeptVertices& kept, Index* to) {
    for (std::size_t i = 0; i < n; ++i) to[i] = kept.remap(from[i]);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// Where no vertex between the least and the largest is dropped (most batches: the vertices of
// nearby triangles are near), every new number is the old less the same count; otherwise
// eight at a time: their words' `full` gathered, and eight in full words (the common case)
// renumbered without a branch each.
__attribute__((target("avx2"))) void remap_avx2(const Index* from, std::size_t n,
                                                const KeptVertices& kept, Index* to) {
    if (n == 0) return;
    __m256i least = _mm256_set1_epi32(-1), largest = _mm256_setzero_si256();
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(from + i));
        least = _mm256_min_epu32(least, v), largest = _mm256_max_epu32(largest, v);
    }
    alignas(32) Index lanes[16];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), least);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes + 8), largest);
    Index lo = from[0], hi = from[0];
    for (int l = 0; l < 8; ++l) lo = std::min(lo, lanes[l]), hi = std::max(hi, lanes[8 + l]);
    for (std::size_t j = i; j < n; ++j) lo = std::min(lo, from[j]), hi = std::max(hi, from[j]);
    const Index dropped = lo - kept.remap(lo);
    if (hi - kept.remap(hi) == dropped) {
        const __m256i less = _mm256_set1_epi32(int(dropped));
        for (i = 0; i + 8 <= n; i += 8) {
            const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(from + i));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(to + i), _mm256_sub_epi32(v, less));
        }
        for (; i < n; ++i) to[i] = from[i] - dropped;
        return;
    }
    const int* full = reinterpret_cast<const int*>(kept.full.data());
    const __m256i low = _mm256_set1_epi32(63), not_full = _mm256_set1_epi32(-1);
    for (i = 0; i + 8 <= n; i += 8) {
        const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(from + i));
        const __m256i base = _mm256_i32gather_epi32(full, _mm256_srli_epi32(v, 6), 4);
        const __m256i odd = _mm256_cmpeq_epi32(base, not_full);
        if (!_mm256_testz_si256(odd, odd)) {
            remap_plain(from + i, 8, kept, to + i);
            continue;
        }
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(to + i),
                            _mm256_add_epi32(base, _mm256_and_si256(v, low)));
    }
    remap_plain(from + i, n - i, kept, to + i);
}
#endif

void remap(const Index* from, std::size_t n, const KeptVertices& kept, Index* to) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (has_avx2()) return remap_avx2(from, n, kept, to);
#endif
    remap_plain(from, n, kept, to);
}

// Where new triangles go: their own slots, or (those before `hold`) a thread's buffer, whose
// first triangle is new triangle `first`.
struct TrianglePlaces {
    Index* idx;
    Index* buffer;
    std::size_t first, hold;
    Index* at(std::size_t o) const { return o < hold ? buffer + 3 * (o - first) : idx + 3 * o; }
    // How many of n triangles from o on go to one run of places.
    std::size_t together(std::size_t o, std::size_t n) const {
        return o < hold ? std::min(n, hold - o) : n;
    }
};

// One new chunk of triangles, [begin, end), filled from the old triangles from `start` on
// (dropped runs skipped whole) and written to `places`, a batch at a time renumbered.
void move_chunk(const Index* idx, const MeshAnalysis& a, const std::vector<char>& drop,
                const KeptVertices& kept, ChunkStart start, std::size_t begin, std::size_t end,
                const TrianglePlaces& places) {
    std::size_t t = start.triangle, run = start.run;
    Index offset = start.offset;
    for (std::size_t o = begin; o < end;) {
        const TriangleRun& old = a.runs[run];
        if (drop[old.piece]) {
            t += old.triangles - offset;
            ++run, offset = 0;
            continue;
        }
        const std::size_t count = std::min<std::size_t>(old.triangles - offset, end - o);
        for (std::size_t first = 0; first < count;) {
            const std::size_t n = places.together(o + first, std::min(kBatch, count - first));
            remap(idx + 3 * (t + first), 3 * n, kept, places.at(o + first));
            first += n;
        }
        t += count, o += count;
        offset += Index(count);
        if (offset == old.triangles) ++run, offset = 0;
    }
}

// The kept triangles moved in place and their vertices renumbered, in one run of new chunks a
// thread (move_chunk). Chunk k writes [k C, (k + 1) C) from old triangles at or after each
// place; only a thread's first places that lie before its own old triangles may hold old
// triangles of the threads before it, not yet read (as many as the triangles dropped before
// it): those wait in a buffer until every thread is done.
void move_triangles(Mesh& mesh, const MeshAnalysis& a, const std::vector<char>& drop,
                    const KeptVertices& kept, unsigned threads) {
    std::size_t nt = 0;
    const std::vector<ChunkStart> starts = new_chunks(a, drop, nt);
    Index* idx = mesh.indices.data();
    const std::size_t chunks = starts.size();
    const std::size_t parts = std::min<std::size_t>(threads, chunks);
    std::vector<std::vector<Index>> held(parts);
    const auto part_start = [&](std::size_t r) { return r * chunks / parts; };
    parallel_chunks(parts, threads, [&](std::size_t r) {
        const std::size_t k0 = part_start(r), k1 = part_start(r + 1);
        const std::size_t first = k0 * kTriangleChunk;
        const std::size_t hold = std::min(std::min(nt, k1 * kTriangleChunk), starts[k0].triangle);
        held[r].resize(3 * (std::max(hold, first) - first));
        Index* buffer = held[r].data();
        const TrianglePlaces places{idx, buffer, first, hold};
        for (std::size_t k = k0; k < k1; ++k) {
            const std::size_t begin = k * kTriangleChunk;
            const std::size_t end = std::min(nt, begin + kTriangleChunk);
            move_chunk(idx, a, drop, kept, starts[k], begin, end, places);
        }
    });
    for (std::size_t r = 0; r < parts; ++r)
        std::copy(held[r].begin(), held[r].end(), idx + 3 * part_start(r) * kTriangleChunk);
    mesh.indices.resize(3 * nt);
}

}  // namespace

void keep_pieces(Mesh& mesh, MeshAnalysis& a, const std::vector<char>& drop, bool update) {
    const std::size_t count = a.pieces.count;
    // The kept pieces' new numbers and statistics: the same triangles, so the same sums
    // (FixedSum: in any order and any chunks alike).
    std::vector<Index> renumber(count, no_piece);
    std::vector<MeshStats> stats;
    for (std::size_t q = 0; q < count; ++q) {
        if (drop[q]) continue;
        renumber[q] = Index(stats.size());
        stats.push_back(a.stats[q]);
    }
    if (stats.size() == count) return;
    const unsigned threads = thread_count();
    const std::size_t nv = mesh.vertex_count();
    const KeptVertices kept = kept_vertices(a, drop, nv, threads);
    const std::size_t kept_count = kept.first_kept.back();
    move_triangles(mesh, a, drop, kept, threads);
    trace("keep pieces: triangles moved");
    move_vertices(mesh, update ? &a.pieces.of_vertex : nullptr, renumber, kept, threads);
    mesh.positions.resize(3 * kept_count);
    if (!mesh.normals.empty()) mesh.normals.resize(3 * kept_count);
    if (update) a.pieces.of_vertex.resize(kept_count);
    if (!mesh.atoms.empty() || !mesh.colors.empty() || !mesh.scalars.empty()) {
        // (Not met by the engine, which adds them after the removal.)
        std::vector<Index> list(kept_count);
        for (std::size_t v = 0, i = 0; v < nv; ++v)
            if (kept.kept(v)) list[i++] = Index(v);
        Mesh rest;
        rest.atoms = std::move(mesh.atoms), rest.colors = std::move(mesh.colors);
        rest.scalars = std::move(mesh.scalars);
        keep_vertices(rest, list);
        mesh.atoms = std::move(rest.atoms), mesh.colors = std::move(rest.colors);
        mesh.scalars = std::move(rest.scalars);
    }
    trace("keep pieces: vertices moved");
    if (!update) return;
    a.runs = kept_runs(a, drop, renumber);
    a.pieces.count = stats.size();
    a.stats = std::move(stats);
}

void keep_pieces_plain(Mesh& mesh, MeshAnalysis& a, const std::vector<char>& drop, bool update) {
    const auto dropped = [&](Index v) {
        const Index piece = a.pieces.of_vertex[v];
        return piece != no_piece && drop[piece];
    };
    std::vector<Index> kept, new_number(mesh.vertex_count(), no_piece);
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        if (dropped(v)) continue;
        new_number[v] = Index(kept.size());
        kept.push_back(v);
    }
    std::vector<Index> indices;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        if (!dropped(mesh.indices[3 * t]))
            for (int k = 0; k < 3; ++k) indices.push_back(new_number[mesh.indices[3 * t + k]]);
    keep_vertices(mesh, kept);
    mesh.indices = std::move(indices);
    if (update) a = analyse_mesh(mesh, a.topology, "keep_pieces_plain");
}

MeshStats total_stats(const MeshAnalysis& analysis, const Mesh& mesh) {
    MeshStats total;
    for (const MeshStats& s : analysis.stats) {
        total.area += s.area;
        total.volume += s.volume;
        total.pieces += s.pieces;
        total.closed_pieces += s.closed_pieces;
        total.boundary_edges += s.boundary_edges;
        total.nonmanifold_edges += s.nonmanifold_edges;
        total.nonmanifold_vertices += s.nonmanifold_vertices;
        total.inconsistent_edges += s.inconsistent_edges;
        total.degenerate_triangles += s.degenerate_triangles;
        total.euler_characteristic += s.euler_characteristic;
    }
    // All vertices, referenced or not; the Euler characteristic above counts referenced ones.
    total.vertices = mesh.vertex_count();
    total.triangles = mesh.triangle_count();
    return total;
}

MeshStats total_stats(const Mesh& mesh, unsigned threads) {
    return total_stats(analyse_mesh(mesh, true, "mesh statistics", threads), mesh);
}

}  // namespace detail

bool MeshStats::is_closed_manifold() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && nonmanifold_vertices == 0 &&
           inconsistent_edges == 0 && degenerate_triangles == 0 && volume > 0.0;
}

MeshStats compute_stats(const Mesh& mesh) { return detail::total_stats(mesh, 0); }

std::vector<MeshStats> piece_stats(const Mesh& mesh) {
    std::vector<MeshStats> pieces = detail::analyse_mesh(mesh, true, "mesh statistics").stats;
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const MeshStats& a, const MeshStats& b) { return a.area > b.area; });
    return pieces;
}

}  // namespace fdmsurf
