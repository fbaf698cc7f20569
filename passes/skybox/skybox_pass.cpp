// SkyboxPass: a fullscreen triangle at the reverse-Z far plane, depth test GREATER_OR_EQUAL
// without writes, LOAD of the HDR target; rays from the camera rotation alone (exact at any
// distance from the origin), and cubemap or direct equirect sampling (docs/conventions.md), or
// a fade between two cubemaps (a sequence's previous and current frames).
#include "builtin_passes.hpp"
#include "pass_error.hpp"
#include "skybox_rules.hpp"
#include <skygraph/device.hpp>
#include <skygraph/pipeline_builder.hpp>
#include "scene_camera.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace skygraph::passes {
namespace {

class SkyboxPass final : public PassImplementation {
public:
    explicit SkyboxPass(const PassDesc& desc)
        : rotationDeg_(desc.params.value("rotation_deg", 0.0)),
          // "direction" writes the world-space view ray instead of the sky: for tests of the
          // ray's accuracy (into an fp32 target) and for debugging orientation.
          outputDirection_(desc.params.value("output", std::string("radiance")) == "direction") {}

    void createPipelines(const PipelineContext& ctx) override {
        const BoundResource *env = nullptr, *previous = nullptr;
        for (const auto& r : ctx.resources) {
            if (r.usage && r.usage->slot == "environment") env = &r;
            if (r.usage && r.usage->slot == "previous") previous = &r;
        }
        const bool cube = env && env->desc->type == ResourceType::Cube;
        // A graph built in code has not been through the loader's check.
        if (const auto problem = skyboxFadeProblem(env ? env->desc : nullptr, previous ? previous->desc : nullptr))
            throw ExecutorError(detail::passError(*ctx.pass, previous->desc->name, *problem));
        // Which textures, if any, decide the pipeline: each mode binds only what it samples. The
        // environment's type picks cubemap or equirect sampling; the `sampling` param only states
        // it, and the type's usage check refuses one that disagrees.
        const int mode = !env ? 0 : previous ? 3 : cube ? 1 : 2;
        GraphicsPipelineRecipe recipe;
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/skybox.vert");
        recipe.fragment = compileShader(*ctx.shaders, VK_SHADER_STAGE_FRAGMENT_BIT, "passes/skybox.frag",
                                        {{"SKY_MODE", std::to_string(mode)},
                                         {"SKY_OUTPUT_DIRECTION", outputDirection_ ? "1" : "0"}});
        recipe.renderPass = ctx.renderPass;
        recipe.depthTest = true;
        recipe.depthWrite = false;
        recipe.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
        if (mode != 0)
            recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
        if (mode == 3)
            recipe.bindings.push_back({1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
        recipe.pushConstantBytes = sizeof(Push);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
        mode_ = mode;
    }

    /// Every handle comes from the RecordContext (push descriptors): an imported image's swap
    /// keeps this implementation.
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }

    void record(const RecordContext& ctx) override {
        const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr;
        const CameraView view = cameraView(scene, ctx.renderArea);
        const double rotation = math::radians(
            scene && scene->environment ? scene->environment->rotationDeg : rotationDeg_);
        const double tanHalf = std::tan(math::radians(view.fovYDeg) / 2.0);
        Push push{};
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) push.cameraToWorld[c][r] = float(view.cameraToWorld[c][r]);
        push.projection[0] = float(view.aspect * tanHalf);
        push.projection[1] = float(tanHalf);
        push.projection[2] = float(std::sin(rotation));
        push.projection[3] = float(std::cos(rotation));
        push.mode[0] = mode_;
        const auto sun = scene && scene->environment ? scene->environment->sunDirection
                                                     : SceneEnvironment{}.sunDirection;
        for (int i = 0; i < 3; ++i) push.sun[i] = float(sun[size_t(i)]);
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        if (mode_ != 0) {
            const BoundResource* env = ctx.slot("environment");
            push.environment[0] = float(env->extent.height);
            const SkyFade* fade = ctx.frame ? ctx.frame->get<SkyFade>() : nullptr;
            push.environment[1] = float(std::clamp(fade ? fade->current : 1.0, 0.0, 1.0));
            const VkDescriptorImageInfo image{mode_ == 2 ? ctx.repeatSampler : ctx.linearSampler, env->view,
                                              env->usage->layout};
            VkDescriptorImageInfo previousImage{};
            std::array<VkWriteDescriptorSet, 2> writes{sampledImageWrite(0, &image), VkWriteDescriptorSet{}};
            if (mode_ == 3) {
                const BoundResource* previous = ctx.slot("previous");
                previousImage = {ctx.linearSampler, previous->view, previous->usage->layout};
                writes[1] = sampledImageWrite(1, &previousImage);
            }
            pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.layout.get(), 0,
                             mode_ == 3 ? 2u : 1u, writes.data());
        }
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           0, sizeof(push), &push);
        setViewportAndScissor(ctx.cmd, ctx.renderArea);
        vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
    }

private:
    struct Push {  // matches `Sky` in shaders/passes/skybox.{vert,frag}
        float cameraToWorld[3][4];
        float projection[4];
        int32_t mode[4];
        float environment[4];
        float sun[4];
    };
    double rotationDeg_;
    bool outputDirection_;
    int mode_ = 0;
    GraphicsPipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

std::unique_ptr<PassImplementation> makeSkyboxPass(const PassDesc& desc) {
    return std::make_unique<SkyboxPass>(desc);
}

}  // namespace skygraph::passes
