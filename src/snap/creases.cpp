// Crease recovery on union-of-balls meshes (see creases.hpp): exact placement on spheres,
// circles and three-sphere points, by edge and triangle splits that keep a closed manifold one.
#include "snap/creases.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>
#include <utility>

#include "base/parallel.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/half_edges.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf::detail {

BallUnion::BallUnion(const Atoms& atoms, double radius_add, double pi_iso) {
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const double r = double(atoms.radius[i]) + radius_add;
        const double r2 = r * r + pi_iso;
        if (!(r2 > 0.0)) continue;
        for (int a = 0; a < 3; ++a) centre_.push_back(atoms.xyz[3 * i + a]);
        radius_.push_back(std::sqrt(r2));
        r_max_ = std::max(r_max_, radius_.back());
    }
    const std::size_t n = radius_.size();
    if (n == 0) return;
    // Cells of half the largest radius (a query visits few balls beyond its reach), at most
    // about 256 per axis.
    double hi[3];
    for (int a = 0; a < 3; ++a) {
        origin_[a] = hi[a] = centre_[a];
        for (std::size_t i = 1; i < n; ++i) {
            origin_[a] = std::min(origin_[a], centre_[3 * i + a]);
            hi[a] = std::max(hi[a], centre_[3 * i + a]);
        }
    }
    cell_ = std::max(0.5 * r_max_, 1e-3);
    for (int a = 0; a < 3; ++a) cell_ = std::max(cell_, (hi[a] - origin_[a]) / 255.0);
    for (int a = 0; a < 3; ++a) dims_[a] = std::int64_t((hi[a] - origin_[a]) / cell_) + 1;
    const std::size_t cells = std::size_t(dims_[0] * dims_[1] * dims_[2]);
    std::vector<std::uint32_t> cell_of(n);
    start_.assign(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        std::int64_t c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = std::min(dims_[a] - 1, std::int64_t((centre_[3 * i + a] - origin_[a]) / cell_));
        cell_of[i] = std::uint32_t((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
        ++start_[cell_of[i] + 1];
    }
    for (std::size_t k = 0; k < cells; ++k) start_[k + 1] += start_[k];
    {
        std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
        items_.resize(n);
        for (std::size_t i = 0; i < n; ++i) items_[fill[cell_of[i]]++] = std::uint32_t(i);
    }
    // Neighbour lists: centres closer than the sum of the radii (plus a hair, so that balls
    // that touch are listed: a point on both spheres must see both).
    std::vector<std::vector<std::uint32_t>> lists(n);
    parallel_chunks((n + 255) / 256, thread_count(), [&](std::size_t c) {
        for (std::size_t i = 256 * c; i < std::min(n, 256 * (c + 1)); ++i) {
            const double* p = &centre_[3 * i];
            for_each_within(p, radius_[i] + r_max_, [&](std::uint32_t j) {
                if (j == i) return;
                const double* q = &centre_[3 * std::size_t(j)];
                const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                const double reach = radius_[i] + radius_[j] + 1e-6;
                if (dx * dx + dy * dy + dz * dz < reach * reach) lists[i].push_back(j);
            });
            std::sort(lists[i].begin(), lists[i].end());
        }
    });
    nb_start_.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) nb_start_[i + 1] = nb_start_[i] + lists[i].size();
    nb_.reserve(nb_start_[n] + 1);
    for (const auto& l : lists) nb_.insert(nb_.end(), l.begin(), l.end());
    nb_.push_back(0);  // so that &nb_[0] is valid with no neighbours at all
}

namespace {

using Index = std::uint32_t;
constexpr Index kNone = ~Index{0};

double dist(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

// The spheres a vertex lies on: one on a sphere's open patch, two on a crease, three at a corner.
struct Label {
    std::array<Index, 3> b{kNone, kNone, kNone};
    std::uint8_t n = 0;
    bool has(Index i) const {
        return (n > 0 && b[0] == i) || (n > 1 && b[1] == i) || (n > 2 && b[2] == i);
    }
    void add(Index i) {
        if (n < 3 && !has(i)) b[n++] = i;
    }
};

Label common(const Label& x, const Label& y) {
    Label c;
    if (x.n == 1 && y.n == 1) {  // the usual case
        if (x.b[0] == y.b[0]) c.add(x.b[0]);
        return c;
    }
    for (int k = 0; k < x.n; ++k)
        if (y.has(x.b[k])) c.add(x.b[k]);
    return c;
}

bool subset(const Label& x, const Label& y) {
    for (int k = 0; k < x.n; ++k)
        if (!y.has(x.b[k])) return false;
    return true;
}

struct Circle {
    Vec3 m, u;  // centre, unit axis
    double rho;
};

// Distance (Å) under which a point counts as on a sphere, and above which inside as buried.
constexpr double kOnSphere = 1e-6;
// Å: how far from the union's boundary a point may lie to be projected onto it.
constexpr double kReach = 1.0;
// A crossing edge's split point may lie up to this many edge lengths from the chord: a crease
// at the bottom of a groove narrower than the spacing lies below the chord that bridges it
// (measured on 4HHB: allowing 2 rather than 1 edge length resolves 80% of the remaining
// crossings of that kind and takes the per-atom area error from 0.069 to 0.061 Å² for sas).
constexpr double kMaxDeviation = 2.0;

class Geometry {
public:
    explicit Geometry(const BallUnion& balls) : balls_(balls) {}

    Vec3 centre(Index i) const {
        const double* c = balls_.centre(i);
        return {c[0], c[1], c[2]};
    }
    double radius(Index i) const { return balls_.radius(i); }

    // Calls f(j) for every ball that may contain or touch q: the neighbours of a ball of
    // `label` (q lies on that sphere, so any ball that reaches q meets it), else every ball
    // whose centre lies within the largest radius.
    template <class F>
    void for_each_reaching(const Vec3& q, const Label& label, F&& f) const {
        if (label.n == 0) {
            balls_.for_each_within(q.data(), balls_.max_radius() + kOnSphere, f);
            return;
        }
        Index i = label.b[0];
        for (int k = 1; k < label.n; ++k)
            if (balls_.neighbour_count(label.b[k]) < balls_.neighbour_count(i)) i = label.b[k];
        for (const Index* j = balls_.neighbours_begin(i); j != balls_.neighbours_end(i); ++j) f(*j);
    }

    // True when q (on the spheres of `label`) lies inside no ball but those of `label`, which
    // gains every other sphere q lies on; false when some ball buries it (its index in
    // `burier`).
    bool classify(const Vec3& q, Label& label, Index* burier = nullptr) const {
        bool exposed = true;
        const Label on = label;
        for_each_reaching(q, on, [&](Index j) {
            if (!exposed || label.has(j)) return;
            const double d = dist(q, centre(j)) - radius(j);
            if (d < -kOnSphere) {
                exposed = false;
                if (burier) *burier = j;
            } else if (d <= kOnSphere) {
                label.add(j);
            }
        });
        return exposed;
    }

    // Every ball that buries q (on the spheres of `label`), other than those of `label`.
    void buriers(const Vec3& q, const Label& label, std::vector<Index>& out) const {
        out.clear();
        for_each_reaching(q, label, [&](Index j) {
            if (!label.has(j) && dist(q, centre(j)) < radius(j) - kOnSphere) out.push_back(j);
        });
    }

    // Every ball whose sphere passes within `reach` of q.
    void near(const Vec3& q, double reach, std::vector<Index>& out) const {
        out.clear();
        balls_.for_each_within(q.data(), balls_.max_radius() + reach, [&](Index j) {
            if (std::abs(dist(q, centre(j)) - radius(j)) <= reach) out.push_back(j);
        });
    }

    bool circle(Index i, Index j, Circle& c) const {
        const Vec3 ci = centre(i), cj = centre(j);
        const Vec3 e = sub(cj, ci);
        const double d = norm(e);
        const double ri = radius(i), rj = radius(j);
        if (!(d > 1e-9) || d >= ri + rj || d <= std::abs(ri - rj)) return false;
        const double a = (d * d + ri * ri - rj * rj) / (2.0 * d);
        const double rho2 = ri * ri - a * a;
        if (!(rho2 > 0.0)) return false;
        c.u = scale(e, 1.0 / d);
        c.m = add(ci, scale(c.u, a));
        c.rho = std::sqrt(rho2);
        return true;
    }

    static Vec3 closest_on_circle(const Circle& c, const Vec3& x) {
        Vec3 w = sub(x, c.m);
        w = sub(w, scale(c.u, dot(w, c.u)));
        double len = norm(w);
        if (!(len > 1e-12)) {  // on the axis: any point of the circle is as near
            const Vec3 t = std::abs(c.u[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
            w = cross(c.u, t);
            len = norm(w);
        }
        return add(c.m, scale(w, c.rho / len));
    }

    // The two points on spheres i, j and k (false when the three do not meet in two points).
    bool triple_points(Index i, Index j, Index k, Vec3 out[2]) const {
        const Vec3 ci = centre(i);
        const Vec3 e1 = sub(centre(j), ci), e2 = sub(centre(k), ci);
        const double ri2 = radius(i) * radius(i);
        const double b1 = 0.5 * (dot(e1, e1) + ri2 - radius(j) * radius(j));
        const double b2 = 0.5 * (dot(e2, e2) + ri2 - radius(k) * radius(k));
        const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
        const double det = g11 * g22 - g12 * g12;
        if (!(det > 1e-12 * g11 * g22)) return false;  // centres (nearly) on a line
        const double alpha = (b1 * g22 - b2 * g12) / det, beta = (b2 * g11 - b1 * g12) / det;
        const Vec3 y0 = add(scale(e1, alpha), scale(e2, beta));
        const Vec3 n = cross(e1, e2);
        const double t2 = (ri2 - dot(y0, y0)) / dot(n, n);
        if (!(t2 > 0.0)) return false;
        const double t = std::sqrt(t2);
        out[0] = add(ci, add(y0, scale(n, t)));
        out[1] = add(ci, sub(y0, scale(n, t)));
        return true;
    }

    // A point of the union's boundary near p: the radial projection onto the ball of least
    // power distance if no ball buries it, else the nearest exposed point of a circle of that
    // ball with a burying ball, else the nearest exposed three-sphere point of such circles.
    bool project(const Vec3& p, Vec3& q, Label& label) const {
        Index i = kNone;
        double best = std::numeric_limits<double>::infinity();
        // Every ball whose sphere passes within kReach of p: its power distance is below that
        // of any farther ball as long as p lies within kReach of the union's boundary.
        balls_.for_each_within(p.data(), balls_.max_radius() + kReach, [&](Index j) {
            const Vec3 d = sub(p, centre(j));
            const double pi = dot(d, d) - radius(j) * radius(j);
            if (pi < best) {
                best = pi;
                i = j;
            }
        });
        if (i == kNone) return false;
        const Vec3 ci = centre(i);
        const Vec3 d = sub(p, ci);
        const double len = norm(d);
        if (!(len > 1e-9)) return false;
        const Vec3 r = add(ci, scale(d, radius(i) / len));
        Label l;
        l.add(i);
        if (classify(r, l)) {
            q = r;
            label = l;
            return true;
        }
        Label only_i;
        only_i.add(i);
        std::vector<Index> around;
        buriers(r, only_i, around);
        double best_d = std::numeric_limits<double>::infinity();
        std::vector<Index> deeper;
        for (const Index j : around) {
            Circle c;
            if (!circle(i, j, c)) continue;
            const Vec3 x = closest_on_circle(c, p);
            Label lx;
            lx.add(i);
            lx.add(j);
            if (classify(x, lx)) {
                if (dist(x, p) < best_d) {
                    best_d = dist(x, p);
                    q = x;
                    label = lx;
                }
            }
        }
        if (best_d < std::numeric_limits<double>::infinity()) return true;
        // No exposed circle point: the nearest exposed three-sphere point.
        for (const Index j : around) {
            Circle c;
            if (!circle(i, j, c)) continue;
            const Vec3 x = closest_on_circle(c, p);
            Label ij;
            ij.add(i);
            ij.add(j);
            buriers(x, ij, deeper);
            for (const Index k : deeper) {
                Vec3 t[2];
                if (!triple_points(i, j, k, t)) continue;
                for (const Vec3& y : t) {
                    Label ly;
                    ly.add(i);
                    ly.add(j);
                    ly.add(k);
                    if (classify(y, ly) && dist(y, p) < best_d) {
                        best_d = dist(y, p);
                        q = y;
                        label = ly;
                    }
                }
            }
        }
        return best_d < std::numeric_limits<double>::infinity();
    }

private:
    const BallUnion& balls_;
};

Vec3 position(const Mesh& mesh, Index v) {
    const float* p = &mesh.positions[3 * std::size_t(v)];
    return {p[0], p[1], p[2]};
}

// Distance from the midpoint of a chord of length `len` to its arc on a circle of radius r.
double sagitta(double r, double len) {
    const double half = 0.5 * len;
    return half >= r ? r : r - std::sqrt(r * r - half * half);
}

enum class SplitKind : std::uint8_t { Crease, Chord, Other };

struct EdgeSplit {
    std::uint64_t key;
    Vec3 p;
    Label label;
    SplitKind kind;
};

class Recovery {
public:
    Recovery(Mesh& mesh, const BallUnion& balls, const CreaseOptions& options, CreaseStats& stats)
        : mesh_(mesh), geo_(balls), options_(options), stats_(stats) {}

    void run() {
        project_vertices();
        snap_vertices();
        for (int round = 0; round < options_.max_rounds; ++round) {
            if (mesh_.triangle_count() >= options_.max_triangles) {
                stats_.stopped_at_size = true;
                break;
            }
            stats_.rounds = round + 1;
            // Edges (crossings and chords) first, then corners: a corner's triangle appears in
            // a round's splits and gets its three-sphere point before the next round could cut
            // its edges.
            const std::size_t splits = split_edges(options_.chord_tolerance > 0.0);
            const std::size_t corners = insert_corners();
            if (splits + corners == 0) break;
        }
        finish();
    }

private:
    // Every input vertex onto the boundary of the union.
    void project_vertices() {
        const std::size_t nv = mesh_.vertex_count();
        labels_.assign(nv, Label{});
        constexpr std::size_t kChunk = 1024;
        const std::size_t chunks = (nv + kChunk - 1) / kChunk;
        std::vector<std::size_t> unresolved(chunks, 0);
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(nv, (c + 1) * kChunk);
            for (std::size_t v = c * kChunk; v < end; ++v) {
                Vec3 q;
                Label l;
                if (!geo_.project(position(mesh_, Index(v)), q, l)) {
                    ++unresolved[c];
                    continue;
                }
                for (int a = 0; a < 3; ++a) mesh_.positions[3 * v + a] = float(q[a]);
                labels_[v] = l;
            }
        });
        for (const std::size_t u : unresolved) stats_.unresolved += u;
        stats_.projected = nv - stats_.unresolved;
    }

    // Vertices next to a crease moved onto it, before any split: for each vertex, the nearest
    // exposed point of a circle between its sphere and the sphere of a neighbour across a
    // crease, when the vertex is the nearer end of that crossing edge and the move is at most
    // half the edge. Moves are applied greedily, nearest first, with no two neighbours moving
    // and no triangle of the vertex's fan folding over; the vertex count does not grow where
    // a split would have added one.
    void snap_vertices() {
        const std::size_t nv = mesh_.vertex_count(), nt = mesh_.triangle_count();
        const std::vector<Index>& idx = mesh_.indices;
        // Triangles around each vertex (counting sort).
        std::vector<Index> start(nv + 1, 0), fan(3 * nt);
        for (const Index v : idx) ++start[v + 1];
        for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
        {
            std::vector<Index> fill(start.begin(), start.end() - 1);
            for (std::size_t t = 0; t < nt; ++t)
                for (int k = 0; k < 3; ++k) fan[fill[idx[3 * t + k]]++] = Index(t);
        }
        struct Move {
            double d;
            Index v;
            Vec3 p;
            Label label;
        };
        constexpr std::size_t kChunk = 2048;
        const std::size_t chunks = (nv + kChunk - 1) / kChunk;
        std::vector<std::vector<Move>> found(chunks);
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(nv, (c + 1) * kChunk);
            for (std::size_t v = c * kChunk; v < end; ++v) {
                const Label& lv = labels_[v];
                if (lv.n != 1) continue;
                const Vec3 pv = position(mesh_, Index(v));
                Move best{std::numeric_limits<double>::infinity(), Index(v), {}, {}};
                for (Index f = start[v]; f < start[v + 1]; ++f) {
                    const Index t = fan[f];
                    for (int k = 0; k < 3; ++k) {
                        const Index w = idx[3 * t + k];
                        if (w == v || labels_[w].n == 0 || share(Index(v), w)) continue;
                        const Vec3 pw = position(mesh_, w);
                        const double len = dist(pv, pw);
                        for (int y = 0; y < labels_[w].n; ++y) {
                            Circle circle;
                            if (!geo_.circle(lv.b[0], labels_[w].b[y], circle)) continue;
                            const double fa = dot(sub(pv, circle.m), circle.u);
                            const double fb = dot(sub(pw, circle.m), circle.u);
                            // v must be the nearer end of the chord's crossing.
                            if (!(fa <= 0.0 && fb > 0.0) || -fa > fb) continue;
                            const Vec3 q = Geometry::closest_on_circle(circle, pv);
                            const double d = dist(q, pv);
                            if (d >= best.d || d > 0.5 * len) continue;
                            Label l;
                            l.add(lv.b[0]);
                            l.add(labels_[w].b[y]);
                            if (!geo_.classify(q, l)) continue;
                            best = {d, Index(v), q, l};
                        }
                    }
                }
                if (best.d < std::numeric_limits<double>::infinity()) found[c].push_back(best);
            }
        });
        std::vector<Move> moves;
        for (auto& f : found) moves.insert(moves.end(), f.begin(), f.end());
        std::sort(moves.begin(), moves.end(),
                  [](const Move& a, const Move& b) { return a.d != b.d ? a.d < b.d : a.v < b.v; });
        std::vector<std::uint8_t> locked(nv, 0);
        std::size_t moved = 0;
        for (const Move& m : moves) {
            if (locked[m.v]) continue;
            // The fan must not fold over at the new position.
            const Vec3 old_p = position(mesh_, m.v);
            const Label old_l = labels_[m.v];
            for (int a = 0; a < 3; ++a) mesh_.positions[3 * std::size_t(m.v) + a] = float(m.p[a]);
            labels_[m.v] = m.label;
            bool bad = false;
            for (Index f = start[m.v]; f < start[m.v + 1] && !bad; ++f) {
                const Index t = fan[f];
                bad = folded(idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]);
            }
            if (bad) {
                for (int a = 0; a < 3; ++a)
                    mesh_.positions[3 * std::size_t(m.v) + a] = float(old_p[a]);
                labels_[m.v] = old_l;
                continue;
            }
            ++moved;
            for (Index f = start[m.v]; f < start[m.v + 1]; ++f)
                for (int k = 0; k < 3; ++k) locked[idx[3 * fan[f] + k]] = 1;
        }
        stats_.snapped = moved;
    }

    // The split of a crossing edge: its ends lie on spheres (la, lb) with none in common.
    // Preferred: where the chord meets the plane of a circle of an end's sphere i with the other
    // end's sphere j, moved onto that circle, if no ball buries it there. Else the surface goes
    // from i to j over a third ball k (one that buries the circle (i, j), or joins two balls
    // that do not meet): the exposed point of circle (i, k) or (k, j), or of the three-sphere
    // points of i, j and k, nearest the chord. Else the nearest surface point of the midpoint,
    // if it lies on a sphere of neither end. Every split point shares a sphere with an end and
    // is not on that end's spheres only, so that the crossing moves on.
    bool crossing_split(const Label& la, const Label& lb, const Vec3& pa, const Vec3& pb,
                        double len, EdgeSplit& s) const {
        double best = std::numeric_limits<double>::infinity();
        auto consider = [&](const Vec3& q, Label l, const Vec3& from) {
            if (subset(l, la) || subset(l, lb)) return;
            const double d = dist(q, from);
            if (d < best && d <= kMaxDeviation * len && geo_.classify(q, l)) {
                best = d;
                s.p = q;
                s.label = l;
                s.kind = SplitKind::Crease;
            }
        };
        auto circle_point = [&](Index i, Index j) {
            Circle circle;
            if (!geo_.circle(i, j, circle)) return;
            // The chord must cross the circle's plane: from i's side (a) to j's (b).
            const double fa = dot(sub(pa, circle.m), circle.u);
            const double fb = dot(sub(pb, circle.m), circle.u);
            if (!(fa <= 0.0 && fb >= 0.0) || fa == fb) return;
            const Vec3 x = add(pa, scale(sub(pb, pa), fa / (fa - fb)));
            Label l;
            l.add(i);
            l.add(j);
            consider(Geometry::closest_on_circle(circle, x), l, x);
        };
        for (int x = 0; x < la.n; ++x)
            for (int y = 0; y < lb.n; ++y) circle_point(la.b[x], lb.b[y]);
        if (best < std::numeric_limits<double>::infinity()) return true;
        const Vec3 mid = scale(add(pa, pb), 0.5);
        std::vector<Index> third;
        geo_.near(mid, len, third);
        for (const Index k : third) {
            if (la.has(k) || lb.has(k)) continue;
            for (int x = 0; x < la.n; ++x) circle_point(la.b[x], k);
            for (int y = 0; y < lb.n; ++y) circle_point(k, lb.b[y]);
            for (int x = 0; x < la.n; ++x)
                for (int y = 0; y < lb.n; ++y) {
                    Vec3 tp[2];
                    if (!geo_.triple_points(la.b[x], lb.b[y], k, tp)) continue;
                    Label l;
                    l.add(la.b[x]);
                    l.add(lb.b[y]);
                    l.add(k);
                    for (const Vec3& y3 : tp) consider(y3, l, mid);
                }
        }
        if (best < std::numeric_limits<double>::infinity()) return true;
        Vec3 q;
        Label l;
        if (!geo_.project(mid, q, l) || dist(q, mid) > kMaxDeviation * len) return false;
        bool brings_new = false;
        for (int k = 0; k < l.n; ++k) brings_new |= !la.has(l.b[k]) && !lb.has(l.b[k]);
        if (!brings_new) return false;
        s.p = q;
        s.label = l;
        s.kind = SplitKind::Other;
        return true;
    }

    // The split of edge (a, b), if it needs one. `chords`: also edges whose ends share a ball,
    // when their arc lies farther than the tolerance from them.
    bool decide(Index a, Index b, bool chords, EdgeSplit& s) const {
        const Label& la = labels_[a];
        const Label& lb = labels_[b];
        if (la.n == 0 || lb.n == 0) return false;
        const Vec3 pa = position(mesh_, a), pb = position(mesh_, b);
        const double len = dist(pa, pb);
        if (!(len > options_.min_edge)) return false;
        const Vec3 mid = scale(add(pa, pb), 0.5);
        const Label c = common(la, lb);
        if (c.n == 0) return crossing_split(la, lb, pa, pb, len, s);
        if (!chords) return false;
        const double tol = options_.chord_tolerance;
        if (c.n >= 2) {
            Circle circle;
            if (geo_.circle(c.b[0], c.b[1], circle)) {
                const double sag = sagitta(circle.rho, len);
                if (sag <= tol) return false;
                const Vec3 q = Geometry::closest_on_circle(circle, mid);
                Label l;
                l.add(c.b[0]);
                l.add(c.b[1]);
                // Along the crease only if the arc is where a crease edge's would be.
                if (dist(q, mid) <= 1.5 * sag + 1e-6 && geo_.classify(q, l)) {
                    s.p = q;
                    s.label = l;
                    s.kind = SplitKind::Chord;
                    return true;
                }
            }
        }
        // On one ball: the largest sagitta among the common balls decides.
        Index i = c.b[0];
        for (int k = 1; k < c.n; ++k)
            if (geo_.radius(c.b[k]) < geo_.radius(i)) i = c.b[k];
        const double sag = sagitta(geo_.radius(i), len);
        if (sag <= tol) return false;
        const Vec3 ci = geo_.centre(i);
        const Vec3 d = sub(mid, ci);
        const double dn = norm(d);
        if (!(dn > 1e-9)) return false;
        const Vec3 q = add(ci, scale(d, geo_.radius(i) / dn));
        Label l;
        l.add(i);
        if (geo_.classify(q, l)) {
            s.p = q;
            s.label = l;
            s.kind = SplitKind::Chord;
            return true;
        }
        Vec3 g;
        Label lg;
        if (!geo_.project(mid, g, lg) || dist(g, mid) > len) return false;
        s.p = g;
        s.label = lg;
        s.kind = SplitKind::Other;
        return true;
    }

    static std::uint64_t edge_key(Index a, Index b) {
        return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
    }

    // The new vertex of edge (a, b) in this round's splits, or kNone.
    Index split_vertex(const std::vector<std::uint64_t>& keys, const std::vector<Index>& ids,
                       Index a, Index b) const {
        if (!touched_[a] || !touched_[b]) return kNone;
        const std::uint64_t k = edge_key(a, b);
        const auto it = std::lower_bound(keys.begin(), keys.end(), k);
        return it != keys.end() && *it == k ? ids[std::size_t(it - keys.begin())] : kNone;
    }

    // One round of edge splits; returns how many edges were split. Each undirected edge is
    // decided once, from its half-edge with the smaller start vertex (decide is symmetric in
    // what it uses); the splits are found again from either triangle by their sorted keys, so
    // no edge table is built.
    std::size_t split_edges(bool chords) {
        const std::vector<Index>& idx = mesh_.indices;
        const std::size_t nt = mesh_.triangle_count();
        constexpr std::size_t kChunk = 4096;
        const std::size_t chunks = (nt + kChunk - 1) / kChunk;
        std::vector<std::vector<EdgeSplit>> found(chunks);
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(nt, (c + 1) * kChunk);
            for (std::size_t t = c * kChunk; t < end; ++t)
                for (int k = 0; k < 3; ++k) {
                    const Index a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
                    if (a >= b) continue;
                    EdgeSplit s;
                    if (decide(a, b, chords, s)) {
                        s.key = edge_key(a, b);
                        found[c].push_back(s);
                    }
                }
        });
        // Sorted by key (pairs of key and place, not the records), one per key.
        std::vector<std::pair<std::uint64_t, const EdgeSplit*>> order;
        for (const auto& f : found)
            for (const EdgeSplit& e : f) order.emplace_back(e.key, &e);
        if (order.empty()) return 0;
        std::sort(order.begin(), order.end(),
                  [](const auto& x, const auto& y) { return x.first < y.first; });
        order.erase(std::unique(order.begin(), order.end(),
                                [](const auto& x, const auto& y) { return x.first == y.first; }),
                    order.end());
        std::vector<EdgeSplit> splits(order.size());
        for (std::size_t k = 0; k < order.size(); ++k) splits[k] = *order[k].second;
        order = {};
        found = {};
        const std::size_t nv = mesh_.vertex_count();
        if (nv + splits.size() > std::size_t(kNone)) {
            throw Error(ErrorCode::InvalidArgument,
                        "creases: the mesh would have more than 2^32 - 1 vertices");
        }
        // Provisional vertices nv, nv + 1, ... in key order; a withdrawn one stays unreferenced
        // (dropped at the end).
        std::vector<std::uint64_t> keys(splits.size());
        std::vector<Index> ids(splits.size());
        touched_.resize(nv + splits.size(), 0);
        mesh_.positions.reserve(3 * (nv + splits.size()));
        labels_.reserve(nv + splits.size());
        for (std::size_t k = 0; k < splits.size(); ++k) {
            keys[k] = splits[k].key;
            ids[k] = Index(nv + k);
            touched_[splits[k].key >> 32] = 1;
            touched_[splits[k].key & 0xffffffffu] = 1;
            for (int a = 0; a < 3; ++a) mesh_.positions.push_back(float(splits[k].p[a]));
            labels_.push_back(splits[k].label);
        }
        // The triangles with a split edge.
        std::vector<std::vector<Index>> hit(chunks);
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(nt, (c + 1) * kChunk);
            for (std::size_t t = c * kChunk; t < end; ++t) {
                const Index* v = &idx[3 * t];
                if (int(touched_[v[0]]) + touched_[v[1]] + touched_[v[2]] < 2) continue;
                for (int k = 0; k < 3; ++k)
                    if (split_vertex(keys, ids, v[k], v[(k + 1) % 3]) != kNone) {
                        hit[c].push_back(Index(t));
                        break;
                    }
            }
        });
        std::vector<Index> triangles;
        for (const auto& h : hit) triangles.insert(triangles.end(), h.begin(), h.end());
        hit.clear();
        const auto slots = edge_slots(triangles, keys);
        veto_folds(triangles, slots, ids);
        std::size_t kept = 0;
        for (std::size_t k = 0; k < splits.size(); ++k) {
            if (ids[k] == kNone) continue;
            ++kept;
            switch (splits[k].kind) {
                case SplitKind::Crease:
                    ++stats_.crease_splits;
                    break;
                case SplitKind::Chord:
                    ++stats_.chord_splits;
                    break;
                case SplitKind::Other:
                    ++stats_.other_splits;
                    break;
            }
        }
        stats_.vetoed += splits.size() - kept;
        if (kept > 0) retriangulate(triangles, slots, ids);
        std::fill(touched_.begin(), touched_.end(), 0);
        return kept;
    }

    bool share(Index a, Index b) const { return common(labels_[a], labels_[b]).n > 0; }

    // The triangles that replace triangle t given the new vertices m of its edges (m[k] on
    // the edge from corner k to corner k + 1; itself when none is split): 2, 3 or 4 in the same
    // orientation. Writes 3 indices per triangle into o and returns the count.
    int split_triangle(std::size_t t, const Index m[3], Index* o) const {
        const Index* v = &mesh_.indices[3 * t];
        int n = 0;
        auto emit = [&](Index x, Index y, Index z) {
            o[3 * n] = x;
            o[3 * n + 1] = y;
            o[3 * n + 2] = z;
            ++n;
        };
        const int k = (m[0] != kNone) + (m[1] != kNone) + (m[2] != kNone);
        if (k == 0) {
            emit(v[0], v[1], v[2]);
        } else if (k == 3) {
            emit(v[0], m[0], m[2]);
            emit(v[1], m[1], m[0]);
            emit(v[2], m[2], m[1]);
            emit(m[0], m[1], m[2]);
        } else if (k == 1) {
            const int e = m[0] != kNone ? 0 : m[1] != kNone ? 1 : 2;
            const Index a = v[e], b = v[(e + 1) % 3], c = v[(e + 2) % 3];
            emit(a, m[e], c);
            emit(m[e], b, c);
        } else {
            // Edges e and e + 1 split, e + 2 (from v[e + 2] to v[e]) not: the corner v[e + 1] is
            // cut off, the quad (v[e], m[e], m[e + 1], v[e + 2]) split along a diagonal whose
            // ends share a sphere, the shorter if both or neither do.
            const int e = m[2] == kNone ? 0 : m[0] == kNone ? 1 : 2;
            const Index a = v[e], b = v[(e + 1) % 3], c = v[(e + 2) % 3];
            const Index p = m[e], q = m[(e + 1) % 3];
            emit(p, b, q);
            const bool s1 = share(a, q), s2 = share(p, c);
            bool first = s1;
            if (s1 == s2)
                first = dist(position(mesh_, a), position(mesh_, q)) <=
                        dist(position(mesh_, p), position(mesh_, c));
            if (first) {  // diagonal a - q
                emit(a, p, q);
                emit(a, q, c);
            } else {  // diagonal p - c
                emit(a, p, c);
                emit(p, q, c);
            }
        }
        return n;
    }

    // The outward normal at vertex v: its sphere's, or the sum of its spheres' (not normalised).
    Vec3 vertex_normal(Index v) const {
        const Label& l = labels_[v];
        const Vec3 p = position(mesh_, v);
        Vec3 n{0, 0, 0};
        if (l.n == 0) {
            if (mesh_.normals.size() >= 3 * std::size_t(v) + 3)
                n = {mesh_.normals[3 * v], mesh_.normals[3 * v + 1], mesh_.normals[3 * v + 2]};
            return n;
        }
        for (int k = 0; k < l.n; ++k) {
            const Vec3 d = sub(p, geo_.centre(l.b[k]));
            const double len = norm(d);
            if (len > 0.0) n = add(n, scale(d, 1.0 / len));
        }
        return n;
    }

    // Whether triangle (x, y, z) faces against the normals of its corners.
    bool folded(Index x, Index y, Index z) const {
        const Vec3 px = position(mesh_, x);
        const Vec3 n = cross(sub(position(mesh_, y), px), sub(position(mesh_, z), px));
        const Vec3 m = add(add(vertex_normal(x), vertex_normal(y)), vertex_normal(z));
        return dot(n, m) <= 0.0;
    }

    // For each listed triangle, the positions in `keys` of its split edges (kNone: not split).
    std::vector<std::array<Index, 3>> edge_slots(const std::vector<Index>& triangles,
                                                 const std::vector<std::uint64_t>& keys) const {
        std::vector<std::array<Index, 3>> slots(triangles.size());
        constexpr std::size_t kChunk = 4096;
        parallel_chunks((triangles.size() + kChunk - 1) / kChunk, thread_count(),
                        [&](std::size_t c) {
                            const std::size_t end = std::min(triangles.size(), (c + 1) * kChunk);
                            for (std::size_t i = c * kChunk; i < end; ++i) {
                                const Index* v = &mesh_.indices[3 * std::size_t(triangles[i])];
                                for (int k = 0; k < 3; ++k) {
                                    slots[i][k] = kNone;
                                    const Index a = v[k], b = v[(k + 1) % 3];
                                    if (!touched_[a] || !touched_[b]) continue;
                                    const std::uint64_t key = edge_key(a, b);
                                    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
                                    if (it != keys.end() && *it == key)
                                        slots[i][k] = Index(it - keys.begin());
                                }
                            }
                        });
        return slots;
    }

    static void slot_vertices(const std::array<Index, 3>& slot, const std::vector<Index>& ids,
                              Index m[3]) {
        for (int k = 0; k < 3; ++k) m[k] = slot[k] == kNone ? kNone : ids[slot[k]];
    }

    // Withdraws (ids[k] = kNone) the splits of every listed triangle that they would fold over
    // (a sub-triangle facing against its corners' normals, unless a sliver of under 5% of the
    // triangle's area, or the triangle already did), until none would.
    void veto_folds(const std::vector<Index>& triangles,
                    const std::vector<std::array<Index, 3>>& slots, std::vector<Index>& ids) {
        const std::vector<Index>& idx = mesh_.indices;
        std::vector<Index> check(triangles.size());
        for (std::size_t i = 0; i < check.size(); ++i) check[i] = Index(i);
        for (int pass = 0; pass < 8 && !check.empty(); ++pass) {
            constexpr std::size_t kChunk = 1024;
            const std::size_t chunks = (check.size() + kChunk - 1) / kChunk;
            std::vector<std::vector<Index>> veto(chunks);
            parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
                const std::size_t end = std::min(check.size(), (c + 1) * kChunk);
                Index out[12], m[3];
                for (std::size_t j = c * kChunk; j < end; ++j) {
                    const std::size_t i = check[j], t = triangles[i];
                    slot_vertices(slots[i], ids, m);
                    if (m[0] == kNone && m[1] == kNone && m[2] == kNone) continue;
                    if (folded(idx[3 * t], idx[3 * t + 1], idx[3 * t + 2])) continue;
                    const Vec3 p0 = position(mesh_, idx[3 * t]);
                    const Vec3 p1 = position(mesh_, idx[3 * t + 1]),
                               p2 = position(mesh_, idx[3 * t + 2]);
                    const double whole = norm(cross(sub(p1, p0), sub(p2, p0)));
                    const double longest = std::max({dist(p0, p1), dist(p1, p2), dist(p2, p0)});
                    const int n = split_triangle(t, m, out);
                    bool bad = false;
                    for (int k = 0; k < n && !bad; ++k) {
                        if (!folded(out[3 * k], out[3 * k + 1], out[3 * k + 2])) continue;
                        const Vec3 q0 = position(mesh_, out[3 * k]),
                                   q1 = position(mesh_, out[3 * k + 1]),
                                   q2 = position(mesh_, out[3 * k + 2]);
                        const double twice = norm(cross(sub(q1, q0), sub(q2, q0)));
                        bad = twice > 0.05 * whole && twice > 0.02 * longest * longest;
                    }
                    if (!bad) continue;
                    for (int k = 0; k < 3; ++k)
                        if (m[k] != kNone) veto[c].push_back(slots[i][k]);
                }
            });
            std::vector<std::uint8_t> changed;
            bool any = false;
            for (const auto& list : veto)
                for (const Index slot : list) {
                    ids[slot] = kNone;
                    any = true;
                }
            if (!any) return;
            // Only the triangles that lost a split need another look.
            std::vector<Index> next;
            for (const Index i : check) {
                Index m[3];
                slot_vertices(slots[i], ids, m);
                bool lost = false;
                for (int k = 0; k < 3; ++k) lost |= slots[i][k] != kNone && m[k] == kNone;
                if (lost) next.push_back(i);
            }
            check.swap(next);
        }
    }

    // Every listed triangle replaced by its split_triangle: the first in its place, the others
    // appended.
    void retriangulate(const std::vector<Index>& triangles,
                       const std::vector<std::array<Index, 3>>& slots,
                       const std::vector<Index>& ids) {
        constexpr std::size_t kChunk = 1024;
        const std::size_t chunks = (triangles.size() + kChunk - 1) / kChunk;
        std::vector<std::vector<Index>> extra(chunks);
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(triangles.size(), (c + 1) * kChunk);
            Index out[12], m[3];
            for (std::size_t i = c * kChunk; i < end; ++i) {
                const std::size_t t = triangles[i];
                slot_vertices(slots[i], ids, m);
                const int n = split_triangle(t, m, out);
                extra[c].insert(extra[c].end(), out + 3, out + 3 * n);
                // Written after every read of this triangle's corners (no other triangle reads
                // them: each chunk owns its triangles).
                std::copy(out, out + 3, &mesh_.indices[3 * t]);
            }
        });
        std::size_t more = 0;
        for (const auto& e : extra) more += e.size();
        mesh_.indices.reserve(mesh_.indices.size() + more);
        for (const auto& e : extra) mesh_.indices.insert(mesh_.indices.end(), e.begin(), e.end());
    }

    // Triangles whose corners pairwise share a sphere but share none all three span a point
    // where three spheres meet: that point, when exposed and near, splits the triangle in three.
    std::size_t insert_corners() {
        const std::size_t nt = mesh_.triangle_count();
        constexpr std::size_t kChunk = 4096;
        const std::size_t chunks = (nt + kChunk - 1) / kChunk;
        struct Corner {
            Index triangle;
            Vec3 p;
            Label label;
            std::array<Index, 4> key;
        };
        std::vector<std::vector<Corner>> found(chunks);
        const std::vector<Index>& idx = mesh_.indices;
        parallel_chunks(chunks, thread_count(), [&](std::size_t c) {
            const std::size_t end = std::min(nt, (c + 1) * kChunk);
            for (std::size_t t = c * kChunk; t < end; ++t) {
                const Label& A = labels_[idx[3 * t]];
                const Label& B = labels_[idx[3 * t + 1]];
                const Label& C = labels_[idx[3 * t + 2]];
                if (A.n == 0 || B.n == 0 || C.n == 0) continue;
                const Label ab = common(A, B), bc = common(B, C), ca = common(C, A);
                if (ab.n == 0 || bc.n == 0 || ca.n == 0 || common(ab, C).n > 0) continue;
                const Index i = ab.b[0], j = bc.b[0], k = ca.b[0];
                Vec3 pts[2];
                if (!geo_.triple_points(i, j, k, pts)) continue;
                const Vec3 p0 = position(mesh_, idx[3 * t]), p1 = position(mesh_, idx[3 * t + 1]),
                           p2 = position(mesh_, idx[3 * t + 2]);
                const Vec3 centroid = scale(add(add(p0, p1), p2), 1.0 / 3.0);
                const double reach = std::max({dist(p0, p1), dist(p1, p2), dist(p2, p0)});
                const int which = dist(pts[0], centroid) <= dist(pts[1], centroid) ? 0 : 1;
                if (dist(pts[which], centroid) > reach) continue;
                Label l;
                l.add(i);
                l.add(j);
                l.add(k);
                if (!geo_.classify(pts[which], l)) continue;
                // The fan around the point must not fold over.
                Vec3 nw{0, 0, 0};
                for (int z = 0; z < 3; ++z) {
                    const Vec3 d = sub(pts[which], geo_.centre(l.b[z]));
                    nw = add(nw, scale(d, 1.0 / norm(d)));
                }
                const Vec3 corner[3] = {p0, p1, p2};
                bool bad = false;
                for (int z = 0; z < 3 && !bad; ++z) {
                    const Vec3& x = corner[z];
                    const Vec3& y = corner[(z + 1) % 3];
                    const Vec3 n = cross(sub(y, x), sub(pts[which], x));
                    const Vec3 m = add(
                        add(vertex_normal(idx[3 * t + z]), vertex_normal(idx[3 * t + (z + 1) % 3])),
                        nw);
                    bad = dot(n, m) <= 0.0;
                }
                if (bad) continue;
                std::array<Index, 4> key{i, j, k, 0};
                std::sort(key.begin(), key.begin() + 3);
                // Which of the two points: the side of the centres' plane it lies on.
                const Vec3 n = cross(sub(geo_.centre(key[1]), geo_.centre(key[0])),
                                     sub(geo_.centre(key[2]), geo_.centre(key[0])));
                key[3] = dot(sub(pts[which], geo_.centre(key[0])), n) > 0.0 ? 1 : 0;
                found[c].push_back({Index(t), pts[which], l, key});
            }
        });
        std::vector<Corner> accepted;
        for (const auto& f : found)
            for (const Corner& c : f)
                if (corner_keys_.insert(c.key).second) accepted.push_back(c);
        if (accepted.empty()) return 0;
        std::vector<Index>& out = mesh_.indices;
        out.reserve(out.size() + 6 * accepted.size());
        for (const Corner& c : accepted) {
            const Index w = Index(labels_.size());
            for (int a = 0; a < 3; ++a) mesh_.positions.push_back(float(c.p[a]));
            labels_.push_back(c.label);
            const Index a = out[3 * c.triangle], b = out[3 * c.triangle + 1],
                        d = out[3 * c.triangle + 2];
            out[3 * c.triangle + 2] = w;  // (a, b, w)
            out.insert(out.end(), {b, d, w, d, a, w});
        }
        stats_.corners += accepted.size();
        return accepted.size();
    }

    // Normals from the spheres, the final counts, attributes cleared.
    void finish() {
        const std::size_t nv = mesh_.vertex_count();
        mesh_.normals.resize(3 * nv, 0.0f);
        for (std::size_t v = 0; v < nv; ++v) {
            const Label& l = labels_[v];
            if (l.n == 0) continue;
            const Vec3 p = position(mesh_, Index(v));
            Vec3 n{0, 0, 0};
            for (int k = 0; k < l.n; ++k) {
                const Vec3 d = sub(p, geo_.centre(l.b[k]));
                const double len = norm(d);
                if (len > 0.0) n = add(n, scale(d, 1.0 / len));
            }
            const double len = norm(n);
            if (!(len > 0.0)) continue;
            for (int a = 0; a < 3; ++a) mesh_.normals[3 * v + a] = float(n[a] / len);
        }
        // Vertices of withdrawn splits are referenced by no triangle: dropped.
        std::vector<Index> remap(nv, kNone);
        for (const Index v : mesh_.indices) remap[v] = 0;
        std::vector<Index> kept;
        kept.reserve(nv);
        for (std::size_t v = 0; v < nv; ++v)
            if (remap[v] == 0) {
                remap[v] = Index(kept.size());
                kept.push_back(Index(v));
            }
        if (kept.size() < nv) {
            clear_attributes(mesh_);
            keep_vertices(mesh_, kept);
            for (Index& v : mesh_.indices) v = remap[v];
            std::vector<Label> labels(kept.size());
            for (std::size_t k = 0; k < kept.size(); ++k) labels[k] = labels_[kept[k]];
            labels_ = std::move(labels);
        }
        for (std::size_t h = 0; h < mesh_.indices.size(); ++h) {
            const Index a = mesh_.indices[h], b = mesh_.indices[h % 3 == 2 ? h - 2 : h + 1];
            if (a < b && labels_[a].n > 0 && labels_[b].n > 0 && !share(a, b))
                ++stats_.crossings_left;
        }
        clear_attributes(mesh_);
        stats_.crease_vertices = stats_.corner_vertices = 0;
        for (const Label& l : labels_) {
            stats_.crease_vertices += l.n == 2;
            stats_.corner_vertices += l.n == 3;
        }
    }

    struct KeyHash {
        std::size_t operator()(const std::array<Index, 4>& k) const {
            std::size_t h = 1469598103934665603ull;
            for (const Index x : k) h = (h ^ x) * 1099511628211ull;
            return h;
        }
    };

    Mesh& mesh_;
    Geometry geo_;
    const CreaseOptions& options_;
    CreaseStats& stats_;
    std::vector<Label> labels_;
    std::vector<std::uint8_t> touched_;  // per vertex: an end of a split edge this round
    std::unordered_set<std::array<Index, 4>, KeyHash> corner_keys_;
};

}  // namespace

CreaseStats recover_creases(Mesh& mesh, const BallUnion& balls, const CreaseOptions& options) {
    validate_mesh(mesh, "creases", true);
    CreaseStats stats;
    if (mesh.triangle_count() == 0 || balls.size() == 0) return stats;
    if (mesh.normals.size() != mesh.positions.size())
        mesh.normals.assign(mesh.positions.size(), 0.0f);
    Recovery(mesh, balls, options, stats).run();
    return stats;
}

}  // namespace fdmsurf::detail
