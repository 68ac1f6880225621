// A 2D image, its memory and one view, move-only (the renderer's offscreen targets).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <utility>

namespace fdmsurf::detail {

class Context;

class DeviceImage {
public:
    DeviceImage() = default;
    // Device-local, optimal tiling, one mip level and layer; the view covers `aspect` (no view
    // when `usage` has only transfers).
    DeviceImage(const Context& ctx, VkFormat format, std::uint32_t width, std::uint32_t height,
                VkImageUsageFlags usage, VkImageAspectFlags aspect, const char* name);
    ~DeviceImage() { reset(); }
    DeviceImage(DeviceImage&& o) noexcept { *this = std::move(o); }
    DeviceImage& operator=(DeviceImage&& o) noexcept;
    DeviceImage(const DeviceImage&) = delete;
    DeviceImage& operator=(const DeviceImage&) = delete;

    VkImage handle() const { return image_; }
    VkImageView view() const { return view_; }
    VkFormat format() const { return format_; }
    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }
    explicit operator bool() const { return image_ != VK_NULL_HANDLE; }
    void reset();

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    std::uint32_t width_ = 0, height_ = 0;
};

}  // namespace fdmsurf::detail
