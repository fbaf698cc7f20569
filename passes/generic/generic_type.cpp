// Generic: performs every declared access for real. The executor records it (and every pass
// type without recording code) itself, from the plan: framework/executor/renderer_generic.cpp.
#include "builtin_pass_types.hpp"

namespace skygraph::passes {

PassTypeInfo genericPassType() {
    return {"Generic", {}, true, {}, "Performs every declared access for real; for tests and random graphs."};
}

}  // namespace skygraph::passes
