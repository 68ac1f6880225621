// The power cell's filter of caps (src/base/power_cell.hpp), against sampling: on real atoms'
// caps and on made-up ones with touching and repeated planes, no point of the sphere that the
// kept caps leave exposed may be buried by a dropped cap, and a ball called buried may have no
// exposed point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "base/power_cell.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using fdmsurf::detail::CellPlane;
using fdmsurf::detail::CellVerdict;
using fdmsurf::detail::PowerCell;
using fdmsurf::detail::Vec3;

namespace {

// Points spread evenly over the unit sphere (a golden-angle spiral).
std::vector<Vec3> sphere_points(int count) {
    std::vector<Vec3> points;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / count, r = std::sqrt(1.0 - z * z);
        points.push_back({r * std::cos(golden * i), r * std::sin(golden * i), z});
    }
    return points;
}

// The filter's verdict on `planes` (largest cap first), checked on `points`. Points within
// `margin` of a plane are left out: whether they are buried is rounding's call. Returns the
// verdict; `kept` the number of planes kept.
CellVerdict check_filter(PowerCell& cell, const std::vector<CellPlane>& planes,
                         const std::vector<Vec3>& points, std::size_t& kept,
                         const std::string& what) {
    std::vector<std::uint32_t> order(planes.size()), keep;
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return planes[a].h < planes[b].h; });
    const CellVerdict verdict = cell.filter(planes, order, keep);
    std::vector<std::uint8_t> is_kept(planes.size(), verdict != CellVerdict::Filtered);
    for (const std::uint32_t k : keep) is_kept[k] = 1;
    kept = verdict == CellVerdict::Filtered ? keep.size() : planes.size();
    constexpr double margin = 1e-9;
    std::size_t wrong = 0;
    for (const Vec3& n : points) {
        bool near = false, buried = false, buried_by_kept = false;
        for (std::size_t p = 0; p < planes.size(); ++p) {
            const double d = fdmsurf::detail::dot(n, planes[p].u) - planes[p].h;
            near = near || std::abs(d) < margin;
            buried = buried || d > 0.0;
            buried_by_kept = buried_by_kept || (is_kept[p] && d > 0.0);
        }
        if (near) continue;
        if (verdict == CellVerdict::Buried) wrong += !buried;
        else wrong += buried != buried_by_kept;
    }
    EXPECT_EQ(wrong, 0u) << what;
    // A plane whose face is inside the ball: its circle (where the plane meets the sphere) has
    // no exposed point, 360 points of it checked.
    if (verdict == CellVerdict::Filtered) {
        std::size_t exposed = 0;
        for (std::size_t j = 0; j < planes.size(); ++j) {
            if (!cell.face_in_ball(std::uint32_t(j))) continue;
            const Vec3& u = planes[j].u;
            const Vec3 t = std::abs(u[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
            Vec3 e1 = fdmsurf::detail::cross(u, t);
            e1 = fdmsurf::detail::scale(e1, 1.0 / std::sqrt(fdmsurf::detail::dot(e1, e1)));
            const Vec3 e2 = fdmsurf::detail::cross(u, e1);
            const double rho = std::sqrt(1.0 - planes[j].h * planes[j].h);
            for (int a = 0; a < 360; ++a) {
                const double theta = 2.0 * std::numbers::pi * a / 360.0;
                Vec3 n = fdmsurf::detail::scale(u, planes[j].h);
                n = fdmsurf::detail::add(n, fdmsurf::detail::scale(e1, rho * std::cos(theta)));
                n = fdmsurf::detail::add(n, fdmsurf::detail::scale(e2, rho * std::sin(theta)));
                bool near = false, buried = false;
                for (std::size_t p = 0; p < planes.size(); ++p) {
                    if (p == j) continue;
                    const double d = fdmsurf::detail::dot(n, planes[p].u) - planes[p].h;
                    near = near || std::abs(d) < margin;
                    buried = buried || d > 0.0;
                }
                exposed += !near && !buried;
            }
        }
        EXPECT_EQ(exposed, 0u) << what << ": exposed points on circles of faces inside the ball";
    }
    return verdict;
}

CellPlane plane(Vec3 u, double h) {
    const double len = std::sqrt(fdmsurf::detail::dot(u, u));
    return {{u[0] / len, u[1] / len, u[2] / len}, h};
}

// A plane of random direction (uniform in the cube, +z when nearly 0) and height.
CellPlane random_plane(std::mt19937& random, std::uniform_real_distribution<double>& unit,
                       std::uniform_real_distribution<double>& height) {
    Vec3 u{unit(random), unit(random), unit(random)};
    if (fdmsurf::detail::dot(u, u) < 1e-6) u = {0, 0, 1};
    return plane(u, height(random));
}

}  // namespace

TEST(PowerCell, KeepsEveryCapThatBuriesAnExposedPointOfCrambin) {
    // Each atom's caps as the exact areas make them (probe 1.4 Å), checked on 4,000 points.
    const Structure s = read_structure(fdmsurf::test::data_path("1crn.pdb"));
    const Atoms& atoms = s.atoms;
    const std::vector<Vec3> points = sphere_points(4000);
    PowerCell cell;
    std::size_t buried = 0, filtered = 0, caps = 0, kept_caps = 0;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const double ri = atoms.radius[i] + 1.4;
        std::vector<CellPlane> planes;
        for (std::size_t j = 0; j < atoms.size(); ++j) {
            if (j == i) continue;
            const double rj = atoms.radius[j] + 1.4;
            const Vec3 e{double(atoms.xyz[3 * j]) - atoms.xyz[3 * i],
                         double(atoms.xyz[3 * j + 1]) - atoms.xyz[3 * i + 1],
                         double(atoms.xyz[3 * j + 2]) - atoms.xyz[3 * i + 2]};
            const double d = std::sqrt(fdmsurf::detail::dot(e, e));
            if (d >= ri + rj) continue;
            const double h = (d * d + ri * ri - rj * rj) / (2.0 * d * ri);
            if (h <= -1.0 || h >= 1.0) continue;
            planes.push_back(plane(e, h));
        }
        if (planes.empty()) continue;
        std::size_t kept = 0;
        const CellVerdict verdict =
            check_filter(cell, planes, points, kept, "crambin atom " + std::to_string(i + 1));
        buried += verdict == CellVerdict::Buried;
        filtered += verdict == CellVerdict::Filtered;
        if (verdict == CellVerdict::Filtered) {
            caps += planes.size();
            kept_caps += kept;
        }
    }
    // The filter does its work: a good part of crambin's atoms are buried at 1.4 Å, and the
    // others keep far fewer caps than they have.
    EXPECT_GT(buried, atoms.size() / 5);
    EXPECT_GT(filtered, atoms.size() / 2);
    EXPECT_LT(double(kept_caps), 0.5 * double(caps));
}

TEST(PowerCell, CubesOfCapsAreBuriedOrKeptWhole) {
    const std::vector<Vec3> points = sphere_points(6000);
    PowerCell cell;
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const double h : {0.3, 0.5, 0.57735026918962573, 0.6, 0.8, 0.95}) {
        std::vector<CellPlane> planes;
        for (const Vec3& a : axes) planes.push_back(plane(a, h));
        std::size_t kept = 0;
        const CellVerdict verdict =
            check_filter(cell, planes, points, kept, "cube " + std::to_string(h));
        // Six caps of angular radius acos(h) cover the sphere when the cube's corners, at
        // h √3, are inside the ball.
        if (h * std::sqrt(3.0) < 1.0 - 1e-9) {
            EXPECT_EQ(verdict, CellVerdict::Buried) << h;
        }
        if (h > 0.6) {
            EXPECT_EQ(verdict, CellVerdict::Filtered) << h;
            EXPECT_EQ(kept, 6u) << h;
        }
        // A seventh plane beyond a face changes nothing and goes; a corner's plane that cuts
        // the sphere stays.
        planes.push_back(plane({1, 0, 0}, std::min(0.99, h + 0.1)));
        planes.push_back(plane({1, 1, 1}, 0.98));
        const CellVerdict more =
            check_filter(cell, planes, points, kept, "cube and more " + std::to_string(h));
        if (h > 0.6) {
            EXPECT_EQ(more, CellVerdict::Filtered) << h;
            EXPECT_EQ(kept, 7u) << h;
        }
        // Planes through an edge and through a corner of the cube, exactly.
        planes.resize(6);
        planes.push_back(plane({1, 1, 0}, h * std::sqrt(2.0)));
        planes.push_back(plane({1, 1, 1}, h * std::sqrt(3.0)));
        check_filter(cell, planes, points, kept, "cube, edge and corner " + std::to_string(h));
    }
}

TEST(PowerCell, RepeatedTouchingAndRandomPlanesKeepTheExposedRegion) {
    // Random planes, some repeated exactly, some through a vertex of the others, some nearly
    // tangent: the verdict may give up (Unknown keeps every cap), never lose a cap that counts.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), height(-0.3, 0.95);
    const std::vector<Vec3> points = sphere_points(3000);
    PowerCell cell;
    int unknown = 0;
    for (int round = 0; round < 300; ++round) {
        std::vector<CellPlane> planes;
        const int count = 3 + round % 40;
        for (int p = 0; p < count; ++p) {
            planes.push_back(random_plane(random, unit, height));
            if (p % 7 == 3) planes.push_back(planes.back());  // the same plane twice
            if (p % 11 == 5) planes.push_back(plane({0, 0, 1}, 0.9999999));  // nearly tangent
        }
        std::size_t kept = 0;
        unknown += check_filter(cell, planes, points, kept, "round " + std::to_string(round)) ==
                   CellVerdict::Unknown;
    }
    EXPECT_LT(unknown, 30);
}

TEST(PowerCell, EveryExposedCrossingIsOnAnEdgeHandedOn) {
    // Where two circles cross at a point that no other cap holds, the cell must hand that pair
    // on among its edges in the ball: the sphere patches cross no other pairs.
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), height(-0.2, 0.9);
    PowerCell cell;
    int checked = 0;
    for (int round = 0; round < 400; ++round) {
        std::vector<CellPlane> planes;
        const int count = 2 + round % 30;
        for (int p = 0; p < count; ++p) planes.push_back(random_plane(random, unit, height));
        std::vector<std::uint32_t> order(planes.size()), keep;
        std::iota(order.begin(), order.end(), 0u);
        if (cell.filter(planes, order, keep) != CellVerdict::Filtered || cell.touched()) continue;
        const auto& edges = cell.edges_in_ball();
        for (std::size_t j = 0; j < planes.size(); ++j)
            for (std::size_t k = j + 1; k < planes.size(); ++k) {
                // The circles' crossings: x = p u_j + q u_k ± t (u_j × u_k) on the unit sphere.
                const Vec3 &a = planes[j].u, &b = planes[k].u;
                const double g = fdmsurf::detail::dot(a, b), w2 = 1.0 - g * g;
                if (w2 < 1e-9) continue;
                const double p = (planes[j].h - planes[k].h * g) / w2;
                const double q = (planes[k].h - planes[j].h * g) / w2;
                const double rest = 1.0 - (p * p + q * q + 2.0 * p * q * g);
                if (rest <= 1e-12) continue;
                const Vec3 c = fdmsurf::detail::cross(a, b);
                for (const double sign : {1.0, -1.0}) {
                    const double t = sign * std::sqrt(rest / w2);
                    const Vec3 x{p * a[0] + q * b[0] + t * c[0], p * a[1] + q * b[1] + t * c[1],
                                 p * a[2] + q * b[2] + t * c[2]};
                    bool exposed = true;
                    for (std::size_t l = 0; l < planes.size() && exposed; ++l)
                        exposed = l == j || l == k ||
                                  fdmsurf::detail::dot(x, planes[l].u) - planes[l].h < -1e-9;
                    if (!exposed) continue;
                    bool handed_on = false;
                    for (const auto& [e0, e1] : edges)
                        handed_on = handed_on || (e0 == j && e1 == k) || (e0 == k && e1 == j);
                    EXPECT_TRUE(handed_on) << "round " << round << " planes " << j << ", " << k;
                    ++checked;
                }
            }
    }
    EXPECT_GT(checked, 500);
}

// A box of planes |y|, |z| <= 0.2 capped by x <= 0.3: the face x = 0.3 lies inside the ball (its
// corners 0.41 from the centre), so its circle is buried though the plane is kept; the side
// faces run out of the ball and are not inside it.
TEST(PowerCell, AFaceInsideTheBallIsFlagged) {
    const std::vector<CellPlane> planes = {plane({1, 0, 0}, 0.3), plane({0, 1, 0}, 0.2),
                                           plane({0, -1, 0}, 0.2), plane({0, 0, 1}, 0.2),
                                           plane({0, 0, -1}, 0.2)};
    PowerCell cell;
    std::size_t kept = 0;
    const CellVerdict verdict =
        check_filter(cell, planes, sphere_points(4000), kept, "a face inside the ball");
    ASSERT_EQ(verdict, CellVerdict::Filtered);
    EXPECT_EQ(kept, planes.size());
    EXPECT_TRUE(cell.face_in_ball(0));
    for (std::uint32_t j = 1; j < planes.size(); ++j) EXPECT_FALSE(cell.face_in_ball(j)) << j;
}
