// The declarations of the environment pipeline's passes (graphs/ibl.json): their slots and
// params (recording code: environment_passes.cpp).
#include "builtin_pass_types.hpp"
#include "ibl_formats.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo equirectToCubemapPassType() {
    return {"EquirectToCubemapPass",
            {ofTypes(slot("equirect", Stage::Compute, {Access::Read}, BindAs::Sampled, "equirectangular HDR source"),
                     {ResourceType::Image2D}),
             ofTypes(slot("cubemap", Stage::Compute, {Access::Write}, BindAs::Storage, "cube faces, one mip"),
                     {ResourceType::Cube})},
            false,
            rules({{"supersample", integerIn(1, 16)}}),
            "Resamples an equirect map into cube faces (Vulkan face selection rules).",
            {},
            iblStorageCheck("EquirectToCubemapPass", "cubemap")};
}

PassTypeInfo cubemapMipPassType() {
    return {"CubemapMipPass",
            {ofTypes(slot("source", Stage::Compute, {Access::Read}, BindAs::Sampled, "the level above"),
                     {ResourceType::Cube}),
             ofTypes(slot("target", Stage::Compute, {Access::Write}, BindAs::Storage, "the level written"),
                     {ResourceType::Cube})},
            false,
            rules({}),
            "Writes one mip level of a cubemap from the level above.",
            {},
            iblStorageCheck("CubemapMipPass", "target")};
}

PassTypeInfo irradiancePassType() {
    return {"IrradiancePass",
            {ofTypes(slot("environment", Stage::Compute, {Access::Read}, BindAs::Sampled,
                          "environment cubemap with mips"),
                     {ResourceType::Cube}),
             ofTypes(slot("irradiance", Stage::Compute, {Access::Write}, BindAs::Storage, "small irradiance cube"),
                     {ResourceType::Cube})},
            false,
            rules({{"samples", integerIn(1, 1 << 20)}}),
            "Cosine-weighted diffuse convolution.",
            {},
            iblStorageCheck("IrradiancePass", "irradiance")};
}

PassTypeInfo prefilterPassType() {
    return {"PrefilterPass",
            {ofTypes(slot("environment", Stage::Compute, {Access::Read}, BindAs::Sampled,
                          "environment cubemap with mips"),
                     {ResourceType::Cube}),
             ofTypes(slot("prefiltered", Stage::Compute, {Access::Write}, BindAs::Storage,
                          "one usage per mip; roughness = mip / (mips - 1)", false, true),
                     {ResourceType::Cube})},
            false,
            rules({{"samples", integerIn(1, 1 << 20)}}),
            "GGX-prefiltered specular, one roughness per mip.",
            {},
            iblStorageCheck("PrefilterPass", "prefiltered", true)};
}

PassTypeInfo brdfLutPassType() {
    return {"BrdfLutPass",
            {ofTypes(slot("lut", Stage::Compute, {Access::Write}, BindAs::Storage, "R16G16_SFLOAT split-sum table"),
                     {ResourceType::Image2D})},
            false,
            rules({{"samples", integerIn(1, 1 << 20)}}),
            "Split-sum BRDF integration table.",
            {},
            iblStorageCheck("BrdfLutPass", "lut")};
}

}  // namespace skygraph::passes
