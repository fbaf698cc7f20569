#include "vignette_pass.hpp"

#include <skygraph/pipeline_builder.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace embed {
namespace {

using namespace skygraph;

std::string readShader(const char* relativePath) {
    const std::string path = std::string(EMBED_DATA_DIR) + "/" + relativePath;
    std::ifstream in(path);
    if (!in) throw ExecutorError("cannot read shader '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

class VignettePass final : public PassImplementation {
public:
    explicit VignettePass(const PassDesc& desc) : strength_(desc.params.value("strength", 0.5)) {}

    void createPipelines(const PipelineContext& ctx) override {
        GraphicsPipelineRecipe recipe;
        // skygraph's installed fullscreen triangle, found through the renderer's shader
        // directory; the fragment shader is the application's own.
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/fullscreen.vert");
        recipe.fragment = ctx.shaders->compile(VK_SHADER_STAGE_FRAGMENT_BIT, readShader("shaders/vignette.frag"),
                                               "vignette.frag");
        recipe.renderPass = ctx.renderPass;
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
        recipe.pushConstantBytes = sizeof(float);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource* input = ctx.slot("input");
        const VkDescriptorImageInfo image{ctx.linearSampler, input->view, input->usage->layout};
        const VkWriteDescriptorSet write = sampledImageWrite(0, &image);
        const float strength = static_cast<float>(strength_);
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.layout.get(), 0, 1, &write);
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           0, sizeof(strength), &strength);
        setViewportAndScissor(ctx.cmd, ctx.renderArea);
        vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
    }

    // The input's view comes from the RecordContext each time: an importImage swap keeps the pass.
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }

private:
    double strength_;
    GraphicsPipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

skygraph::PassTypeInfo vignettePassType() {
    using namespace skygraph;
    PassTypeInfo info;
    info.name = "VignettePass";
    info.slots = {
        SlotDecl{.name = "input", .stage = Stage::Fragment, .accesses = {Access::Read}, .as = BindAs::Sampled,
                 .doc = "image to darken"},
        SlotDecl{.name = "output", .stage = Stage::ColorAttachment, .accesses = {Access::Write}, .doc = "result"},
    };
    info.validateParams = [](const nlohmann::json& params) {
        std::vector<ParamError> errors;
        for (const auto& [key, value] : params.items()) {
            if (key != "strength") errors.push_back(ParamError::forKey(key, "unknown parameter; expected strength"));
            else if (!value.is_number() || value.get<double>() < 0.0 || value.get<double>() > 1.0)
                errors.push_back(ParamError::forKey(key, "expected a number in [0, 1], got " + value.dump()));
        }
        return errors;
    };
    info.doc = "Darkens towards the corners (the embedding example's own pass).";
    return info;
}

std::unique_ptr<skygraph::PassImplementation> makeVignettePass(const skygraph::PassDesc& desc) {
    return std::make_unique<VignettePass>(desc);
}

double vignetteFactor(double strength, uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
    const double u = (x + 0.5) / width - 0.5, v = (y + 0.5) / height - 0.5;
    const double d2 = (u * u + v * v) / 0.5;
    return 1.0 - strength * d2;
}

}  // namespace embed
