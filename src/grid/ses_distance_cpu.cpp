// CPU references of the exact SES field: the binned evaluation shaders/ses_distance.comp mirrors,
// and a brute-force one (faces, circles and three-sphere points, all checked for burial).
#include "grid/ses_distance_cpu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/vec3.hpp"
#include "shader_interface.h"

namespace fdmsurf::detail {

namespace {

// The radial projection of p onto the sphere (c, R) (any point of it when p = c; the shader's
// choice, +x, below 1e-6 Å).
Vec3 projection(const Vec3& c, double R, const Vec3& p) {
    const Vec3 v = sub(p, c);
    const double len = norm(v);
    return len > 1e-6 ? add(c, scale(v, R / len)) : add(c, Vec3{R, 0, 0});
}

// Bins of `f` within `reach` of p (inclusive ranges, clamped like the shader's).
struct BinRange {
    int lo[3], hi[3];
};
BinRange bins_near(const SesFeatures& f, const Vec3& p, double reach) {
    BinRange r;
    const double q[3] = {p[0], p[1], p[2]};
    for (int a = 0; a < 3; ++a) {
        auto cell = [&](double x) {
            return static_cast<int>(
                std::clamp(std::floor((x - f.origin[a]) / f.bin_size), 0.0, double(f.dims[a] - 1)));
        };
        r.lo[a] = cell(q[a] - reach);
        r.hi[a] = cell(q[a] + reach);
    }
    return r;
}

template <typename Fn>
void for_bins(const SesFeatures& f, const BinRange& r, Fn&& fn) {
    for (int z = r.lo[2]; z <= r.hi[2]; ++z)
        for (int y = r.lo[1]; y <= r.hi[1]; ++y)
            for (int x = r.lo[0]; x <= r.hi[0]; ++x)
                fn((std::size_t(z) * f.dims[1] + y) * f.dims[0] + x);
}

}  // namespace

double ses_distance(const SesFeatures& f, const double p_in[3], double d_max, double* gradient,
                    bool every_face) {
    const Vec3 p{p_in[0], p_in[1], p_in[2]};
    auto sphere = [&](std::uint32_t s, Vec3& c, double& R) {
        c = {f.spheres[4 * s], f.spheres[4 * s + 1], f.spheres[4 * s + 2]};
        R = f.spheres[4 * s + 3];
    };
    auto set_gradient = [&](const Vec3& g) {
        if (gradient) gradient[0] = g[0], gradient[1] = g[1], gradient[2] = g[2];
    };
    const BinRange near = bins_near(f, p, f.r_max + d_max);
    double lb = -std::numeric_limits<double>::infinity();
    Vec3 lb_centre{0, 0, 0};
    double lb_radius = 0.0;
    std::uint32_t deepest = 0;
    bool tie = false;  // another ball exactly as deep as the deepest
    for_bins(f, near, [&](std::size_t b) {
        for (std::uint32_t s = f.sphere_start[b]; s < f.sphere_start[b + 1]; ++s) {
            Vec3 c;
            double R;
            sphere(s, c, R);
            const double v = R - norm(sub(p, c));
            tie = v == lb || (tie && v < lb);
            if (v > lb) lb = v, lb_centre = c, lb_radius = R, deepest = s;
        }
    });
    // Is q (on sphere `self`) inside another ball?
    auto buried = [&](const Vec3& q, std::uint32_t self) {
        bool inside = false;
        for_bins(f, bins_near(f, q, f.r_max), [&](std::size_t qb) {
            for (std::uint32_t k = f.sphere_start[qb]; k < f.sphere_start[qb + 1] && !inside; ++k) {
                if (k == self) continue;
                Vec3 ck;
                double Rk;
                sphere(k, ck, Rk);
                const Vec3 w = sub(q, ck);
                inside = dot(w, w) < Rk * Rk;
            }
        });
        return inside;
    };
    if (lb <= 0.0) {
        // Outside the balls: minus the distance to them, which falls towards the nearest centre.
        if (lb <= -d_max) {
            set_gradient({0, 0, 0});
            return -d_max;
        }
        const Vec3 v = sub(p, lb_centre);
        const double len = norm(v);
        set_gradient(len > 0.0 ? scale(v, -1.0 / len) : Vec3{0, 0, 0});
        return lb;
    }
    if (lb >= d_max) {
        set_gradient({0, 0, 0});
        return d_max;
    }
    // The deepest ball's face is lb away, the least d can be: exposed, it is the answer.
    {
        const Vec3 q = projection(lb_centre, lb_radius, p);
        if (!buried(q, deepest)) {
            const double len = norm(sub(p, q));
            set_gradient(len > 0.0 ? scale(sub(p, q), 1.0 / len) : Vec3{0, 0, 0});
            return lb;
        }
    }
    double best = d_max;
    Vec3 nearest{0, 0, 0};
    bool found = false;
    // The nearest arc's point is only needed for the gradient, of the arc that ends nearest.
    constexpr std::uint32_t kNoArc = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t best_arc = kNoArc;
    for_bins(f, bins_near(f, p, f.rho_max + d_max), [&](std::size_t b) {
        for (std::uint32_t a = f.arc_start[b]; a < f.arc_start[b + 1]; ++a) {
            // No point of the circle is nearer than |p - m| - rho.
            const SesArc& arc = f.arcs[a];
            const Vec3 v = sub(p, Vec3{arc.m[0], arc.m[1], arc.m[2]});
            const double reach = arc.rho + best;
            if (dot(v, v) >= reach * reach) continue;
            const double d = arc_distance(arc, p_in, nullptr, best);
            if (d < best) best = d, best_arc = a, found = true;
        }
    });
    // The other faces: the reference tries every one; without every_face, as the shader, only
    // a ball exactly as deep as the deepest can be nearer than the arcs (ses_distance.comp).
    if (every_face || tie) for_bins(f, near, [&](std::size_t b) {
        for (std::uint32_t s = f.sphere_start[b]; s < f.sphere_start[b + 1]; ++s) {
            Vec3 c;
            double R;
            sphere(s, c, R);
            const double face = std::abs(norm(sub(p, c)) - R);
            // d >= lb: an exposed face is never nearer than lb, so a nearer one is buried (every
            // ball holding p but the deepest, done above).
            if (s == deepest || face < lb || face >= best) continue;
            const Vec3 q = projection(c, R, p);
            if (!buried(q, s)) best = face, nearest = q, found = true, best_arc = kNoArc;
        }
    });
    if (best_arc != kNoArc && gradient) {
        double q[3];
        arc_distance(f.arcs[best_arc], p_in, q);
        nearest = {q[0], q[1], q[2]};
    }
    const double len = norm(sub(p, nearest));
    if (found && len > 0.0)
        set_gradient(scale(sub(p, nearest), 1.0 / len));
    else
        set_gradient({0, 0, 0});
    return best;
}

double ses_distance_brute(const Atoms& atoms, float probe, const double p_in[3], double d_max) {
    const Vec3 p{p_in[0], p_in[1], p_in[2]};
    std::vector<Vec3> c;
    std::vector<double> R;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const Vec3 ci{atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
        const double Ri = double(atoms.radius[i]) + probe;
        if (norm(sub(p, ci)) < Ri + d_max) c.push_back(ci), R.push_back(Ri);
    }
    const std::size_t n = c.size();
    double lb = -d_max;
    for (std::size_t i = 0; i < n; ++i) lb = std::max(lb, R[i] - norm(sub(p, c[i])));
    if (lb <= 0.0) return lb;
    if (lb >= d_max) return d_max;
    // q lies on the spheres in `on` (up to three); is it inside any other ball?
    auto exposed = [&](const Vec3& q, std::size_t i, std::size_t j, std::size_t k) {
        for (std::size_t l = 0; l < n; ++l) {
            if (l == i || l == j || l == k) continue;
            const Vec3 w = sub(q, c[l]);
            if (dot(w, w) < R[l] * R[l] - 1e-9) return false;
        }
        return true;
    };
    const std::size_t none = n;
    double best = d_max;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 q = projection(c[i], R[i], p);
        if (exposed(q, i, none, none)) best = std::min(best, std::abs(norm(sub(p, c[i])) - R[i]));
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const Vec3 dij = sub(c[j], c[i]);
            const double d = norm(dij);
            if (d >= R[i] + R[j] || d <= std::abs(R[i] - R[j])) continue;
            const Vec3 u = scale(dij, 1.0 / d);
            const double a = (d * d + R[i] * R[i] - R[j] * R[j]) / (2.0 * d);
            const double rho = std::sqrt(std::max(R[i] * R[i] - a * a, 0.0));
            const Vec3 m = add(c[i], scale(u, a));
            // The circle's nearest point: p projected onto its plane, pushed out to radius rho.
            Vec3 w = sub(sub(p, m), scale(u, dot(sub(p, m), u)));
            double wl = norm(w);
            if (wl < 1e-12) {
                w = cross(u, std::abs(u[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
                wl = norm(w);
            }
            const Vec3 q = add(m, scale(w, rho / wl));
            if (exposed(q, i, j, none)) best = std::min(best, norm(sub(p, q)));
            // Points where a third sphere meets this circle.
            const Vec3 e1 = scale(w, 1.0 / wl);
            const Vec3 e2 = cross(u, e1);
            for (std::size_t k = j + 1; k < n; ++k) {
                // |m + rho (cos t e1 + sin t e2) - c_k|^2 = R_k^2
                const Vec3 wk = sub(m, c[k]);
                const double A = dot(wk, e1), B = dot(wk, e2);
                const double M = std::sqrt(A * A + B * B);
                const double E = R[k] * R[k] - dot(wk, wk) - rho * rho;
                if (M == 0.0 || std::abs(E) > 2.0 * rho * M) continue;
                const double phi = std::atan2(B, A), open = std::acos(E / (2.0 * rho * M));
                for (double t : {phi + open, phi - open}) {
                    const Vec3 v =
                        add(m, scale(add(scale(e1, std::cos(t)), scale(e2, std::sin(t))), rho));
                    if (exposed(v, i, j, k)) best = std::min(best, norm(sub(p, v)));
                }
            }
        }
    return best;
}

std::vector<float> ses_field_cpu(const SesFeatures& f, const GridPlan& plan) {
    const auto& d = plan.info.dims;
    std::vector<float> out(plan.field_floats(), 0.0f);
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                // The point as the shader computes it: origin + spacing * index, in float.
                const double p[3] = {double(plan.info.origin[0] + plan.info.spacing * float(x)),
                                     double(plan.info.origin[1] + plan.info.spacing * float(y)),
                                     double(plan.info.origin[2] + plan.info.spacing * float(z))};
                out[(std::size_t(z) * d[1] + y) * plan.pitch + x] = std::max(
                    static_cast<float>(ses_distance(f, p, plan.ses_d_max)), plan.ses_d_min);
            }
    return out;
}

std::vector<std::uint32_t> ses_box_classes_cpu(const SesFeatures& f, const GridPlan& plan,
                                               std::uint32_t points_z) {
    const auto& d = plan.info.dims;
    const std::uint32_t span[3] = {shader::kSesGroupX, shader::kSesGroupY,
                                   shader::kSesGroupZ * points_z};
    std::uint32_t boxes[3];
    for (int a = 0; a < 3; ++a) boxes[a] = (d[a] + span[a] - 1) / span[a];
    std::vector<std::uint32_t> out(static_cast<std::size_t>(boxes[0]) * boxes[1] * boxes[2]);
    for (std::size_t box = 0; box < out.size(); ++box) {
        const std::uint32_t b[3] = {std::uint32_t(box % boxes[0]),
                                    std::uint32_t(box / boxes[0] % boxes[1]),
                                    std::uint32_t(box / (std::size_t(boxes[0]) * boxes[1]))};
        double centre[3], r2 = 0.0;
        for (int a = 0; a < 3; ++a) {
            const std::uint32_t first = b[a] * span[a];
            const std::uint32_t last = std::min(first + span[a], d[a]) - 1;
            // The corners as the shaders compute grid points: origin + spacing * index, in float.
            const double lo = plan.info.origin[a] + plan.info.spacing * float(first);
            const double hi = plan.info.origin[a] + plan.info.spacing * float(last);
            centre[a] = 0.5 * (lo + hi);
            r2 += (hi - lo) * (hi - lo);
        }
        const double r = 0.5 * std::sqrt(r2);
        const double bound = std::min(double(plan.ses_d_min) - r, 0.0) - kSesBoxSlack;
        bool outside = true;
        for (std::size_t s = 0; s < f.sphere_count() && outside; ++s) {
            const float* q = &f.spheres[4 * s];
            const double dx = centre[0] - q[0], dy = centre[1] - q[1], dz = centre[2] - q[2];
            outside = q[3] - std::sqrt(dx * dx + dy * dy + dz * dz) <= bound;
        }
        out[box] = outside ? shader::kSesBoxOutside : shader::kSesBoxBand;
    }
    return out;
}

}  // namespace fdmsurf::detail
