// FDMSURF_FAULT: see fault_injection.hpp.
#include "vulkan/fault_injection.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <string>
#include <string_view>

namespace fdmsurf::detail {
namespace {

struct Fault {
    enum Kind { None, DeviceLost, OutOfMemory } kind = None;
    long wait = 1;         // device-lost: the wait that fails, 1-based
    std::string name;      // out-of-memory: the allocation that fails
};

Fault parse_fault() {
    Fault f;
    const char* env = std::getenv("FDMSURF_FAULT");
    if (!env) return f;
    const std::string_view text(env);
    const std::size_t colon = text.find(':');
    const std::string_view kind = text.substr(0, colon);
    const std::string arg(colon == std::string_view::npos ? "" : text.substr(colon + 1));
    if (kind == "device-lost") {
        f.kind = Fault::DeviceLost;
        if (!arg.empty()) f.wait = std::max(1L, std::strtol(arg.c_str(), nullptr, 10));
    } else if (kind == "out-of-memory" && !arg.empty()) {
        f.kind = Fault::OutOfMemory;
        f.name = arg;
    }
    return f;
}

const Fault& fault() {
    static const Fault f = parse_fault();
    return f;
}

}  // namespace

VkResult injected_wait_result(VkResult real) noexcept {
    if (real != VK_SUCCESS || fault().kind != Fault::DeviceLost) return real;
    static std::atomic<long> waits{0};
    return ++waits == fault().wait ? VK_ERROR_DEVICE_LOST : real;
}

bool allocation_fault(const char* name) noexcept {
    return fault().kind == Fault::OutOfMemory && name != nullptr && fault().name == name;
}

}  // namespace fdmsurf::detail
