// The pipeline (Giard & Macq 2010): density, spectral filter, marching cubes, on one device.
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "core/engine_impl.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "filter/spectral_filter.hpp"
#include "grid/atom_bins.hpp"
#include "grid/density_gpu.hpp"
#include "grid/grid_plan.hpp"
#include "isosurface/marching_cubes_gpu.hpp"
#include "vulkan/check.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf {
namespace detail {

namespace {

// The largest spacing change that brings `bytes` under `limit` (sizes scale as 1/h³).
std::string spacing_hint(double bytes, double limit, float spacing) {
    double h = spacing * std::cbrt(bytes / limit) * 1.05;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f", std::ceil(h * 100.0) / 100.0);
    return buf;
}

}  // namespace

SurfaceResult EngineImpl::run(const Atoms& atoms, const SurfaceOptions& options) {
    SurfaceResult result;
    double t0 = now_ms();
    GridPlan plan = plan_grid(atoms, options);
    result.grid = plan.info;
    const auto& d = plan.info.dims;
    if (plan.filtered && options.spacing > 1.0f / (2.0f * plan.info.cutoff)) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "spacing %.3g Å is too coarse for the filter cut-off %.3g 1/Å: the filter "
                      "cannot act unless spacing <= 1/(2 cut-off) = %.3g Å",
                      options.spacing, plan.info.cutoff, 1.0 / (2.0 * plan.info.cutoff));
        result.warnings.emplace_back(buf);
    }
    const double field_bytes = double(plan.field_floats()) * sizeof(float);
    const double limit = double(context.limits().max_storage_buffer_range);
    if (field_bytes > limit)
        throw Error(ErrorCode::DeviceLimit,
                    "the grid of " + std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " +
                        std::to_string(d[2]) + " points needs " +
                        std::to_string(static_cast<long long>(field_bytes) >> 20) +
                        " MiB in one storage buffer, more than this device's maxStorageBufferRange (" +
                        std::to_string(static_cast<long long>(limit) >> 20) +
                        " MiB); a spacing of " + spacing_hint(field_bytes, limit, options.spacing) +
                        " Å would fit");
    AtomBins bins = bin_atoms(atoms, plan);
    result.times.push_back({"bin-atoms", now_ms() - t0, false});

    StagingArena arena;
    Buffer field(context, static_cast<VkDeviceSize>(field_bytes), MemoryUse::Device, "field");
    commands.begin();
    density.record(commands, arena, bins, plan, field);
    if (plan.filtered) filter.record(commands, field, plan, options.filter);
    McParams mc;
    for (int a = 0; a < 3; ++a) mc.origin[a] = plan.info.origin[a];
    mc.spacing = plan.info.spacing;
    mc.iso = plan.iso;
    mc.z_begin = 0;
    mc.z_end = d[2] - 1;
    GpuMesh gpu = marching_cubes.run(commands, arena, field, d[0], d[1], d[2], plan.pitch, mc);
    for (const StageTime& t : marching_cubes.stage_times()) result.times.push_back(t);
    result.mesh = marching_cubes.read_back(commands, gpu);
    for (const StageTime& t : commands.stage_times()) result.times.push_back(t);
    return result;
}


std::vector<float> EngineImpl::compute_field(const Atoms& atoms, const GridPlan& plan, bool filtered,
                                             FilterShape shape) {
    AtomBins bins = bin_atoms(atoms, plan);
    StagingArena arena;
    const std::size_t bytes = plan.field_floats() * sizeof(float);
    Buffer field(context, bytes, MemoryUse::Device, "field");
    commands.begin();
    density.record(commands, arena, bins, plan, field);
    if (filtered) filter.record(commands, field, plan, shape);
    const Buffer& host = readback_buffer(context, commands, arena, field, bytes, "field_readback");
    commands.barrier_to_host();
    commands.submit_and_wait();
    host.invalidate();
    std::vector<float> out(plan.field_floats());
    std::memcpy(out.data(), host.mapped(), bytes);
    return out;
}

void EngineImpl::filter_field(std::vector<float>& values, const GridPlan& plan, FilterShape shape) {
    StagingArena arena;
    const std::size_t bytes = values.size() * sizeof(float);
    commands.begin();
    Buffer field = upload_buffer(context, commands, arena, values.data(), bytes, "field");
    commands.barrier_compute();
    filter.record(commands, field, plan, shape);
    const Buffer& host = readback_buffer(context, commands, arena, field, bytes, "field_readback");
    commands.barrier_to_host();
    commands.submit_and_wait();
    host.invalidate();
    std::memcpy(values.data(), host.mapped(), bytes);
}

Mesh EngineImpl::run_marching_cubes(const FieldView& f, const McParams& params) {
    StagingArena arena;
    const std::size_t bytes = std::size_t(f.pitch) * f.ny * f.nz * sizeof(float);
    commands.begin();
    Buffer field = upload_buffer(context, commands, arena, f.data, bytes, "field");
    commands.barrier_compute();
    GpuMesh gpu = marching_cubes.run(commands, arena, field, f.nx, f.ny, f.nz, f.pitch, params);
    return marching_cubes.read_back(commands, gpu);
}

}  // namespace detail

Engine::Engine(const EngineOptions& options) : impl_(std::make_unique<detail::EngineImpl>(options)) {}
Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

SurfaceResult Engine::make_surface(const Atoms& atoms, const SurfaceOptions& options) {
    return impl_->run(atoms, options);
}

const DeviceInfo& Engine::device() const { return impl_->context.info(); }

std::vector<std::string> Engine::take_validation_messages() {
    return impl_->context.take_messages();
}

std::vector<DeviceInfo> list_devices() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r != VK_SUCCESS) throw Error(ErrorCode::NoDevice, detail::no_device_help(), r);
    std::vector<DeviceInfo> out;
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    if (count) vkEnumeratePhysicalDevices(instance, &count, devices.data());
    for (std::uint32_t i = 0; i < count; ++i) out.push_back(detail::describe_device(devices[i], i));
    vkDestroyInstance(instance, nullptr);
    return out;
}

}  // namespace fdmsurf
