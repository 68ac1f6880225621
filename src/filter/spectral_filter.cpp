// Spectral filter (Giard & Macq 2010; ALGORITHM.md §3) on VkFFT; VkFFT's C result codes become
// fdmsurf::Error here and nowhere else.
#include "filter/spectral_filter.hpp"
#include "base/trace.hpp"

#include <clocale>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <vector>
#include <string>

#include "vulkan/shaders.hpp"
#include "filter/vkfft_compat.hpp"
#include "shader_interface.h"
#include "vulkan/buffer.hpp"
#include "vulkan/check.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {
namespace {

std::mutex g_glslang_mutex;
int g_glslang_users = 0;

void check_fft(VkFFTResult r, const char* what) {
    if (r != VKFFT_SUCCESS)
        throw Error(ErrorCode::Fft, std::string("VkFFT ") + what + " failed with VkFFTResult " +
                                        std::to_string(static_cast<int>(r)),
                    static_cast<int>(r));
}

// VkFFT 1.2.26 writes each kernel's GLSL under the "C" locale (decimal points): it keeps the
// pointer that setlocale(LC_ALL, NULL) returns, switches to "C", and restores from that pointer
// afterwards. glibc frees the string behind the pointer at the switch unless the locale was "C"
// already, so in a process whose locale is not "C" (Python sets the user's, an application may)
// the restore read freed memory: a heap-use-after-free, found by AddressSanitizer in the Python
// module's tests. Plans are made with "C" set here first, under which VkFFT's pointer is glibc's
// static name, and the caller's locale is restored from a copy. One plan at a time in the
// process (engines on several threads make their plans in turn): the locale is the whole
// process's, and another thread calling setlocale meanwhile would still race with VkFFT.
class CLocaleForVkFFT {
public:
    CLocaleForVkFFT() : lock_(mutex()) {
        const char* current = std::setlocale(LC_ALL, nullptr);
        if (current && std::strcmp(current, "C") != 0) {
            saved_ = current;  // a copy: the next setlocale frees `current`
            std::setlocale(LC_ALL, "C");
        }
    }
    ~CLocaleForVkFFT() {
        if (!saved_.empty()) std::setlocale(LC_ALL, saved_.c_str());
    }
    CLocaleForVkFFT(const CLocaleForVkFFT&) = delete;
    CLocaleForVkFFT& operator=(const CLocaleForVkFFT&) = delete;

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> lock_;
    std::string saved_;
};

// Bytes of a field of `dims` points in the in-place R2C layout (2 (nx/2 + 1) floats per row).
std::uint64_t r2c_field_bytes(const std::array<std::uint32_t, 3>& dims) {
    return std::uint64_t(2) * (dims[0] / 2 + 1) * dims[1] * dims[2] * sizeof(float);
}

}  // namespace

void glslang_acquire() {
    std::lock_guard<std::mutex> lock(g_glslang_mutex);
    if (g_glslang_users == 0 && !glslang_initialize_process())
        throw Error(ErrorCode::Fft, "glslang_initialize_process failed");
    ++g_glslang_users;
    trace("glslang: process initialised");
}

void glslang_release() {
    std::lock_guard<std::mutex> lock(g_glslang_mutex);
    if (--g_glslang_users == 0) glslang_finalize_process();
}

struct FftPlan {
    VkFFTApplication app{};
    VkFFTConfiguration config{};
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    // VkFFT rebinds its descriptors only when the *address* of the VkBuffer it is given changes,
    // and keeps that address. So the handle lives here, in one of two slots, and every launch
    // switches slots: the address always differs, so VkFFT always rewrites its descriptors.
    // (Comparing handles is not enough: drivers reuse the handle of a destroyed buffer.)
    VkBuffer slots[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
    int current = 0;
    std::uint64_t buffer_size = 0;
    VkBuffer* bind(VkBuffer buffer) {
        current ^= 1;
        slots[current] = buffer;
        return &slots[current];
    }
    bool initialised = false;
    bool from_cache = false;  // loaded from the plan cache
    bool stored = false;      // built and written to the plan cache
    ~FftPlan() {
        if (initialised) deleteVkFFT(&app);
    }
};

SpectralFilter::SpectralFilter(Context& ctx)
    : ctx_(ctx), cache_(PlanCache::default_directory()) {
    ShaderCode code = shader_code(Shader::SpectralMask);
    mask_ = ComputePipeline(ctx, code.words, code.bytes, 1, sizeof(shader::SpectralMaskPush),
                            "spectral_mask");
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = ctx.queue_family();
    FDM_VK_CHECK(vkCreateCommandPool(ctx.device(), &pool, nullptr, &pool_));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkResult r = vkCreateFence(ctx.device(), &fence, nullptr, &fence_);
    if (r != VK_SUCCESS) {
        vkDestroyCommandPool(ctx.device(), pool_, nullptr);
        FDM_VK_CHECK(r);
    }
}

SpectralFilter::~SpectralFilter() {
    plans_.clear();
    if (fence_) vkDestroyFence(ctx_.device(), fence_, nullptr);
    if (pool_) vkDestroyCommandPool(ctx_.device(), pool_, nullptr);
}

FftPlan& SpectralFilter::plan_for(const std::array<std::uint32_t, 3>& dims, const Buffer& field) {
    auto it = plans_.find(dims);
    if (it != plans_.end()) return *it->second;
    // Each plan holds a few MiB: keep the most recent few (the disk cache makes a re-plan cheap).
    // (8: Engine::prepare's seven canonical sizes and one more stay in memory.)
    constexpr std::size_t kMaxPlans = 8;
    if (plans_.size() >= kMaxPlans) {
        plans_.erase(plan_order_.front());
        plan_order_.erase(plan_order_.begin());
    }
    plan_order_.push_back(dims);
    auto plan = std::make_unique<FftPlan>();
    plan->physical = ctx_.physical_device();
    plan->device = ctx_.device();
    plan->queue = ctx_.queue();
    plan->pool = pool_;
    plan->fence = fence_;
    plan->slots[0] = field.handle();
    plan->buffer_size = r2c_field_bytes(dims);
    VkFFTConfiguration& c = plan->config;
    c.FFTdim = 3;
    c.size[0] = dims[0];
    c.size[1] = dims[1];
    c.size[2] = dims[2];
    c.physicalDevice = &plan->physical;
    c.device = &plan->device;
    c.queue = &plan->queue;
    c.commandPool = &plan->pool;
    c.fence = &plan->fence;
    c.isCompilerInitialized = 1;  // glslang_acquire() did it, process-wide
    c.performR2C = 1;
    c.normalize = 0;  // the mask pass scales by 1/N
    c.buffer = &plan->slots[0];
    c.bufferSize = &plan->buffer_size;
    // VkFFT compiles GLSL at plan creation (0.2-0.6 s per size on lavapipe): reuse the SPIR-V
    // of an earlier run when the cache has it for this size, device, driver and versions.
    const DeviceInfo& dev = ctx_.info();
    const std::string key = "vkfft " + std::to_string(VkFFTGetVersion()) + " fdmsurf " +
                            FDMSURF_VERSION + " r2c " + std::to_string(dims[0]) + "x" +
                            std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " device " +
                            dev.name + " driver " + dev.driver + " api " + dev.api_version;
    std::optional<std::vector<std::uint32_t>> cached = cache_.load(key);
    trace(cached ? "filter: FFT plan read from the plan cache" : "filter: FFT plan not in the plan cache");
    VkFFTResult r = VKFFT_ERROR_FAILED_TO_INITIALIZE;
    const CLocaleForVkFFT c_locale;
    if (cached) {
        plan->config.loadApplicationFromString = 1;
        plan->config.loadApplicationString = cached->data();
        r = initializeVkFFT(&plan->app, plan->config);
        plan->config.loadApplicationFromString = 0;
        plan->config.loadApplicationString = nullptr;
        if (r == VKFFT_SUCCESS) {
            plan->from_cache = true;
        } else {
            // A stale or damaged entry that passed the checksum: plan from scratch and rewrite.
            deleteVkFFT(&plan->app);
            plan->app = VkFFTApplication{};
        }
    }
    if (r != VKFFT_SUCCESS) {
        plan->config.saveApplicationToString = cache_.directory().empty() ? 0 : 1;
        check_fft(initializeVkFFT(&plan->app, plan->config), "plan creation");
        if (plan->config.saveApplicationToString && plan->app.saveApplicationString)
            plan->stored = cache_.store(key, plan->app.saveApplicationString,
                                        plan->app.applicationStringSize);
    }
    plan->initialised = true;
    if (trace_on()) {
        char what[200];
        std::snprintf(what, sizeof what,
                      "filter: VkFFT initialised (%s; kernel passes per axis %u %u %u; temp buffer %s)",
                      plan->from_cache ? "from the cache" : "compiled",
                      unsigned(plan->app.localFFTPlan ? plan->app.localFFTPlan->numAxisUploads[0] : 0),
                      unsigned(plan->app.localFFTPlan ? plan->app.localFFTPlan->numAxisUploads[1] : 0),
                      unsigned(plan->app.localFFTPlan ? plan->app.localFFTPlan->numAxisUploads[2] : 0),
                      plan->app.configuration.allocateTempBuffer ? "allocated" : "none");
        trace(what);
    }
    FftPlan& ref = *plan;
    plans_.emplace(dims, std::move(plan));
    return ref;
}

SpectralFilter::PlanStatus SpectralFilter::prepare(const std::array<std::uint32_t, 3>& dims) {
    if (auto it = plans_.find(dims); it != plans_.end())
        return {it->second->from_cache, it->second->stored};
    // VkFFT builds its descriptors on the buffer it is planned with; every launch rebinds the
    // field (FftPlan::bind), so this one may go when the plan is built.
    const Buffer field(ctx_, r2c_field_bytes(dims), MemoryUse::Device, "prepare_field");
    const FftPlan& plan = plan_for(dims, field);
    return {plan.from_cache, plan.stored};
}

void SpectralFilter::record(Commands& cmds, const Buffer& field, const GridPlan& plan,
                            FilterShape shape) {
    const auto& d = plan.info.dims;
    FftPlan& fft = plan_for({d[0], d[1], d[2]}, field);
    trace("filter: FFT plan ready");
    VkCommandBuffer cmd = cmds.handle();
    VkFFTLaunchParams launch{};
    launch.commandBuffer = &cmd;
    launch.buffer = fft.bind(field.handle());
    launch.inputBuffer = launch.buffer;
    launch.outputBuffer = launch.buffer;
    check_fft(VkFFTAppend(&fft.app, -1, &launch), "forward transform");
    cmds.mark("fft-forward");
    cmds.barrier_compute();

    shader::SpectralMaskPush push{};
    push.nx = d[0];
    push.ny = d[1];
    push.nz = d[2];
    push.cx = d[0] / 2 + 1;
    push.fx = 1.0f / (d[0] * plan.info.spacing);
    push.fy = 1.0f / (d[1] * plan.info.spacing);
    push.fz = 1.0f / (d[2] * plan.info.spacing);
    push.cutoff = plan.info.cutoff;
    push.scale = static_cast<float>(1.0 / (double(d[0]) * d[1] * d[2]));
    push.shape = shape == FilterShape::Gaussian ? shader::kFilterGaussian : shader::kFilterIdeal;
    cmds.dispatch(mask_, {whole(field)}, &push,
                  (push.cx + shader::kMaskGroupX - 1) / shader::kMaskGroupX,
                  (d[1] + shader::kMaskGroupY - 1) / shader::kMaskGroupY, d[2]);
    cmds.mark("mask");
    cmds.barrier_compute();

    check_fft(VkFFTAppend(&fft.app, 1, &launch), "inverse transform");
    cmds.mark("fft-inverse");
    cmds.barrier_compute();
}

}  // namespace fdmsurf::detail
