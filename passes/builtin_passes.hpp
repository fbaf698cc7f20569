// Factories of the built-in passes' recording code (the declarations are in
// builtin_pass_types.cpp). PassLibrary::withBuiltins() pairs the two.
#pragma once

#include <skygraph/pass.hpp>

#include <memory>

namespace skygraph::passes {

[[nodiscard]] std::unique_ptr<PassImplementation> makeTonemappingPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeSkyboxPass(const PassDesc& desc);
[[nodiscard]] std::unique_ptr<PassImplementation> makeForwardPass(const PassDesc& desc);

}  // namespace skygraph::passes
