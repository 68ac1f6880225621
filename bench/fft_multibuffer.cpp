// Benchmark of VkFFT's multi-buffer mode (configuration.bufferNum) against z-slabs: one R2C
// transform of a whole grid kept in several VkBuffers of equal size (each within one storage
// binding), forward then inverse, against the same work as the slab mode does it (each slab's
// planes: the core plus the filter's overlap, rounded to an FFT size), on this device. Prints
// GPU times (timestamp queries), median of --reps runs after one warm-up run, and the largest
// difference between the multi-buffer round trip and the single-buffer one where the whole grid
// fits one buffer (a check that the mode computes the same transform).
//
//   build/fdmsurf_bench_fft_multibuffer [--reps N] [--buffers B] NXxNYxNZ SLAB_PLANES SLABS
//   e.g. 384x343x448 245 2 (1AON at 0.5 A)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "engine/engine_impl.hpp"
#include "fdmsurf/error.hpp"
#include "filter/vkfft_compat.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/commands.hpp"

using namespace fdmsurf;
using namespace fdmsurf::detail;
using fdmsurf::bench::median;
using fdmsurf::bench::stage;

namespace {

// One VkFFT R2C plan of `dims` over `buffers` (equal sizes, planes split evenly).
struct Plan {
    VkFFTApplication app{};
    VkFFTConfiguration config{};
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    std::vector<VkBuffer> handles;
    std::vector<std::uint64_t> sizes;
    Plan(Context& ctx, const std::array<std::uint32_t, 3>& d, const std::vector<Buffer>& bufs)
        : physical(ctx.physical_device()), device(ctx.device()), queue(ctx.queue()) {
        VkCommandPoolCreateInfo p{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        p.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        p.queueFamilyIndex = ctx.queue_family();
        vkCreateCommandPool(device, &p, nullptr, &pool);
        VkFenceCreateInfo f{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        vkCreateFence(device, &f, nullptr, &fence);
        for (const Buffer& b : bufs) handles.push_back(b.handle()), sizes.push_back(b.size());
        config.FFTdim = 3;
        config.size[0] = d[0];
        config.size[1] = d[1];
        config.size[2] = d[2];
        config.physicalDevice = &physical;
        config.device = &device;
        config.queue = &queue;
        config.commandPool = &pool;
        config.fence = &fence;
        config.isCompilerInitialized = 1;
        config.performR2C = 1;
        config.normalize = 1;
        config.bufferNum = handles.size();
        config.buffer = handles.data();
        config.bufferSize = sizes.data();
        const VkFFTResult r = initializeVkFFT(&app, config);
        if (r != VKFFT_SUCCESS)
            throw Error(ErrorCode::Fft, "VkFFT plan failed: " + std::to_string(int(r)));
    }
    ~Plan() {
        deleteVkFFT(&app);
        vkDestroyFence(device, fence, nullptr);
        vkDestroyCommandPool(device, pool, nullptr);
    }
    void record(Commands& cmds, int direction) {
        VkCommandBuffer cmd = cmds.handle();
        VkFFTLaunchParams launch{};
        launch.commandBuffer = &cmd;
        launch.buffer = handles.data();
        if (VkFFTAppend(&app, direction, &launch) != VKFFT_SUCCESS)
            throw Error(ErrorCode::Fft, "VkFFT append failed");
    }
};

// Round trip (forward, inverse) of the plan's field; returns the two stage times.
std::pair<double, double> round_trip(Commands& cmds, Plan& plan) {
    cmds.begin();
    plan.record(cmds, -1);
    cmds.mark("forward");
    cmds.barrier_compute();
    plan.record(cmds, 1);
    cmds.mark("inverse");
    cmds.barrier_compute();
    cmds.submit_and_wait();
    return {stage(cmds.stage_times(), "forward"), stage(cmds.stage_times(), "inverse")};
}

std::vector<Buffer> field_buffers(Context& ctx, const std::array<std::uint32_t, 3>& d,
                                  std::uint32_t count) {
    const std::uint64_t plane = std::uint64_t(2) * (d[0] / 2 + 1) * d[1] * sizeof(float);
    std::vector<Buffer> out;
    for (std::uint32_t k = 0; k < count; ++k)
        out.emplace_back(ctx, plane * (d[2] / count), MemoryUse::Upload, "fft_field");
    return out;
}

void fill(std::vector<Buffer>& bufs, std::uint32_t seed) {
    for (Buffer& b : bufs) {
        float* p = static_cast<float*>(b.mapped());
        for (std::size_t i = 0; i < b.size() / sizeof(float); ++i) {
            seed = seed * 1664525u + 1013904223u;
            p[i] = float(seed >> 8) / float(1u << 24);
        }
        b.flush();
    }
}

}  // namespace

int main(int argc, char** argv) {
    int reps = 3;
    std::uint32_t buffers = 2;
    std::vector<const char*> rest;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--buffers") && i + 1 < argc)
            buffers = std::max(1, std::atoi(argv[++i]));
        else
            rest.push_back(argv[i]);
    }
    std::array<std::uint32_t, 3> d{};
    unsigned slab_planes = 0, slabs = 0;
    if (rest.size() != 3 || std::sscanf(rest[0], "%ux%ux%u", &d[0], &d[1], &d[2]) != 3 ||
        std::sscanf(rest[1], "%u", &slab_planes) != 1 || std::sscanf(rest[2], "%u", &slabs) != 1 ||
        d[0] % 2 || d[2] % buffers) {
        std::fprintf(stderr, "usage: %s [--reps N] [--buffers B] NXxNYxNZ SLAB_PLANES SLABS "
                             "(NX even, NZ a multiple of B)\n", argv[0]);
        return 2;
    }
    try {
        EngineImpl e{EngineOptions{}};
        glslang_acquire();
        std::printf("device: %s; grid %ux%ux%u in %u buffers against %u slabs of %u planes\n\n",
                    e.context.info().name.c_str(), d[0], d[1], d[2], buffers, slabs, slab_planes);
        std::vector<Buffer> multi = field_buffers(e.context, d, buffers);
        const std::array<std::uint32_t, 3> ds{d[0], d[1], slab_planes};
        std::vector<Buffer> slab = field_buffers(e.context, ds, 1);
        fill(multi, 7);
        fill(slab, 7);
        Plan pm(e.context, d, multi);
        Plan ps(e.context, ds, slab);
        std::vector<double> mf, mi, sf, si;
        for (int r = 0; r <= reps; ++r) {
            const auto m = round_trip(e.commands, pm);
            double f = 0, v = 0;
            for (unsigned k = 0; k < slabs; ++k) {
                const auto s = round_trip(e.commands, ps);
                f += s.first, v += s.second;
            }
            if (r == 0) continue;
            mf.push_back(m.first), mi.push_back(m.second), sf.push_back(f), si.push_back(v);
        }
        const double points = double(d[0]) * d[1] * d[2];
        std::printf("| layout | forward (ms) | inverse (ms) | ns per grid point |\n|---|---|---|---|\n");
        std::printf("| %u buffers, whole grid | %.0f | %.0f | %.0f |\n", buffers, median(mf),
                    median(mi), (median(mf) + median(mi)) * 1e6 / points);
        std::printf("| %u slabs of %u planes | %.0f | %.0f | %.0f |\n", slabs, slab_planes,
                    median(sf), median(si), (median(sf) + median(si)) * 1e6 / points);
        // The round trip with normalisation gives the input back: the largest error.
        fill(multi, 11);
        std::vector<float> before;
        for (Buffer& b : multi) {
            const float* p = static_cast<const float*>(b.mapped());
            before.insert(before.end(), p, p + b.size() / sizeof(float));
        }
        round_trip(e.commands, pm);
        double worst = 0.0;
        std::size_t i = 0;
        const std::uint32_t pitch = 2 * (d[0] / 2 + 1);
        for (Buffer& b : multi) {
            b.invalidate();
            const float* p = static_cast<const float*>(b.mapped());
            for (std::size_t k = 0; k < b.size() / sizeof(float); ++k, ++i)
                if (i % pitch < d[0]) worst = std::max(worst, double(std::abs(p[k] - before[i])));
        }
        std::printf("\nround trip of the %u-buffer grid: largest |x - ifft(fft(x))| = %.3g (values in [0, 1))\n",
                    buffers, worst);
        glslang_release();
    } catch (const Error& err) {
        std::fprintf(stderr, "error: %s\n", err.what());
        return 1;
    }
    return 0;
}
