// fdmsurf's one exception type: every library failure is an fdmsurf::Error with a code.
#pragma once

#include <stdexcept>
#include <string>

namespace fdmsurf {

enum class ErrorCode {
    InvalidArgument,  // an option out of range (spacing <= 0, probe < 0, ...)
    Io,               // a file that cannot be opened, read or written
    Format,           // malformed, truncated or unrecognised input
    EmptySelection,   // no atoms left after selection
    NoDevice,         // no usable Vulkan device
    DeviceLimit,      // the job does not fit the device's limits
    Vulkan,           // a Vulkan call failed (vk_result() holds the VkResult)
    Fft,              // VkFFT failed (vk_result() holds the VkFFTResult)
    Internal,         // a broken invariant: a bug in fdmsurf
};

const char* to_string(ErrorCode code) noexcept;

class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message, int vk_result = 0)
        : std::runtime_error(message), code_(code), vk_result_(vk_result) {}
    ErrorCode code() const noexcept { return code_; }
    // The VkResult or VkFFTResult behind a Vulkan or Fft error, 0 otherwise.
    int vk_result() const noexcept { return vk_result_; }

private:
    ErrorCode code_;
    int vk_result_;
};

}  // namespace fdmsurf
