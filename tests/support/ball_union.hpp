// Test helper: unions of balls (the vdw and sas surfaces) measured independently of fdmsurf:
// the area of up to three balls in closed form (spheres less their exposed caps, Gauss-Bonnet for
// two caps that overlap), the volume of any number by stratified Monte Carlo, and which spheres a
// point lies on.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "fdmsurf/structure.hpp"

namespace fdmsurf::test {

using V3 = std::array<double, 3>;

struct Ball {
    V3 c;
    double r;
};

inline V3 sub3(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm3(const V3& a) { return std::sqrt(dot3(a, a)); }

// The balls of `atoms` with radius r + add.
inline std::vector<Ball> balls_of(const Atoms& atoms, double add) {
    std::vector<Ball> balls(atoms.size());
    for (std::size_t i = 0; i < atoms.size(); ++i)
        balls[i] = {{atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]},
                    atoms.radius[i] + add};
    return balls;
}

// Area of the intersection of two caps of half-angles tj, tk whose axes are d apart, on the unit
// sphere: Gauss-Bonnet on the lens bounded by two small-circle arcs (corner angles gamma, arcs of
// phi_j and phi_k about their axes, of geodesic curvature cot t).
inline double cap_overlap(double tj, double tk, double d) {
    constexpr double pi = std::numbers::pi;
    if (d >= tj + tk) return 0.0;
    if (d <= std::abs(tj - tk)) return 2.0 * pi * (1.0 - std::cos(std::min(tj, tk)));
    const double gamma = std::acos(std::clamp(
        (std::cos(d) - std::cos(tj) * std::cos(tk)) / (std::sin(tj) * std::sin(tk)), -1.0, 1.0));
    auto arc = [&](double a, double b) {
        return 2.0 * std::acos(std::clamp(
                         (std::cos(b) - std::cos(a) * std::cos(d)) / (std::sin(a) * std::sin(d)),
                         -1.0, 1.0));
    };
    return 2.0 * pi - 2.0 * gamma - arc(tj, tk) * std::cos(tj) - arc(tk, tj) * std::cos(tk);
}

// Area of the union of up to three balls, none inside another: each sphere less the caps the
// others bury, the overlap of two caps added back.
inline double union_area(const std::vector<Ball>& balls) {
    constexpr double pi = std::numbers::pi;
    double area = 0.0;
    for (std::size_t i = 0; i < balls.size(); ++i) {
        const double r = balls[i].r;
        std::vector<std::pair<V3, double>> caps;  // axis, half-angle
        for (std::size_t j = 0; j < balls.size(); ++j) {
            if (j == i) continue;
            const V3 e = sub3(balls[j].c, balls[i].c);
            const double d = norm3(e);
            if (d >= r + balls[j].r) continue;
            const double a = (d * d + r * r - balls[j].r * balls[j].r) / (2.0 * d);
            caps.push_back({{e[0] / d, e[1] / d, e[2] / d}, std::acos(a / r)});
        }
        double exposed = 4.0 * pi;
        for (const auto& c : caps) exposed -= 2.0 * pi * (1.0 - std::cos(c.second));
        if (caps.size() == 2) {
            const double d = std::acos(std::clamp(dot3(caps[0].first, caps[1].first), -1.0, 1.0));
            exposed += cap_overlap(caps[0].second, caps[1].second, d);
        }
        area += r * r * exposed;
    }
    return area;
}

// Volume of the union by stratified Monte Carlo: one uniform point in each cell of a lattice of
// step `cell` (Å) over the bounding box, tested against the balls binned in cells of the largest
// diameter; fixed seed. The standard error is about sqrt(area / cell²) · cell³ / 2.
inline double union_volume(const std::vector<Ball>& balls, double cell) {
    V3 lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
    double r_max = 0.0;
    for (const Ball& b : balls) {
        r_max = std::max(r_max, b.r);
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.c[a] - b.r);
            hi[a] = std::max(hi[a], b.c[a] + b.r);
        }
    }
    const double bin = 2.0 * r_max;
    std::int64_t nb[3], n[3];
    for (int a = 0; a < 3; ++a) {
        nb[a] = std::int64_t((hi[a] - lo[a]) / bin) + 1;
        n[a] = std::int64_t(std::ceil((hi[a] - lo[a]) / cell));
    }
    std::vector<std::vector<std::uint32_t>> bins(std::size_t(nb[0] * nb[1] * nb[2]));
    auto bin_of = [&](double x, int a) {
        return std::clamp<std::int64_t>(std::int64_t((x - lo[a]) / bin), 0, nb[a] - 1);
    };
    for (std::size_t i = 0; i < balls.size(); ++i)
        bins[std::size_t((bin_of(balls[i].c[2], 2) * nb[1] + bin_of(balls[i].c[1], 1)) * nb[0] +
                         bin_of(balls[i].c[0], 0))]
            .push_back(std::uint32_t(i));
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t inside = 0;
    for (std::int64_t z = 0; z < n[2]; ++z)
        for (std::int64_t y = 0; y < n[1]; ++y)
            for (std::int64_t x = 0; x < n[0]; ++x) {
                const V3 p{lo[0] + cell * (double(x) + u(rng)), lo[1] + cell * (double(y) + u(rng)),
                           lo[2] + cell * (double(z) + u(rng))};
                const std::int64_t b[3] = {bin_of(p[0], 0), bin_of(p[1], 1), bin_of(p[2], 2)};
                bool in = false;
                for (std::int64_t k = std::max<std::int64_t>(b[2] - 1, 0);
                     !in && k <= std::min(b[2] + 1, nb[2] - 1); ++k)
                    for (std::int64_t j = std::max<std::int64_t>(b[1] - 1, 0);
                         !in && j <= std::min(b[1] + 1, nb[1] - 1); ++j)
                        for (std::int64_t i = std::max<std::int64_t>(b[0] - 1, 0);
                             !in && i <= std::min(b[0] + 1, nb[0] - 1); ++i)
                            for (const std::uint32_t q :
                                 bins[std::size_t((k * nb[1] + j) * nb[0] + i)]) {
                                const V3 d = sub3(p, balls[q].c);
                                if (dot3(d, d) <= balls[q].r * balls[q].r) {
                                    in = true;
                                    break;
                                }
                            }
                inside += in;
            }
    return double(inside) * cell * cell * cell;
}

// The spheres a point lies on (within `tolerance`), and whether a ball buries it.
struct OnSpheres {
    std::vector<int> on;
    bool buried = false;
};
inline OnSpheres spheres_of(const std::vector<Ball>& balls, const V3& p, double tolerance) {
    OnSpheres s;
    for (std::size_t i = 0; i < balls.size(); ++i) {
        const double d = norm3(sub3(p, balls[i].c)) - balls[i].r;
        if (std::abs(d) <= tolerance)
            s.on.push_back(int(i));
        else if (d < 0.0)
            s.buried = true;
    }
    return s;
}

inline bool share_sphere(const OnSpheres& a, const OnSpheres& b) {
    for (int i : a.on)
        if (std::find(b.on.begin(), b.on.end(), i) != b.on.end()) return true;
    return false;
}

// Radius of the circle on which balls a and b meet.
inline double circle_radius(const Ball& a, const Ball& b) {
    const double d = norm3(sub3(b.c, a.c));
    const double x = (d * d + a.r * a.r - b.r * b.r) / (2.0 * d);
    return std::sqrt(a.r * a.r - x * x);
}

}  // namespace fdmsurf::test
