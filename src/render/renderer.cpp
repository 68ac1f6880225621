// Drawing a DeviceMesh offscreen: the framing sphere on the device (render_bounds.comp), the
// scene pass on the mesh's own buffers (render.vert/frag), the compositing pass (occlusion,
// depth cue, outline, background, the mean of each pixel's samples: composite.frag), one
// read-back.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "engine/engine_impl.hpp"
#include "fdmsurf/render.hpp"
#include "fdmsurf/vulkan_interop.hpp"
#include "render/camera.hpp"
#include "render/render_pipelines.hpp"
#include "shader_interface.h"
#include "vulkan/check.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"
#include "vulkan/pipeline.hpp"
#include "vulkan/shaders.hpp"

namespace fdmsurf {
namespace detail {
namespace {

float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

std::uint8_t linear_to_srgb8(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(s * 255.0f));
}

// Pixels of a transparent picture carry premultiplied colour (the mean of a pixel's samples
// is right so); PNG wants it straight.
void straighten_alpha(std::vector<std::uint8_t>& rgba) {
    std::array<float, 256> decode{};
    for (int i = 0; i < 256; ++i) decode[i] = srgb_to_linear(float(i) / 255.0f);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        const std::uint8_t a = rgba[i + 3];
        if (a == 0) {
            rgba[i] = rgba[i + 1] = rgba[i + 2] = 0;
        } else if (a != 255) {
            const float scale = 255.0f / float(a);
            for (int k = 0; k < 3; ++k) rgba[i + k] = linear_to_srgb8(decode[rgba[i + k]] * scale);
        }
    }
}

// The scene pass's push constants: the view's rotation `rot` and the framing `f`.
shader::RenderPush scene_push(const std::array<float, 9>& rot, const Framing& f) {
    shader::RenderPush rp{};
    rp.row0_x = rot[0], rp.row0_y = rot[1], rp.row0_z = rot[2];
    rp.row1_x = rot[3], rp.row1_y = rot[4], rp.row1_z = rot[5];
    rp.row2_x = rot[6], rp.row2_y = rot[7], rp.row2_z = rot[8];
    rp.center_x = f.sphere.center[0];
    rp.center_y = f.sphere.center[1];
    rp.center_z = f.sphere.center[2];
    rp.scale_x = 1.0f / f.half_width;
    rp.scale_y = 1.0f / f.half_height;
    rp.depth_scale = 0.5f / f.half_depth;
    return rp;
}

// The compositing pass's push constants: background, ambient occlusion, depth cue and outline
// of `o`, for the framing `f` at `s` samples per axis.
shader::CompositePush composite_push(const RenderOptions& o, const Framing& f, std::uint32_t s) {
    const bool transparent = o.background[3] == 0;
    shader::CompositePush cp{};
    if (!transparent) {
        cp.background_r = srgb_to_linear(o.background[0] / 255.0f);
        cp.background_g = srgb_to_linear(o.background[1] / 255.0f);
        cp.background_b = srgb_to_linear(o.background[2] / 255.0f);
        cp.background_a = 1.0f;
    }
    cp.depth_range = 2.0f * f.half_depth;
    cp.pixel_size = f.pixel_size / float(s);
    cp.ao_strength = o.ambient_occlusion;
    cp.ao_radius = o.ambient_occlusion_radius > 0.0f ? o.ambient_occlusion_radius
                                                     : std::max(4.0f, 0.05f * f.sphere.radius);
    cp.depth_cue = o.depth_cue;
    cp.samples = s;
    if (o.outline) {
        const std::uint32_t width_px = std::max<std::uint32_t>(1, (o.width + 256) / 512);
        cp.outline = float(width_px * s);
        // A step in depth worth a line: larger than the surface's own slope can make between
        // neighbours a line's width apart (grazing faces), and than a probe's radius.
        cp.outline_step = std::max(1.4f, 4.0f * f.pixel_size * float(width_px));
    }
    return cp;
}

}  // namespace

struct RendererImpl {
    explicit RendererImpl(EngineImpl& e)
        : engine(e), context(e.context), commands(e.commands), pipelines(context) {
        if (!context.limits().graphics)
            throw Error(ErrorCode::InvalidArgument,
                        "rendering needs a queue family with graphics; the engine's queue "
                        "family " +
                            std::to_string(context.queue_family()) + " has compute only");
        ShaderCode b = shader_code(Shader::RenderBounds);
        bounds_pipeline = ComputePipeline(context, b.words, b.bytes, 2, sizeof(shader::BoundsPush),
                                          "render_bounds");
        bounds_words =
            Buffer(context, 8 * sizeof(std::uint32_t), MemoryUse::Upload, "render_bounds");
        uniform_color =
            Buffer(context, 2 * sizeof(std::uint32_t), MemoryUse::Upload, "render_uniform_color");
        VkPhysicalDeviceFeatures features;
        vkGetPhysicalDeviceFeatures(context.physical_device(), &features);
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(context.physical_device(), &props);
        max_index =
            features.fullDrawIndexUint32 ? 0xfffffffeu : props.limits.maxDrawIndexedIndexValue;
    }

    std::uint32_t samples_for(const RenderOptions& o) const {
        const std::uint32_t max = context.limits().max_image_dimension_2d;
        if (o.supersample < 2) return 1;
        return (o.width * 2 <= max && o.height * 2 <= max) ? 2 : 1;
    }

    // Bytes of device memory a picture's targets take at `samples` per axis: the scene's
    // colour, normal and depth per sample, the picture and its readback per pixel.
    std::uint64_t target_bytes(std::uint32_t width, std::uint32_t height,
                               std::uint32_t samples) const {
        const std::uint64_t pixels = std::uint64_t(width) * height;
        const std::uint64_t depth = pipelines.depth_format() == VK_FORMAT_D16_UNORM ? 2 : 4;
        return pixels * samples * samples * (4 + 4 + depth) + pixels * (4 + 4);
    }

    void check(const RenderOptions& o) const;
    BoundingSphere bounds(const DeviceMesh& mesh, const GpuMesh& gpu);
    RenderResult render(const DeviceMesh& mesh, const GpuMesh& gpu, const Buffer* attributes,
                        const RenderOptions& o);
    // render's steps.
    std::uint32_t samples_within_memory(const RenderOptions& o) const;
    void record_scene(VkCommandBuffer cmd, const DeviceMesh& mesh, const GpuMesh& gpu,
                      const Buffer* attributes, bool colored, VkPipeline scene,
                      const shader::RenderPush& rp, float rot_zz, std::uint32_t w, std::uint32_t h);
    void record_composite(VkCommandBuffer cmd, const RenderOptions& o,
                          const shader::CompositePush& cp);

    EngineImpl& engine;
    Context& context;
    Commands& commands;
    RenderPipelines pipelines;
    ComputePipeline bounds_pipeline;
    Buffer bounds_words;
    Buffer uniform_color;
    std::unique_ptr<RenderTargets> targets;
    std::uint32_t max_index = 0;
};

void RendererImpl::check(const RenderOptions& o) const {
    const std::uint32_t max = context.limits().max_image_dimension_2d;
    auto fail = [](const std::string& message) {
        throw Error(ErrorCode::InvalidArgument, "rendering: " + message);
    };
    if (o.width == 0 || o.height == 0)
        fail("the image size " + std::to_string(o.width) + " x " + std::to_string(o.height) +
             " has no pixels");
    if (o.width > max || o.height > max)
        fail("the image size " + std::to_string(o.width) + " x " + std::to_string(o.height) +
             " exceeds this device's maxImageDimension2D (" + std::to_string(max) + " on " +
             context.info().name + ")");
    if (o.supersample != 1 && o.supersample != 2)
        fail("supersample must be 1 or 2 (got " + std::to_string(o.supersample) + ")");
    for (float a : o.rotate)
        if (!std::isfinite(a)) fail("the rotation angles must be finite numbers");
    if (!(o.ambient_occlusion >= 0.0f && o.ambient_occlusion <= 1.0f))
        fail("the ambient occlusion strength must be within [0, 1]");
    if (!(o.ambient_occlusion_radius >= 0.0f) || !std::isfinite(o.ambient_occlusion_radius))
        fail("the ambient occlusion radius must be a finite number of Å >= 0");
    if (!(o.depth_cue >= 0.0f && o.depth_cue <= 1.0f)) fail("the depth cue must be within [0, 1]");
    for (float c : o.frame.center)
        if (!std::isfinite(c)) fail("the framed sphere's centre must be finite");
    if (!std::isfinite(o.frame.radius)) fail("the framed sphere's radius must be finite");
}

BoundingSphere RendererImpl::bounds(const DeviceMesh& mesh, const GpuMesh& gpu) {
    BoundingSphere sphere;
    const std::uint32_t nv = mesh.vertex_count();
    if (nv == 0) return sphere;
    // Ordered-uint encodings: the lower corner starts at the largest value, the upper at 0.
    std::uint32_t init[8] = {0xffffffffu, 0xffffffffu, 0xffffffffu, 0, 0, 0, 0, 0};
    std::memcpy(bounds_words.mapped(), init, sizeof init);
    bounds_words.flush();
    // Chunks of whole workgroups that fit one binding; their offsets (multiples of 64
    // vertices, 1,536 bytes) meet any minStorageBufferOffsetAlignment (at most 256).
    const std::uint64_t range = context.limits().max_storage_buffer_range;
    const std::size_t chunk =
        std::max<std::size_t>(1, range / 24 / shader::kBoundsGroup) * shader::kBoundsGroup;
    commands.begin();
    // The mesh was written by an earlier submission's compute shaders (or uploaded).
    commands.barrier_compute();
    for (std::uint32_t pass = 0; pass < 2; ++pass) {
        for (std::size_t first = 0; first < nv; first += chunk) {
            const std::size_t n = std::min<std::size_t>(chunk, nv - first);
            // About 64 vertices per invocation.
            const std::uint64_t groups =
                (n + 64 * shader::kBoundsGroup - 1) / (64 * shader::kBoundsGroup);
            const auto [gx, gy] = commands.fold_groups(groups);
            shader::BoundsPush p{};
            p.vertex_count = static_cast<std::uint32_t>(n);
            p.groups_x = gx;
            p.pass = pass;
            const BufferRange in{gpu.vertices.handle(), first * 24, n * 24};
            commands.dispatch(bounds_pipeline, {in, whole(bounds_words)}, &p, gx, gy);
        }
        commands.barrier_compute();
    }
    commands.barrier_to_host();
    commands.mark("render-bounds");
    commands.submit_and_wait();
    bounds_words.invalidate();
    std::uint32_t words[8];
    std::memcpy(words, bounds_words.mapped(), sizeof words);
    auto unordered = [](std::uint32_t u) {
        const std::uint32_t bits = (u & 0x80000000u) ? u & 0x7fffffffu : ~u;
        float f;
        std::memcpy(&f, &bits, sizeof f);
        return f;
    };
    for (int a = 0; a < 3; ++a)
        sphere.center[a] = 0.5f * (unordered(words[a]) + unordered(words[3 + a]));
    float far2;
    std::memcpy(&far2, &words[6], sizeof far2);
    sphere.radius = std::sqrt(far2);
    return sphere;
}

// The supersampling a picture of `o` gets where its targets fit the device's free memory (a
// 16384² picture takes 5 GiB; on lavapipe, of the host's): dropped to 1 where supersampling alone
// does not fit; DeviceLimit where nothing does. The targets held now count as free (they would
// be replaced), where the device reports its budget (else the heap's size is all there is to go
// by).
std::uint32_t RendererImpl::samples_within_memory(const RenderOptions& o) const {
    std::uint32_t s = samples_for(o);
    if (const VkDeviceSize available = context.available_device_memory(); available > 0) {
        const std::uint64_t held =
            targets && context.has_memory_budget()
                ? target_bytes(targets->width(), targets->height(), targets->samples())
                : 0;
        const std::uint64_t room = available + held;
        if (s > 1 && target_bytes(o.width, o.height, s) > room) s = 1;
        if (target_bytes(o.width, o.height, s) > room) {
            char text[320];
            std::snprintf(text, sizeof text,
                          "rendering: a %u x %u picture needs %.2f GiB of device memory for its "
                          "targets, more than the %.2f GiB %s has free; ask for a smaller "
                          "--image-size",
                          o.width, o.height,
                          double(target_bytes(o.width, o.height, s)) / 1073741824.0,
                          double(room) / 1073741824.0, context.info().name.c_str());
            throw Error(ErrorCode::DeviceLimit, text);
        }
    }
    return s;
}

// The scene pass: the mesh drawn into the supersampled colour, normal and depth targets.
void RendererImpl::record_scene(VkCommandBuffer cmd, const DeviceMesh& mesh, const GpuMesh& gpu,
                                const Buffer* attributes, bool colored, VkPipeline scene,
                                const shader::RenderPush& rp, float rot_zz, std::uint32_t w,
                                std::uint32_t h) {
    RenderTargets& t = *targets;
    const VkViewport viewport{0.0f, 0.0f, float(w), float(h), 0.0f, 1.0f};
    const VkRect2D area{{0, 0}, {w, h}};
    {
        VkClearValue clear[3]{};
        clear[0].color = {{0.0f, 0.0f, 0.0f, 0.0f}};
        clear[1].color = {{0.5f, 0.5f, 1.0f, 0.0f}};
        clear[2].depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        begin.renderPass = pipelines.scene_pass();
        begin.framebuffer = t.scene_framebuffer;
        begin.renderArea = area;
        begin.clearValueCount = 3;
        begin.pClearValues = clear;
        vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
        if (scene) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene);
            vkCmdSetViewport(cmd, 0, 1, &viewport);
            vkCmdSetScissor(cmd, 0, 1, &area);
            const VkBuffer buffers[2] = {gpu.vertices.handle(),
                                         colored ? attributes->handle() : uniform_color.handle()};
            const VkDeviceSize offsets[2] = {0, 0};
            vkCmdBindVertexBuffers(cmd, 0, 2, buffers, offsets);
            vkCmdBindIndexBuffer(cmd, gpu.indices.handle(), 0, VK_INDEX_TYPE_UINT32);
            vkCmdPushConstants(cmd, pipelines.scene_layout(), VK_SHADER_STAGE_VERTEX_BIT, 0,
                               sizeof rp, &rp);
            // Marching cubes writes triangles plane by plane along z: drawn in slices from
            // the viewer's side of z first, most hidden fragments fail the early depth test
            // instead of being shaded and then covered (lavapipe shades in that order).
            const std::uint32_t tris = mesh.triangle_count();
            const std::uint32_t slices = std::clamp<std::uint32_t>(tris / 16384, 1, 64);
            const std::uint32_t per = (tris + slices - 1) / slices;
            const bool near_last = rot_zz > 0.0f;  // the viewer on the +z side
            for (std::uint32_t k = 0; k < slices; ++k) {
                const std::uint32_t slice = near_last ? slices - 1 - k : k;
                const std::uint32_t first = slice * per;
                if (first >= tris) continue;
                const std::uint32_t count = std::min(per, tris - first);
                vkCmdDrawIndexed(cmd, 3 * count, 1, 3 * first, 0, 0);
            }
        }
        vkCmdEndRenderPass(cmd);
    }
    commands.mark("render-scene");
}

// The compositing pass: one fragment per pixel of the picture from the scene's targets.
void RendererImpl::record_composite(VkCommandBuffer cmd, const RenderOptions& o,
                                    const shader::CompositePush& cp) {
    RenderTargets& t = *targets;
    {
        // One fragment per pixel of the picture, averaging its samples.
        const VkViewport out_viewport{0.0f, 0.0f, float(o.width), float(o.height), 0.0f, 1.0f};
        const VkRect2D out_area{{0, 0}, {o.width, o.height}};
        VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        begin.renderPass = pipelines.composite_pass();
        begin.framebuffer = t.composite_framebuffer;
        begin.renderArea = out_area;
        vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.composite_pipeline());
        vkCmdSetViewport(cmd, 0, 1, &out_viewport);
        vkCmdSetScissor(cmd, 0, 1, &out_area);
        const VkDescriptorSet set = pipelines.composite_set();
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.composite_layout(),
                                0, 1, &set, 0, nullptr);
        vkCmdPushConstants(cmd, pipelines.composite_layout(), VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof cp, &cp);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        vkCmdEndRenderPass(cmd);
    }
    commands.mark("render-shade");
}

RenderResult RendererImpl::render(const DeviceMesh& mesh, const GpuMesh& gpu,
                                  const Buffer* attributes, const RenderOptions& o) {
    check(o);
    const double t0 = now_ms();
    RenderResult result;
    if (mesh.vertex_count() > 0 && mesh.vertex_count() - 1 > max_index)
        throw Error(ErrorCode::DeviceLimit,
                    "rendering: the mesh has " + std::to_string(mesh.vertex_count()) +
                        " vertices, more than this device draws with 32-bit indices (" +
                        std::to_string(max_index + 1ull) +
                        ": fullDrawIndexUint32 is not supported)");
    std::vector<StageTime> times;
    BoundingSphere sphere = o.frame;
    if (!(sphere.radius > 0.0f)) {
        sphere = bounds(mesh, gpu);
        times = commands.stage_times();
    }
    const Framing f = frame_sphere(sphere, o.width, o.height);
    result.frame = f.sphere;
    result.pixel_size = f.pixel_size;
    const std::uint32_t s = samples_within_memory(o);
    if (!targets || !targets->matches(o.width, o.height, s)) {
        targets.reset();
        targets = std::make_unique<RenderTargets>(context, pipelines, o.width, o.height, s);
    }
    result.supersample = s;
    RenderTargets& t = *targets;
    pipelines.bind_inputs(t.scene_color.view(), t.scene_depth.view(), t.scene_normal.view());
    const std::uint32_t w = o.width * s, h = o.height * s;

    const std::array<float, 9> rot = view_rotation(o.view, o.rotate);
    const shader::RenderPush rp = scene_push(rot, f);

    const bool transparent = o.background[3] == 0;
    const shader::CompositePush cp = composite_push(o, f, s);

    const bool colored = attributes != nullptr && *attributes;
    if (!colored) {
        const std::uint32_t words[2] = {0xffffffffu,
                                        std::uint32_t(o.color[0]) | std::uint32_t(o.color[1]) << 8 |
                                            std::uint32_t(o.color[2]) << 16 | 0xff000000u};
        std::memcpy(uniform_color.mapped(), words, sizeof words);
        uniform_color.flush();
    }
    const VkPipeline scene = mesh.triangle_count() > 0
                                 ? pipelines.scene_pipeline(colored, o.double_sided)
                                 : VK_NULL_HANDLE;

    commands.begin();
    VkCommandBuffer cmd = commands.handle();
    // The barrier fdmsurf/vulkan_interop.hpp documents: the mesh's compute (or transfer) writes
    // made visible to vertex input.
    {
        VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT;
        vkCmdPipelineBarrier(cmd,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
    }
    record_scene(cmd, mesh, gpu, attributes, colored, scene, rp, rot[8], w, h);
    record_composite(cmd, o, cp);
    const VkImageSubresourceLayers layers{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    VkBufferImageCopy copy{};
    copy.imageSubresource = layers;
    copy.imageExtent = {o.width, o.height, 1};
    vkCmdCopyImageToBuffer(cmd, t.picture.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           t.readback.handle(), 1, &copy);
    commands.barrier_to_host();
    commands.mark("render-read");
    commands.submit_and_wait();
    times.insert(times.end(), commands.stage_times().begin(), commands.stage_times().end());

    t.readback.invalidate();
    result.image.width = o.width;
    result.image.height = o.height;
    result.image.rgba.resize(std::size_t(o.width) * o.height * 4);
    std::memcpy(result.image.rgba.data(), t.readback.mapped(), result.image.rgba.size());
    if (transparent) straighten_alpha(result.image.rgba);
    double device = 0.0;
    for (const StageTime& st : times) device += st.ms;
    times.push_back({"render-host", std::max(now_ms() - t0 - device, 0.0), false});
    result.times = std::move(times);
    return result;
}

}  // namespace detail

Renderer::Renderer(Engine& engine) : impl_(std::make_unique<detail::RendererImpl>(engine.impl())) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::check(const RenderOptions& options) const { impl_->check(options); }

BoundingSphere Renderer::bounds(const DeviceMesh& mesh) {
    if (!mesh.buffers_) return {};
    return impl_->bounds(mesh, mesh.buffers_->mesh);
}

RenderResult Renderer::render(const DeviceMesh& mesh, const RenderOptions& options) {
    if (!mesh.buffers_) {
        // A default-constructed DeviceMesh: nothing to draw.
        static const detail::GpuMesh empty;
        DeviceMesh none;
        return impl_->render(none, empty, nullptr, options);
    }
    return impl_->render(mesh, mesh.buffers_->mesh, &mesh.buffers_->attributes, options);
}

}  // namespace fdmsurf
