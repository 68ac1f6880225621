// One way to check a VkResult: throw fdmsurf::Error naming the call, the result, file and line.
#pragma once

#include <vulkan/vulkan.h>

#include <string>

#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {

const char* vk_result_name(VkResult result) noexcept;

[[noreturn]] void throw_vk_error(VkResult result, const char* call, const char* file, int line);

}  // namespace fdmsurf::detail

// VK_TIMEOUT, VK_NOT_READY and VK_INCOMPLETE are not success here: any result other than
// VK_SUCCESS throws. Calls that legitimately return them are handled where they are made.
#define FDM_VK_CHECK(call)                                                                  \
    do {                                                                                    \
        VkResult fdm_vk_result_ = (call);                                                   \
        if (fdm_vk_result_ != VK_SUCCESS)                                                   \
            ::fdmsurf::detail::throw_vk_error(fdm_vk_result_, #call, __FILE__, __LINE__);   \
    } while (0)
