// JSON cannot tell 4 from 4.0, but a graph file's counts and sizes are integers: a message
// refusing a whole number written as a float says how to write it. Header-only, for the
// libraries; not installed.
#pragma once

#include <cmath>

namespace skygraph {

/// " (write it as an integer)" for a whole number in [lowest, highest], where the integer
/// would have been taken, else "": a value out of range is wrong however it is written.
[[nodiscard]] inline const char* integerHint(double value, double lowest, double highest) noexcept {
    return std::isfinite(value) && value == std::floor(value) && value >= lowest && value <= highest
               ? " (write it as an integer)"
               : "";
}

}  // namespace skygraph
