// BenchComputeTonemapPass and the graph variants (see gpu_compute_tonemap.hpp).
#include "gpu_compute_tonemap.hpp"

#include <skygraph/pipeline_builder.hpp>
#include <skygraph/scene.hpp>

#include <stdexcept>

namespace skygraph::gpubench {
namespace {

// tonemap.frag's body; each invocation shades a 2x2 block of an 16x16-pixel tile, issuing its
// four loads before any store (the fastest shape of gpu_probes' measurements on the H100).
constexpr const char* kShader = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "common/tonemap.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D hdrInput;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D outImage;
layout(push_constant) uniform Params { float exposureEv; int toneOperator; int encodeSrgb; } params;
void shade(ivec2 p, ivec2 size) {
    if (any(greaterThanEqual(p, size))) return;
    vec3 c = tonemap(texelFetch(hdrInput, p, 0).rgb, params.exposureEv, params.toneOperator);
    if (params.encodeSrgb != 0) c = srgbEncode(c);
    imageStore(outImage, p, vec4(c, 1.0));
}
void main() {
    ivec2 size = imageSize(outImage);
    ivec2 base = ivec2(gl_WorkGroupID.xy) * 16 + ivec2(gl_LocalInvocationID.xy);
    shade(base, size);
    shade(base + ivec2(8, 0), size);
    shade(base + ivec2(0, 8), size);
    shade(base + ivec2(8, 8), size);
})";

int operatorIndex(const std::string& name) {
    if (name == "aces_hill") return 1;
    if (name == "khronos_pbr_neutral") return 2;
    if (name == "passthrough") return 3;
    return 0;
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

class ComputeTonemapPass final : public PassImplementation {
public:
    explicit ComputeTonemapPass(const PassDesc& desc)
        : exposureEv_(desc.params.value("exposure_ev", 0.0)),
          operator_(operatorIndex(desc.params.value("operator", std::string("aces_narkowicz")))) {}

    void createPipelines(const PipelineContext& ctx) override {
        for (const auto& r : ctx.resources) {
            if (r.usage && r.usage->slot == "output" && r.format != VK_FORMAT_R8G8B8A8_UNORM)
                throw ExecutorError("pass '" + ctx.desc->name + "': BenchComputeTonemapPass writes R8G8B8A8_UNORM only");
        }
        ComputePipelineRecipe recipe;
        recipe.compute = ctx.shaders->compile(VK_SHADER_STAGE_COMPUTE_BIT, kShader, "BenchComputeTonemapPass");
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
                           {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
        recipe.pushConstantBytes = sizeof(Push);
        pipeline_ = createComputePipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource* hdr = ctx.slot("hdr");
        const BoundResource* out = ctx.slot("output");
        Push push{static_cast<float>(exposureEv_), operator_, 1};  // UNORM output: the shader encodes
        if (const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr) {
            push.exposureEv = static_cast<float>(scene->exposureEv);
            push.toneOperator = operatorIndex(effectiveTonemapper(*scene));
        }
        const VkDescriptorImageInfo images[2] = {{ctx.linearSampler, hdr->view, hdr->usage->layout},
                                                 {VK_NULL_HANDLE, out->view, out->usage->layout}};
        VkWriteDescriptorSet writes[2] = {sampledImageWrite(0, &images[0]), sampledImageWrite(1, &images[1])};
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout.get(), 0, 2, writes);
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(ctx.cmd, (out->extent.width + 15) / 16, (out->extent.height + 15) / 16, 1);
    }

private:
    struct Push {
        float exposureEv;
        int32_t toneOperator;
        int32_t encodeSrgb;
    };
    double exposureEv_;
    int operator_;
    ComputePipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

void addComputeTonemapPass(PassLibrary& library) {
    PassTypeInfo info;
    info.name = "BenchComputeTonemapPass";
    info.slots = {SlotDecl{"hdr", Stage::Compute, {Access::Read}, BindAs::Sampled, false, false, "HDR input"},
                  SlotDecl{"output", Stage::Compute, {Access::Write}, BindAs::Storage, false, false,
                           "display-referred output, R8G8B8A8_UNORM"}};
    info.doc = "gpu_frame_bench: TonemappingPass as a compute shader.";
    library.add(std::move(info), [](const PassDesc& desc) { return std::make_unique<ComputeTonemapPass>(desc); });
}

nlohmann::json graphVariant(nlohmann::json graph, const std::string& variant) {
    if (variant != "unorm-swapchain" && variant != "compute-tonemap")
        throw std::invalid_argument("unknown graph variant '" + variant + "' (unorm-swapchain, compute-tonemap)");
    auto& resources = graph.at("resources");
    if (!resources.contains("swapchain"))
        throw std::invalid_argument("graph variant '" + variant + "': the graph has no resource 'swapchain'");
    const bool compute = variant == "compute-tonemap";
    resources["swapchain"]["format"] = compute ? "R8G8B8A8_UNORM" : "B8G8R8A8_UNORM";
    graph["name"] = graph.value("name", std::string("graph")) + "@" + variant;
    if (!compute) return graph;
    int rewritten = 0;
    for (auto& pass : graph.at("passes")) {
        if (pass.value("type", std::string()) != "TonemappingPass") continue;
        pass["type"] = "BenchComputeTonemapPass";
        for (auto& [name, usage] : pass.at("uses").items()) {
            const std::string text = usage.get<std::string>();
            usage = text.substr(0, text.find('@')) + "@Compute";
        }
        ++rewritten;
    }
    if (rewritten == 0) throw std::invalid_argument("graph variant 'compute-tonemap': the graph has no TonemappingPass");
    return graph;
}

}  // namespace skygraph::gpubench
