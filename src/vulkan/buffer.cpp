// Storage buffers: memory type choice, allocation checked against the device's limits.
#include "vulkan/buffer.hpp"

#include <string>

#include "vulkan/check.hpp"
#include "vulkan/context.hpp"
#include "vulkan/fault_injection.hpp"

namespace fdmsurf::detail {
namespace {

int find_memory_type(const VkPhysicalDeviceMemoryProperties& props, std::uint32_t allowed,
                     VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
    int fallback = -1;
    for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i) {
        if (!(allowed & (1u << i))) continue;
        VkMemoryPropertyFlags f = props.memoryTypes[i].propertyFlags;
        if ((f & required) != required) continue;
        if ((f & preferred) == preferred) return static_cast<int>(i);
        if (fallback < 0) fallback = static_cast<int>(i);
    }
    return fallback;
}

}  // namespace

Buffer::Buffer(const Context& ctx, VkDeviceSize size, MemoryUse use, const char* name)
    : device_(ctx.device()), size_(size) {
    if (size == 0) size = 4;  // Vulkan forbids empty buffers; an empty mesh still binds one
    const DeviceLimits& lim = ctx.limits();
    if (lim.max_allocation_size && size > lim.max_allocation_size)
        throw Error(ErrorCode::DeviceLimit,
                    std::string("buffer '") + name + "' needs " + std::to_string(size >> 20) +
                        " MiB, more than the device's maxMemoryAllocationSize (" +
                        std::to_string(lim.max_allocation_size >> 20) + " MiB)");
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    // Vertex and index usage too, so that a renderer on the same device can draw the mesh.
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                 VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                 VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    FDM_VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &buffer_));
    try {
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device_, buffer_, &req);
        const auto& props = ctx.memory_properties();
        int type = -1;
        switch (use) {
            case MemoryUse::Device:
                type = find_memory_type(props, req.memoryTypeBits, 0,
                                        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
                break;
            case MemoryUse::Upload:
                type = find_memory_type(props, req.memoryTypeBits,
                                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                        VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
                break;
            case MemoryUse::Readback:
                type = find_memory_type(props, req.memoryTypeBits,
                                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                        VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
                break;
        }
        if (type < 0)
            throw Error(ErrorCode::DeviceLimit,
                        std::string("no suitable memory type for buffer '") + name + "'");
        VkMemoryPropertyFlags flags = props.memoryTypes[type].propertyFlags;
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = static_cast<std::uint32_t>(type);
        VkResult r = allocation_fault(name)
                                 ? VK_ERROR_OUT_OF_DEVICE_MEMORY
                                 : vkAllocateMemory(device_, &alloc, nullptr, &memory_);
        if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
            throw Error(ErrorCode::DeviceLimit,
                        std::string("out of memory allocating ") + std::to_string(req.size >> 20) +
                            " MiB for buffer '" + name + "'; try a coarser --spacing",
                        r);
        FDM_VK_CHECK(r);
        FDM_VK_CHECK(vkBindBufferMemory(device_, buffer_, memory_, 0));
        if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
            FDM_VK_CHECK(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
            coherent_ = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
        }
        ctx.set_name(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<std::uint64_t>(buffer_), name);
    } catch (...) {
        reset();
        throw;
    }
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
        coherent_ = std::exchange(o.coherent_, true);
    }
    return *this;
}

void Buffer::reset() {
    if (!device_) return;
    if (mapped_) vkUnmapMemory(device_, memory_);
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

void Buffer::flush() const {
    if (!mapped_ || coherent_) return;
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = memory_;
    range.size = VK_WHOLE_SIZE;
    FDM_VK_CHECK(vkFlushMappedMemoryRanges(device_, 1, &range));
}

void Buffer::invalidate() const {
    if (!mapped_ || coherent_) return;
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = memory_;
    range.size = VK_WHOLE_SIZE;
    FDM_VK_CHECK(vkInvalidateMappedMemoryRanges(device_, 1, &range));
}

}  // namespace fdmsurf::detail
