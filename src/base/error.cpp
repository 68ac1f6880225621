// Names of error codes, for messages and --stats json.
#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace fdmsurf {

const char* to_string(ErrorCode code) noexcept {
    switch (code) {
        case ErrorCode::InvalidArgument: return "invalid-argument";
        case ErrorCode::Io: return "io";
        case ErrorCode::Format: return "format";
        case ErrorCode::EmptySelection: return "empty-selection";
        case ErrorCode::NoDevice: return "no-device";
        case ErrorCode::DeviceLimit: return "device-limit";
        case ErrorCode::Vulkan: return "vulkan";
        case ErrorCode::Fft: return "fft";
        case ErrorCode::Internal: return "internal";
    }
    return "unknown";
}

const char* version() noexcept { return FDMSURF_VERSION; }

}  // namespace fdmsurf
