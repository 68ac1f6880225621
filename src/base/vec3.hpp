// A plain double-precision 3-vector for host geometry (crease snap, refinement, comparison,
// curvature, exact areas and SES features, the marching-cubes table generator): std::array with
// named functions rather than operators, since operators on a std type are found by argument-
// dependent lookup only in std. Each function is the textbook expression in a fixed order
// (x, y, z; dot sums left to right), so results are the same bits wherever it is used.
// Header-only and standard-library-only: fdmsurf_mc_tablegen includes it without the library.
#pragma once

#include <array>
#include <cmath>

namespace fdmsurf::detail {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

}  // namespace fdmsurf::detail
