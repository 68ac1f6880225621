// VkResult names and the exception thrown for a failed Vulkan call.
#include "vulkan/check.hpp"

#include <cstring>

namespace fdmsurf::detail {

const char* vk_result_name(VkResult result) noexcept {
    switch (result) {
#define FDM_CASE(x) case x: return #x
        FDM_CASE(VK_SUCCESS);
        FDM_CASE(VK_NOT_READY);
        FDM_CASE(VK_TIMEOUT);
        FDM_CASE(VK_EVENT_SET);
        FDM_CASE(VK_EVENT_RESET);
        FDM_CASE(VK_INCOMPLETE);
        FDM_CASE(VK_ERROR_OUT_OF_HOST_MEMORY);
        FDM_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY);
        FDM_CASE(VK_ERROR_INITIALIZATION_FAILED);
        FDM_CASE(VK_ERROR_DEVICE_LOST);
        FDM_CASE(VK_ERROR_MEMORY_MAP_FAILED);
        FDM_CASE(VK_ERROR_LAYER_NOT_PRESENT);
        FDM_CASE(VK_ERROR_EXTENSION_NOT_PRESENT);
        FDM_CASE(VK_ERROR_FEATURE_NOT_PRESENT);
        FDM_CASE(VK_ERROR_INCOMPATIBLE_DRIVER);
        FDM_CASE(VK_ERROR_TOO_MANY_OBJECTS);
        FDM_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED);
        FDM_CASE(VK_ERROR_FRAGMENTED_POOL);
        FDM_CASE(VK_ERROR_UNKNOWN);
        FDM_CASE(VK_ERROR_OUT_OF_POOL_MEMORY);
        FDM_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE);
        FDM_CASE(VK_ERROR_FRAGMENTATION);
#undef FDM_CASE
        default: return "VkResult(unknown)";
    }
}

void throw_vk_error(VkResult result, const char* call, const char* file, int line) {
    const char* base = std::strrchr(file, '/');
    std::string where = std::string(base ? base + 1 : file) + ":" + std::to_string(line);
    std::string text = std::string("Vulkan call failed: ") + call + " returned " +
                       vk_result_name(result) + " (" + where + ")";
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
        text += "; try a coarser --spacing";
    if (result == VK_ERROR_DEVICE_LOST)
        text += ": the Vulkan device was lost (a driver reset, a GPU fault or a removed GPU)";
    throw Error(ErrorCode::Vulkan, text, static_cast<int>(result));
}

}  // namespace fdmsurf::detail
