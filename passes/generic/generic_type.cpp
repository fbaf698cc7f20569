// Generic: performs every declared access for real. Its recording code, which a renderer also
// runs for every pass type without recording code of its own: generic_pass.cpp.
#include "builtin_pass_types.hpp"

namespace skygraph::passes {

PassTypeInfo genericPassType() {
    return {"Generic", {}, true, {}, "Performs every declared access for real; for tests and random graphs."};
}

}  // namespace skygraph::passes
