// Byte counts as the plan's text, DOT and SVG print them.
#pragma once

#include <cstdint>
#include <cstdio>
#include <iterator>
#include <string>

namespace skygraph {

/// "0", "512 B", "1.0 KiB", "16.00 MiB", "2.50 GiB", "11.00 TiB": small buffers stay readable
/// next to large images, and an absurd size reads as one.
inline std::string byteText(uint64_t bytes) {
    if (bytes == 0) return "0";
    if (bytes < 1024) return std::to_string(bytes) + " B";
    static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double value = static_cast<double>(bytes) / 1024.0;
    size_t unit = 0;
    // One decimal in KiB, two above. A value that would round to 1024 of its unit
    // ("1024.0 KiB" from 1 MiB less 51 bytes) is printed in the next.
    while (unit + 1 < std::size(kUnits) && value >= (unit == 0 ? 1023.95 : 1023.995)) {
        value /= 1024.0;
        ++unit;
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.*f %s", unit == 0 ? 1 : 2, value, kUnits[unit]);
    return text;
}

}  // namespace skygraph
