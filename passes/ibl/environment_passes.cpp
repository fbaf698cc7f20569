// Recording code of the environment pipeline (graphs/ibl.json): equirect -> cube faces, the
// cube's mip chain, irradiance, GGX prefiltered specular and the split-sum BRDF table. Each
// is one compute shader under shaders/passes/ibl/; docs/environment.md explains the math.
#include "../builtin_passes.hpp"
#include "ibl_compute.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>

namespace skygraph::passes {
namespace {

using ibl::IblComputeProgram;

/// Filtered importance sampling reads each sample one level blurrier than its footprint
/// (Krivanek & Colbert's +1): fewer artefacts from texels that no sample hits.
constexpr float kLodBias = 1.0f;

const BoundResource& requireSlot(const RecordContext& ctx, std::string_view slot, size_t nth = 0) {
    const BoundResource* r = ctx.slot(slot, nth);
    if (!r) throw ExecutorError("pass '" + ctx.desc->name + "': slot '" + std::string(slot) + "' is not bound");
    return *r;
}

const BoundResource& requireSlot(const PipelineContext& ctx, std::string_view slot) {
    const BoundResource* r = ibl::findSlot(ctx, slot);
    if (!r) throw ExecutorError("pass '" + ctx.desc->name + "': slot '" + std::string(slot) + "' is not bound");
    return *r;
}

uint32_t samplesParam(const PassDesc& desc, uint32_t fallback) {
    return desc.params.value("samples", fallback);
}

class EquirectToCubemapPass final : public PassImplementation {
public:
    explicit EquirectToCubemapPass(const PassDesc& desc) : supersample_(desc.params.value("supersample", 2)) {}

    void createPipelines(const PipelineContext& ctx) override {
        program_.create(ctx, "passes/ibl/equirect_to_cube.comp", requireSlot(ctx, "cubemap"), true, sizeof(Push));
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& cube = requireSlot(ctx, "cubemap");
        program_.bind(ctx, &requireSlot(ctx, "equirect"), ctx.repeatSampler, cube);
        const Push push{int32_t(cube.extent.width), supersample_};
        program_.dispatch(ctx.cmd, &push, sizeof(push), cube.extent.width, cube.extent.height, 6);
    }

private:
    struct Push {
        int32_t faceSize, supersample;
    };
    int32_t supersample_;
    IblComputeProgram program_;
};

class CubemapMipPass final : public PassImplementation {
public:
    explicit CubemapMipPass(const PassDesc&) {}

    void createPipelines(const PipelineContext& ctx) override {
        program_.create(ctx, "passes/ibl/cubemap_mip.comp", requireSlot(ctx, "target"), true, sizeof(int32_t));
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& target = requireSlot(ctx, "target");
        program_.bind(ctx, &requireSlot(ctx, "source"), ctx.linearSampler, target);
        const auto size = int32_t(target.extent.width);
        program_.dispatch(ctx.cmd, &size, sizeof(size), target.extent.width, target.extent.height, 6);
    }

private:
    IblComputeProgram program_;
};

class IrradiancePass final : public PassImplementation {
public:
    explicit IrradiancePass(const PassDesc& desc) : samples_(samplesParam(desc, 512)) {}

    void createPipelines(const PipelineContext& ctx) override {
        program_.create(ctx, "passes/ibl/irradiance.comp", requireSlot(ctx, "irradiance"), true, sizeof(Push));
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& environment = requireSlot(ctx, "environment");
        const BoundResource& target = requireSlot(ctx, "irradiance");
        program_.bind(ctx, &environment, ctx.linearSampler, target);
        const Push push{int32_t(target.extent.width), int32_t(samples_), float(environment.extent.width), kLodBias};
        program_.dispatch(ctx.cmd, &push, sizeof(push), target.extent.width, target.extent.height, 6);
    }

private:
    struct Push {
        int32_t faceSize, samples;
        float environmentSize, lodBias;
    };
    uint32_t samples_;
    IblComputeProgram program_;
};

/// Perceptual roughness of mip `mip` of a prefiltered cube with `mips` levels: linear,
/// mip / (mips - 1), so mip 0 is the mirror and the last mip roughness 1.
float roughnessOfMip(uint32_t mip, uint32_t mips) { return mips <= 1 ? 0.0f : float(mip) / float(mips - 1); }

class PrefilterPass final : public PassImplementation {
public:
    explicit PrefilterPass(const PassDesc& desc) : samples_(samplesParam(desc, 1024)) {}

    void createPipelines(const PipelineContext& ctx) override {
        program_.create(ctx, "passes/ibl/prefilter.comp", requireSlot(ctx, "prefiltered"), true, sizeof(Push));
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& environment = requireSlot(ctx, "environment");
        for (size_t nth = 0; const BoundResource* target = ctx.slot("prefiltered", nth); ++nth) {
            program_.bind(ctx, &environment, ctx.linearSampler, *target);
            const uint32_t mip = target->usage->range.baseMip;
            const Push push{int32_t(target->extent.width), int32_t(samples_), float(environment.extent.width),
                            roughnessOfMip(mip, mipCount(*target)), kLodBias};
            program_.dispatch(ctx.cmd, &push, sizeof(push), target->extent.width, target->extent.height, 6);
        }
    }

private:
    struct Push {
        int32_t faceSize, samples;
        float environmentSize, roughness, lodBias;
    };
    /// The prefiltered resource's level count (a full chain when the graph says "full").
    static uint32_t mipCount(const BoundResource& target) {
        if (target.desc->mips != 0) return target.desc->mips;
        const uint32_t base = target.extent.width << target.usage->range.baseMip;
        return uint32_t(std::bit_width(std::max(base, 1u)));
    }
    uint32_t samples_;
    IblComputeProgram program_;
};

class BrdfLutPass final : public PassImplementation {
public:
    explicit BrdfLutPass(const PassDesc& desc) : samples_(samplesParam(desc, 512)) {}

    void createPipelines(const PipelineContext& ctx) override {
        program_.create(ctx, "passes/ibl/brdf_lut.comp", requireSlot(ctx, "lut"), false, sizeof(Push));
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& lut = requireSlot(ctx, "lut");
        program_.bind(ctx, nullptr, VK_NULL_HANDLE, lut);
        const Push push{int32_t(lut.extent.width), int32_t(lut.extent.height), int32_t(samples_)};
        program_.dispatch(ctx.cmd, &push, sizeof(push), lut.extent.width, lut.extent.height, 1);
    }

private:
    struct Push {
        int32_t width, height, samples;
    };
    uint32_t samples_;
    IblComputeProgram program_;
};

}  // namespace

std::unique_ptr<PassImplementation> makeEquirectToCubemapPass(const PassDesc& desc) {
    return std::make_unique<EquirectToCubemapPass>(desc);
}
std::unique_ptr<PassImplementation> makeCubemapMipPass(const PassDesc& desc) {
    return std::make_unique<CubemapMipPass>(desc);
}
std::unique_ptr<PassImplementation> makeIrradiancePass(const PassDesc& desc) {
    return std::make_unique<IrradiancePass>(desc);
}
std::unique_ptr<PassImplementation> makePrefilterPass(const PassDesc& desc) {
    return std::make_unique<PrefilterPass>(desc);
}
std::unique_ptr<PassImplementation> makeBrdfLutPass(const PassDesc& desc) {
    return std::make_unique<BrdfLutPass>(desc);
}

}  // namespace skygraph::passes
