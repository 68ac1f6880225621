// Marching cubes on the host over rows of packed inside bits. Three passes over the planes, each
// plane on one thread: (1) a bit per point, value >= iso; (2) per point row, the words of points
// whose +x, +y and +z edges are crossed (a bit's xor with its neighbour's) and the vertices
// before each word, and per row of cells the triangles of its cells; (3) after prefix sums over
// the rows, the vertices and triangles written where the serial order puts them. A cell is
// visited only when its eight corners are not all on one side, which the words tell 64 at a time.
#include "isosurface/marching_cubes_host.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "base/cpu_features.hpp"
#include "base/parallel.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf_generated/mc_tables.hpp"

namespace fdmsurf::detail {
namespace {

using Word = std::uint64_t;

// w shifted down by one bit, the next word's lowest bit on top: bit j says point j + 1.
inline Word next_bits(Word w, Word following) { return (w >> 1) | (following << 63); }

// Every plane there and given.
bool has_planes(const PlaneStack& f) {
    if (f.planes.size() != f.nz) return false;
    for (const float* plane : f.planes) {
        if (plane == nullptr) return false;
    }
    return true;
}

// The three passes of marching_cubes_host over the planes [p.z_begin, p.z_end] of f, in order:
// inside_bits, count_crossings (then prefix_sums over the rows), build_mesh.
struct BitMarcher {
    const PlaneStack& f;
    const McParams& p;
    const unsigned threads;
    const std::uint32_t nx, ny;
    const std::uint32_t planes;
    const std::size_t words;   // per point row
    const std::size_t rows;    // point rows, planes * ny
    std::vector<Word> inside;  // a bit per point, value >= iso; the bits past nx stay 0
    std::vector<Word> cross_x, cross_y, cross_z;  // points whose +x, +y, +z edges are crossed
    std::vector<std::uint32_t> before;            // vertices of the row before word k
    std::vector<std::uint64_t> first_vertex, first_triangle;  // per row, then prefix sums

    BitMarcher(const PlaneStack& f_in, const McParams& p_in, unsigned threads_in)
        : f(f_in),
          p(p_in),
          threads(threads_in),
          nx(f_in.nx),
          ny(f_in.ny),
          planes(p_in.z_end - p_in.z_begin + 1),
          words((nx + 63) / 64),
          rows(std::size_t(planes) * ny) {}

    std::size_t row_of(std::size_t zi, std::size_t y) const { return zi * ny + y; }

    // Points x with x + 1 < nx (they own an x edge; cells start there) in word k.
    Word below_last(std::size_t k) const {
        const std::size_t first = 64 * k;
        if (first + 1 >= nx) return 0;
        const std::size_t n = nx - 1 - first;
        return n >= 64 ? ~Word{0} : (Word{1} << n) - 1;
    }

    // (1) Inside bits.
    void inside_bits() {
        inside.resize(rows * words);
        parallel_chunks(planes, threads, [&](std::size_t zi) {
            const float* plane = f.planes[p.z_begin + zi];
            for (std::uint32_t y = 0; y < ny; ++y) {
                const float* row = plane + std::size_t(y) * f.pitch;
                Word* out = &inside[row_of(zi, y) * words];
                for (std::size_t k = 0; k < words; ++k) {
                    const std::uint32_t end = std::uint32_t(std::min<std::size_t>(nx, 64 * k + 64));
                    Word bits = 0;
                    for (std::uint32_t x = std::uint32_t(64 * k); x < end; ++x)
                        bits |= Word(row[x] >= p.iso) << (x - 64 * k);
                    out[k] = bits;
                }
            }
        });
    }

    // The cells of row (y, zi) whose corners are not all on one side, one word at a time;
    // body(k, j, cube) for each, in x order.
    template <class Body>
    [[gnu::always_inline]] inline void for_cells(std::size_t zi, std::uint32_t y,
                                                 const Body& body) const {
        const Word* r[4] = {&inside[row_of(zi, y) * words], &inside[row_of(zi, y + 1) * words],
                            &inside[row_of(zi + 1, y) * words],
                            &inside[row_of(zi + 1, y + 1) * words]};
        for (std::size_t k = 0; k < words; ++k) {
            Word b[4], n[4];
            for (int i = 0; i < 4; ++i) {
                b[i] = r[i][k];
                n[i] = next_bits(b[i], k + 1 < words ? r[i][k + 1] & 1 : 0);
            }
            const Word column = (b[0] ^ b[1]) | (b[0] ^ b[2]) | (b[0] ^ b[3]);
            const Word next_column = (n[0] ^ n[1]) | (n[0] ^ n[2]) | (n[0] ^ n[3]);
            for (Word active = (column | next_column | (b[0] ^ n[0])) & below_last(k); active;
                 active &= active - 1) {
                const int j = std::countr_zero(active);
                unsigned cube = 0;
                for (int i = 0; i < 4; ++i) {
                    cube |= unsigned((b[i] >> j) & 1) << (2 * i);
                    cube |= unsigned((n[i] >> j) & 1) << (2 * i + 1);
                }
                body(k, j, cube);
            }
        }
    }

    // (2) Crossed edges per point and counts per row.
    void count_crossings() {
        cross_x.resize(rows * words);
        cross_y.resize(rows * words);
        cross_z.resize(rows * words);
        before.resize(rows * words);
        first_vertex.assign(rows + 1, 0);
        first_triangle.assign(rows + 1, 0);
        parallel_chunks(planes, threads, [&](std::size_t zi) { count_plane(zi); });
    }

    // Plane zi's crossed edges and its rows' counts (count_crossings).
    FDMSURF_POPCNT_CLONES void count_plane(std::size_t zi) {
        for (std::uint32_t y = 0; y < ny; ++y) {
            const std::size_t row = row_of(zi, y);
            const Word* b = &inside[row * words];
            std::uint32_t count = 0;
            for (std::size_t k = 0; k < words; ++k) {
                const std::size_t i = row * words + k;
                cross_x[i] =
                    (b[k] ^ next_bits(b[k], k + 1 < words ? b[k + 1] & 1 : 0)) & below_last(k);
                cross_y[i] = y + 1 < ny ? b[k] ^ inside[row_of(zi, y + 1) * words + k] : 0;
                cross_z[i] = zi + 1 < planes ? b[k] ^ inside[row_of(zi + 1, y) * words + k] : 0;
                before[i] = count;
                count += std::uint32_t(std::popcount(cross_x[i]) + std::popcount(cross_y[i]) +
                                       std::popcount(cross_z[i]));
            }
            first_vertex[row + 1] = count;
            std::uint64_t triangles = 0;
            if (zi + 1 < planes && y + 1 < ny) {
                for_cells(zi, y, [&](std::size_t, int, unsigned cube) {
                    triangles += mc::kTriCount[cube];
                });
            }
            first_triangle[row + 1] = triangles;
        }
    }

    void prefix_sums() {
        for (std::size_t row = 0; row < rows; ++row) {
            first_vertex[row + 1] += first_vertex[row];
            first_triangle[row + 1] += first_triangle[row];
        }
        if (first_vertex[rows] > std::numeric_limits<std::uint32_t>::max() - 3) {
            throw Error(ErrorCode::InvalidArgument,
                        "marching cubes: more than 2^32 vertices; use smaller slabs");
        }
    }

    // The vertex of the crossed edge from point (x, y, zi) along `axis`.
    [[gnu::always_inline]] inline std::uint32_t vertex_of(std::uint32_t x, std::uint32_t y,
                                                          std::size_t zi, int axis) const {
        const std::size_t i = row_of(zi, y) * words + x / 64;
        const Word low = (Word{1} << (x % 64)) - 1, bit = Word{1} << (x % 64);
        const Word crossed[3] = {cross_x[i], cross_y[i], cross_z[i]};
        if (!(crossed[axis] & bit))
            throw Error(ErrorCode::Internal, "marching cubes: table edge not crossed");
        std::uint64_t v = first_vertex[row_of(zi, y)] + before[i];
        for (int a = 0; a < 3; ++a) v += std::uint64_t(std::popcount(crossed[a] & low));
        for (int a = 0; a < axis; ++a) v += (crossed[a] & bit) != 0;
        return std::uint32_t(v);
    }

    // (3) Vertices and triangles where the serial order puts them, after the vertices and
    // triangles `mesh` holds, its vertex count added to the indices.
    void build_mesh(Mesh& mesh, double reserve_scale) const {
        const std::size_t v0 = mesh.vertex_count(), i0 = mesh.indices.size();
        grow_mesh_for_part(mesh, first_vertex[rows], 3 * first_triangle[rows], reserve_scale);
        parallel_chunks(planes, threads, [&](std::size_t zi) { build_plane(mesh, zi, v0, i0); });
    }

    // Plane zi's vertices and triangles (build_mesh), after the v0 vertices and i0 indices the
    // mesh held before the part.
    FDMSURF_POPCNT_CLONES void build_plane(Mesh& mesh, std::size_t zi, std::size_t v0,
                                           std::size_t i0) const {
        const std::uint32_t z = p.z_begin + std::uint32_t(zi), base = std::uint32_t(v0);
        for (std::uint32_t y = 0; y < ny; ++y) {
            const std::size_t row = row_of(zi, y);
            std::size_t v = v0 + first_vertex[row];
            for (std::size_t k = 0; k < words; ++k) {
                const std::size_t i = row * words + k;
                const Word crossed[3] = {cross_x[i], cross_y[i], cross_z[i]};
                for (Word m = crossed[0] | crossed[1] | crossed[2]; m; m &= m - 1) {
                    const int j = std::countr_zero(m);
                    const std::uint32_t q[3] = {std::uint32_t(64 * k) + std::uint32_t(j), y, z};
                    for (int a = 0; a < 3; ++a) {
                        if (!((crossed[a] >> j) & 1)) continue;
                        mc_vertex(f, q, a, p, &mesh.positions[3 * v], &mesh.normals[3 * v]);
                        ++v;
                    }
                }
            }
            if (zi + 1 >= planes || y + 1 >= ny) continue;
            std::uint32_t* out = mesh.indices.data() + i0 + 3 * first_triangle[row];
            for_cells(
                zi, y, [&](std::size_t k, int j, unsigned cube) __attribute__((always_inline)) {
                    const std::uint32_t x = std::uint32_t(64 * k) + std::uint32_t(j);
                    for (int c = 0; c < 3 * mc::kTriCount[cube]; ++c) {
                        const int e = mc::kTriEdges[cube][c];
                        *out++ =
                            base + vertex_of(x + mc::kEdgeOwner[e][0], y + mc::kEdgeOwner[e][1],
                                             zi + mc::kEdgeOwner[e][2], mc::kEdgeAxis[e]);
                    }
                });
        }
    }
};

}  // namespace

void marching_cubes_host_append(const PlaneStack& f, const McParams& p, Mesh& out,
                                double reserve_scale, unsigned threads) {
    check_mc_arguments(has_planes(f), f.nx, f.ny, f.nz, f.pitch, p);
    BitMarcher m(f, p, thread_count(threads));
    m.inside_bits();
    m.count_crossings();
    m.prefix_sums();
    m.build_mesh(out, reserve_scale);
}

Mesh marching_cubes_host(const PlaneStack& f, const McParams& p, unsigned threads) {
    Mesh mesh;
    marching_cubes_host_append(f, p, mesh, 1.0, threads);
    return mesh;
}

}  // namespace fdmsurf::detail
