// The example's own pass type, registered next to skygraph's built-ins: a checkerboard of two
// linear HDR colours, drawn into a colour attachment. Both halves: the declaration the compiler
// checks graphs against, and the recording code.
#pragma once

#include <skygraph/pass.hpp>

#include <array>
#include <cstdint>
#include <memory>

namespace window_example {

/// One slot, "output" (Write@ColorAttachment); params {"colors": [[r, g, b], [r, g, b]] (linear,
/// each in [0, 64]), "tile": integer in [1, 4096] (pixels)}, both required.
[[nodiscard]] skygraph::PassTypeInfo checkerPassType();

/// Recording code for one CheckerPass of a graph.
[[nodiscard]] std::unique_ptr<skygraph::PassImplementation> makeCheckerPass(const skygraph::PassDesc& desc);

}  // namespace window_example
