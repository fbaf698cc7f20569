// TonemappingPass: HDR -> display. Exposure and operator come from the scene when one is set
// (FrameData<Scene>), else from the pass's params.
#include "builtin_passes.hpp"
#include <skygraph/pipeline_builder.hpp>

#include <skygraph/scene.hpp>

#include <nlohmann/json.hpp>

namespace skygraph::passes {
namespace {

int operatorIndex(const std::string& name) {
    if (name == "aces_hill") return 1;
    if (name == "khronos_pbr_neutral") return 2;
    if (name == "passthrough") return 3;
    return 0;  // aces_narkowicz, the seed's default
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

class TonemappingPass final : public PassImplementation {
public:
    explicit TonemappingPass(const PassDesc& desc)
        : exposureEv_(desc.params.value("exposure_ev", 0.0)),
          operator_(operatorIndex(desc.params.value("operator", std::string("aces_narkowicz")))) {}

    void createPipelines(const PipelineContext& ctx) override {
        const BoundResource* output = nullptr;
        for (const auto& r : ctx.resources)
            if (r.usage && r.usage->slot == "output") output = &r;
        GraphicsPipelineRecipe recipe;
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/fullscreen.vert");
        recipe.fragment = compileShader(*ctx.shaders, VK_SHADER_STAGE_FRAGMENT_BIT, "passes/tonemap.frag");
        recipe.renderPass = ctx.renderPass;
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
        recipe.pushConstantBytes = sizeof(Push);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
        // An *_SRGB attachment encodes in hardware (the seed's design); anything else needs
        // the shader to encode.
        encodeSrgb_ = output && !isSrgb(output->format);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource* hdr = ctx.slot("hdr");
        Push push{static_cast<float>(exposureEv_), operator_, encodeSrgb_ ? 1 : 0};
        if (const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr) {
            push.exposureEv = static_cast<float>(scene->exposureEv);
            push.toneOperator = operatorIndex(effectiveTonemapper(*scene));
        }
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
    double exposureEv_;
    int operator_;
    bool encodeSrgb_ = false;
    GraphicsPipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

std::unique_ptr<PassImplementation> makeTonemappingPass(const PassDesc& desc) {
    return std::make_unique<TonemappingPass>(desc);
}

}  // namespace skygraph::passes
