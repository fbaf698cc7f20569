// Device::memoryModel(): the device's memory requirements for exactly the images and buffers a
// renderer creates, asked without creating them; cached, safe from any thread, refusing what
// the device cannot create, and refusing to answer once its device is gone. And
// Device::allocatedBytes(), what renderers hold.
#include "executor_test_util.hpp"

#include "device_memory_model.hpp"
#include "resource_creation.hpp"

#include <thread>
#include <vector>

namespace skygraph::test {
namespace {

ResourceDesc image(ResourceType type, const char* format, uint32_t layers = 1) {
    ResourceDesc d;
    d.name = "probe";
    d.type = type;
    d.format = *findFormat(format);
    d.layers = layers;
    return d;
}

ResourceDesc buffer(uint64_t bytes) {
    ResourceDesc d;
    d.name = "probe";
    d.type = ResourceType::Buffer;
    d.sizeBytes = bytes;
    return d;
}

MemoryQuery query(const ResourceDesc& d, uint32_t w, uint32_t h, uint32_t mips, VkImageUsageFlags usage) {
    MemoryQuery q;
    q.resource = &d;
    q.width = w;
    q.height = h;
    q.mips = mips;
    q.layers = std::max(1u, d.layers);
    q.imageUsage = kAlwaysUsable.image | usage;
    return q;
}

enum class Sharing { Exclusive, Concurrent };

/// What the device says for an image really created the way the renderer creates it: exclusive,
/// or concurrent over the device's queue families as the renderer creates what the plan
/// shares (the same as exclusive on a device of one family, where nothing is shared).
VkMemoryRequirements created(const MemoryQuery& q, Sharing sharing) {
    const VkDevice device = sharedDevice().device();
    const detail::ConcurrentFamilies families = detail::distinctFamilies(sharedDevice().queueFamilies());
    VkMemoryRequirements req{};
    if (q.resource->isImage()) {
        VkImageCreateInfo ci = detail::imageCreateInfo(*q.resource, q.width, q.height, q.mips, q.layers, q.imageUsage);
        if (sharing == Sharing::Concurrent) detail::shareConcurrently(ci, families);
        VkImage image;
        EXPECT_EQ(vkCreateImage(device, &ci, nullptr, &image), VK_SUCCESS);
        vkGetImageMemoryRequirements(device, image, &req);
        vkDestroyImage(device, image, nullptr);
    } else {
        VkBufferCreateInfo ci = detail::bufferCreateInfo(*q.resource, q.bufferUsage);
        if (sharing == Sharing::Concurrent) detail::shareConcurrently(ci, families);
        VkBuffer b;
        EXPECT_EQ(vkCreateBuffer(device, &ci, nullptr, &b), VK_SUCCESS);
        vkGetBufferMemoryRequirements(device, b, &req);
        vkDestroyBuffer(device, b, nullptr);
    }
    return req;
}

using MemoryModelTest = ExecutorTest;

TEST_F(MemoryModelTest, AnswersWhatTheCreatedResourceNeeds) {
    const auto model = sharedDevice().memoryModel();
    ASSERT_TRUE(model);
    EXPECT_EQ(model, sharedDevice().memoryModel()) << "one model per device";
    EXPECT_EQ(model->name(), sharedDevice().name());
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(sharedDevice().physicalDevice(), &props);
    EXPECT_EQ(model->bufferImageGranularity(), props.limits.bufferImageGranularity);
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(sharedDevice().physicalDevice(), &mem);

    const ResourceDesc color = image(ResourceType::Image2D, "R16G16B16A16_SFLOAT");
    const ResourceDesc cube = image(ResourceType::Cube, "R8G8B8A8_UNORM", 6);
    const ResourceDesc depth = image(ResourceType::Image2D, "D24_UNORM_S8_UINT");
    const ResourceDesc array = image(ResourceType::Image2DArray, "R32_UINT", 3);
    const ResourceDesc storage = buffer(1000);
    MemoryQuery bufferQuery;
    bufferQuery.resource = &storage;
    bufferQuery.bufferUsage = kAlwaysUsable.buffer | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    for (const MemoryQuery& q :
         {query(color, 37, 19, 6, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT),
          query(cube, 32, 32, 6, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT),
          query(depth, 64, 48, 1, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT),
          query(array, 16, 8, 2, VK_IMAGE_USAGE_STORAGE_BIT), bufferQuery}) {
        // Memory is placed before the plan says which transients are shared concurrently: the
        // answer serves the resource created either way, and asks no more than the larger.
        const MemoryRequirements answer = model->requirements(q);
        const VkMemoryRequirements exclusive = created(q, Sharing::Exclusive);
        const VkMemoryRequirements concurrent = created(q, Sharing::Concurrent);
        EXPECT_EQ(answer.size, std::max(exclusive.size, concurrent.size)) << q.resource->format.name;
        EXPECT_EQ(answer.alignment, std::max(exclusive.alignment, concurrent.alignment)) << q.resource->format.name;
        EXPECT_NE(answer.memoryTypeBits, 0u);
        EXPECT_EQ(answer.memoryTypeBits & ~(exclusive.memoryTypeBits & concurrent.memoryTypeBits), 0u);
        for (uint32_t t = 0; t < mem.memoryTypeCount; ++t)
            if (answer.memoryTypeBits & (1u << t)) {
                EXPECT_TRUE(mem.memoryTypes[t].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) << "type " << t;
            }
    }
}

// Where a driver answers differently for a resource shared concurrently (the spec allows it:
// some GPUs keep no compression for concurrent images), the placement must hold it either way.
TEST(MemoryModelSharing, ServesBothSharingModes) {
    const MemoryRequirements exclusive{196608, 65536, 0b0111};
    const MemoryRequirements concurrent{131072, 4096, 0b0110};
    const MemoryRequirements both = detail::servingBothSharingModes(exclusive, concurrent, "hdr", "gpu");
    EXPECT_EQ(both.size, 196608u);
    EXPECT_EQ(both.alignment, 65536u);
    EXPECT_EQ(both.memoryTypeBits, 0b0110u);
    const MemoryRequirements larger = detail::servingBothSharingModes({4096, 256, 1}, {8192, 1024, 1}, "hdr", "gpu");
    EXPECT_EQ(larger.size, 8192u);
    EXPECT_EQ(larger.alignment, 1024u);
    try {
        (void)detail::servingBothSharingModes({4096, 256, 0b01}, {4096, 256, 0b10}, "hdr", "gpu");
        FAIL() << "requirements with no memory type in common were combined";
    } catch (const ExecutorError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "resource 'hdr': device 'gpu' has no DEVICE_LOCAL memory type for it both exclusive and shared "
                  "concurrently; nothing was allocated");
    }
}

TEST_F(MemoryModelTest, AnswersTheSameFromManyThreads) {
    const auto model = sharedDevice().memoryModel();
    const ResourceDesc color = image(ResourceType::Image2D, "R8G8B8A8_UNORM");
    std::vector<MemoryRequirements> first;
    for (uint32_t w = 1; w <= 64; ++w) first.push_back(model->requirements(query(color, w, 17, 1, 0)));
    std::vector<std::thread> threads;
    std::vector<int> mismatches(8, 0);
    for (size_t t = 0; t < mismatches.size(); ++t)
        threads.emplace_back([&, t] {
            for (uint32_t round = 0; round < 20; ++round)
                for (uint32_t w = 1; w <= 64; ++w) {
                    // Half the threads ask new questions while the others hit the cache.
                    const uint32_t h = t % 2 ? 17 : 17 + round + 1;
                    const MemoryRequirements r = model->requirements(query(color, w, h, 1, 0));
                    if (h == 17 && !(r == first[w - 1])) ++mismatches[t];
                }
        });
    for (std::thread& t : threads) t.join();
    for (size_t t = 0; t < mismatches.size(); ++t) EXPECT_EQ(mismatches[t], 0) << "thread " << t;
}

TEST_F(MemoryModelTest, RefusesWhatTheDeviceCannotCreateBeforeAskingIt) {
    const auto model = sharedDevice().memoryModel();
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(sharedDevice().physicalDevice(), &props);
    const ResourceDesc color = image(ResourceType::Image2D, "R8G8B8A8_UNORM");
    try {
        (void)model->requirements(query(color, props.limits.maxImageDimension2D + 1, 1, 1, 0));
        FAIL() << "an image past maxImageDimension2D was answered";
    } catch (const DeviceCapacityError& e) {
        EXPECT_NE(std::string(e.what()).find("maxImageDimension2D"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'probe'"), std::string::npos) << e.what();
    }
    const ResourceDesc depth = image(ResourceType::Image2D, "D32_SFLOAT");
    EXPECT_THROW((void)model->requirements(query(depth, 8, 8, 1, VK_IMAGE_USAGE_STORAGE_BIT)), ExecutorError);
}

// The model may outlive its device (compile options share it), but must not call into a
// destroyed VkDevice: it refuses instead, saying why.
TEST(MemoryModelLifetime, AfterTheDeviceIsDestroyedItThrows) {
    DeviceOptions o;
    const char* name = std::getenv("SKYGRAPH_TEST_DEVICE");
    o.device = name ? name : "llvmpipe";
    o.logMessages = false;
    o.validation = true;
    auto device = Device::create(o);
    const std::shared_ptr<const MemoryModel> model = device->memoryModel();
    const ResourceDesc color = image(ResourceType::Image2D, "R8G8B8A8_UNORM");
    const MemoryRequirements before = model->requirements(query(color, 16, 16, 1, 0));
    EXPECT_GT(before.size, 0u);
    EXPECT_EQ(device->messageCount(), 0u) << "the validation layer reported the model's questions";
    const std::string deviceName = device->name();
    device.reset();
    EXPECT_EQ(model->name(), deviceName) << "still named, for messages";
    for (const uint32_t size : {16u, 32u}) {  // cached and new questions alike
        try {
            (void)model->requirements(query(color, size, size, 1, 0));
            FAIL() << "answered after the device was destroyed";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("after the device was destroyed"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW((void)model->bufferImageGranularity(), ExecutorError);
}

// Device::allocatedBytes() counts what renderers hold: up while a renderer lives, and for a
// shared image until its last holder lets go, back to where it was after.
TEST_F(MemoryModelTest, AllocatedBytesFollowWhatRenderersHold) {
    Device& device = sharedDevice();
    const uint64_t before = device.allocatedBytes();
    const std::string graph = graphWithSwapchain(
        "held", R"("big": { "type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [256, 256],
                            "external": true, "final": "ShaderRead" })",
        R"({ "name": "fill", "type": "Generic", "uses": { "big": "Write@Compute", "swapchain": "Write@ColorAttachment" } })");
    SharedImage kept;
    {
        Renderer renderer(device, compileText(graph), genericOptions(1));
        renderer.renderFrame();
        renderer.waitIdle();
        EXPECT_GE(device.allocatedBytes(), before + 256 * 256 * 16) << "the 1 MiB image at least";
        kept = renderer.shareImage("big");
    }
    const uint64_t keptBytes = device.allocatedBytes() - before;
    EXPECT_GE(keptBytes, 256u * 256 * 16) << "the shared image outlives its renderer";
    EXPECT_LT(keptBytes, 2u * 256 * 256 * 16) << "and nothing else of it does";
    kept = SharedImage();
    EXPECT_EQ(device.allocatedBytes(), before);
}

}  // namespace
}  // namespace skygraph::test
