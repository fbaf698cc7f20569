// The built-in pass types as a registry: PassRegistry::withBuiltins() and
// registerBuiltinPassTypes() (declared in include/skygraph/pass_registry.hpp). Plain data,
// no device code: this library (skygraph_pass_types) is all a compile-only tool links
// besides the compiler.
#include "builtin_pass_types.hpp"

namespace skygraph {

void registerBuiltinPassTypes(PassRegistry& r) {
    r.add(passes::genericPassType());
    r.add(passes::forwardPassType());
    r.add(passes::skyboxPassType());
    r.add(passes::tonemappingPassType());
    r.add(passes::tonemappingComputePassType());
    r.add(passes::imguiPassType());
    r.add(passes::pathTracePassType());
    r.add(passes::equirectToCubemapPassType());
    r.add(passes::cubemapMipPassType());
    r.add(passes::irradiancePassType());
    r.add(passes::prefilterPassType());
    r.add(passes::brdfLutPassType());
    r.add(passes::uploadPassType());
}

PassRegistry PassRegistry::withBuiltins() {
    PassRegistry r;
    registerBuiltinPassTypes(r);
    return r;
}

}  // namespace skygraph
