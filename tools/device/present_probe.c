// Can this machine's Vulkan driver present to an X11 window, and what do acquire, submit and
// present cost the calling thread? tools/device/present-probe.sh builds and runs it on the GPU
// machine against a carried Xvfb (docs/performance.md, "Presenting"). Plain C against the
// loader and GLFW, so it needs no build of skygraph there.
#include <vulkan/vulkan.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdio.h>
#include <time.h>

static double threadMicroseconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

#define CHECK(call)                                        \
    do {                                                   \
        VkResult r_ = (call);                              \
        if (r_ != VK_SUCCESS) {                            \
            printf("%s failed: VkResult %d\n", #call, r_); \
            return 1;                                      \
        }                                                  \
    } while (0)

enum { kMaxImages = 8, kWarmup = 20, kFrames = 600 };

int main(void) {
    setvbuf(stdout, NULL, _IONBF, 0);  // a crash inside the driver must not eat what came before
    if (!glfwInit()) {
        printf("glfwInit failed (no X server?)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(1280, 720, "present probe", NULL, NULL);
    uint32_t extensionCount = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&extensionCount);
    VkApplicationInfo app = {VK_STRUCTURE_TYPE_APPLICATION_INFO, NULL, "present probe", 1, NULL, 0, VK_API_VERSION_1_3};
    VkInstanceCreateInfo instanceInfo = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, NULL, 0, &app, 0, NULL,
                                         extensionCount, extensions};
    VkInstance instance;
    CHECK(vkCreateInstance(&instanceInfo, NULL, &instance));
    VkSurfaceKHR surface;
    CHECK(glfwCreateWindowSurface(instance, window, NULL, &surface));
    uint32_t deviceCount = 1;
    VkPhysicalDevice physical;
    vkEnumeratePhysicalDevices(instance, &deviceCount, &physical);
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical, &properties);
    printf("device %s, driver version 0x%x\n", properties.deviceName, properties.driverVersion);
    printf("asking whether queue family 0 can present to the window...\n");
    VkBool32 canPresent = VK_FALSE;
    CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(physical, 0, surface, &canPresent));
    printf("queue family 0 can present: %s\n", canPresent ? "yes" : "no");
    if (!canPresent) return 2;

    VkSurfaceCapabilitiesKHR caps;
    CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &caps));
    uint32_t formatCount = 1;
    VkSurfaceFormatKHR format;
    vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &formatCount, &format);
    uint32_t modeCount = 8;
    VkPresentModeKHR modes[8];
    vkGetPhysicalDeviceSurfacePresentModesKHR(physical, surface, &modeCount, modes);
    VkPresentModeKHR mode = VK_PRESENT_MODE_FIFO_KHR;
    for (uint32_t i = 0; i < modeCount; ++i)
        if (modes[i] == VK_PRESENT_MODE_IMMEDIATE_KHR) mode = modes[i];

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, NULL, 0, 0, 1, &priority};
    const char* swapchainExtension = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    VkDeviceCreateInfo deviceInfo = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, NULL, 0, 1, &queueInfo, 0, NULL, 1,
                                     &swapchainExtension, NULL};
    VkDevice device;
    CHECK(vkCreateDevice(physical, &deviceInfo, NULL, &device));
    VkQueue queue;
    vkGetDeviceQueue(device, 0, 0, &queue);
    VkSwapchainCreateInfoKHR swapchainInfo = {
        VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR, NULL, 0, surface, caps.minImageCount + 1, format.format,
        format.colorSpace, caps.currentExtent, 1, VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_SHARING_MODE_EXCLUSIVE, 0, NULL,
        caps.currentTransform, VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, mode, VK_TRUE, VK_NULL_HANDLE};
    VkSwapchainKHR swapchain;
    CHECK(vkCreateSwapchainKHR(device, &swapchainInfo, NULL, &swapchain));
    uint32_t imageCount = kMaxImages;
    VkImage images[kMaxImages];
    vkGetSwapchainImagesKHR(device, swapchain, &imageCount, images);

    // One command buffer per image: clear it and hand it to the presentation engine.
    VkCommandPoolCreateInfo poolInfo = {VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, NULL, 0, 0};
    VkCommandPool pool;
    CHECK(vkCreateCommandPool(device, &poolInfo, NULL, &pool));
    VkCommandBuffer commands[kMaxImages];
    VkCommandBufferAllocateInfo allocateInfo = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, NULL, pool,
                                                VK_COMMAND_BUFFER_LEVEL_PRIMARY, imageCount};
    CHECK(vkAllocateCommandBuffers(device, &allocateInfo, commands));
    const VkImageSubresourceRange color = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (uint32_t i = 0; i < imageCount; ++i) {
        VkCommandBufferBeginInfo begin = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        vkBeginCommandBuffer(commands[i], &begin);
        VkImageMemoryBarrier toClear = {VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER, NULL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                                        VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                        VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED, images[i], color};
        vkCmdPipelineBarrier(commands[i], VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL,
                             0, NULL, 1, &toClear);
        const VkClearColorValue blue = {{0.2f, 0.4f, 0.8f, 1.0f}};
        vkCmdClearColorImage(commands[i], images[i], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &blue, 1, &color);
        VkImageMemoryBarrier toPresent = toClear;
        toPresent.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        toPresent.dstAccessMask = 0;
        toPresent.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        toPresent.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
        vkCmdPipelineBarrier(commands[i], VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0,
                             NULL, 0, NULL, 1, &toPresent);
        vkEndCommandBuffer(commands[i]);
    }
    VkSemaphoreCreateInfo semaphoreInfo = {VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore acquired[2], rendered[kMaxImages];
    for (int i = 0; i < 2; ++i) CHECK(vkCreateSemaphore(device, &semaphoreInfo, NULL, &acquired[i]));
    for (uint32_t i = 0; i < imageCount; ++i) CHECK(vkCreateSemaphore(device, &semaphoreInfo, NULL, &rendered[i]));
    VkFenceCreateInfo fenceInfo = {VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, NULL, VK_FENCE_CREATE_SIGNALED_BIT};
    VkFence done[2];
    for (int i = 0; i < 2; ++i) CHECK(vkCreateFence(device, &fenceInfo, NULL, &done[i]));

    double wait = 0, acquire = 0, submit = 0, present = 0;
    for (int frame = 0; frame < kWarmup + kFrames; ++frame) {
        if (frame == kWarmup) wait = acquire = submit = present = 0;
        const int slot = frame & 1;
        const double t0 = threadMicroseconds();
        vkWaitForFences(device, 1, &done[slot], VK_TRUE, UINT64_MAX);
        vkResetFences(device, 1, &done[slot]);
        const double t1 = threadMicroseconds();
        uint32_t index = 0;
        CHECK(vkAcquireNextImageKHR(device, swapchain, UINT64_MAX, acquired[slot], VK_NULL_HANDLE, &index));
        const double t2 = threadMicroseconds();
        const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkSubmitInfo submitInfo = {VK_STRUCTURE_TYPE_SUBMIT_INFO, NULL, 1, &acquired[slot], &waitStage, 1,
                                   &commands[index], 1, &rendered[index]};
        CHECK(vkQueueSubmit(queue, 1, &submitInfo, done[slot]));
        const double t3 = threadMicroseconds();
        VkPresentInfoKHR presentInfo = {VK_STRUCTURE_TYPE_PRESENT_INFO_KHR, NULL, 1, &rendered[index], 1, &swapchain,
                                        &index, NULL};
        CHECK(vkQueuePresentKHR(queue, &presentInfo));
        const double t4 = threadMicroseconds();
        wait += t1 - t0;
        acquire += t2 - t1;
        submit += t3 - t2;
        present += t4 - t3;
        glfwPollEvents();
    }
    printf("%u images %ux%u, present mode %d; per frame, the calling thread's CPU time in us: fence wait %.1f, "
           "acquire %.1f, submit %.1f, present %.1f\n",
           imageCount, caps.currentExtent.width, caps.currentExtent.height, mode, wait / kFrames,
           acquire / kFrames, submit / kFrames, present / kFrames);
    vkDeviceWaitIdle(device);
    return 0;
}
