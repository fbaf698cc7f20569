// ImGuiPass: the application's Dear ImGui draw data, recorded by Debian's libimgui Vulkan
// backend (1.86) inside the render pass the executor makes from the plan, so that the
// overlay's attachment access is in the plan and under the validation layer like every other
// graphics pass.
//
// The backend keeps one state per ImGui context and takes a render pass at initialisation,
// whose pipeline then works in every compatible render pass (same format, one sample). So
// the passes of one context share one backend while their targets agree: a rebuilt plan
// (an edit, a resize) takes it from the plan it replaces while that still holds it, with its
// pipeline and font atlas. Otherwise a backend is made at the first record, once the plan it
// replaces is gone. The backend rotates its vertex buffers per draw with no fence of its
// own, so one pass at a time records with it: a second one recording while the first lives
// is an error.
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
#include <memory>
#include <string>

namespace skygraph::passes {
namespace {

/// Dear ImGui's Vulkan backend, initialised for one context, device and target format; shut
/// down when the last ImGuiPass using it is destroyed.
class ImGuiBackend {
public:
    struct Key {
        ImGuiContext* context = nullptr;
        VkDevice device = VK_NULL_HANDLE;
        VkFormat format = VK_FORMAT_UNDEFINED;
        uint32_t imageCount = 0;  // vertex/index buffers rotated over; a user may need fewer
    };

    /// The live backend when `key` fits it, else null.
    static std::shared_ptr<ImGuiBackend> share(const Key& key) {
        std::shared_ptr<ImGuiBackend> b = live().lock();
        const bool fits = b && b->key_.context == key.context && b->key_.device == key.device &&
                          b->key_.format == key.format && b->key_.imageCount >= key.imageCount;
        return fits ? b : nullptr;
    }

    /// A new backend, which uploads its font atlas in `cmd`. Throws when another ImGuiPass
    /// still holds the context with a backend that does not fit `key`.
    static std::shared_ptr<ImGuiBackend> make(const Key& key, ImGui_ImplVulkan_InitInfo info, VkRenderPass renderPass,
                                              VkCommandBuffer cmd, const std::string& pass) {
        if (!live().expired())
            throw ExecutorError("pass '" + pass + "': the Dear ImGui context is still drawn by an ImGuiPass of "
                                "another device, target format or frame count (one backend per context)");
        ImGui::SetCurrentContext(key.context);
        if (ImGui::GetIO().BackendRendererUserData)
            throw ExecutorError("pass '" + pass + "': the Dear ImGui context already has another renderer backend");
        auto b = std::shared_ptr<ImGuiBackend>(new ImGuiBackend(key));
        VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
        VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        pi.maxSets = 1;
        pi.poolSizeCount = 1;
        pi.pPoolSizes = &size;
        if (vkCreateDescriptorPool(key.device, &pi, nullptr, &b->pool_) != VK_SUCCESS)
            throw ExecutorError("pass '" + pass + "': vkCreateDescriptorPool failed");
        info.DescriptorPool = b->pool_;
        if (!ImGui_ImplVulkan_Init(&info, renderPass))
            throw ExecutorError("pass '" + pass + "': ImGui_ImplVulkan_Init failed");
        b->initialized_ = true;
        if (!ImGui_ImplVulkan_CreateFontsTexture(cmd))
            throw ExecutorError("pass '" + pass + "': ImGui_ImplVulkan_CreateFontsTexture failed");
        live() = b;
        return b;
    }

    ~ImGuiBackend() {
        if (initialized_) {
            ImGuiContext* current = ImGui::GetCurrentContext();
            ImGui::SetCurrentContext(key_.context);
            ImGui_ImplVulkan_Shutdown();
            ImGui::SetCurrentContext(current);
        }
        if (pool_) vkDestroyDescriptorPool(key_.device, pool_, nullptr);
    }
    ImGuiBackend(const ImGuiBackend&) = delete;
    ImGuiBackend& operator=(const ImGuiBackend&) = delete;

    /// Records the context's draw data for `recorder`, which must be the only pass recording
    /// with this backend while it lives (release() when it goes).
    void record(VkCommandBuffer cmd, const void* recorder, const std::string& pass) {
        if (recorder_ && recorder_ != recorder)
            throw ExecutorError("pass '" + pass + "': another ImGuiPass records the same Dear ImGui context (one "
                                "renderer at a time draws a context)");
        recorder_ = recorder;
        ImGui::SetCurrentContext(key_.context);
        ImDrawData* data = ImGui::GetDrawData();
        if (data && data->Valid && data->CmdListsCount > 0) ImGui_ImplVulkan_RenderDrawData(data, cmd);
    }

    void release(const void* recorder) noexcept {
        if (recorder_ == recorder) recorder_ = nullptr;
    }

private:
    explicit ImGuiBackend(const Key& key) : key_(key) {}
    static std::weak_ptr<ImGuiBackend>& live() {
        static std::weak_ptr<ImGuiBackend> backend;
        return backend;
    }
    Key key_;
    const void* recorder_ = nullptr;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    bool initialized_ = false;
};

void checkResult(VkResult result) {
    if (result < 0) throw ExecutorError("Dear ImGui's Vulkan backend: VkResult " + std::to_string(int(result)));
}

class ImGuiPass final : public PassImplementation {
public:
    explicit ImGuiPass(const PassDesc& desc) : name_(desc.name) {}
    ~ImGuiPass() override {
        if (backend_) backend_->release(this);
    }

    void createPipelines(const PipelineContext& ctx) override {
        key_.context = ImGui::GetCurrentContext();
        if (!key_.context) return;  // nothing to draw: the target passes through
        key_.device = ctx.device;
        key_.format = ctx.resources.empty() ? VK_FORMAT_UNDEFINED : ctx.resources[0].format;
        // The backend rotates its vertex and index buffers over ImageCount frames; a frame slot
        // is reused only after its fence, so one buffer per slot is never overwritten in use.
        key_.imageCount = std::max<uint32_t>(2, uint32_t(ctx.frameSlots.size()));
        init_.Instance = ctx.instance;
        init_.PhysicalDevice = ctx.physicalDevice;
        init_.Device = ctx.device;
        init_.QueueFamily = ctx.queueFamily;
        init_.Queue = ctx.queue;
        init_.Subpass = 0;
        init_.MinImageCount = 2;
        init_.ImageCount = key_.imageCount;
        init_.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
        init_.CheckVkResultFn = &checkResult;
        renderPass_ = ctx.renderPass;
        backend_ = ImGuiBackend::share(key_);  // the plan this one replaces may still hold it
    }

    void recordBeforeRenderPass(const RecordContext& ctx) override {
        if (key_.context && !backend_) backend_ = ImGuiBackend::make(key_, init_, renderPass_, ctx.cmd, name_);
    }

    void record(const RecordContext& ctx) override {
        if (backend_) backend_->record(ctx.cmd, this, name_);
    }

private:
    std::string name_;
    ImGuiBackend::Key key_;
    ImGui_ImplVulkan_InitInfo init_{};
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    std::shared_ptr<ImGuiBackend> backend_;
};

}  // namespace

std::unique_ptr<PassImplementation> makeImGuiPass(const PassDesc& desc) { return std::make_unique<ImGuiPass>(desc); }

}  // namespace skygraph::passes
