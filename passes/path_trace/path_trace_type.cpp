// PathTracePass's declaration: its slots and params (recording code: path_trace_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo pathTracePassType() {
    return {"PathTracePass",
            {ofTypes(slot("accumulation", Stage::Compute, {Access::ReadWrite}, BindAs::Storage,
                          "running sum of samples"),
                     {ResourceType::Image2D}),
             ofTypes(slot("environment", Stage::Compute, {Access::Read}, BindAs::Sampled, "environment", true),
                     {ResourceType::Image2D})},
            false,
            rules({{"samples_per_frame", integerIn(1, 4096)}, {"max_bounces", integerIn(1, 64)}}),
            "Progressive path tracer of the scene's analytic objects."};
}

}  // namespace skygraph::passes
