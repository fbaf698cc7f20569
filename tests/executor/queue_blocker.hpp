// Holds up a device's queue the way another renderer's long frame would, for as long as a test
// says: what shows that a call waits only for its own renderer's work, deterministically.
#pragma once

#include <skygraph/device.hpp>

#include <vulkan/vulkan_core.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace skygraph::test {

/// Submits to `device.queue()` a batch that waits for a timeline semaphore which only the host
/// signals: work submitted to that queue after it, and any wait for the device or the queue to
/// be idle, waits until release(). So that a call that does wait for it fails the test instead
/// of hanging it, a watchdog thread releases it after `limit`; released() then tells that the
/// caller had to wait for it. Use on the device's thread; not copyable.
class QueueBlocker {
public:
    explicit QueueBlocker(Device& device, std::chrono::milliseconds limit = std::chrono::seconds(5))
        : device_(device.device()), queue_(device.queue()) {
        VkSemaphoreTypeCreateInfo type{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
        type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &type};
        EXPECT_EQ(vkCreateSemaphore(device_, &sci, nullptr, &semaphore_), VK_SUCCESS);
        VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
        wait.semaphore = semaphore_;
        wait.value = 1;
        wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        VkSubmitInfo2 batch{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        batch.waitSemaphoreInfoCount = 1;
        batch.pWaitSemaphoreInfos = &wait;
        EXPECT_EQ(vkQueueSubmit2(queue_, 1, &batch, VK_NULL_HANDLE), VK_SUCCESS);
        watchdog_ = std::thread([this, limit] {
            std::unique_lock lock(mutex_);
            if (!wake_.wait_for(lock, limit, [this] { return asked_; })) timedOut_ = true;
            VkSemaphoreSignalInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO};
            signal.semaphore = semaphore_;
            signal.value = 1;
            vkSignalSemaphore(device_, &signal);
            released_ = true;
        });
    }
    ~QueueBlocker() {
        release();
        vkQueueWaitIdle(queue_);
        vkDestroySemaphore(device_, semaphore_, nullptr);
    }
    QueueBlocker(const QueueBlocker&) = delete;
    QueueBlocker& operator=(const QueueBlocker&) = delete;

    /// Whether the queue runs again: released, by release() or by the watchdog.
    [[nodiscard]] bool released() const noexcept { return released_; }
    /// Whether the watchdog had to release it: something waited for the queue.
    [[nodiscard]] bool timedOut() const noexcept { return timedOut_; }
    /// Lets the queue run, and returns once the semaphore is signalled.
    void release() {
        if (!watchdog_.joinable()) return;
        {
            std::lock_guard lock(mutex_);
            asked_ = true;
        }
        wake_.notify_one();
        watchdog_.join();
    }

private:
    VkDevice device_;
    VkQueue queue_;
    VkSemaphore semaphore_ = VK_NULL_HANDLE;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool asked_ = false;
    std::atomic<bool> timedOut_{false};
    std::atomic<bool> released_{false};
    std::thread watchdog_;
};

}  // namespace skygraph::test
