#include "checker_pass.hpp"

#include <skygraph/pipeline_builder.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>

namespace window_example {
namespace {

using namespace skygraph;

struct CheckerParams {
    float colorA[4];
    float colorB[4];
    int32_t tile;
};

std::string readShader(const char* relativePath) {
    const std::string path = std::string(WINDOW_DATA_DIR) + "/" + relativePath;
    std::ifstream in(path);
    if (!in) throw ExecutorError("cannot read shader '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

class CheckerPass final : public PassImplementation {
public:
    explicit CheckerPass(const PassDesc& desc) {
        // The compiler ran checkerPassType()'s validator on these params: they are well formed.
        const nlohmann::json& params = desc.params.json();
        const nlohmann::json& colors = params.at("colors");
        for (int c = 0; c < 3; ++c) {
            params_.colorA[c] = colors[0][c].get<float>();
            params_.colorB[c] = colors[1][c].get<float>();
        }
        params_.colorA[3] = params_.colorB[3] = 1.0f;
        params_.tile = params.at("tile").get<int32_t>();
    }

    void createPipelines(const PipelineContext& ctx) override {
        GraphicsPipelineRecipe recipe;
        // skygraph's installed fullscreen triangle; the fragment shader is the application's.
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/fullscreen.vert");
        recipe.fragment = ctx.shaders->compile(VK_SHADER_STAGE_FRAGMENT_BIT, readShader("shaders/checker.frag"),
                                               "checker.frag");
        recipe.renderPass = ctx.renderPass;
        recipe.pushConstantBytes = sizeof(CheckerParams);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
    }

    void record(const RecordContext& ctx) override {
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           0, sizeof(params_), &params_);
        setViewportAndScissor(ctx.cmd, ctx.renderArea);
        vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
    }

    // It binds no resource at all: an importImage swap keeps the pass.
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }

private:
    CheckerParams params_{};
    GraphicsPipeline pipeline_;
};

bool isColor(const nlohmann::json& value) {
    if (!value.is_array() || value.size() != 3) return false;
    for (const auto& c : value)
        if (!c.is_number() || c.get<double>() < 0.0 || c.get<double>() > 64.0) return false;
    return true;
}

}  // namespace

skygraph::PassTypeInfo checkerPassType() {
    using namespace skygraph;
    PassTypeInfo info;
    info.name = "CheckerPass";
    info.slots = {SlotDecl{.name = "output", .stage = Stage::ColorAttachment, .accesses = {Access::Write},
                           .doc = "the checkerboard (linear colours)"}};
    info.validateParams = [](const nlohmann::json& params) {
        std::vector<ParamError> errors;
        for (const auto& [key, value] : params.items()) {
            if (key == "colors") {
                if (!value.is_array() || value.size() != 2 || !isColor(value[0]) || !isColor(value[1]))
                    errors.push_back(ParamError::forKey(
                        key, "expected two [r, g, b] colours, each channel in [0, 64], got " + value.dump()));
            } else if (key == "tile") {
                if (!value.is_number_integer() || value.get<int64_t>() < 1 || value.get<int64_t>() > 4096)
                    errors.push_back(ParamError::forKey(key, "expected an integer in [1, 4096], got " + value.dump()));
            } else {
                errors.push_back(ParamError::forKey(key, "unknown parameter; expected colors, tile"));
            }
        }
        for (const char* required : {"colors", "tile"})
            if (!params.contains(required))
                errors.push_back(ParamError::forKey(required, "required parameter is missing"));
        return errors;
    };
    info.doc = "Tiles of two linear colours (the window example's own pass).";
    return info;
}

std::unique_ptr<skygraph::PassImplementation> makeCheckerPass(const skygraph::PassDesc& desc) {
    return std::make_unique<CheckerPass>(desc);
}

}  // namespace window_example
