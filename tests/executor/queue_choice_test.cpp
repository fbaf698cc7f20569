// Which queue each queue kind submits to (device_selection.hpp's chooseQueues), from queue
// family lists shaped like real devices': no device needed.
#include "device_selection.hpp"

#include <gtest/gtest.h>

namespace skygraph::test {
namespace {

using detail::chooseQueues;
using detail::QueueChoice;
using detail::QueueFamilyFacts;

QueueFamilyFacts graphicsFamily(uint32_t queues) {
    return {.graphicsAndCompute = true, .timestamps = true, .compute = true, .transfers = true, .queueCount = queues};
}
QueueFamilyFacts computeFamily(uint32_t queues) {
    return {.timestamps = true, .compute = true, .transfers = true, .queueCount = queues};
}
QueueFamilyFacts transferFamily(bool wholeTexels = true) {
    return {.timestamps = true, .transfers = wholeTexels, .queueCount = 2};
}

constexpr size_t kGraphics = 0, kCompute = 1, kTransfer = 2;

TEST(QueueChoice, DedicatedFamiliesWhereTheDeviceHasThem) {
    // NVIDIA's layout: graphics (16 queues), transfer-only, compute-only.
    const auto q = chooseQueues({graphicsFamily(16), transferFamily(), computeFamily(8)}, 0, true);
    EXPECT_EQ(q[kGraphics], (QueueChoice{0, 0}));
    EXPECT_EQ(q[kCompute], (QueueChoice{2, 0}));
    EXPECT_EQ(q[kTransfer], (QueueChoice{1, 0}));
}

TEST(QueueChoice, OneFamilyOfOneQueueSharesIt) {
    // lavapipe: one family with one queue.
    const auto q = chooseQueues({graphicsFamily(1)}, 0, true);
    for (const QueueChoice& c : q) EXPECT_EQ(c, (QueueChoice{0, 0}));
}

TEST(QueueChoice, SecondGraphicsQueueWhenNoComputeFamily) {
    const auto q = chooseQueues({graphicsFamily(4)}, 0, true);
    EXPECT_EQ(q[kCompute], (QueueChoice{0, 1}));
    EXPECT_EQ(q[kTransfer], (QueueChoice{0, 1})) << "transfer follows compute when there is no DMA family";
}

TEST(QueueChoice, TransferFamilyWithCoarseGranularityIsPassedOver) {
    // A DMA family that copies only whole mips (minImageTransferGranularity 0x0x0) cannot take
    // every copy a plan asks for.
    const auto q = chooseQueues({graphicsFamily(1), computeFamily(2), transferFamily(false)}, 0, true);
    EXPECT_EQ(q[kTransfer], (QueueChoice{1, 0}));
}

TEST(QueueChoice, NotSeparateSharesTheGraphicsQueue) {
    const auto q = chooseQueues({graphicsFamily(16), transferFamily(), computeFamily(8)}, 0, false);
    for (const QueueChoice& c : q) EXPECT_EQ(c, (QueueChoice{0, 0}));
}

TEST(QueueChoice, GraphicsFamilyIsNotTakenForCompute) {
    // The graphics family listed after a compute family: compute still takes the dedicated one.
    const auto q = chooseQueues({computeFamily(2), graphicsFamily(1)}, 1, true);
    EXPECT_EQ(q[kGraphics], (QueueChoice{1, 0}));
    EXPECT_EQ(q[kCompute], (QueueChoice{0, 0}));
    EXPECT_EQ(q[kTransfer], (QueueChoice{0, 0}));
}

}  // namespace
}  // namespace skygraph::test
