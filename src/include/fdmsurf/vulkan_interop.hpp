// Running fdmsurf on an application's own Vulkan device, with the mesh left in device buffers
// that a renderer binds directly (no read-back).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"

namespace fdmsurf {

// Handles that the application owns; fdmsurf never destroys them. The device must support
// Vulkan 1.1; `queue` belongs to `queue_family`, which must support compute (a renderer's
// graphics-and-compute family, so that its draws can use the buffers without an ownership
// transfer). Pass it through EngineOptions::external; it must outlive the Engine.
struct ExternalDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
};

namespace detail { struct DeviceMeshBuffers; }
class Renderer;  // fdmsurf/render.hpp

// A surface mesh in two device buffers (three with colours), owned by this object (released
// when it is destroyed, which must happen before the VkDevice is). Every buffer carries the
// STORAGE, VERTEX, INDEX, TRANSFER_SRC and TRANSFER_DST usages. The work that wrote them has completed (fdmsurf waited on its fence)
// when Engine::make_device_surface returns. The renderer must still make those compute-shader
// writes visible to its own use with a memory barrier in its command buffer: src stage
// COMPUTE_SHADER, access SHADER_WRITE; dst stage VERTEX_INPUT (or its own), access
// VERTEX_ATTRIBUTE_READ | INDEX_READ. A fence wait orders execution; it does not make device
// writes available to other device stages.
class DeviceMesh {
public:
    DeviceMesh();
    ~DeviceMesh();
    DeviceMesh(DeviceMesh&&) noexcept;
    DeviceMesh& operator=(DeviceMesh&&) noexcept;

    // 6 floats per vertex: position (Å), then the outward unit normal; stride 24 bytes.
    VkBuffer vertex_buffer() const;
    // 3 uint32 indices per triangle, counter-clockwise seen from outside.
    VkBuffer index_buffer() const;
    // 2 uint32 per vertex (stride 8 bytes): the index of its atom in the Atoms given (least
    // power distance, as Mesh::atoms; 0xffffffff when unknown), then its colour as R8G8B8A8
    // (sRGB, red in the lowest byte, alpha 255): bind it at offset 4 with stride 8 as a
    // VK_FORMAT_R8G8B8A8_UNORM vertex attribute. VK_NULL_HANDLE when the mesh has no colours
    // (SurfaceOptions::properties.color None, or an uploaded Mesh without colors). Same usages
    // and synchronisation as the other two.
    VkBuffer attribute_buffer() const;
    std::uint32_t vertex_count() const;
    std::uint32_t triangle_count() const;

private:
    friend class Engine;
    friend class Renderer;
    std::unique_ptr<detail::DeviceMeshBuffers> buffers_;
};

struct DeviceSurfaceResult {
    DeviceMesh mesh;
    GridInfo grid;
    std::vector<StageTime> times;
    std::vector<std::string> warnings;
};

}  // namespace fdmsurf
