// A storage buffer and its memory, move-only; host-visible buffers are mapped for their life.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <utility>

namespace fdmsurf::detail {

class Context;

enum class MemoryUse {
    Device,    // GPU only: device-local
    Upload,    // written by the host, read by the GPU
    Readback,  // written by the GPU, read by the host (cached where possible)
};

class Buffer {
public:
    Buffer() = default;
    Buffer(const Context& ctx, VkDeviceSize size, MemoryUse use, const char* name);
    ~Buffer() { reset(); }
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    // Host pointer for Upload and Readback buffers (and Device buffers on devices whose
    // device-local memory is host-visible, such as lavapipe); nullptr otherwise.
    void* mapped() const { return mapped_; }
    bool host_visible() const { return mapped_ != nullptr; }
    // Makes host writes visible to the device, and device writes visible to the host, for
    // memory that is not host-coherent.
    void flush() const;
    void invalidate() const;
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
    void reset();

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
    bool coherent_ = true;
};

}  // namespace fdmsurf::detail
