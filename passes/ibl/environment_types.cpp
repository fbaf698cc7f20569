// The declarations of the environment pipeline's passes (graphs/ibl.json): their slots and
// params (recording code: environment_passes.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo equirectToCubemapPassType() {
    return {"EquirectToCubemapPass",
            {slot("equirect", Stage::Compute, {Access::Read}, BindAs::Sampled, "equirectangular HDR source"),
             slot("cubemap", Stage::Compute, {Access::Write}, BindAs::Storage, "cube faces, one mip")},
            false, rules({{"supersample", integerIn(1, 16)}}),
            "Resamples an equirect map into cube faces (Vulkan face selection rules)."};
}

PassTypeInfo cubemapMipPassType() {
    return {"CubemapMipPass",
            {slot("source", Stage::Compute, {Access::Read}, BindAs::Sampled, "the level above"),
             slot("target", Stage::Compute, {Access::Write}, BindAs::Storage, "the level written")},
            false, rules({}), "Writes one mip level of a cubemap from the level above."};
}

PassTypeInfo irradiancePassType() {
    return {"IrradiancePass",
            {slot("environment", Stage::Compute, {Access::Read}, BindAs::Sampled, "environment cubemap with mips"),
             slot("irradiance", Stage::Compute, {Access::Write}, BindAs::Storage, "small irradiance cube")},
            false, rules({{"samples", integerIn(1, 1 << 20)}}), "Cosine-weighted diffuse convolution."};
}

PassTypeInfo prefilterPassType() {
    return {"PrefilterPass",
            {slot("environment", Stage::Compute, {Access::Read}, BindAs::Sampled, "environment cubemap with mips"),
             slot("prefiltered", Stage::Compute, {Access::Write}, BindAs::Storage,
                  "one usage per mip; roughness = mip / (mips - 1)", false, true)},
            false, rules({{"samples", integerIn(1, 1 << 20)}}), "GGX-prefiltered specular, one roughness per mip."};
}

PassTypeInfo brdfLutPassType() {
    return {"BrdfLutPass",
            {slot("lut", Stage::Compute, {Access::Write}, BindAs::Storage, "R16G16_SFLOAT split-sum table")},
            false, rules({{"samples", integerIn(1, 1 << 20)}}), "Split-sum BRDF integration table."};
}

}  // namespace skygraph::passes
