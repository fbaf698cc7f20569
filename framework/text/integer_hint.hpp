// JSON cannot tell 4 from 4.0, but a graph file's counts and sizes are integers: a message
// refusing a whole number written as a float says how to write it. Header-only, for the
// libraries; not installed.
#pragma once

#include <cmath>

namespace skygraph {

/// " (write it as an integer)" for a whole number that digits alone would have given as an
/// integer (-2^63 to 2^64 - 1; past them digits are read as a float too), else "".
[[nodiscard]] inline const char* integerHint(double value) noexcept {
    return std::isfinite(value) && value == std::floor(value) && value >= -0x1p63 && value < 0x1p64
               ? " (write it as an integer)"
               : "";
}

}  // namespace skygraph
