// TonemappingPass (fragment) and TonemappingComputePass: HDR -> display with the same math
// (shaders/common/tonemap.glsl). Exposure and operator come from the scene when one is set
// (FrameData<Scene>), else from the pass's params.
#include "builtin_passes.hpp"
#include "tonemapping_rules.hpp"
#include <skygraph/pipeline_builder.hpp>

#include <skygraph/scene.hpp>

#include <nlohmann/json.hpp>

namespace skygraph::passes {
namespace {

int operatorIndex(const std::string& name) {
    if (name == "aces_hill") return 1;
    if (name == "khronos_pbr_neutral") return 2;
    if (name == "passthrough") return 3;
    return 0;  // aces_narkowicz, the default
}

int operatorIndex(Tonemapper t) {
    switch (t) {
        case Tonemapper::AcesNarkowicz: return 0;
        case Tonemapper::AcesHill: return 1;
        case Tonemapper::KhronosPbrNeutral: return 2;
        case Tonemapper::Passthrough: return 3;
    }
    return 0;
}

bool isSrgb(VkFormat f) {
    const auto info = findFormat(f);
    return info && info->srgb;
}

/// Both passes' settings: exposure and operator from the params, overridden per frame by the
/// scene when one is set.
class ToneSettings {
public:
    explicit ToneSettings(const PassDesc& desc)
        : exposureEv_(desc.params.value("exposure_ev", 0.0)),
          operator_(operatorIndex(desc.params.value("operator", std::string("aces_narkowicz")))) {}

    /// Exposure (EV) and operator index for the frame being recorded.
    [[nodiscard]] std::pair<float, int32_t> forFrame(const RecordContext& ctx) const {
        if (const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr)
            return {static_cast<float>(scene->exposureEv), operatorIndex(effectiveTonemapper(*scene))};
        return {static_cast<float>(exposureEv_), operator_};
    }

private:
    double exposureEv_;
    int operator_;
};

/// The resource bound to the `output` slot, or nullptr.
const BoundResource* boundOutput(const PipelineContext& ctx) {
    for (const auto& r : ctx.resources)
        if (r.usage && r.usage->slot == "output") return &r;
    return nullptr;
}

class TonemappingPass final : public PassImplementation {
public:
    explicit TonemappingPass(const PassDesc& desc)
        : settings_(desc) {}

    void createPipelines(const PipelineContext& ctx) override {
        const BoundResource* output = boundOutput(ctx);
        GraphicsPipelineRecipe recipe;
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/fullscreen.vert");
        recipe.fragment = compileShader(*ctx.shaders, VK_SHADER_STAGE_FRAGMENT_BIT, "passes/tonemap.frag");
        recipe.renderPass = ctx.renderPass;
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
        recipe.pushConstantBytes = sizeof(Push);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
        // An *_SRGB attachment encodes in hardware; anything else needs the shader to encode.
        encodeSrgb_ = output && !isSrgb(output->format);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource* hdr = ctx.slot("hdr");
        const auto [exposureEv, op] = settings_.forFrame(ctx);
        const Push push{exposureEv, op, encodeSrgb_ ? 1 : 0};
        const VkDescriptorImageInfo image{ctx.linearSampler, hdr->view, hdr->usage->layout};
        const VkWriteDescriptorSet write = sampledImageWrite(0, &image);
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.layout.get(), 0, 1, &write);
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           0, sizeof(push), &push);
        setViewportAndScissor(ctx.cmd, ctx.renderArea);
        vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
    }

private:
    struct Push {
        float exposureEv;
        int32_t toneOperator;
        int32_t encodeSrgb;
    };
    ToneSettings settings_;
    bool encodeSrgb_ = false;
    GraphicsPipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

/// Storage images cannot be sRGB, so the compute pass always encodes sRGB in the shader and
/// writes a UNORM or float image: through its GLSL format qualifier, or, for B8G8R8A8_UNORM
/// (which has none; the storage swapchain format surfaces offer), through the view's format.
std::vector<std::pair<std::string, std::string>> storageFormatDefines(const PipelineContext& ctx, const BoundResource& output) {
    switch (output.format) {
        case VK_FORMAT_R8G8B8A8_UNORM: return {{"OUT_FORMAT", "rgba8"}};
        case VK_FORMAT_R16G16B16A16_SFLOAT: return {{"OUT_FORMAT", "rgba16f"}};
        case VK_FORMAT_R32G32B32A32_SFLOAT: return {{"OUT_FORMAT", "rgba32f"}};
        default: break;
    }
    const std::string where = "pass '" + ctx.desc->name + "', resource '" + (output.desc ? output.desc->name : "?") + "'";
    if (output.format == VK_FORMAT_B8G8R8A8_UNORM) {
        VkPhysicalDeviceFeatures features;
        vkGetPhysicalDeviceFeatures(ctx.physicalDevice, &features);
        VkFormatProperties3 props3{VK_STRUCTURE_TYPE_FORMAT_PROPERTIES_3};
        VkFormatProperties2 props{VK_STRUCTURE_TYPE_FORMAT_PROPERTIES_2, &props3};
        vkGetPhysicalDeviceFormatProperties2(ctx.physicalDevice, output.format, &props);
        if (features.shaderStorageImageWriteWithoutFormat &&
            (props3.optimalTilingFeatures & VK_FORMAT_FEATURE_2_STORAGE_WRITE_WITHOUT_FORMAT_BIT))
            return {{"OUT_FORMAT_UNKNOWN", "1"}};
        throw ExecutorError(where + ": this device cannot write B8G8R8A8_UNORM storage images without a format "
                                    "qualifier (shaderStorageImageWriteWithoutFormat); use R8G8B8A8_UNORM");
    }
    const auto info = findFormat(output.format);
    throw ExecutorError(where + ": " +
                        tonemappingComputeOutputProblem(info ? std::string(info->name) : std::to_string(output.format)));
}

class TonemappingComputePass final : public PassImplementation {
public:
    explicit TonemappingComputePass(const PassDesc& desc)
        : settings_(desc) {}

    void createPipelines(const PipelineContext& ctx) override {
        const BoundResource* output = boundOutput(ctx);
        if (!output) throw ExecutorError("pass '" + ctx.desc->name + "': no resource bound to slot 'output'");
        ComputePipelineRecipe recipe;
        recipe.compute = compileShader(*ctx.shaders, VK_SHADER_STAGE_COMPUTE_BIT, "passes/tonemap.comp",
                                       storageFormatDefines(ctx, *output));
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
                           {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
        recipe.pushConstantBytes = sizeof(Push);
        pipeline_ = createComputePipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource* hdr = ctx.slot("hdr");
        const BoundResource* out = ctx.slot("output");
        const auto [exposureEv, op] = settings_.forFrame(ctx);
        const Push push{exposureEv, op};
        const VkDescriptorImageInfo images[2] = {{ctx.linearSampler, hdr->view, hdr->usage->layout},
                                                 {VK_NULL_HANDLE, out->view, out->usage->layout}};
        VkWriteDescriptorSet writes[2] = {sampledImageWrite(0, &images[0]), sampledImageWrite(1, &images[1])};
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout.get(), 0, 2, writes);
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        // tonemap.comp: 8x8 invocations per 16x16 pixels.
        vkCmdDispatch(ctx.cmd, (out->extent.width + 15) / 16, (out->extent.height + 15) / 16, 1);
    }

private:
    struct Push {
        float exposureEv;
        int32_t toneOperator;
    };
    ToneSettings settings_;
    ComputePipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

std::unique_ptr<PassImplementation> makeTonemappingComputePass(const PassDesc& desc) {
    return std::make_unique<TonemappingComputePass>(desc);
}

std::unique_ptr<PassImplementation> makeTonemappingPass(const PassDesc& desc) {
    return std::make_unique<TonemappingPass>(desc);
}

}  // namespace skygraph::passes
