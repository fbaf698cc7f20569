// PassLibrary::withBuiltins(): the built-in declarations paired with their recording code.
// A renderer runs types without recording code with this library's Generic, which performs
// exactly their declared accesses.
#include "builtin_passes.hpp"

namespace skygraph {

PassLibrary PassLibrary::withBuiltins() {
    const PassRegistry declarations = PassRegistry::withBuiltins();
    const std::pair<const char*, PassFactory> factories[] = {
        {"Generic", passes::makeGenericPass},
        {"TonemappingPass", passes::makeTonemappingPass},
        {"TonemappingComputePass", passes::makeTonemappingComputePass},
        {"SkyboxPass", passes::makeSkyboxPass},
        {"ForwardPass", passes::makeForwardPass},
        {"PathTracePass", passes::makePathTracePass},
        {"ImGuiPass", passes::makeImGuiPass},
        {"EquirectToCubemapPass", passes::makeEquirectToCubemapPass},
        {"CubemapMipPass", passes::makeCubemapMipPass},
        {"IrradiancePass", passes::makeIrradiancePass},
        {"PrefilterPass", passes::makePrefilterPass},
        {"BrdfLutPass", passes::makeBrdfLutPass},
        {"UploadPass", passes::makeUploadPass},
    };
    PassLibrary library;
    library.registry_ = declarations;
    for (const auto& [type, make] : factories) library.factories_.emplace(type, make);
    return library;
}

const PassLibrary& PassLibrary::genericOnly() {
    static const PassLibrary library = [] {
        PassLibrary generic;
        generic.add(*PassRegistry::withBuiltins().find("Generic"), passes::makeGenericPass);
        return generic;
    }();
    return library;
}

}  // namespace skygraph
