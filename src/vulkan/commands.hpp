// Recording and submitting compute work: dispatches, the barriers we need, copies, timestamps.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"

namespace fdmsurf::detail {

class Buffer;
class ComputePipeline;
class Context;

struct BufferRange {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize range = VK_WHOLE_SIZE;
};
BufferRange whole(const Buffer& b);

// One command buffer, reused: begin(), record, submit_and_wait(). Owns its pool, fence,
// descriptor pool and timestamp query pool.
class Commands {
public:
    explicit Commands(Context& ctx);
    ~Commands();
    Commands(const Commands&) = delete;
    Commands& operator=(const Commands&) = delete;

    void begin();
    void dispatch(const ComputePipeline& pipeline, std::initializer_list<BufferRange> buffers,
                  const void* push, std::uint32_t gx, std::uint32_t gy = 1, std::uint32_t gz = 1);
    // `groups` workgroups of a flat dispatch, folded into rows of at most
    // maxComputeWorkGroupCount[0]: {x, y} with x * y >= groups (the shader skips the excess);
    // dispatch() checks y against the device.
    std::array<std::uint32_t, 2> fold_groups(std::uint64_t groups) const;
    // Compute writes visible to later compute reads and writes.
    void barrier_compute();
    // Compute writes visible to transfer, then transfer writes visible to the host.
    void copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset = 0,
              VkDeviceSize dst_offset = 0);
    // Sets every 32-bit word of `dst` to `value` (a transfer, after earlier compute and host
    // writes; follow it with barrier_compute() before a shader reads or writes `dst`).
    void fill(const Buffer& dst, std::uint32_t value);
    // Fills `bytes` bytes (a multiple of 4) of `dst` from `offset` (a multiple of 4).
    void fill(const Buffer& dst, VkDeviceSize offset, VkDeviceSize bytes, std::uint32_t value);
    void barrier_to_host();
    void barrier_host_to_compute();
    // Marks the end of a stage named `name` (GPU timestamp when the queue has them).
    void mark(const char* name);
    // Submits and waits on the fence with a finite timeout; throws on VK_TIMEOUT.
    void submit_and_wait(std::uint64_t timeout_ns = 600ull * 1000 * 1000 * 1000);
    // Stage times of the last submission, from timestamps or host clocks.
    const std::vector<StageTime>& stage_times() const { return times_; }

    VkCommandBuffer handle() const { return cmd_; }
    VkCommandPool pool() const { return pool_; }
    VkFence fence() const { return fence_; }

private:
    void release();
    Context& ctx_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptors_ = VK_NULL_HANDLE;
    VkQueryPool queries_ = VK_NULL_HANDLE;
    std::uint32_t query_count_ = 0;
    std::vector<std::string> marks_;
    std::vector<StageTime> times_;
    double begin_host_ms_ = 0;
};

double now_ms();

}  // namespace fdmsurf::detail
