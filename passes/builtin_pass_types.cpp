// Declarations of the built-in pass types: their slots and parameters, as plain data.
// Recording code lives with the executor; this file is what the compiler checks against.
#include <skygraph/pass_registry.hpp>

#include <nlohmann/json.hpp>

namespace skygraph {
namespace {

using nlohmann::json;

SlotDecl slot(std::string name, Stage stage, std::vector<Access> accesses, BindAs as,
              std::string doc, bool optional = false, bool repeated = false) {
    return SlotDecl{std::move(name), stage, std::move(accesses), as, optional, repeated, std::move(doc)};
}

/// Checks the keys of a params object against a list of (key, checker) pairs.
struct ParamRule {
    std::string key;
    std::function<std::string(const json&)> check;  // empty string = fine
};

ParamValidator rules(std::vector<ParamRule> list) {
    return [list = std::move(list)](const json& params) {
        std::vector<ParamError> errors;
        for (const auto& item : params.items()) {
            // Named copies, not structured bindings: clang 14 (the fuzz build) cannot capture those.
            const std::string& key = item.key();
            const json& value = item.value();
            auto it = std::find_if(list.begin(), list.end(), [&](const ParamRule& r) { return r.key == key; });
            if (it == list.end()) {
                std::string known;
                for (const auto& r : list) known += (known.empty() ? "" : ", ") + r.key;
                errors.push_back({key, "unknown parameter; expected " + (known.empty() ? "none" : known)});
                continue;
            }
            if (std::string problem = it->check(value); !problem.empty())
                errors.push_back({key, problem});
        }
        return errors;
    };
}

std::function<std::string(const json&)> oneOf(std::vector<std::string> values) {
    return [values = std::move(values)](const json& v) -> std::string {
        if (v.is_string() && std::find(values.begin(), values.end(), v.get<std::string>()) != values.end())
            return {};
        std::string list;
        for (const auto& s : values) list += (list.empty() ? "" : ", ") + s;
        return "expected one of " + list + ", got " + v.dump();
    };
}

std::function<std::string(const json&)> numberIn(double lo, double hi) {
    return [lo, hi](const json& v) -> std::string {
        if (v.is_number() && v.get<double>() >= lo && v.get<double>() <= hi) return {};
        return "expected a number in [" + json(lo).dump() + ", " + json(hi).dump() + "], got " + v.dump();
    };
}

std::function<std::string(const json&)> integerIn(int64_t lo, int64_t hi) {
    return [lo, hi](const json& v) -> std::string {
        if (v.is_number_integer() && v.get<int64_t>() >= lo && v.get<int64_t>() <= hi) return {};
        return "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v.dump();
    };
}

}  // namespace

void registerBuiltinPassTypes(PassRegistry& r) {
    const auto RW = std::vector{Access::ReadWrite};
    const auto R = std::vector{Access::Read};
    const auto W = std::vector{Access::Write};
    const auto W_RW = std::vector{Access::Write, Access::ReadWrite};

    r.add({"Generic", {}, true, {},
           "Performs every declared access for real; for tests and random graphs."});

    r.add({"ForwardPass",
           {slot("color", Stage::ColorAttachment, W_RW, BindAs::Default, "HDR target the objects shade into"),
            slot("depth", Stage::DepthAttachment, W_RW, BindAs::Default, "reverse-Z depth, cleared to 0"),
            slot("environment", Stage::Fragment, R, BindAs::Sampled, "environment cubemap", true),
            slot("irradiance", Stage::Fragment, R, BindAs::Sampled, "diffuse IBL", true),
            slot("prefiltered", Stage::Fragment, R, BindAs::Sampled, "specular IBL, one roughness per mip", true),
            slot("brdf_lut", Stage::Fragment, R, BindAs::Sampled, "split-sum BRDF table", true)},
           false, rules({{"debug_view", oneOf({"none", "normal", "metallic", "roughness", "ao"})}}),
           "Metal/rough GGX shading of the scene's objects."});

    r.add({"SkyboxPass",
           {slot("depth", Stage::DepthAttachment, R, BindAs::Default, "rejects covered pixels (GREATER_OR_EQUAL)"),
            slot("color", Stage::ColorAttachment, RW, BindAs::Default, "HDR target; sky fills uncovered pixels"),
            slot("environment", Stage::Fragment, R, BindAs::Sampled, "cubemap or equirect environment", true)},
           false,
           rules({{"sampling", oneOf({"cubemap", "equirect"})},
                  {"rotation_deg", numberIn(-360.0, 360.0)},
                  {"output", oneOf({"radiance", "direction"})}}),
           "Fullscreen-triangle sky at the reverse-Z far plane."});

    r.add({"TonemappingPass",
           {slot("hdr", Stage::Fragment, R, BindAs::Sampled, "HDR input"),
            slot("output", Stage::ColorAttachment, W, BindAs::Default, "display-referred output")},
           false,
           rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                  {"exposure_ev", numberIn(-64.0, 64.0)}}),
           "Exposure (2^EV), a tone curve, and sRGB encoding from the output format."});

    r.add({"TonemappingComputePass",
           {slot("hdr", Stage::Compute, R, BindAs::Sampled, "HDR input"),
            slot("output", Stage::Compute, W, BindAs::Storage,
                 "display-referred output: R8G8B8A8_UNORM (or a float format), sRGB-encoded by the shader")},
           false,
           rules({{"operator", oneOf({"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"})},
                  {"exposure_ev", numberIn(-64.0, 64.0)}}),
           "TonemappingPass as a compute shader (same math), writing a storage image with sRGB encoded by the shader."});

    r.add({"PathTracePass",
           {slot("accumulation", Stage::Compute, RW, BindAs::Storage, "running sum of samples"),
            slot("environment", Stage::Compute, R, BindAs::Sampled, "environment", true)},
           false, rules({{"samples_per_frame", integerIn(1, 4096)}, {"max_bounces", integerIn(1, 64)}}),
           "Progressive path tracer of the scene's analytic objects."});

    r.add({"EquirectToCubemapPass",
           {slot("equirect", Stage::Compute, R, BindAs::Sampled, "equirectangular HDR source"),
            slot("cubemap", Stage::Compute, W, BindAs::Storage, "cube faces, one mip")},
           false, rules({{"supersample", integerIn(1, 16)}}),
           "Resamples an equirect map into cube faces (Vulkan face selection rules)."});

    r.add({"CubemapMipPass",
           {slot("source", Stage::Compute, R, BindAs::Sampled, "the level above"),
            slot("target", Stage::Compute, W, BindAs::Storage, "the level written")},
           false, rules({}), "Writes one mip level of a cubemap from the level above."});

    r.add({"IrradiancePass",
           {slot("environment", Stage::Compute, R, BindAs::Sampled, "environment cubemap with mips"),
            slot("irradiance", Stage::Compute, W, BindAs::Storage, "small irradiance cube")},
           false, rules({{"samples", integerIn(1, 1 << 20)}}), "Cosine-weighted diffuse convolution."});

    r.add({"PrefilterPass",
           {slot("environment", Stage::Compute, R, BindAs::Sampled, "environment cubemap with mips"),
            slot("prefiltered", Stage::Compute, W, BindAs::Storage,
                 "one usage per mip; roughness = mip / (mips - 1)", false, true)},
           false, rules({{"samples", integerIn(1, 1 << 20)}}), "GGX-prefiltered specular, one roughness per mip."});

    r.add({"BrdfLutPass",
           {slot("lut", Stage::Compute, W, BindAs::Storage, "R16G16_SFLOAT split-sum table")},
           false, rules({{"samples", integerIn(1, 1 << 20)}}), "Split-sum BRDF integration table."});
}

}  // namespace skygraph
