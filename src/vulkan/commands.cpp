// Command recording, barriers, fenced submission with a timeout, and GPU timestamps.
#include "vulkan/commands.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include "vulkan/buffer.hpp"
#include "vulkan/check.hpp"
#include "vulkan/context.hpp"
#include "vulkan/fault_injection.hpp"
#include "vulkan/pipeline.hpp"

namespace fdmsurf::detail {
namespace {
constexpr std::uint32_t kMaxQueries = 64;
constexpr std::uint32_t kMaxSets = 256;
}  // namespace

double now_ms() {
    using namespace std::chrono;
    return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

BufferRange whole(const Buffer& b) { return {b.handle(), 0, VK_WHOLE_SIZE}; }

Commands::Commands(Context& ctx) : ctx_(ctx) {
    VkDevice dev = ctx.device();
    try {
        VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pool.queueFamilyIndex = ctx.queue_family();
        FDM_VK_CHECK(vkCreateCommandPool(dev, &pool, nullptr, &pool_));
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool_;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        FDM_VK_CHECK(vkAllocateCommandBuffers(dev, &alloc, &cmd_));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        FDM_VK_CHECK(vkCreateFence(dev, &fence, nullptr, &fence_));
        VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kMaxSets * 8};
        VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dp.maxSets = kMaxSets;
        dp.poolSizeCount = 1;
        dp.pPoolSizes = &size;
        FDM_VK_CHECK(vkCreateDescriptorPool(dev, &dp, nullptr, &descriptors_));
        if (ctx.limits().timestamp_period_ns > 0) {
            VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            q.queryType = VK_QUERY_TYPE_TIMESTAMP;
            q.queryCount = kMaxQueries;
            FDM_VK_CHECK(vkCreateQueryPool(dev, &q, nullptr, &queries_));
        }
    } catch (...) {
        release();
        throw;
    }
}

Commands::~Commands() { release(); }

void Commands::release() {
    VkDevice dev = ctx_.device();
    if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
    if (descriptors_) vkDestroyDescriptorPool(dev, descriptors_, nullptr);
    if (fence_) vkDestroyFence(dev, fence_, nullptr);
    if (pool_) vkDestroyCommandPool(dev, pool_, nullptr);
    queries_ = VK_NULL_HANDLE;
    descriptors_ = VK_NULL_HANDLE;
    fence_ = VK_NULL_HANDLE;
    pool_ = VK_NULL_HANDLE;
}

void Commands::begin() {
    FDM_VK_CHECK(vkResetDescriptorPool(ctx_.device(), descriptors_, 0));
    FDM_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    FDM_VK_CHECK(vkBeginCommandBuffer(cmd_, &info));
    marks_.clear();
    query_count_ = 0;
    if (queries_) {
        vkCmdResetQueryPool(cmd_, queries_, 0, kMaxQueries);
        vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, query_count_++);
    }
    begin_host_ms_ = now_ms();
}

std::array<std::uint32_t, 2> Commands::fold_groups(std::uint64_t groups) const {
    const std::uint64_t x = std::min<std::uint64_t>(groups, ctx_.limits().max_workgroup_count[0]);
    if (x == 0) return {0, 0};
    const std::uint64_t y = (groups + x - 1) / x;
    return {static_cast<std::uint32_t>(x),
            static_cast<std::uint32_t>(std::min<std::uint64_t>(y, UINT32_MAX))};
}

void Commands::dispatch(const ComputePipeline& pipeline, std::initializer_list<BufferRange> buffers,
                        const void* push, std::uint32_t gx, std::uint32_t gy, std::uint32_t gz) {
    if (buffers.size() != pipeline.bindings())
        throw Error(ErrorCode::Internal, std::string("pipeline ") + pipeline.name() +
                                             ": wrong number of buffers bound");
    const DeviceLimits& lim = ctx_.limits();
    if (gx > lim.max_workgroup_count[0] || gy > lim.max_workgroup_count[1] ||
        gz > lim.max_workgroup_count[2])
        throw Error(ErrorCode::DeviceLimit,
                    std::string("pipeline ") + pipeline.name() + " needs " + std::to_string(gx) +
                        " x " + std::to_string(gy) + " x " + std::to_string(gz) +
                        " workgroups, more than the device's maxComputeWorkGroupCount");
    if (gx == 0 || gy == 0 || gz == 0) return;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkDescriptorSetLayout layout = pipeline.set_layout();
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = descriptors_;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    FDM_VK_CHECK(vkAllocateDescriptorSets(ctx_.device(), &alloc, &set));
    std::vector<VkDescriptorBufferInfo> infos;
    std::vector<VkWriteDescriptorSet> writes;
    infos.reserve(buffers.size());
    for (const BufferRange& b : buffers) infos.push_back({b.buffer, b.offset, b.range});
    for (std::uint32_t i = 0; i < infos.size(); ++i) {
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.dstBinding = i;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &infos[i];
        writes.push_back(w);
    }
    vkUpdateDescriptorSets(ctx_.device(), static_cast<std::uint32_t>(writes.size()), writes.data(),
                           0, nullptr);
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set,
                            0, nullptr);
    if (pipeline.push_bytes())
        vkCmdPushConstants(cmd_, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           pipeline.push_bytes(), push);
    vkCmdDispatch(cmd_, gx, gy, gz);
}

void Commands::barrier_compute() {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void Commands::barrier_host_to_compute() {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_HOST_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &b, 0, nullptr, 0, nullptr);
}

void Commands::copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes, VkDeviceSize src_offset,
                    VkDeviceSize dst_offset) {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
    if (bytes == 0) return;
    VkBufferCopy region{src_offset, dst_offset, bytes};
    vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
}

void Commands::fill(const Buffer& dst, std::uint32_t value) {
    fill(dst, 0, VK_WHOLE_SIZE, value);
}

void Commands::fill(const Buffer& dst, VkDeviceSize offset, VkDeviceSize bytes,
                    std::uint32_t value) {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask =
        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
    vkCmdFillBuffer(cmd_, dst.handle(), offset, bytes, value);
}

void Commands::barrier_to_host() {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void Commands::mark(const char* name) {
    marks_.emplace_back(name);
    if (queries_ && query_count_ < kMaxQueries)
        vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, query_count_++);
}

void Commands::submit_and_wait(std::uint64_t timeout_ns) {
    FDM_VK_CHECK(vkEndCommandBuffer(cmd_));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    FDM_VK_CHECK(vkResetFences(ctx_.device(), 1, &fence_));
    FDM_VK_CHECK(vkQueueSubmit(ctx_.queue(), 1, &submit, fence_));
    VkResult r =
        injected_wait_result(vkWaitForFences(ctx_.device(), 1, &fence_, VK_TRUE, timeout_ns));
    // Before throwing, let the queue drain: the buffers that unwinding frees may still be in use,
    // and the command buffer may not be reset while pending.
    if (r != VK_SUCCESS) vkQueueWaitIdle(ctx_.queue());
    if (r == VK_TIMEOUT)
        throw Error(ErrorCode::Vulkan,
                    "GPU work did not finish within " + std::to_string(timeout_ns / 1000000000ull) +
                        " s (vkWaitForFences returned VK_TIMEOUT)",
                    r);
    FDM_VK_CHECK(r);
    double host_total = now_ms() - begin_host_ms_;
    times_.clear();
    if (queries_ && query_count_ == marks_.size() + 1) {
        std::vector<std::uint64_t> ts(query_count_);
        FDM_VK_CHECK(vkGetQueryPoolResults(ctx_.device(), queries_, 0, query_count_,
                                           ts.size() * sizeof(std::uint64_t), ts.data(),
                                           sizeof(std::uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        double period = ctx_.limits().timestamp_period_ns;
        for (std::size_t i = 0; i < marks_.size(); ++i)
            times_.push_back({marks_[i], double(ts[i + 1] - ts[i]) * period * 1e-6, true});
    } else if (!marks_.empty()) {
        // Without timestamps only the whole submission can be timed.
        std::string name = marks_.front();
        for (std::size_t i = 1; i < marks_.size(); ++i) name += "+" + marks_[i];
        times_.push_back({name, host_total, false});
    }
}

}  // namespace fdmsurf::detail
