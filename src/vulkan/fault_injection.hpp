// Faults a test can ask for, to prove that fdmsurf survives what a real device does rarely:
// a lost device and an allocation that fails. Off unless FDMSURF_FAULT is set; read once.
//
//   FDMSURF_FAULT=device-lost        the first wait for GPU work reports VK_ERROR_DEVICE_LOST
//   FDMSURF_FAULT=device-lost:N      the N-th one (1-based) does
//   FDMSURF_FAULT=out-of-memory:NAME the allocation of the buffer or image NAME ("field_slab",
//                                    "mc_vertices", ...) reports VK_ERROR_OUT_OF_DEVICE_MEMORY
//
// The work itself runs as usual; only the result the program sees is replaced, at the one
// place where the real driver would return it (Commands::submit_and_wait, Buffer and Image
// allocation), so every path after it (messages, exit codes, unwinding, no output left) is the
// real one. docs/reliability.md.
#pragma once

#include <vulkan/vulkan.h>

namespace fdmsurf::detail {

// `real`, or VK_ERROR_DEVICE_LOST when this wait is the one FDMSURF_FAULT names.
VkResult injected_wait_result(VkResult real) noexcept;

// True when FDMSURF_FAULT names this allocation: the caller then takes
// VK_ERROR_OUT_OF_DEVICE_MEMORY instead of calling vkAllocateMemory.
bool allocation_fault(const char* name) noexcept;

}  // namespace fdmsurf::detail
