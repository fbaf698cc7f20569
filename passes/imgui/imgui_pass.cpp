// ImGuiPass: the application's Dear ImGui draw data, recorded by Debian's libimgui Vulkan
// backend (1.86) inside the render pass the executor makes from the plan, so that the
// overlay's attachment access is in the plan and under the validation layer like every other
// graphics pass.
//
// The backend keeps one state per ImGui context and takes its render pass at initialisation.
// A rebuilt plan makes the new implementation before it destroys the old one, so the backend
// is initialised at the first record (the old one has shut it down by then), not in
// createPipelines.
//
// The one thing recorded that is not the plan's: the backend uploads its font atlas itself,
// with its own two image barriers on its own font image, in the first frame, before the
// render pass (ImGui_ImplVulkan_CreateFontsTexture takes a command buffer, and 1.86 cannot
// sample an image it did not create). The image is private to the backend; no plan resource
// is touched by it.
#include "builtin_passes.hpp"

#include <skygraph/device.hpp>

#include <imgui.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <string>

namespace skygraph::passes {
namespace {

class ImGuiPass final : public PassImplementation {
public:
    explicit ImGuiPass(const PassDesc& desc) : name_(desc.name) {}

    ~ImGuiPass() override {
        if (initialized_) {
            ImGuiContext* current = ImGui::GetCurrentContext();
            ImGui::SetCurrentContext(context_);
            ImGui_ImplVulkan_Shutdown();
            ImGui::SetCurrentContext(current);
        }
        if (pool_) vkDestroyDescriptorPool(init_.Device, pool_, nullptr);
    }

    void createPipelines(const PipelineContext& ctx) override {
        context_ = ImGui::GetCurrentContext();
        if (!context_) return;  // nothing to draw: the target passes through
        const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
        VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        pi.maxSets = 1;
        pi.poolSizeCount = 1;
        pi.pPoolSizes = &size;
        if (vkCreateDescriptorPool(ctx.device, &pi, nullptr, &pool_) != VK_SUCCESS)
            throw ExecutorError("pass '" + name_ + "': vkCreateDescriptorPool failed");
        init_.Instance = ctx.instance;
        init_.PhysicalDevice = ctx.physicalDevice;
        init_.Device = ctx.device;
        init_.QueueFamily = ctx.queueFamily;
        init_.Queue = ctx.queue;
        init_.DescriptorPool = pool_;
        init_.Subpass = 0;
        // The backend rotates its vertex and index buffers over ImageCount frames; a frame slot
        // is reused only after its fence, so one buffer per slot is never overwritten in use.
        init_.MinImageCount = 2;
        init_.ImageCount = std::max<uint32_t>(2, uint32_t(ctx.frameSlots.size()));
        init_.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
        init_.CheckVkResultFn = &checkResult;
        renderPass_ = ctx.renderPass;
    }

    void recordBeforeRenderPass(const RecordContext& ctx) override {
        if (!context_ || initialized_) return;
        ImGui::SetCurrentContext(context_);
        if (ImGui::GetIO().BackendRendererUserData)
            throw ExecutorError("pass '" + name_ +
                                "': the Dear ImGui context already has a renderer backend (one ImGuiPass per "
                                "context, and no other Vulkan backend on it)");
        if (!ImGui_ImplVulkan_Init(&init_, renderPass_))
            throw ExecutorError("pass '" + name_ + "': ImGui_ImplVulkan_Init failed");
        initialized_ = true;
        if (!ImGui_ImplVulkan_CreateFontsTexture(ctx.cmd))
            throw ExecutorError("pass '" + name_ + "': ImGui_ImplVulkan_CreateFontsTexture failed");
    }

    void record(const RecordContext& ctx) override {
        if (!initialized_) return;
        ImGui::SetCurrentContext(context_);
        ImDrawData* data = ImGui::GetDrawData();
        if (data && data->Valid && data->CmdListsCount > 0) ImGui_ImplVulkan_RenderDrawData(data, ctx.cmd);
    }

private:
    static void checkResult(VkResult result) {
        if (result < 0) throw ExecutorError("Dear ImGui's Vulkan backend: VkResult " + std::to_string(int(result)));
    }

    std::string name_;
    ImGuiContext* context_ = nullptr;
    ImGui_ImplVulkan_InitInfo init_{};
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    bool initialized_ = false;
};

}  // namespace

std::unique_ptr<PassImplementation> makeImGuiPass(const PassDesc& desc) { return std::make_unique<ImGuiPass>(desc); }

}  // namespace skygraph::passes
