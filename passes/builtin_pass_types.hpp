// Declarations of the built-in pass types (slots, params), one function per type, each
// defined beside its pass's recording code (forward/forward_type.cpp, ...).
// registerBuiltinPassTypes() (builtin_pass_types.cpp) adds them all.
#pragma once

#include <skygraph/pass_registry.hpp>

namespace skygraph::passes {

/// Any usages, no slots; its recording code is generic/generic_pass.cpp.
[[nodiscard]] PassTypeInfo genericPassType();
[[nodiscard]] PassTypeInfo forwardPassType();
[[nodiscard]] PassTypeInfo skyboxPassType();
[[nodiscard]] PassTypeInfo tonemappingPassType();
[[nodiscard]] PassTypeInfo tonemappingComputePassType();
[[nodiscard]] PassTypeInfo pathTracePassType();
[[nodiscard]] PassTypeInfo imguiPassType();
// The environment pipeline (ibl/environment_types.cpp).
[[nodiscard]] PassTypeInfo equirectToCubemapPassType();
[[nodiscard]] PassTypeInfo cubemapMipPassType();
[[nodiscard]] PassTypeInfo irradiancePassType();
[[nodiscard]] PassTypeInfo prefilterPassType();
[[nodiscard]] PassTypeInfo brdfLutPassType();
/// Copies staged pixels into a resource (upload/upload_type.cpp).
[[nodiscard]] PassTypeInfo uploadPassType();

}  // namespace skygraph::passes
