// Images: device-local memory, a view, a debug name; out of memory is a DeviceLimit error.
#include "vulkan/image.hpp"

#include <string>

#include "vulkan/check.hpp"
#include "vulkan/context.hpp"
#include "vulkan/fault_injection.hpp"

namespace fdmsurf::detail {

DeviceImage::DeviceImage(const Context& ctx, VkFormat format, std::uint32_t width,
                         std::uint32_t height, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                         const char* name)
    : device_(ctx.device()), format_(format), width_(width), height_(height) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    FDM_VK_CHECK(vkCreateImage(device_, &info, nullptr, &image_));
    try {
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device_, image_, &req);
        const VkPhysicalDeviceMemoryProperties& props = ctx.memory_properties();
        int type = -1;
        for (std::uint32_t i = 0; i < props.memoryTypeCount && type < 0; ++i)
            if ((req.memoryTypeBits & (1u << i)) &&
                (props.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
                type = static_cast<int>(i);
        for (std::uint32_t i = 0; i < props.memoryTypeCount && type < 0; ++i)
            if (req.memoryTypeBits & (1u << i)) type = static_cast<int>(i);
        if (type < 0)
            throw Error(ErrorCode::DeviceLimit,
                        std::string("no suitable memory type for image '") + name + "'");
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = static_cast<std::uint32_t>(type);
        const VkResult r = allocation_fault(name)
                                 ? VK_ERROR_OUT_OF_DEVICE_MEMORY
                                 : vkAllocateMemory(device_, &alloc, nullptr, &memory_);
        if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
            throw Error(ErrorCode::DeviceLimit,
                        "out of memory allocating " + std::to_string(req.size >> 20) +
                            " MiB for image '" + name + "' (" + std::to_string(width) + " x " +
                            std::to_string(height) + "); try a smaller image size",
                        r);
        FDM_VK_CHECK(r);
        FDM_VK_CHECK(vkBindImageMemory(device_, image_, memory_, 0));
        // A view only for images that shaders or framebuffers use (not for copies alone).
        if (usage &
            (VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)) {
            VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
            view.image = image_;
            view.viewType = VK_IMAGE_VIEW_TYPE_2D;
            view.format = format;
            view.subresourceRange = {aspect, 0, 1, 0, 1};
            FDM_VK_CHECK(vkCreateImageView(device_, &view, nullptr, &view_));
        }
        ctx.set_name(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<std::uint64_t>(image_), name);
    } catch (...) {
        reset();
        throw;
    }
}

DeviceImage& DeviceImage::operator=(DeviceImage&& o) noexcept {
    if (this != &o) {
        reset();
        device_ = std::exchange(o.device_, VK_NULL_HANDLE);
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        view_ = std::exchange(o.view_, VK_NULL_HANDLE);
        format_ = std::exchange(o.format_, VK_FORMAT_UNDEFINED);
        width_ = std::exchange(o.width_, 0);
        height_ = std::exchange(o.height_, 0);
    }
    return *this;
}

void DeviceImage::reset() {
    if (!device_) return;
    if (view_) vkDestroyImageView(device_, view_, nullptr);
    if (image_) vkDestroyImage(device_, image_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    view_ = VK_NULL_HANDLE;
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

}  // namespace fdmsurf::detail
