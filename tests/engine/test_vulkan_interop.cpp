// fdmsurf on an application's own VkDevice, the mesh left in device buffers (renderer interop).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"
#include "support/gpu_fixture.hpp"

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL record(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    static_cast<std::vector<std::string>*>(user)->push_back(data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

// A minimal "renderer": its own instance (validation on), device and queue.
struct Renderer {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    std::vector<std::string> messages;
    std::string why_not;

    Renderer() {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_1;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &ext;
        if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) {
            why_not = "no Vulkan instance with the validation layer";
            return;
        }
        VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        m.pfnUserCallback = record;
        m.pUserData = &messages;
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
        if (create) create(instance, &m, nullptr, &messenger);
        std::uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        if (count == 0) {
            why_not = "no Vulkan device";
            return;
        }
        std::vector<VkPhysicalDevice> devices(count);
        vkEnumeratePhysicalDevices(instance, &count, devices.data());
        physical = devices[0];
        std::uint32_t nf = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &nf, nullptr);
        std::vector<VkQueueFamilyProperties> fams(nf);
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &nf, fams.data());
        for (family = 0; family < nf; ++family)
            if (fams[family].queueFlags & VK_QUEUE_GRAPHICS_BIT &&
                fams[family].queueFlags & VK_QUEUE_COMPUTE_BIT)
                break;
        float priority = 1.0f;
        VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        q.queueFamilyIndex = family;
        q.queueCount = 1;
        q.pQueuePriorities = &priority;
        VkDeviceCreateInfo d{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        d.queueCreateInfoCount = 1;
        d.pQueueCreateInfos = &q;
        if (family == nf || vkCreateDevice(physical, &d, nullptr, &device) != VK_SUCCESS) {
            why_not = "no graphics and compute queue";
            return;
        }
        vkGetDeviceQueue(device, family, 0, &queue);
    }
    ~Renderer() {
        if (device) vkDestroyDevice(device, nullptr);
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            instance ? vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT") : nullptr);
        if (destroy && messenger) destroy(instance, messenger, nullptr);
        if (instance) vkDestroyInstance(instance, nullptr);
    }

    // Copies `bytes` of `src` to the host, as a renderer's tooling would.
    std::vector<char> read(VkBuffer src, VkDeviceSize bytes) {
        std::vector<char> out(bytes);
        if (bytes == 0) return out;
        VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bi.size = bytes;
        bi.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        VkBuffer dst;
        EXPECT_EQ(vkCreateBuffer(device, &bi, nullptr, &dst), VK_SUCCESS);
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device, dst, &req);
        VkPhysicalDeviceMemoryProperties mp;
        vkGetPhysicalDeviceMemoryProperties(physical, &mp);
        std::uint32_t type = 0;
        for (; type < mp.memoryTypeCount; ++type)
            if ((req.memoryTypeBits & (1u << type)) &&
                (mp.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) &&
                (mp.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT))
                break;
        VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        ai.allocationSize = req.size;
        ai.memoryTypeIndex = type;
        VkDeviceMemory mem;
        EXPECT_EQ(vkAllocateMemory(device, &ai, nullptr, &mem), VK_SUCCESS);
        vkBindBufferMemory(device, dst, mem, 0);
        VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pi.queueFamilyIndex = family;
        VkCommandPool pool;
        vkCreateCommandPool(device, &pi, nullptr, &pool);
        VkCommandBufferAllocateInfo ca{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ca.commandPool = pool;
        ca.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ca.commandBufferCount = 1;
        VkCommandBuffer cmd;
        vkAllocateCommandBuffers(device, &ca, &cmd);
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        vkBeginCommandBuffer(cmd, &begin);
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, src, dst, 1, &region);
        VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                             &b, 0, nullptr, 0, nullptr);
        vkEndCommandBuffer(cmd);
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        vkQueueSubmit(queue, 1, &si, VK_NULL_HANDLE);
        vkQueueWaitIdle(queue);
        void* p = nullptr;
        vkMapMemory(device, mem, 0, VK_WHOLE_SIZE, 0, &p);
        std::memcpy(out.data(), p, bytes);
        vkUnmapMemory(device, mem);
        vkDestroyCommandPool(device, pool, nullptr);
        vkDestroyBuffer(device, dst, nullptr);
        vkFreeMemory(device, mem, nullptr);
        return out;
    }
};

}  // namespace

TEST(VulkanInterop, SurfaceOnTheApplicationsDeviceStaysInDeviceBuffers) {
    Renderer r;
    if (!r.why_not.empty()) {
        if (fdmsurf_test::device_required()) FAIL() << r.why_not;
        GTEST_SKIP() << r.why_not;
    }
    const fdmsurf::Structure s = fdmsurf::read_structure(FDMSURF_TEST_DATA_DIR "/1crn.pdb");
    fdmsurf::ExternalDevice ext{r.instance, r.physical, r.device, r.queue, r.family};
    fdmsurf::SurfaceOptions options;
    options.min_cavity_volume = 0.0f;  // the device path keeps every piece; compare like with like
    {
        // The device's filter and marching cubes for the host mesh too (a CPU device would run
        // them on the host, the same surface to float rounding): compared bit for bit.
        fdmsurf::Engine engine(fdmsurf::EngineOptions{.external = &ext,
                                                      .gaussian_filter = fdmsurf::StagePlace::Device,
                                                      .marching_cubes = fdmsurf::StagePlace::Device});
        const fdmsurf::SurfaceResult host = engine.make_surface(s.atoms, options);
        const fdmsurf::DeviceSurfaceResult dev = engine.make_device_surface(s.atoms, options);
        ASSERT_NE(dev.mesh.vertex_buffer(), VK_NULL_HANDLE);
        ASSERT_EQ(dev.mesh.vertex_count(), host.mesh.vertex_count());
        ASSERT_EQ(dev.mesh.triangle_count(), host.mesh.triangle_count());
        const std::vector<char> v = r.read(dev.mesh.vertex_buffer(), dev.mesh.vertex_count() * 24ull);
        const std::vector<char> i = r.read(dev.mesh.index_buffer(), dev.mesh.triangle_count() * 12ull);
        ASSERT_EQ(std::memcmp(i.data(), host.mesh.indices.data(), i.size()), 0);
        const float* f = reinterpret_cast<const float*>(v.data());
        for (std::size_t k = 0; k < host.mesh.vertex_count(); ++k)
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(f[6 * k + c], host.mesh.positions[3 * k + c]);
                ASSERT_EQ(f[6 * k + 3 + c], host.mesh.normals[3 * k + c]);
            }
        // Colours by chain are found on the device: each vertex's atom and colour, as the
        // host mesh has them.
        fdmsurf::SurfaceOptions colored = options;
        colored.properties.color = fdmsurf::ColorScheme::Chain;
        const fdmsurf::DeviceSurfaceResult cdev = engine.make_device_surface(s.atoms, colored);
        const fdmsurf::SurfaceResult chost = engine.make_surface(s.atoms, colored);
        ASSERT_NE(cdev.mesh.attribute_buffer(), VK_NULL_HANDLE);
        ASSERT_EQ(cdev.mesh.vertex_count(), chost.mesh.vertex_count());
        const std::vector<char> a = r.read(cdev.mesh.attribute_buffer(), cdev.mesh.vertex_count() * 8ull);
        const auto* words = reinterpret_cast<const std::uint32_t*>(a.data());
        for (std::size_t k = 0; k < chost.mesh.vertex_count(); ++k) {
            ASSERT_EQ(words[2 * k], chost.mesh.atoms[k]) << "vertex " << k;
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ((words[2 * k + 1] >> (8 * c)) & 0xff, chost.mesh.colors[3 * k + c]);
            ASSERT_EQ(words[2 * k + 1] >> 24, 0xffu);
        }
        // Properties and the coulombic colours need the host mesh: refused, not left out.
        colored.properties.color = fdmsurf::ColorScheme::Coulombic;
        EXPECT_THROW(engine.make_device_surface(s.atoms, colored), fdmsurf::Error);
        colored.properties.color = fdmsurf::ColorScheme::None;
        colored.properties.scalars = {fdmsurf::VertexProperty::MeanCurvature};
        EXPECT_THROW(engine.make_device_surface(s.atoms, colored), fdmsurf::Error);
        // fdmsurf's renderer draws on the application's device and queue too.
        fdmsurf::Renderer renderer(engine);
        fdmsurf::RenderOptions ro;
        ro.width = 96;
        ro.height = 64;
        ro.background = {0, 0, 0, 0};
        const fdmsurf::RenderResult pic = renderer.render(cdev.mesh, ro);
        std::size_t drawn = 0;
        for (std::size_t p = 3; p < pic.image.rgba.size(); p += 4) drawn += pic.image.rgba[p] == 255;
        EXPECT_GT(drawn, 96u * 64u / 8u);
    }  // renderer, engine and device meshes released before the application's device
    for (const std::string& m : r.messages) ADD_FAILURE() << "validation: " << m;
}

TEST(VulkanInterop, NullHandlesAreRefused) {
    fdmsurf::ExternalDevice ext;
    try {
        fdmsurf::Engine engine(fdmsurf::EngineOptions{.external = &ext});
        FAIL() << "expected Error(InvalidArgument)";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
    }
}
