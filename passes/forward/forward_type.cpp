// ForwardPass's declaration: its slots and params (recording code: forward_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo forwardPassType() {
    return {"ForwardPass",
            {slot("color", Stage::ColorAttachment, {Access::Write, Access::ReadWrite}, BindAs::Default,
                  "HDR target the objects shade into"),
             slot("depth", Stage::DepthAttachment, {Access::Write, Access::ReadWrite}, BindAs::Default,
                  "reverse-Z depth, cleared to 0"),
             ofTypes(slot("environment", Stage::Fragment, {Access::Read}, BindAs::Sampled, "environment cubemap", true),
                     {ResourceType::Cube}),
             ofTypes(slot("irradiance", Stage::Fragment, {Access::Read}, BindAs::Sampled, "diffuse IBL", true),
                     {ResourceType::Cube}),
             ofTypes(slot("prefiltered", Stage::Fragment, {Access::Read}, BindAs::Sampled,
                          "specular IBL, one roughness per mip", true),
                     {ResourceType::Cube}),
             ofTypes(slot("brdf_lut", Stage::Fragment, {Access::Read}, BindAs::Sampled, "split-sum BRDF table", true),
                     {ResourceType::Image2D})},
            false,
            rules({{"debug_view", oneOf({"none", "normal", "metallic", "roughness", "ao"})}}),
            "Metal/rough GGX shading of the scene's objects."};
}

}  // namespace skygraph::passes
