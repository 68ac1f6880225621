// The orthographic camera of the renderer: how a framed sphere maps onto the image.
#pragma once

#include <cstdint>

#include "fdmsurf/render.hpp"

namespace fdmsurf::detail {

// Margin on each side of the framed sphere, as a fraction of its diameter.
inline constexpr float kFrameMargin = 0.03f;

struct Framing {
    BoundingSphere sphere;                        // radius > 0
    float pixel_size = 0.0f;                      // Å per pixel
    float half_width = 0.0f, half_height = 0.0f;  // Å from the centre to the image's edges
    float half_depth = 0.0f;                      // Å from the centre to the near and far planes
};

Framing frame_sphere(const BoundingSphere& sphere, std::uint32_t width, std::uint32_t height);

}  // namespace fdmsurf::detail
