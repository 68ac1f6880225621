// Tests of device discovery and selection (src/vulkan/context.cpp): list_devices, --device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/surface.hpp"
#include "support/gpu_fixture.hpp"
#include "engine/engine_impl.hpp"
#include "vulkan/shaders.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"

namespace {

using fdmsurf::DeviceInfo;
using fdmsurf::Engine;
using fdmsurf::EngineOptions;
using fdmsurf::Error;
using fdmsurf::ErrorCode;

// list_devices(), or the reason there is none (then `devices` is empty).
struct Listing {
    std::vector<DeviceInfo> devices;
    std::string reason;
};

Listing list() {
    Listing out;
    try {
        out.devices = fdmsurf::list_devices();
    } catch (const Error& e) {
        if (e.code() != ErrorCode::NoDevice) throw;
        out.reason = std::string("list_devices threw NoDevice: ") + e.what();
        return out;
    }
    if (out.devices.empty()) out.reason = "list_devices found no Vulkan device";
    return out;
}

bool any_usable(const std::vector<DeviceInfo>& devices) {
    return std::any_of(devices.begin(), devices.end(),
                       [](const DeviceInfo& d) { return d.usable; });
}

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

// Skips (or, with FDMSURF_REQUIRE_DEVICE=1, fails) the calling test when there is no device.
#define REQUIRE_DEVICES(listing)                                             \
    do {                                                                     \
        if ((listing).devices.empty()) {                                     \
            if (fdmsurf_test::device_required()) FAIL() << (listing).reason; \
            GTEST_SKIP() << (listing).reason;                                \
        }                                                                    \
    } while (0)

TEST(Context, ListDevicesFindsAUsableDevice) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    std::string reasons;
    for (std::size_t i = 0; i < l.devices.size(); ++i) {
        const DeviceInfo& d = l.devices[i];
        SCOPED_TRACE(d.name);
        EXPECT_EQ(d.index, i);
        EXPECT_FALSE(d.name.empty());
        EXPECT_FALSE(d.type.empty());
        EXPECT_FALSE(d.api_version.empty());
        if (d.usable) {
            EXPECT_GT(d.max_storage_buffer_range, 0u);
        } else {
            EXPECT_FALSE(d.reason.empty()) << "an unusable device must say why";
            reasons += "\n  " + d.name + ": " + d.reason;
        }
    }
    if (!any_usable(l.devices)) {
        if (fdmsurf_test::device_required()) FAIL() << "no usable device:" << reasons;
        GTEST_SKIP() << "no usable device:" << reasons;
    }
}

TEST(Context, DeviceNameMatchingNothingThrowsNoDevice) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    const std::string want = "no-such-gpu-7f3a";
    try {
        Engine engine(EngineOptions{.device = want});
        FAIL() << "Engine accepted device \"" << want << "\" and chose " << engine.device().name;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::NoDevice) << e.what();
        EXPECT_NE(std::string(e.what()).find(want), std::string::npos)
            << "the message should name the device asked for: " << e.what();
    }
}

TEST(Context, OutOfRangeDeviceIndexThrowsNoDevice) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    for (const std::string& index : {std::to_string(l.devices.size()), std::string("4096")}) {
        SCOPED_TRACE("device " + index);
        try {
            Engine engine(EngineOptions{.device = index});
            ADD_FAILURE() << "Engine accepted device index " << index << " of " << l.devices.size();
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::NoDevice) << e.what();
            EXPECT_NE(std::string(e.what()).find(index), std::string::npos) << e.what();
        }
    }
}

TEST(Context, DeviceByIndexAndByCaseInsensitiveName) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    auto it = std::find_if(l.devices.begin(), l.devices.end(),
                           [](const DeviceInfo& d) { return d.usable; });
    if (it == l.devices.end()) {
        if (fdmsurf_test::device_required()) FAIL() << "no usable device";
        GTEST_SKIP() << "no usable device";
    }
    {
        Engine engine(EngineOptions{.device = std::to_string(it->index)});
        EXPECT_EQ(engine.device().name, it->name);
        EXPECT_EQ(engine.device().index, it->index);
        EXPECT_TRUE(engine.device().usable);
    }
    {
        Engine engine(EngineOptions{.device = upper(it->name)});
        // Another device may contain the same name; only the chosen one's name must match.
        EXPECT_NE(upper(engine.device().name).find(upper(it->name)), std::string::npos)
            << engine.device().name;
    }
}

TEST(Context, MaxBufferRangeOverrideLowersTheLimitOnly) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    if (!any_usable(l.devices)) GTEST_SKIP() << "no usable device";
    Engine engine(EngineOptions{.max_buffer_range = 8u << 20});
    EXPECT_LE(engine.impl().context.limits().max_storage_buffer_range, 8u << 20);
    Engine huge(EngineOptions{.max_buffer_range = ~std::uint64_t(0)});
    EXPECT_EQ(huge.impl().context.limits().max_storage_buffer_range,
              huge.device().max_storage_buffer_range)
        << "an override above the device's limit must not raise it";
}

// The memory a new allocation can still get: never more than the heap, never nothing on an
// idle device; with VK_EXT_memory_budget (NVIDIA, AMD; lavapipe 22.3 lacks it) it falls when
// this process holds memory.
TEST(Context, AvailableDeviceMemoryIsWithinTheHeap) {
    Listing l = list();
    REQUIRE_DEVICES(l);
    if (!any_usable(l.devices)) GTEST_SKIP() << "no usable device";
    Engine engine;
    const auto& context = engine.impl().context;
    const std::uint64_t heap = context.limits().device_memory;
    const std::uint64_t before = context.available_device_memory();
    EXPECT_GT(before, 0u);
    EXPECT_LE(before, heap);
    if (!context.has_memory_budget()) {
        EXPECT_EQ(before, heap);
        return;
    }
    const VkDeviceSize bytes = 256u << 20;
    fdmsurf::detail::Buffer held(context, bytes, fdmsurf::detail::MemoryUse::Device, "held");
    EXPECT_LE(context.available_device_memory() + bytes / 2, before)
        << "256 MiB held should show in the budget";
}

}  // namespace

namespace {

// Pipelines are made at their first use (src/vulkan/pipeline.hpp): a run whose stages all go to
// the host compiles none; handle() makes one, moves keep it, and a push-constant size beyond the
// device's is refused at once, as before.
class LazyPipelines : public GpuTest {};

TEST_F(LazyPipelines, AreMadeAtFirstUseOnly) {
    using fdmsurf::detail::ComputePipeline;
    using fdmsurf::detail::Shader;
    auto& ctx = impl().context;
    const auto code = fdmsurf::detail::shader_code(Shader::McScan);
    ComputePipeline p(ctx, code.words, code.bytes, 2, 8, "lazy_scan");
    EXPECT_FALSE(p.made());
    EXPECT_NE(p.handle(), VK_NULL_HANDLE);
    EXPECT_TRUE(p.made());
    EXPECT_NE(p.layout(), VK_NULL_HANDLE);
    ComputePipeline moved = std::move(p);
    EXPECT_TRUE(moved.made());
    EXPECT_FALSE(p.made());
    ComputePipeline late(ctx, code.words, code.bytes, 2, 8, "lazy_scan_2");
    late.make();
    EXPECT_TRUE(late.made());
    // Moved before it is made, it is still made at first use.
    ComputePipeline unmade(ctx, code.words, code.bytes, 2, 8, "lazy_scan_3");
    ComputePipeline taken = std::move(unmade);
    EXPECT_FALSE(taken.made());
    EXPECT_NE(taken.handle(), VK_NULL_HANDLE);
    EXPECT_FALSE(unmade.made());
    EXPECT_THROW(ComputePipeline(ctx, code.words, code.bytes, 2,
                                 ctx.limits().max_push_constants + 4, "too_many_constants"),
                 Error);
    EXPECT_TRUE(engine().take_validation_messages().empty());
}

}  // namespace
