// The Vulkan instance, the chosen physical device, its logical device and compute queue.
#pragma once

#include <vulkan/vulkan.h>

#include <mutex>
#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"
#include "fdmsurf/vulkan_interop.hpp"

namespace fdmsurf::detail {

struct DeviceLimits {
    VkDeviceSize max_storage_buffer_range = 0;
    VkDeviceSize max_allocation_size = 0;
    VkDeviceSize device_memory = 0;  // largest device-local heap
    std::uint32_t max_workgroup_count[3] = {0, 0, 0};
    std::uint32_t max_workgroup_invocations = 0;
    std::uint32_t max_push_constants = 0;
    std::uint32_t max_shared_memory = 0;
    double timestamp_period_ns = 0.0;  // 0: no timestamps on the compute queue
    VkDeviceSize min_storage_offset_alignment = 1;
    std::uint32_t max_image_dimension_2d = 0;
    bool graphics = false;  // the queue family supports graphics (the renderer needs it)
};

// Owns instance, debug messenger and device; destroys them in reverse order.
class Context {
public:
    explicit Context(const EngineOptions& options);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    std::uint32_t queue_family() const { return queue_family_; }
    const DeviceLimits& limits() const { return limits_; }
    const DeviceInfo& info() const { return info_; }
    const VkPhysicalDeviceMemoryProperties& memory_properties() const { return memory_; }
    // VkPhysicalDeviceProperties::deviceType is VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe,
    // SwiftShader): the device's work runs on the host's cores.
    bool cpu_device() const {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(physical_, &p);
        return p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    }

    // Device-local memory a new allocation can still get: with VK_EXT_memory_budget (enabled
    // when the device has it), the largest device-local heap's budget less what is in use now,
    // by this process and others; without it, that heap's size (limits().device_memory).
    VkDeviceSize available_device_memory() const;
    bool has_memory_budget() const { return memory_budget_; }

    // Gives a Vulkan object a name that validation messages will show.
    void set_name(VkObjectType type, std::uint64_t handle, const char* name) const;

    std::vector<std::string> take_messages();
    void add_message(std::string message);

private:
    void read_limits(const EngineOptions& options);
    void adopt(const ExternalDevice& external, const EngineOptions& options);
    bool owned_ = true;  // false: the handles belong to the application (a renderer)
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    DeviceLimits limits_;
    DeviceInfo info_;
    VkPhysicalDeviceMemoryProperties memory_{};
    PFN_vkSetDebugUtilsObjectNameEXT set_name_ = nullptr;
    bool memory_budget_ = false;  // VK_EXT_memory_budget enabled on device_
    std::mutex messages_mutex_;
    std::vector<std::string> messages_;
};

// Shared by list_devices and Context: what a physical device is and whether we can use it.
DeviceInfo describe_device(VkPhysicalDevice device, std::uint32_t index);

// The message given when no Vulkan driver or device can be found.
std::string no_device_help();

}  // namespace fdmsurf::detail
