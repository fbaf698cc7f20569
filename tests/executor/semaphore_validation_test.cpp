// What synchronization validation (layer 1.3.239, with QUEUE_SUBMIT checks) sees of semaphores
// between submits, pinned so that docs/queues.md's table stays true: the executor's validated
// path (a binary semaphore per wait, MEMORY_READ in barriers that continue a wait) rests on it.
// Submit A clears an image in GENERAL; submit B copies from it, on the device's one queue.
// Each case is the smallest that shows one behaviour; the reported ones are hazards only where
// the test says so (a layer limitation otherwise).
#include "executor_test_util.hpp"

#include "vk_util.hpp"

#include <optional>

namespace skygraph::test {
namespace {

/// One image, two command buffers and what it takes to submit them; destroyed with the test.
class TwoSubmits {
public:
    explicit TwoSubmits(Device& device) : device_(device), vkd_(device.device()) {
        VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ici.imageType = VK_IMAGE_TYPE_2D;
        ici.format = VK_FORMAT_R8G8B8A8_UNORM;
        ici.extent = {16, 16, 1};
        ici.mipLevels = ici.arrayLayers = 1;
        ici.samples = VK_SAMPLE_COUNT_1_BIT;
        ici.usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        vk::check(vkCreateImage(vkd_, &ici, nullptr, &image_), "vkCreateImage");
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(vkd_, image_, &req);
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = vk::findMemoryType(device.physicalDevice(), req.memoryTypeBits, 0);
        vk::check(vkAllocateMemory(vkd_, &mai, nullptr, &memory_), "vkAllocateMemory");
        vk::check(vkBindImageMemory(vkd_, image_, memory_, 0), "vkBindImageMemory");
        VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bci.size = 16 * 16 * 4;
        bci.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        vk::check(vkCreateBuffer(vkd_, &bci, nullptr, &buffer_), "vkCreateBuffer");
        VkMemoryRequirements breq;
        vkGetBufferMemoryRequirements(vkd_, buffer_, &breq);
        mai.allocationSize = breq.size;
        mai.memoryTypeIndex = vk::findMemoryType(device.physicalDevice(), breq.memoryTypeBits, 0);
        vk::check(vkAllocateMemory(vkd_, &mai, nullptr, &bufferMemory_), "vkAllocateMemory");
        vk::check(vkBindBufferMemory(vkd_, buffer_, bufferMemory_, 0), "vkBindBufferMemory");
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.queueFamilyIndex = device.queueFamily();
        vk::check(vkCreateCommandPool(vkd_, &pci, nullptr, &pool_), "vkCreateCommandPool");
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool_;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 3;
        vk::check(vkAllocateCommandBuffers(vkd_, &ai, cmds_), "vkAllocateCommandBuffers");
    }
    ~TwoSubmits() {
        vkQueueWaitIdle(device_.queue());
        for (VkSemaphore s : semaphores_) vkDestroySemaphore(vkd_, s, nullptr);
        vkDestroyCommandPool(vkd_, pool_, nullptr);
        vkDestroyBuffer(vkd_, buffer_, nullptr);
        vkFreeMemory(vkd_, bufferMemory_, nullptr);
        vkDestroyImage(vkd_, image_, nullptr);
        vkFreeMemory(vkd_, memory_, nullptr);
    }
    TwoSubmits(const TwoSubmits&) = delete;
    TwoSubmits& operator=(const TwoSubmits&) = delete;

    VkSemaphore semaphore(bool timeline) {
        VkSemaphoreTypeCreateInfo type{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
        type.semaphoreType = timeline ? VK_SEMAPHORE_TYPE_TIMELINE : VK_SEMAPHORE_TYPE_BINARY;
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &type};
        VkSemaphore s;
        vk::check(vkCreateSemaphore(vkd_, &sci, nullptr, &s), "vkCreateSemaphore");
        semaphores_.push_back(s);
        return s;
    }

    /// A: UNDEFINED -> GENERAL, then a clear.
    void recordClear() {
        begin(cmds_[0]);
        barrier(cmds_[0], VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        const VkClearColorValue c{};
        const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmds_[0], image_, VK_IMAGE_LAYOUT_GENERAL, &c, 1, &range);
        vk::check(vkEndCommandBuffer(cmds_[0]), "vkEndCommandBuffer");
    }
    /// B (and C): a copy out of the image, after a GENERAL -> TRANSFER_SRC transition whose
    /// source is `transitionSrc` / `transitionSrcAccess` when given.
    void recordCopy(size_t which, std::optional<std::pair<VkPipelineStageFlags2, VkAccessFlags2>> transition) {
        VkCommandBuffer cmd = cmds_[which];
        begin(cmd);
        VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL;
        if (transition) {
            barrier(cmd, transition->first, transition->second, VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
            layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        }
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {16, 16, 1};
        vkCmdCopyImageToBuffer(cmd, image_, layout, buffer_, 1, &region);
        vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    }

    /// A command buffer that records nothing.
    void recordNothing(size_t which) {
        begin(cmds_[which]);
        vk::check(vkEndCommandBuffer(cmds_[which]), "vkEndCommandBuffer");
    }

    void submit(size_t which, std::vector<VkSemaphoreSubmitInfo> waits, std::vector<VkSemaphoreSubmitInfo> signals) {
        VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cbi.commandBuffer = cmds_[which];
        VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        si.commandBufferInfoCount = 1;
        si.pCommandBufferInfos = &cbi;
        si.waitSemaphoreInfoCount = static_cast<uint32_t>(waits.size());
        si.pWaitSemaphoreInfos = waits.data();
        si.signalSemaphoreInfoCount = static_cast<uint32_t>(signals.size());
        si.pSignalSemaphoreInfos = signals.data();
        vk::check(vkQueueSubmit2(device_.queue(), 1, &si, VK_NULL_HANDLE), "vkQueueSubmit2");
    }

private:
    static void begin(VkCommandBuffer cmd) {
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vk::check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    }
    void barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStages, VkAccessFlags2 srcAccess,
                 VkPipelineStageFlags2 dstStages, VkAccessFlags2 dstAccess, VkImageLayout from, VkImageLayout to) {
        VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
        b.srcStageMask = srcStages;
        b.srcAccessMask = srcAccess;
        b.dstStageMask = dstStages;
        b.dstAccessMask = dstAccess;
        b.oldLayout = from;
        b.newLayout = to;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = image_;
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        di.imageMemoryBarrierCount = 1;
        di.pImageMemoryBarriers = &b;
        vkCmdPipelineBarrier2(cmd, &di);
    }

    Device& device_;
    VkDevice vkd_;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory bufferMemory_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmds_[3]{};
    std::vector<VkSemaphore> semaphores_;
};

VkSemaphoreSubmitInfo op(VkSemaphore s, uint64_t value, VkPipelineStageFlags2 stages) {
    VkSemaphoreSubmitInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    info.semaphore = s;
    info.value = value;
    info.stageMask = stages;
    return info;
}

constexpr VkPipelineStageFlags2 kCopy = VK_PIPELINE_STAGE_2_COPY_BIT;
constexpr VkPipelineStageFlags2 kClear = VK_PIPELINE_STAGE_2_CLEAR_BIT;
constexpr const char* kRaw = "SYNC-HAZARD-READ-AFTER-WRITE";
constexpr const char* kWaw = "SYNC-HAZARD-WRITE-AFTER-WRITE";

class SemaphoreValidation : public ExecutorTest {
protected:
    void SetUp() override {
        ExecutorTest::SetUp();
        allowMessages();  // each test asserts its own messages
    }
    void TearDown() override {
        vkQueueWaitIdle(sharedDevice().queue());
        ExecutorTest::TearDown();
    }
    /// A then B, B waiting as `waits` says (A signals `semaphore` at `signalStages`).
    void run(std::optional<std::pair<VkPipelineStageFlags2, VkAccessFlags2>> transition, bool timeline,
             std::optional<VkPipelineStageFlags2> waitStages, VkPipelineStageFlags2 signalStages = kClear) {
        TwoSubmits t(sharedDevice());
        t.recordClear();
        t.recordCopy(1, transition);
        if (!waitStages) {
            t.submit(0, {}, {});
            t.submit(1, {}, {});
            return;
        }
        const VkSemaphore s = t.semaphore(timeline);
        t.submit(0, {}, {op(s, 1, signalStages)});
        t.submit(1, {op(s, 1, *waitStages)}, {});
    }
};

TEST_F(SemaphoreValidation, NoSemaphoreIsReadAfterWrite) {
    run(std::nullopt, false, std::nullopt);
    EXPECT_TRUE(sharedDevice().hasMessage(kRaw)) << formatMessages(sharedDevice());
}

TEST_F(SemaphoreValidation, BinaryAndTimelineAtTheCopysStageAreClean) {
    run(std::nullopt, false, kCopy);
    run(std::nullopt, true, kCopy);
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
}

TEST_F(SemaphoreValidation, AWaitAtAStageThatDoesNotHoldTheCopyIsReadAfterWrite) {
    run(std::nullopt, true, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_TRUE(sharedDevice().hasMessage(kRaw)) << formatMessages(sharedDevice());
}

TEST_F(SemaphoreValidation, ASignalBeforeTheClearIsReadAfterWrite) {
    run(std::nullopt, false, kCopy, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT);
    EXPECT_TRUE(sharedDevice().hasMessage(kRaw)) << formatMessages(sharedDevice());
}

// Why the executor gives each wait a binary semaphore of its own under validation: the layer
// pairs one signal with one wait, so a second wait for the same timeline value is not seen
// (though Vulkan allows it): here an empty submit waits first, at a stage the copy is not in,
// and the copy after the second wait, at the copy's stage, is reported.
TEST_F(SemaphoreValidation, ASecondWaitForOneTimelineSignalIsNotSeenByTheLayer) {
    TwoSubmits t(sharedDevice());
    t.recordClear();
    t.recordNothing(1);
    t.recordCopy(2, std::nullopt);
    const VkSemaphore s = t.semaphore(true);
    t.submit(0, {}, {op(s, 1, kClear)});
    t.submit(1, {op(s, 1, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT)}, {});
    t.submit(2, {op(s, 1, kCopy)}, {});
    EXPECT_TRUE(sharedDevice().hasMessage(kRaw)) << formatMessages(sharedDevice());
}

// Why barriers that continue a wait carry MEMORY_READ: without a read in the source access
// scope the layer does not see the transition ordered after the other submit's write.
TEST_F(SemaphoreValidation, ATransitionAfterAWaitNeedsAReadInItsSourceAccessForTheLayer) {
    run(std::pair{kCopy, VkAccessFlags2(0)}, true, kCopy);
    EXPECT_TRUE(sharedDevice().hasMessage(kWaw)) << formatMessages(sharedDevice());
    sharedDevice().clearMessages();
    run(std::pair{kCopy, VkAccessFlags2(VK_ACCESS_2_MEMORY_READ_BIT)}, true, kCopy);
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
}

// Why random graphs on queues can be reported with write-after-write on lavapipe (docs/queues.md,
// docs/reliability.md): B waits for the clear at the copy's stage, which by vkQueueSubmit2's
// rules also orders every later command of the queue at that stage, so C's transition (source:
// the copy's stage) follows the clear, and C needs no wait of its own. Layer 1.3.239 agrees;
// but give C a further, redundant wait for the clear at a stage the transition is not in, and
// it reports the transition. It imports the clear twice, through C's wait and through B, and
// when it merges two states of one write it keeps the first one's dependency chain only
// (ResourceAccessState::Resolve; layers from 1.3.264 merge the chains). An extra wait can only
// add ordering, so the second report is the layer's.
TEST_F(SemaphoreValidation, ARedundantWaitHidesAnEarlierWaitFromTheLayer) {
    const std::pair transition{kCopy, VkAccessFlags2(VK_ACCESS_2_MEMORY_READ_BIT)};
    for (const bool redundantWait : {false, true}) {
        TwoSubmits t(sharedDevice());
        t.recordClear();
        t.recordNothing(1);
        t.recordCopy(2, transition);
        const VkSemaphore forB = t.semaphore(false);
        const VkSemaphore forC = t.semaphore(false);
        std::vector<VkSemaphoreSubmitInfo> signals{op(forB, 0, kClear)};
        if (redundantWait) signals.push_back(op(forC, 0, kClear));
        t.submit(0, {}, signals);
        t.submit(1, {op(forB, 0, kCopy)}, {});
        std::vector<VkSemaphoreSubmitInfo> waitsOfC;
        if (redundantWait) waitsOfC.push_back(op(forC, 0, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT));
        t.submit(2, waitsOfC, {});
        vkQueueWaitIdle(sharedDevice().queue());
        if (redundantWait) {
            EXPECT_TRUE(sharedDevice().hasMessage(kWaw)) << formatMessages(sharedDevice());
        } else {
            EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
        }
        sharedDevice().clearMessages();
    }
}

}  // namespace
}  // namespace skygraph::test
