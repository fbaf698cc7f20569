// A test-only pass that samples a cube (`environment`) at fixed directions into row 0 of an
// image (`probe`): one texel per direction, for tests that check what a cube holds where.
#pragma once

#include "analytic_environment.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>

#include <sstream>
#include <utility>
#include <vector>

namespace skygraph::test {

class CubeProbe final : public PassImplementation {
public:
    /// `keepsHandles`: what keepsSlotHandles() says (the probe reads them while recording,
    /// so either answer is true of it; false lets an import swap keep it).
    explicit CubeProbe(std::vector<Dir> dirs, bool keepsHandles = true)
        : dirs_(std::move(dirs)), keepsHandles_(keepsHandles) {}

    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return keepsHandles_; }

    void createPipelines(const PipelineContext& ctx) override {
        std::ostringstream src;
        src << "#version 450\nlayout(local_size_x = 1) in;\n"
               "layout(set = 0, binding = 0) uniform samplerCube environment;\n"
               "layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D probe;\n"
            << "const vec3 dirs[" << dirs_.size() << "] = vec3[](";
        for (size_t i = 0; i < dirs_.size(); ++i)
            src << (i ? ", " : "") << "vec3(" << dirs_[i].x << ", " << dirs_[i].y << ", " << dirs_[i].z << ")";
        src << ");\nvoid main() {\n  int i = int(gl_GlobalInvocationID.x);\n"
               "  imageStore(probe, ivec2(i, 0), textureLod(environment, dirs[i], 0.0));\n}\n";
        ComputePipelineRecipe recipe;
        recipe.compute = ctx.shaders->compile(VK_SHADER_STAGE_COMPUTE_BIT, src.str(), "cube_probe.comp");
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
                           {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
        pipeline_ = createComputePipeline(ctx.device, recipe);
        push_ = pushDescriptorFunction(ctx.device);
        keptSlots_.clear();
        for (const std::span<const BoundResource> slot : ctx.frameSlots) keptSlots_.push_back(slot.data());
    }

    void record(const RecordContext& ctx) override {
        // PipelineContext promises that what it points to outlives every call of the pass: a
        // pass may keep its BoundResources' addresses, and read them through those now.
        if (ctx.frameSlot >= keptSlots_.size() || keptSlots_[ctx.frameSlot] != ctx.resources.data() ||
            keptSlots_[ctx.frameSlot]->desc != ctx.resources[0].desc)
            ++recordsAwayFromKeptSlots;
        const BoundResource* env = ctx.slot("environment");
        const BoundResource* out = ctx.slot("probe");
        VkDescriptorImageInfo images[2] = {{ctx.linearSampler, env->view, env->usage->layout},
                                           {VK_NULL_HANDLE, out->view, out->usage->layout}};
        VkWriteDescriptorSet writes[2] = {sampledImageWrite(0, &images[0]), sampledImageWrite(1, &images[1])};
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
        push_(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout.get(), 0, 2, writes);
        vkCmdDispatch(ctx.cmd, uint32_t(dirs_.size()), 1, 1);
    }

    /// The declaration of a pass type `type` recorded by a CubeProbe.
    [[nodiscard]] static PassTypeInfo typeInfo(std::string type) {
        return {std::move(type),
                {SlotDecl{"environment", Stage::Compute, {Access::Read}, BindAs::Sampled, false, false, "cube"},
                 SlotDecl{"probe", Stage::Compute, {Access::Write}, BindAs::Storage, false, false, "values"}},
                false, {}, "samples a cube at fixed directions"};
    }

    /// Records whose resources were not where createPipelines was shown them, by any probe.
    static inline int recordsAwayFromKeptSlots = 0;

private:
    std::vector<Dir> dirs_;
    bool keepsHandles_ = true;
    ComputePipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR push_ = nullptr;
    std::vector<const BoundResource*> keptSlots_;  // per frame slot
};

}  // namespace skygraph::test
