// Mesh refinement: modified butterfly subdivision (Zorin, Schröder & Sweldens, "Interpolating
// subdivision for meshes with arbitrary topology", SIGGRAPH 1996) and Newton projection of the
// new vertices onto the level set of a field (Giard & Macq 2010 suggest both, ALGORITHM.md §5).
#include "refine/refine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <utility>
#include <string>

#include "fdmsurf/error.hpp"
#include "mesh/half_edges.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_validate.hpp"
#include "base/parallel.hpp"

namespace fdmsurf::detail {
namespace {

using Index = HalfEdgeIndex;
constexpr Index kNone = kNoHalfEdge;
// Fans longer than this are treated as open (marching-cubes valences stay far below it).
constexpr int kMaxValence = 64;

// The neighbours of the start vertex of h in fan order, from the end of h on; closed when the
// fan comes back to h, open when it reaches an edge without a twin (or passes kMaxValence).
struct Ring {
    std::array<Index, kMaxValence> v;
    int k = 0;
    bool closed = false;
};

Ring ring_of(const HalfEdges& he, const std::vector<Index>& idx, Index h) {
    Ring r;
    Index x = h;
    while (r.k < kMaxValence) {
        r.v[r.k++] = idx[next_he(x)];
        // prev(x) ends at the vertex; its twin leaves it towards the next neighbour.
        const Index y = he.twin[prev_he(x)];
        if (y == kNone) return r;
        x = y;
        if (x == h) {
            r.closed = true;
            return r;
        }
    }
    return r;
}

// A new vertex as a weighted sum of old ones.
struct Stencil {
    std::array<Index, 2 * kMaxValence + 16> v;
    std::array<double, 2 * kMaxValence + 16> w;
    int n = 0;
    void add(Index i, double weight) {
        v[n] = i;
        w[n] = weight;
        ++n;
    }
};

const std::vector<std::vector<double>>& weight_table() {
    static const std::vector<std::vector<double>> table = [] {
        std::vector<std::vector<double>> t(kMaxValence + 1);
        for (int k = 0; k <= kMaxValence; ++k) t[k] = extraordinary_weights(k);
        return t;
    }();
    return table;
}

void add_extraordinary(Stencil& s, Index v, const Ring& ring, double scale) {
    const std::vector<double>& w = weight_table()[ring.k];
    s.add(v, 0.75 * scale);
    for (int j = 0; j < ring.k; ++j) s.add(ring.v[j], w[j] * scale);
}

// The wing tip across half-edge x, whose triangle's third vertex is `other`: the vertex opposite
// x in the neighbouring triangle, or, without one, the mirror image of `other`.
void add_tip(Stencil& s, const HalfEdges& he, const std::vector<Index>& idx, Index x, Index other,
             double weight) {
    const Index y = he.twin[x];
    if (y != kNone) {
        s.add(idx[prev_he(y)], weight);
    } else {
        s.add(idx[x], weight);
        s.add(idx[next_he(x)], weight);
        s.add(other, -weight);
    }
}

// The 8-point butterfly stencil of the interior edge h (a -> b), g its twin (b -> a).
void add_butterfly(Stencil& s, const HalfEdges& he, const std::vector<Index>& idx, Index h,
                   Index g) {
    const Index a = idx[h], b = idx[next_he(h)], c = idx[prev_he(h)], d = idx[prev_he(g)];
    s.add(a, 0.5);
    s.add(b, 0.5);
    s.add(c, 0.125);
    s.add(d, 0.125);
    add_tip(s, he, idx, next_he(h), a, -0.0625);  // across b c
    add_tip(s, he, idx, prev_he(h), b, -0.0625);  // across c a
    add_tip(s, he, idx, next_he(g), b, -0.0625);  // across a d
    add_tip(s, he, idx, prev_he(g), a, -0.0625);  // across d b
}

// The 4-point scheme along a boundary, h (a -> b) a boundary half-edge.
void add_boundary(Stencil& s, const HalfEdges& he, const std::vector<Index>& idx, Index h) {
    const Index a = idx[h], b = idx[next_he(h)];
    s.add(a, 9.0 / 16.0);
    s.add(b, 9.0 / 16.0);
    // The boundary half-edge leaving b: turn around b through the twins.
    Index x = next_he(h);
    for (int i = 0; i < kMaxValence && he.twin[x] != kNone; ++i) x = next_he(he.twin[x]);
    if (he.twin[x] == kNone && he.kind[he.edge[x]] == EdgeKind::Boundary) {
        s.add(idx[next_he(x)], -1.0 / 16.0);
    } else {  // mirror of a about b
        s.add(b, -2.0 / 16.0);
        s.add(a, 1.0 / 16.0);
    }
    // The boundary half-edge arriving at a.
    x = prev_he(h);
    for (int i = 0; i < kMaxValence && he.twin[x] != kNone; ++i) x = prev_he(he.twin[x]);
    if (he.twin[x] == kNone && he.kind[he.edge[x]] == EdgeKind::Boundary) {
        s.add(idx[x], -1.0 / 16.0);
    } else {
        s.add(a, -2.0 / 16.0);
        s.add(b, 1.0 / 16.0);
    }
}

Stencil edge_stencil(const HalfEdges& he, const std::vector<Index>& idx, Index edge) {
    Stencil s;
    const Index h = he.first[edge];
    const Index a = idx[h], b = idx[next_he(h)];
    switch (he.kind[edge]) {
        case EdgeKind::Singular:
            s.add(a, 0.5);
            s.add(b, 0.5);
            return s;
        case EdgeKind::Boundary:
            add_boundary(s, he, idx, h);
            return s;
        case EdgeKind::Interior:
            break;
    }
    const Index g = he.twin[h];
    const Ring ra = ring_of(he, idx, h), rb = ring_of(he, idx, g);
    const bool ea = ra.closed && ra.k >= 3 && ra.k != 6;
    const bool eb = rb.closed && rb.k >= 3 && rb.k != 6;
    if (ea && eb) {
        add_extraordinary(s, a, ra, 0.5);
        add_extraordinary(s, b, rb, 0.5);
    } else if (ea) {
        add_extraordinary(s, a, ra, 1.0);
    } else if (eb) {
        add_extraordinary(s, b, rb, 1.0);
    } else {
        add_butterfly(s, he, idx, h, g);
    }
    return s;
}

Vec3 apply_stencil(const Stencil& s, const std::vector<float>& xyz) {
    Vec3 p{};
    for (int i = 0; i < s.n; ++i)
        for (int k = 0; k < 3; ++k) p[k] += s.w[i] * double(xyz[3 * std::size_t(s.v[i]) + k]);
    return p;
}

Vec3 position(const Mesh& mesh, Index v) {
    const float* p = &mesh.positions[3 * std::size_t{v}];
    return {p[0], p[1], p[2]};
}

// Twice the area-weighted normal of the triangle of half-edge h.
Vec3 face_normal(const Mesh& mesh, Index h) {
    const Vec3 a = position(mesh, mesh.indices[h]), b = position(mesh, mesh.indices[next_he(h)]),
               c = position(mesh, mesh.indices[prev_he(h)]);
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
}

// The butterfly point p of edge e moved onto the line through the edge's midpoint along the
// edge's normal (the mean of its ends' normals, or of its triangles' without vertex normals):
// only the stencil's offset along the normal, its estimate of the curvature, is kept.
Vec3 along_normal(const Mesh& mesh, const HalfEdges& he, Index e, const Vec3& p, Vec3& unit) {
    const Index h = he.first[e];
    const Index a = mesh.indices[h], b = mesh.indices[next_he(h)];
    Vec3 n{};
    if (!mesh.normals.empty()) {
        for (int k = 0; k < 3; ++k)
            n[k] = double(mesh.normals[3 * a + k]) + mesh.normals[3 * b + k];
    } else {
        n = face_normal(mesh, h);
        if (he.twin[h] != kNone) {
            const Vec3 m = face_normal(mesh, he.twin[h]);
            for (int k = 0; k < 3; ++k) n[k] += m[k];
        }
    }
    const double len2 = dot(n, n);
    if (!(len2 > 0.0) || !std::isfinite(len2)) return p;
    for (int k = 0; k < 3; ++k) unit[k] = n[k] / std::sqrt(len2);
    const Vec3 pa = position(mesh, a), pb = position(mesh, b);
    const Vec3 mid{0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
    const double along =
        ((p[0] - mid[0]) * n[0] + (p[1] - mid[1]) * n[1] + (p[2] - mid[2]) * n[2]) / len2;
    return {mid[0] + along * n[0], mid[1] + along * n[1], mid[2] + along * n[2]};
}

std::string count_text(double n) {
    char buf[32];
    if (n >= 1e6)
        std::snprintf(buf, sizeof buf, "%.1f M", n / 1e6);
    else
        std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}

enum class Outcome { Converged, NotConverged, Outside };

Outcome newton(const SurfaceField& field, const Vec3& start, const ProjectOptions& o, Vec3& out,
               Vec3& g) {
    Vec3 x = start;
    double value = 0.0;
    for (int it = 0;; ++it) {
        if (!field.sample(x, value, g)) return Outcome::Outside;
        const double gg = dot(g, g);
        if (!(gg > 0.0) || !std::isfinite(gg) || !std::isfinite(value)) return Outcome::Outside;
        const double r = value - field.iso();
        const double distance = std::abs(r) / std::sqrt(gg);  // first-order distance to the set
        if (distance <= o.tolerance) {
            // The last step is within the tolerance; taking it squares the residual error.
            for (int a = 0; a < 3; ++a) out[a] = x[a] - r / gg * g[a];
            return Outcome::Converged;
        }
        if (it >= o.iterations) return Outcome::NotConverged;
        const double scale = -r / gg * std::min(1.0, o.max_step / distance);
        for (int a = 0; a < 3; ++a) x[a] += scale * g[a];
        const Vec3 moved{x[0] - start[0], x[1] - start[1], x[2] - start[2]};
        if (dot(moved, moved) > o.max_distance * o.max_distance) return Outcome::NotConverged;
    }
}

// Newton along the line start + s dir (dir a unit vector): s <- s - (f - iso) / (grad f . dir).
// Off: the line meets the level set at a grazing angle (over 78 degrees from the gradient).
enum class LineOutcome { Converged, NotConverged, Outside, Grazing };
LineOutcome newton_on_line(const SurfaceField& field, const Vec3& start, const Vec3& dir,
                           const ProjectOptions& o, Vec3& out, Vec3& g) {
    double s = 0.0, value = 0.0;
    for (int it = 0;; ++it) {
        const Vec3 x{start[0] + s * dir[0], start[1] + s * dir[1], start[2] + s * dir[2]};
        if (!field.sample(x, value, g)) return LineOutcome::Outside;
        const double gg = dot(g, g), gd = dot(g, dir);
        if (!(gg > 0.0) || !std::isfinite(gg) || !std::isfinite(value)) return LineOutcome::Outside;
        if (gd * gd < 0.04 * gg) return LineOutcome::Grazing;
        const double r = value - field.iso();
        const double distance = std::abs(r / gd);
        if (distance <= o.tolerance) {
            s -= r / gd;
            for (int a = 0; a < 3; ++a) out[a] = start[a] + s * dir[a];
            return LineOutcome::Converged;
        }
        if (it >= o.iterations) return LineOutcome::NotConverged;
        s -= r / gd * std::min(1.0, o.max_step / distance);
        if (std::abs(s) > o.max_distance) return LineOutcome::NotConverged;
    }
}

Vec3 vertex(const Mesh& mesh, std::size_t v) {
    return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

}  // namespace

void check_refine_levels(int levels) {
    if (levels < 0 || levels > kMaxRefineLevels) {
        throw Error(ErrorCode::InvalidArgument, "refine must be between 0 and " +
                                                    std::to_string(kMaxRefineLevels) +
                                                    " levels (got " + std::to_string(levels) +
                                                    "); each level multiplies the triangles by 4");
    }
}

void check_refine_size(int levels, std::size_t triangles) {
    check_refine_levels(levels);
    const double refined = double(triangles) * std::pow(4.0, levels);
    if (refined <= double(kMaxRefinedTriangles)) return;
    int fits = levels;
    while (fits > 0 && double(triangles) * std::pow(4.0, fits) > double(kMaxRefinedTriangles))
        --fits;
    std::string hint = fits > 0 ? "use --refine " + std::to_string(fits) + " (" +
                                      count_text(double(triangles) * std::pow(4.0, fits)) +
                                      " triangles) or a coarser spacing"
                                : "use a coarser spacing";
    throw Error(ErrorCode::InvalidArgument, "refine " + std::to_string(levels) + " would turn " +
                                                count_text(double(triangles)) + " triangles into " +
                                                count_text(refined) + ", more than the limit of " +
                                                count_text(double(kMaxRefinedTriangles)) +
                                                " (about 1.6 GB of mesh); " + hint);
}

std::vector<double> extraordinary_weights(int valence) {
    const int k = valence;
    if (k < 3) return {};
    if (k == 3) return {5.0 / 12.0, -1.0 / 12.0, -1.0 / 12.0};
    if (k == 4) return {3.0 / 8.0, 0.0, -1.0 / 8.0, 0.0};
    std::vector<double> w(k);
    for (int j = 0; j < k; ++j) {
        const double a = 2.0 * std::numbers::pi * j / k;
        w[j] = (0.25 + std::cos(a) + 0.5 * std::cos(2.0 * a)) / k;
    }
    return w;
}

void subdivide_butterfly(Mesh& mesh, ButterflyOffset offset) {
    validate_mesh(mesh, "refine", true);
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    if (nt == 0) return;
    const HalfEdges he = build_half_edges(mesh);
    const std::size_t ne = he.first.size();
    if (nv + ne > std::numeric_limits<Index>::max()) {
        throw Error(ErrorCode::InvalidArgument,
                    "refine: the refined mesh would have more than 2^32 - 1 vertices");
    }
    const std::vector<Index>& idx = mesh.indices;
    const bool normals = !mesh.normals.empty();
    std::vector<float> positions(3 * (nv + ne)), out_normals(normals ? 3 * (nv + ne) : 0);
    std::copy(mesh.positions.begin(), mesh.positions.end(), positions.begin());
    if (normals) std::copy(mesh.normals.begin(), mesh.normals.end(), out_normals.begin());
    for (Index e = 0; e < ne; ++e) {
        const Stencil s = edge_stencil(he, idx, e);
        Vec3 p = apply_stencil(s, mesh.positions);
        Vec3 edge_normal{};
        if (offset == ButterflyOffset::Normal) p = along_normal(mesh, he, e, p, edge_normal);
        for (int k = 0; k < 3; ++k) positions[3 * (nv + e) + k] = float(p[k]);
        if (!normals) continue;
        Vec3 n = offset == ButterflyOffset::Normal && dot(edge_normal, edge_normal) > 0.0
                     ? edge_normal
                     : apply_stencil(s, mesh.normals);
        double len = std::sqrt(dot(n, n));
        if (!(len > 1e-12)) {  // the stencil cancelled out: the ends' mean
            const Index a = idx[he.first[e]], b = idx[next_he(he.first[e])];
            for (int k = 0; k < 3; ++k) n[k] = mesh.normals[3 * a + k] + mesh.normals[3 * b + k];
            len = std::sqrt(dot(n, n));
        }
        for (int k = 0; k < 3; ++k)
            out_normals[3 * (nv + e) + k] = len > 0 ? float(n[k] / len) : 0.0f;
    }
    std::vector<Index> indices(4 * idx.size());
    for (std::size_t t = 0; t < nt; ++t) {
        const Index a = idx[3 * t], b = idx[3 * t + 1], c = idx[3 * t + 2];
        const Index ab = Index(nv + he.edge[3 * t]), bc = Index(nv + he.edge[3 * t + 1]),
                    ca = Index(nv + he.edge[3 * t + 2]);
        const Index four[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
        std::copy(four, four + 12, indices.begin() + 12 * t);
    }
    mesh.positions = std::move(positions);
    mesh.normals = std::move(out_normals);
    mesh.indices = std::move(indices);
    // Atoms, colours and scalars are not interpolated: the nearest atom of a new vertex is not
    // one of its edge's ends' in general, and colours and scalars derive from atoms. Refinement
    // runs before the stage that computes them (issue 11), which fills them for every vertex.
    clear_attributes(mesh);
}

// ---------------------------------------------------------------------------------------------
// Fields

GridField::GridField(const float* data, std::array<std::uint32_t, 3> dims, std::uint32_t pitch,
                     Vec3 origin, double spacing, double iso, double outward,
                     GridInterpolation interpolation)
    : data_(data),
      dims_(dims),
      pitch_(pitch),
      origin_(origin),
      spacing_(spacing),
      iso_(iso),
      outward_(outward),
      interpolation_(interpolation) {
    if (data == nullptr || pitch < dims[0] || !(spacing > 0.0)) {
        throw Error(ErrorCode::InvalidArgument, "refine: grid field without data or spacing");
    }
}

bool GridField::sample(const Vec3& p, double& value, Vec3& gradient) const {
    // The interpolation needs points [i - before, i + 1 + after] along each axis.
    const int before = interpolation_ == GridInterpolation::Trilinear ? 0 : 1;
    const int after = before;
    std::int64_t base[3];
    double t[3];
    for (int a = 0; a < 3; ++a) {
        const double u = (p[a] - origin_[a]) / spacing_;
        if (!std::isfinite(u)) return false;
        const double f = std::floor(u);
        if (f - before < 0.0 || f + 1 + after > double(dims_[a]) - 1.0) return false;
        base[a] = std::int64_t(f);
        t[a] = u - f;
    }
    value = 0.0;
    gradient = {0.0, 0.0, 0.0};
    if (interpolation_ == GridInterpolation::CatmullRom) {
        // Separable: w are the cubic's weights of points base - 1 .. base + 2, d their derivatives.
        double w[3][4], d[3][4];
        for (int a = 0; a < 3; ++a) {
            const double x = t[a], x2 = x * x, x3 = x2 * x;
            w[a][0] = 0.5 * (-x3 + 2.0 * x2 - x);
            w[a][1] = 0.5 * (3.0 * x3 - 5.0 * x2 + 2.0);
            w[a][2] = 0.5 * (-3.0 * x3 + 4.0 * x2 + x);
            w[a][3] = 0.5 * (x3 - x2);
            d[a][0] = 0.5 * (-3.0 * x2 + 4.0 * x - 1.0);
            d[a][1] = 0.5 * (9.0 * x2 - 10.0 * x);
            d[a][2] = 0.5 * (-9.0 * x2 + 8.0 * x + 1.0);
            d[a][3] = 0.5 * (3.0 * x2 - 2.0 * x);
        }
        for (int k = 0; k < 4; ++k) {
            for (int j = 0; j < 4; ++j) {
                double sx = 0.0, dx = 0.0;
                for (int i = 0; i < 4; ++i) {
                    const double v = at(base[0] - 1 + i, base[1] - 1 + j, base[2] - 1 + k);
                    sx += w[0][i] * v;
                    dx += d[0][i] * v;
                }
                value += w[1][j] * w[2][k] * sx;
                gradient[0] += w[1][j] * w[2][k] * dx;
                gradient[1] += d[1][j] * w[2][k] * sx;
                gradient[2] += w[1][j] * d[2][k] * sx;
            }
        }
    } else {
        for (int c = 0; c < 8; ++c) {
            const int o[3] = {c & 1, (c >> 1) & 1, (c >> 2) & 1};
            const std::int64_t q[3] = {base[0] + o[0], base[1] + o[1], base[2] + o[2]};
            double w[3], d[3];
            for (int a = 0; a < 3; ++a) {
                w[a] = o[a] ? t[a] : 1.0 - t[a];
                d[a] = o[a] ? 1.0 : -1.0;
            }
            const double v = at(q[0], q[1], q[2]);
            const double weight = w[0] * w[1] * w[2];
            value += weight * v;
            if (interpolation_ == GridInterpolation::Trilinear) {
                gradient[0] += d[0] * w[1] * w[2] * v;
                gradient[1] += w[0] * d[1] * w[2] * v;
                gradient[2] += w[0] * w[1] * d[2] * v;
            } else {  // central differences at the corner, interpolated
                for (int a = 0; a < 3; ++a) {
                    std::int64_t up[3] = {q[0], q[1], q[2]}, down[3] = {q[0], q[1], q[2]};
                    ++up[a];
                    --down[a];
                    gradient[a] +=
                        weight * 0.5 *
                        (double(at(up[0], up[1], up[2])) - at(down[0], down[1], down[2]));
                }
            }
        }
    }
    for (double& g : gradient) g /= spacing_;
    return true;
}

PowerDistanceField::PowerDistanceField(const Atoms& atoms, double radius_add, double iso)
    : iso_(iso) {
    const std::size_t n = atoms.size();
    if (n == 0) return;
    double r_max = 0.0;
    Vec3 lo{}, hi{};
    for (std::size_t i = 0; i < n; ++i) {
        r_max = std::max(r_max, double(atoms.radius[i]) + radius_add);
        for (int a = 0; a < 3; ++a) {
            const double x = atoms.xyz[3 * i + a];
            lo[a] = i == 0 ? x : std::min(lo[a], x);
            hi[a] = i == 0 ? x : std::max(hi[a], x);
        }
    }
    // Any atom outside the 27 cells around a point is at least one cell away from it, so its
    // power distance is at least cell^2 - r_max^2: below that bound the minimum found is exact.
    cell_ = r_max + 2.0;
    auto cell_count = [&] {
        std::int64_t total = 1;
        for (int a = 0; a < 3; ++a) {
            cells_[a] = std::int64_t((hi[a] - lo[a]) / cell_) + 1;
            total *= cells_[a];
        }
        return total;
    };
    while (cell_count() > std::max<std::int64_t>(std::int64_t(4 * n), 1 << 20)) cell_ *= 1.5;
    bound_ = cell_ * cell_ - r_max * r_max;
    origin_ = lo;
    const std::size_t total = std::size_t(cells_[0] * cells_[1] * cells_[2]);
    auto cell_of = [&](std::size_t i) {
        std::int64_t c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = std::min<std::int64_t>(std::int64_t((atoms.xyz[3 * i + a] - lo[a]) / cell_),
                                          cells_[a] - 1);
        return std::size_t((c[2] * cells_[1] + c[1]) * cells_[0] + c[0]);
    };
    start_.assign(total + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start_[cell_of(i) + 1];
    for (std::size_t c = 0; c < total; ++c) start_[c + 1] += start_[c];
    atoms_.resize(4 * n);
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t slot = fill[cell_of(i)]++;
        const double r = atoms.radius[i] + radius_add;
        for (int a = 0; a < 3; ++a) atoms_[4 * slot + a] = atoms.xyz[3 * i + a];
        atoms_[4 * slot + 3] = r * r;
    }
}

bool PowerDistanceField::sample(const Vec3& p, double& value, Vec3& gradient) const {
    if (atoms_.empty()) return false;
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a) {
        const double u = (p[a] - origin_[a]) / cell_;
        if (!std::isfinite(u) || u < -2.0 || u > double(cells_[a]) + 1.0) return false;
        c[a] = std::int64_t(std::floor(u));
    }
    double best = std::numeric_limits<double>::infinity();
    std::size_t arg = 0;
    for (std::int64_t z = std::max<std::int64_t>(c[2] - 1, 0);
         z <= std::min<std::int64_t>(c[2] + 1, cells_[2] - 1); ++z)
        for (std::int64_t y = std::max<std::int64_t>(c[1] - 1, 0);
             y <= std::min<std::int64_t>(c[1] + 1, cells_[1] - 1); ++y)
            for (std::int64_t x = std::max<std::int64_t>(c[0] - 1, 0);
                 x <= std::min<std::int64_t>(c[0] + 1, cells_[0] - 1); ++x) {
                const std::size_t cell = std::size_t((z * cells_[1] + y) * cells_[0] + x);
                for (std::uint32_t i = start_[cell]; i < start_[cell + 1]; ++i) {
                    const double* q = &atoms_[4 * std::size_t(i)];
                    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                    const double pi = dx * dx + dy * dy + dz * dz - q[3];
                    if (pi < best) {
                        best = pi;
                        arg = i;
                    }
                }
            }
    if (!(best < bound_)) return false;
    value = best;
    const double* q = &atoms_[4 * arg];
    for (int a = 0; a < 3; ++a) gradient[a] = 2.0 * (p[a] - q[a]);
    return true;
}

// ---------------------------------------------------------------------------------------------
// Projection

ProjectOptions project_options_for_spacing(double spacing) {
    ProjectOptions o;
    o.max_step = 0.5 * spacing;
    o.max_distance = spacing;
    o.tolerance = 1e-3 * spacing;
    return o;
}

namespace {

// Vertices [begin, end) in index order, or by_cell, by their cells of edge `cell` from `origin`
// (z, then y, then x; cells below the origin count as the first), in index order within a cell.
// A chunk's vertices (marching cubes' order: a few planes) lie in a small box of cells: counted
// into it (a stable counting sort, half the time of sorting (cell, index) pairs on the 12-copy
// shell's snap chunks), else the pairs are sorted (the same order).
std::vector<std::size_t> visit_order(const Mesh& mesh, std::size_t begin, std::size_t end,
                                     bool by_cell, const Vec3& origin, double cell) {
    const std::size_t n = end - begin;
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), begin);
    if (!by_cell || n == 0) return order;
    constexpr double kTop = double((1 << 21) - 1);
    std::vector<std::uint32_t> c(3 * n);  // the cells, x y z per vertex
    std::uint32_t lo[3] = {~0u, ~0u, ~0u}, hi[3] = {0, 0, 0};
    for (std::size_t v = 0; v < n; ++v)
        for (int a = 0; a < 3; ++a) {
            const double t =
                std::floor((mesh.positions[3 * (begin + v) + a] - origin[a]) / cell);
            const std::uint32_t k = std::uint32_t(std::clamp(t, 0.0, kTop));
            c[3 * v + a] = k;
            lo[a] = std::min(lo[a], k), hi[a] = std::max(hi[a], k);
        }
    const std::size_t span[3] = {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
    const double box = double(span[0]) * double(span[1]) * double(span[2]);
    auto box_cell = [&](std::size_t v) {
        return ((std::size_t(c[3 * v + 2] - lo[2]) * span[1] + (c[3 * v + 1] - lo[1])) *
                    span[0] +
                (c[3 * v] - lo[0]));
    };
    if (box <= 4.0 * double(n)) {
        std::vector<std::uint32_t> first(std::size_t(box) + 1, 0);
        for (std::size_t v = 0; v < n; ++v) ++first[box_cell(v) + 1];
        for (std::size_t b = 0; b + 1 < first.size(); ++b) first[b + 1] += first[b];
        for (std::size_t v = 0; v < n; ++v) order[first[box_cell(v)]++] = begin + v;
        return order;
    }
    std::vector<std::pair<std::uint64_t, std::size_t>> keyed(n);
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint64_t key = (std::uint64_t(c[3 * v + 2]) << 42) |
                                  (std::uint64_t(c[3 * v + 1]) << 21) | c[3 * v];
        keyed[v] = {key, begin + v};
    }
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t k = 0; k < n; ++k) order[k] = keyed[k].second;
    return order;
}

}  // namespace

ProjectStats project_onto_field(Mesh& mesh, std::size_t first, const SurfaceField& base_field,
                                const ProjectOptions& options) {
    // Vertices are independent: chunks of them on all threads, each chunk with its own counts.
    // Visited cell by cell, a chunk should hold the marching-cubes vertices of a bin's planes,
    // each bin's all at once: on the 2.43 M-atom shell at 1 Å (25 k vertices a plane, bins of
    // 3.3 planes) chunks of 16 k vertices held less than a plane, so each bin's balls and arcs
    // were gathered again in about five chunks, and the snap took 17.9-19.3 s of CPU; with
    // 128 k, 14.6-15.2 s (512 k no better); 512 had made the cursor no faster than the plain
    // distance. Smaller meshes keep eight chunks a thread or more, down to 16 k.
    const std::size_t nv = mesh.vertex_count();
    const unsigned threads = thread_count();
    const std::size_t todo = first < nv ? nv - first : 0;
    const std::size_t chunk_size =
        std::clamp<std::size_t>(todo / (8 * std::size_t(threads)), 16384, 131072);
    const std::size_t chunks = (todo + chunk_size - 1) / chunk_size;
    std::vector<ProjectStats> per_chunk(chunks);
    const bool along = options.along_normals && mesh.normals.size() == 3 * nv;
    Vec3 cell_origin{};
    double cell = 0.0;
    const bool by_cell = base_field.visit_cells(cell_origin, cell) && cell > 0.0;
    parallel_chunks(chunks, threads, [&](std::size_t c) {
        // The chunk's vertices lie close together: a view keeping its last features serves them,
        // all the better when they come cell by cell.
        const std::unique_ptr<SurfaceField> local = base_field.local();
        const SurfaceField& field = local ? *local : base_field;
        ProjectStats& stats = per_chunk[c];
        const std::size_t end = std::min(nv, first + (c + 1) * chunk_size);
        const std::vector<std::size_t> visit =
            visit_order(mesh, first + c * chunk_size, end, by_cell, cell_origin, cell);
        Vec3 g{};
        auto set_normal = [&](std::size_t v) {
            if (!options.set_normals || mesh.normals.size() != 3 * nv) return;
            const double len = std::sqrt(dot(g, g));
            if (!(len > 0.0) || !std::isfinite(len)) return;
            for (int a = 0; a < 3; ++a)
                mesh.normals[3 * v + a] = float(field.outward() * g[a] / len);
        };
        for (const std::size_t v : visit) {
            Vec3 out;
            if (along) {
                const Vec3 dir{mesh.normals[3 * v], mesh.normals[3 * v + 1],
                               mesh.normals[3 * v + 2]};
                const double len = std::sqrt(dot(dir, dir));
                if (len > 0.5) {
                    const Vec3 unit{dir[0] / len, dir[1] / len, dir[2] / len};
                    const LineOutcome o =
                        newton_on_line(field, vertex(mesh, v), unit, options, out, g);
                    if (o == LineOutcome::Converged) {
                        for (int a = 0; a < 3; ++a) mesh.positions[3 * v + a] = float(out[a]);
                        set_normal(v);
                        ++stats.projected;
                        continue;
                    }
                    if (o == LineOutcome::Outside) {
                        ++stats.outside_field;
                        continue;
                    }
                    ++stats.off_normal;  // grazing or not converged on the line: along the gradient
                }
            }
            switch (newton(field, vertex(mesh, v), options, out, g)) {
                case Outcome::Converged:
                    for (int a = 0; a < 3; ++a) mesh.positions[3 * v + a] = float(out[a]);
                    set_normal(v);
                    ++stats.projected;
                    break;
                case Outcome::NotConverged:
                    ++stats.not_converged;
                    break;
                case Outcome::Outside:
                    ++stats.outside_field;
                    break;
            }
        }
    });
    ProjectStats total;
    for (const ProjectStats& s : per_chunk) {
        total.projected += s.projected;
        total.not_converged += s.not_converged;
        total.outside_field += s.outside_field;
        total.off_normal += s.off_normal;
    }
    return total;
}

void normals_from_field(Mesh& mesh, const SurfaceField& field, std::size_t first,
                        std::size_t last) {
    const std::size_t nv = mesh.vertex_count();
    last = std::min(last, nv);
    if (mesh.normals.size() != 3 * nv) {
        // Start from the area-weighted triangle normals, for vertices the field cannot serve.
        mesh.normals.assign(3 * nv, 0.0f);
        std::vector<double> sum(3 * nv, 0.0);
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const Index* c = &mesh.indices[3 * t];
            const Vec3 a = vertex(mesh, c[0]), b = vertex(mesh, c[1]), d = vertex(mesh, c[2]);
            const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
            const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                         u[0] * w[1] - u[1] * w[0]};
            for (int i = 0; i < 3; ++i)
                for (int a2 = 0; a2 < 3; ++a2) sum[3 * c[i] + a2] += n[a2];
        }
        for (std::size_t v = 0; v < nv; ++v) {
            const Vec3 n{sum[3 * v], sum[3 * v + 1], sum[3 * v + 2]};
            const double len = std::sqrt(dot(n, n));
            if (len > 0.0)
                for (int a = 0; a < 3; ++a) mesh.normals[3 * v + a] = float(n[a] / len);
        }
    }
    constexpr std::size_t kChunk = 1024;
    const std::size_t chunks = first < last ? (last - first + kChunk - 1) / kChunk : 0;
    parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
        const std::size_t end = std::min(last, first + (c + 1) * kChunk);
        for (std::size_t v = first + c * kChunk; v < end; ++v) {
            double value = 0.0;
            Vec3 g;
            if (!field.sample(vertex(mesh, v), value, g)) continue;
            const double len = std::sqrt(dot(g, g));
            if (!(len > 0.0) || !std::isfinite(len)) continue;
            for (int a = 0; a < 3; ++a)
                mesh.normals[3 * v + a] = float(field.outward() * g[a] / len);
        }
    });
}

RefineStats refine_mesh(Mesh& mesh, int levels, const SurfaceField* field,
                        const ProjectOptions& options) {
    check_refine_size(levels, mesh.triangle_count());
    RefineStats stats;
    stats.levels = levels;
    const std::size_t original = mesh.vertex_count();
    for (int level = 0; level < levels; ++level) {
        const std::size_t first = mesh.vertex_count();
        subdivide_butterfly(mesh, ButterflyOffset::Normal);
        stats.new_vertices += mesh.vertex_count() - first;
        if (field == nullptr) continue;
        const ProjectStats p = project_onto_field(mesh, first, *field, options);
        stats.projection.projected += p.projected;
        stats.projection.not_converged += p.not_converged;
        stats.projection.outside_field += p.outside_field;
        stats.projection.off_normal += p.off_normal;
        // The next level's edge normals, and its projection lines, start from these.
        normals_from_field(mesh, *field, first);
    }
    if (field != nullptr && levels > 0) normals_from_field(mesh, *field, 0, original);
    return stats;
}

}  // namespace fdmsurf::detail
