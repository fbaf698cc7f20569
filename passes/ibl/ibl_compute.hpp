// What the environment pipeline's compute passes share: one compute pipeline with a
// push-descriptor set of (optional) one sampled image at binding 0 and one storage image at
// binding 1, the storage format picked from the bound resource, and dispatch helpers.
#pragma once

#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>

#include <string>
#include <string_view>

namespace skygraph::passes::ibl {

/// The first bound usage of `slot` among a pipeline context's resources, or nullptr.
[[nodiscard]] const BoundResource* findSlot(const PipelineContext& ctx, std::string_view slot);

/// The GLSL storage image format qualifier (e.g. "rgba16f") of `resource`'s format. Throws
/// ExecutorError naming the pass and resource for formats a storage image cannot be.
[[nodiscard]] std::string storageQualifier(const PassDesc& pass, const BoundResource& resource);

/// One compute pipeline: `sampled` at binding 0 (when the shader has one) and the storage
/// image at binding 1 (binding 0 when there is no sampled input). Owns its pipeline objects.
class IblComputeProgram {
public:
    /// Compiles shaders/<shader> with OUT_FORMAT set for `storage`; throws ExecutorError.
    void create(const PipelineContext& ctx, const std::string& shader, const BoundResource& storage,
                bool hasSampledInput, uint32_t pushBytes);

    /// Binds the pipeline and pushes the descriptors: `sampled` may be null when the program
    /// has no sampled input. The handles are only read during the call.
    void bind(const RecordContext& ctx, const BoundResource* sampled, VkSampler sampler,
              const BoundResource& storage) const;

    /// Pushes `bytes` of push constants (at offset 0) and dispatches 8x8 groups over
    /// width x height x layers.
    void dispatch(VkCommandBuffer cmd, const void* push, uint32_t bytes, uint32_t width, uint32_t height,
                  uint32_t layers) const;

private:
    ComputePipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
    bool hasSampledInput_ = true;
};

}  // namespace skygraph::passes::ibl
