// The orthographic camera: named views and turns as rotations, and the framing of a sphere.
#include "render/camera.hpp"

#include <cmath>
#include <numbers>

namespace fdmsurf {

const char* to_string(View view) noexcept {
    switch (view) {
        case View::Front:
            return "front";
        case View::Back:
            return "back";
        case View::Left:
            return "left";
        case View::Right:
            return "right";
        case View::Top:
            return "top";
        case View::Bottom:
            return "bottom";
    }
    return "unknown";
}

std::array<float, 9> view_rotation(View view, const std::array<float, 3>& rotate) {
    // Rows: the screen's right, up and towards-the-viewer axes in the structure's frame
    // (right x up = towards: a proper rotation).
    std::array<double, 9> m{};
    switch (view) {
        case View::Front:
            m = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            break;
        case View::Back:
            m = {-1, 0, 0, 0, 1, 0, 0, 0, -1};
            break;
        case View::Left:
            m = {0, 0, 1, 0, 1, 0, -1, 0, 0};
            break;
        case View::Right:
            m = {0, 0, -1, 0, 1, 0, 1, 0, 0};
            break;
        case View::Top:
            m = {1, 0, 0, 0, 0, -1, 0, 1, 0};
            break;
        case View::Bottom:
            m = {1, 0, 0, 0, 0, 1, 0, -1, 0};
            break;
    }
    // Turns about the screen's axes, x first: M = Rz Ry Rx M.
    for (int axis = 0; axis < 3; ++axis) {
        const double a = rotate[axis] * std::numbers::pi / 180.0;
        if (a == 0.0) continue;
        const double c = std::cos(a), s = std::sin(a);
        const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane turned: (y,z) (z,x) (x,y)
        for (int col = 0; col < 3; ++col) {
            const double u = m[3 * i + col], v = m[3 * j + col];
            m[3 * i + col] = c * u - s * v;
            m[3 * j + col] = s * u + c * v;
        }
    }
    std::array<float, 9> out{};
    for (int k = 0; k < 9; ++k) out[k] = static_cast<float>(m[k]);
    return out;
}

bool Image::opaque() const {
    for (std::size_t i = 3; i < rgba.size(); i += 4)
        if (rgba[i] != 255) return false;
    return true;
}

namespace detail {

Framing frame_sphere(const BoundingSphere& sphere, std::uint32_t width, std::uint32_t height) {
    Framing f;
    f.sphere = sphere;
    if (!(f.sphere.radius > 0.0f)) f.sphere.radius = 1.0f;  // an empty mesh: any scale will do
    // The shorter side spans the diameter and a margin of kFrameMargin on each side.
    const float half_short = f.sphere.radius * (1.0f + 2.0f * kFrameMargin);
    f.pixel_size = 2.0f * half_short / float(std::min(width, height));
    f.half_width = 0.5f * f.pixel_size * float(width);
    f.half_height = 0.5f * f.pixel_size * float(height);
    // Depth over the sphere, with the same margin.
    f.half_depth = f.sphere.radius * (1.0f + 2.0f * kFrameMargin);
    return f;
}

}  // namespace detail
}  // namespace fdmsurf
