// Pictures of a surface: a Vulkan graphics pipeline draws a DeviceMesh's own buffers into an
// offscreen image on the engine's device, read back once; PNG files through libpng
// (docs/rendering.md).
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/surface.hpp"

namespace fdmsurf {

class DeviceMesh;  // fdmsurf/vulkan_interop.hpp

// Where the camera looks from. Front: from +z towards -z, x to the right, y up (the
// structure's own axes, as PyMOL's default view). Back: from -z (x to the left). Left: from -x
// (z to the right), Right: from +x (z to the left). Top: from +y (x right, -z up). Bottom:
// from -y (x right, +z up).
enum class View { Front, Back, Left, Right, Top, Bottom };

const char* to_string(View view) noexcept;

// A sphere (Å) that the camera frames: the image's shorter side spans its diameter, with a
// margin of 3% on each side.
struct BoundingSphere {
    std::array<float, 3> center{0.0f, 0.0f, 0.0f};
    float radius = 0.0f;
};

struct RenderOptions {
    std::uint32_t width = 1024;  // pixels, 1 to the device's maxImageDimension2D
    std::uint32_t height = 768;
    View view = View::Front;
    // Degrees about the screen's x (right), y (up) and z (towards the viewer) axes, applied
    // in that order after `view`, counter-clockwise when the axis points at the viewer:
    // {0, 30, 0} brings the molecule's left side 30° towards the viewer.
    std::array<float, 3> rotate{0.0f, 0.0f, 0.0f};
    // sRGB; alpha 0 makes the background transparent (other alphas count as 255).
    std::array<std::uint8_t, 4> background{255, 255, 255, 255};
    // sRGB colour of a mesh without an attribute buffer (no colour scheme).
    std::array<std::uint8_t, 3> color{200, 200, 200};
    // Screen-space ambient occlusion from the depth buffer: 0 (off) to 1, and its radius in Å
    // (0: the larger of 4 Å and 5% of the framed radius).
    float ambient_occlusion = 0.8f;
    float ambient_occlusion_radius = 0.0f;
    // Depth cue: the far side of the framed sphere is darkened by this fraction (0 to 1).
    float depth_cue = 0.35f;
    // Dark lines along silhouettes and depth steps, about width / 512 pixels wide (at least 1).
    bool outline = false;
    // 1 or 2: the scene is drawn at supersample times the size and averaged down (anti-aliased
    // edges; silhouette areas within a fraction of a pixel). 2 falls back to 1 when twice the
    // size exceeds maxImageDimension2D.
    std::uint32_t supersample = 2;
    // Draw back faces too: for open meshes (a patch), whose inside shows. Closed surfaces
    // (every make_device_surface mesh) show their outside only, and culling the back faces
    // halves the triangles rasterised.
    bool double_sided = false;
    // What to frame; radius <= 0: the mesh's own bounding sphere (Renderer::bounds). Give one
    // sphere to several renders to keep their centre and scale the same.
    BoundingSphere frame;
};

// An 8-bit sRGB picture, rows from the top, 4 bytes per pixel (straight, not premultiplied,
// alpha).
struct Image {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<std::uint8_t> rgba;
    bool opaque() const;  // every alpha is 255
};

struct RenderResult {
    Image image;
    BoundingSphere frame;           // the sphere that was framed
    float pixel_size = 0.0f;        // Å per pixel of the image (orthographic: the same everywhere)
    std::uint32_t supersample = 1;  // the factor used
    // "render-bounds" (the bounding sphere, when not given), "render-scene" (drawing),
    // "render-shade" (occlusion, depth cue, outline, background, downsampling), "render-read"
    // (the copy to the host), GPU timestamps where the queue has them; "render-host" the rest
    // of the call on the host clock.
    std::vector<StageTime> times;
};

namespace detail {
struct RendererImpl;
}

// Draws DeviceMeshes made by (or uploaded to) one Engine, on that engine's device and queue,
// which must support graphics (an ExternalDevice's queue family too). The same draw an
// application records on its own: the mesh's vertex, index and attribute buffers bound as they
// are, after the memory barrier that fdmsurf/vulkan_interop.hpp documents. Pipelines are made
// once; the offscreen images are kept for the next render of the same size. Not thread-safe;
// destroy it before its Engine. Throws Error(InvalidArgument) when the queue family has no
// graphics, Error(DeviceLimit) when the device lacks the image formats it needs.
class Renderer {
public:
    explicit Renderer(Engine& engine);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Checks `options` against the device without drawing: Error(InvalidArgument) for a size
    // of 0 or above maxImageDimension2D, a supersample other than 1 or 2, a strength outside
    // [0, 1], a non-finite angle or frame.
    void check(const RenderOptions& options) const;

    // The mesh's bounding sphere (the centre of its box, the largest distance from it), found
    // on the device from the vertex buffer; radius 0 for an empty mesh.
    BoundingSphere bounds(const DeviceMesh& mesh);

    // Draws `mesh` as `options` ask and reads the picture back. An empty mesh gives the
    // background alone.
    RenderResult render(const DeviceMesh& mesh, const RenderOptions& options = {});

private:
    std::unique_ptr<detail::RendererImpl> impl_;
};

// The rotation (row-major 3x3) that takes the structure's axes to the screen's (x right, y up,
// z towards the viewer) for `view` followed by `rotate` (degrees, as RenderOptions::rotate).
std::array<float, 9> view_rotation(View view, const std::array<float, 3>& rotate = {0, 0, 0});

// PNG through libpng: 8-bit RGB when the image is opaque, RGBA otherwise. Written to a
// temporary file beside `path` and renamed: on failure (Error(Io) naming the path) nothing is
// left at `path`. Throws Error(InvalidArgument) for an image whose size and data disagree.
void write_png(const Image& image, const std::string& path);
// The same bytes to a stream; `name` names it in messages ("standard output").
void write_png(const Image& image, std::ostream& out, const std::string& name);
// Reads any PNG libpng reads (palette, grey, 16-bit and interlaced ones converted) as 8-bit
// RGBA; for tests and tools. Throws Error(Io) or Error(Format).
Image read_png(const std::string& path);

}  // namespace fdmsurf
