// Factories of the built-in passes' recording code, each defined in its pass's *_pass.cpp
// (the declarations: builtin_pass_types.hpp). PassLibrary::withBuiltins() pairs the two.
#pragma once

#include <skygraph/pass.hpp>

#include <memory>

namespace skygraph::passes {

/// Generic (passes/generic/generic_pass.cpp), also for types without recording code of their own.
[[nodiscard]] std::unique_ptr<PassImplementation> makeGenericPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeTonemappingPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeTonemappingComputePass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeSkyboxPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeForwardPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makePathTracePass(const PassDesc& desc);
/// Dear ImGui's draw data (passes/imgui/imgui_pass.cpp).
[[nodiscard]] std::unique_ptr<PassImplementation> makeImGuiPass(const PassDesc& desc);
// The environment pipeline (passes/ibl/environment_passes.cpp).
[[nodiscard]] std::unique_ptr<PassImplementation> makeEquirectToCubemapPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeCubemapMipPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeIrradiancePass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makePrefilterPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeBrdfLutPass(const PassDesc& desc);
/// Copies staged pixels (passes/upload/upload_pass.cpp).
[[nodiscard]] std::unique_ptr<PassImplementation> makeUploadPass(const PassDesc& desc);

}  // namespace skygraph::passes
