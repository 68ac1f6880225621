// Vulkan instance and device selection, with a reason recorded for every device not used.
#include "vulkan/context.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <utility>

#include "base/trace.hpp"
#include "shader_interface.h"
#include "vulkan/check.hpp"

namespace fdmsurf::detail {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
// The density pass keeps 1536 atoms (24 KiB) in shared memory, plus a few counters.
constexpr std::uint32_t kSharedMemoryNeeded = 25 * 1024;

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user) {
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        std::string level =
            severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
        static_cast<Context*>(user)->add_message("validation " + level + ": " +
                                                 (data->pMessage ? data->pMessage : ""));
    }
    return VK_FALSE;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

const char* type_name(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

int type_rank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

std::string version_string(std::uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
           "." + std::to_string(VK_API_VERSION_PATCH(v));
}

bool find_compute_queue(VkPhysicalDevice device, std::uint32_t* family) {
    std::uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    // Prefer a compute queue family that also reports timestamps, then one that also does
    // graphics (the renderer, src/render/, draws on the same queue).
    auto rank = [&](std::uint32_t i) {
        return (families[i].timestampValidBits > 0 ? 2 : 0) +
               ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) ? 1 : 0);
    };
    int best = -1;
    for (std::uint32_t i = 0; i < count; ++i) {
        if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (best < 0 || rank(i) > rank(static_cast<std::uint32_t>(best)))
            best = static_cast<int>(i);
    }
    if (best < 0) return false;
    *family = static_cast<std::uint32_t>(best);
    return true;
}

VkInstance create_instance(bool validation, bool* debug_utils) {
    std::uint32_t ext_count = 0;
    VkResult r = vkEnumerateInstanceExtensionProperties(nullptr, &ext_count, nullptr);
    if (r != VK_SUCCESS) throw Error(ErrorCode::NoDevice, no_device_help(), r);
    std::vector<VkExtensionProperties> exts(ext_count);
    vkEnumerateInstanceExtensionProperties(nullptr, &ext_count, exts.data());
    auto has_ext = [&](const char* name) {
        return std::any_of(exts.begin(), exts.end(),
                           [&](const VkExtensionProperties& e) { return !std::strcmp(e.extensionName, name); });
    };
    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    if (validation) {
        std::uint32_t layer_count = 0;
        vkEnumerateInstanceLayerProperties(&layer_count, nullptr);
        std::vector<VkLayerProperties> props(layer_count);
        vkEnumerateInstanceLayerProperties(&layer_count, props.data());
        bool found = std::any_of(props.begin(), props.end(), [](const VkLayerProperties& p) {
            return !std::strcmp(p.layerName, kValidationLayer);
        });
        if (!found)
            throw Error(ErrorCode::NoDevice,
                        "Vulkan validation layer VK_LAYER_KHRONOS_validation not found "
                        "(on Debian: apt-get install vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
    }
    *debug_utils = has_ext(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (*debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "fdmsurf";
    app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.pEngineName = "fdmsurf";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    r = vkCreateInstance(&info, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
        throw Error(ErrorCode::NoDevice, no_device_help(), r);
    FDM_VK_CHECK(r);
    return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
    std::uint32_t count = 0;
    VkResult r = vkEnumeratePhysicalDevices(instance, &count, nullptr);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE) FDM_VK_CHECK(r);
    std::vector<VkPhysicalDevice> devices(count);
    if (count) {
        r = vkEnumeratePhysicalDevices(instance, &count, devices.data());
        if (r != VK_SUCCESS && r != VK_INCOMPLETE) FDM_VK_CHECK(r);
        devices.resize(count);
    }
    return devices;
}

}  // namespace

std::string no_device_help() {
    return "no usable Vulkan device found: install a Vulkan driver: mesa-vulkan-drivers for AMD "
           "and Intel GPUs and for lavapipe, the CPU device (Debian/Ubuntu: apt-get install "
           "mesa-vulkan-drivers); NVIDIA's driver with its Vulkan ICD for an NVIDIA GPU (Debian: "
           "nvidia-vulkan-icd); docs/install.md";
}

DeviceInfo describe_device(VkPhysicalDevice device, std::uint32_t index) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device, &props);
    DeviceInfo info;
    info.index = index;
    info.name = props.deviceName;
    info.type = type_name(props.deviceType);
    info.api_version = version_string(props.apiVersion);
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    if (props.apiVersion >= VK_API_VERSION_1_2) {
        props2.pNext = &driver;
        vkGetPhysicalDeviceProperties2(device, &props2);
        info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
    } else {
        info.driver = "driver version " + std::to_string(props.driverVersion);
    }
    info.max_storage_buffer_range = props.limits.maxStorageBufferRange;
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(device, &mem);
    for (std::uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            info.device_memory = std::max<std::uint64_t>(info.device_memory, mem.memoryHeaps[i].size);

    std::uint32_t family = 0;
    if (props.apiVersion < VK_API_VERSION_1_1) {
        info.reason = "Vulkan " + info.api_version + " is older than the 1.1 fdmsurf needs";
    } else if (!find_compute_queue(device, &family)) {
        info.reason = "no queue family supports compute";
    } else if (props.limits.maxComputeWorkGroupInvocations < shader::kScanGroup ||
               props.limits.maxComputeWorkGroupSize[0] < shader::kScanGroup ||
               props.limits.maxComputeSharedMemorySize < kSharedMemoryNeeded ||
               props.limits.maxPushConstantsSize < 128) {
        info.reason = "compute limits too small (needs " + std::to_string(shader::kScanGroup) +
                      " invocations per workgroup, " + std::to_string(kSharedMemoryNeeded / 1024) +
                      " KiB shared memory, 128 B push constants)";
    } else {
        info.usable = true;
    }
    return info;
}

Context::Context(const EngineOptions& options) {
    if (options.external) {
        adopt(*options.external, options);
        return;
    }
    bool debug_utils = false;
    instance_ = create_instance(options.validation, &debug_utils);
    trace("vulkan: instance");
    try {
        if (debug_utils) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            set_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
                vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
            if (create && options.validation) {
                VkDebugUtilsMessengerCreateInfoEXT info{
                    VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
                info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                       VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
                info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
                info.pfnUserCallback = debug_callback;
                info.pUserData = this;
                FDM_VK_CHECK(create(instance_, &info, nullptr, &messenger_));
            }
        }

        auto devices = physical_devices(instance_);
        trace("vulkan: physical devices listed");
        if (devices.empty()) throw Error(ErrorCode::NoDevice, no_device_help());
        std::vector<DeviceInfo> infos;
        for (std::uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe_device(devices[i], i));

        int chosen = -1;
        const std::string& want = options.device;
        bool numeric = !want.empty() && std::all_of(want.begin(), want.end(), ::isdigit);
        if (numeric) {
            unsigned long idx = std::stoul(want);
            if (idx >= devices.size())
                throw Error(ErrorCode::NoDevice, "--device " + want + ": there are only " +
                                                     std::to_string(devices.size()) +
                                                     " Vulkan device(s) (see --list-devices)");
            if (!infos[idx].usable)
                throw Error(ErrorCode::NoDevice, "device " + want + " (" + infos[idx].name +
                                                     ") cannot be used: " + infos[idx].reason);
            chosen = static_cast<int>(idx);
        } else {
            std::string reasons;
            VkPhysicalDeviceProperties props;
            int best_rank = 99;
            for (std::uint32_t i = 0; i < devices.size(); ++i) {
                if (!want.empty() && lower(infos[i].name).find(lower(want)) == std::string::npos)
                    continue;
                if (!infos[i].usable) {
                    reasons += "; " + infos[i].name + ": " + infos[i].reason;
                    continue;
                }
                vkGetPhysicalDeviceProperties(devices[i], &props);
                if (type_rank(props.deviceType) < best_rank) {
                    best_rank = type_rank(props.deviceType);
                    chosen = static_cast<int>(i);
                }
            }
            if (chosen < 0) {
                if (!want.empty() && reasons.empty())
                    throw Error(ErrorCode::NoDevice,
                                "no Vulkan device name contains \"" + want + "\" (see --list-devices)");
                throw Error(ErrorCode::NoDevice, no_device_help() + reasons);
            }
        }
        physical_ = devices[static_cast<std::size_t>(chosen)];
        info_ = infos[static_cast<std::size_t>(chosen)];
        find_compute_queue(physical_, &queue_family_);

        read_limits(options);

        float priority = 1.0f;
        VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queue.queueFamilyIndex = queue_family_;
        queue.queueCount = 1;
        queue.pQueuePriorities = &priority;
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queue;
        // VK_EXT_memory_budget where the device has it: how much memory is free now, not only
        // how large the heap is (other applications share a GPU's memory).
        std::uint32_t ext_count = 0;
        vkEnumerateDeviceExtensionProperties(physical_, nullptr, &ext_count, nullptr);
        std::vector<VkExtensionProperties> device_exts(ext_count);
        vkEnumerateDeviceExtensionProperties(physical_, nullptr, &ext_count, device_exts.data());
        device_exts.resize(ext_count);
        const char* budget_ext = VK_EXT_MEMORY_BUDGET_EXTENSION_NAME;
        memory_budget_ = std::any_of(device_exts.begin(), device_exts.end(), [&](const auto& e) {
            return std::strcmp(e.extensionName, budget_ext) == 0;
        });
        if (memory_budget_) {
            info.enabledExtensionCount = 1;
            info.ppEnabledExtensionNames = &budget_ext;
        }
        FDM_VK_CHECK(vkCreateDevice(physical_, &info, nullptr, &device_));
        vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
        trace("vulkan: device created");
    } catch (...) {
        if (device_) vkDestroyDevice(device_, nullptr);
        if (messenger_) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance_, messenger_, nullptr);
        }
        vkDestroyInstance(instance_, nullptr);
        throw;
    }
}

VkDeviceSize Context::available_device_memory() const {
    if (!memory_budget_) return limits_.device_memory;
    VkPhysicalDeviceMemoryBudgetPropertiesEXT budget{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_BUDGET_PROPERTIES_EXT};
    VkPhysicalDeviceMemoryProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MEMORY_PROPERTIES_2};
    props.pNext = &budget;
    vkGetPhysicalDeviceMemoryProperties2(physical_, &props);
    // The largest device-local heap, as limits().device_memory counts it.
    int heap = -1;
    for (std::uint32_t i = 0; i < props.memoryProperties.memoryHeapCount; ++i) {
        const VkMemoryHeap& h = props.memoryProperties.memoryHeaps[i];
        if ((h.flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
            (heap < 0 || h.size > props.memoryProperties.memoryHeaps[heap].size))
            heap = static_cast<int>(i);
    }
    if (heap < 0) return limits_.device_memory;
    const VkDeviceSize limit = budget.heapBudget[heap], used = budget.heapUsage[heap];
    return limit > used ? limit - used : 0;
}

void Context::read_limits(const EngineOptions& options) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical_, &props);
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    limits_.max_storage_buffer_range = props.limits.maxStorageBufferRange;
    if (options.max_buffer_range)
        limits_.max_storage_buffer_range =
            std::min<VkDeviceSize>(limits_.max_storage_buffer_range, options.max_buffer_range);
    VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &m3;
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    limits_.max_allocation_size = m3.maxMemoryAllocationSize;
    limits_.device_memory = info_.device_memory;
    for (int i = 0; i < 3; ++i) limits_.max_workgroup_count[i] = props.limits.maxComputeWorkGroupCount[i];
    limits_.max_workgroup_invocations = props.limits.maxComputeWorkGroupInvocations;
    limits_.max_push_constants = props.limits.maxPushConstantsSize;
    limits_.max_shared_memory = props.limits.maxComputeSharedMemorySize;
    limits_.min_storage_offset_alignment = props.limits.minStorageBufferOffsetAlignment;
    std::uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
    limits_.max_image_dimension_2d = props.limits.maxImageDimension2D;
    limits_.graphics = (families[queue_family_].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
    if (families[queue_family_].timestampValidBits > 0)
        limits_.timestamp_period_ns = props.limits.timestampPeriod;
}

void Context::adopt(const ExternalDevice& ext, const EngineOptions& options) {
    if (!ext.instance || !ext.physical_device || !ext.device || !ext.queue)
        throw Error(ErrorCode::InvalidArgument, "external Vulkan device: a handle is null");
    owned_ = false;
    instance_ = ext.instance;
    physical_ = ext.physical_device;
    device_ = ext.device;
    queue_ = ext.queue;
    queue_family_ = ext.queue_family;
    info_ = describe_device(physical_, 0);
    if (!info_.usable)
        throw Error(ErrorCode::NoDevice, "external Vulkan device " + info_.name +
                                             " cannot be used: " + info_.reason);
    std::uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
    if (queue_family_ >= count || !(families[queue_family_].queueFlags & VK_QUEUE_COMPUTE_BIT))
        throw Error(ErrorCode::InvalidArgument,
                    "external Vulkan device: queue family " + std::to_string(queue_family_) +
                        " does not support compute");
    // No object names: the application's instance may not have VK_EXT_debug_utils enabled.
    read_limits(options);
}

Context::~Context() {
    if (!owned_) {
        if (device_) vkQueueWaitIdle(queue_);
        return;
    }
    if (device_) {
        vkDeviceWaitIdle(device_);
        vkDestroyDevice(device_, nullptr);
    }
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

void Context::set_name(VkObjectType type, std::uint64_t handle, const char* name) const {
    if (!set_name_ || !handle) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    set_name_(device_, &info);
}

std::vector<std::string> Context::take_messages() {
    std::lock_guard<std::mutex> lock(messages_mutex_);
    return std::exchange(messages_, {});
}

void Context::add_message(std::string message) {
    std::lock_guard<std::mutex> lock(messages_mutex_);
    messages_.push_back(std::move(message));
}

}  // namespace fdmsurf::detail
