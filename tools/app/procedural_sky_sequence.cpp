// sequenceSunDirection and writeProceduralSkySequence: see procedural_environment.hpp.
#include "procedural_environment.hpp"

#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <vector>

namespace skygraph::app {

std::array<double, 3> sequenceSunDirection(uint32_t frame, uint32_t frames) {
    const double azimuth = 2.0 * math::kPi<double> * frame / std::max(frames, 1u);
    const double elevation = math::radians(25.0);
    return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), -std::cos(elevation) * std::cos(azimuth)};
}

void writeProceduralSkySequence(const std::string& pattern, uint32_t frames, uint32_t width) {
    if (const auto folder = std::filesystem::path(pattern).parent_path(); !folder.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        if (ec) throw ImageError(folder, "cannot make the folder: " + ec.message());
    }
    std::error_code ec;
    for (uint32_t i = 0; i < frames; ++i)
        if (std::filesystem::is_directory(sequenceFrameFile(pattern, i), ec))
            throw ImageError(sequenceFrameFile(pattern, i), "cannot write: it is a folder");
    // A sequence cut short by a failure is no sequence: the frames this run made go again.
    std::vector<std::filesystem::path> made;
    try {
        for (uint32_t i = 0; i < frames; ++i) {
            const std::filesystem::path frame = sequenceFrameFile(pattern, i);
            const bool existed = std::filesystem::exists(frame, ec);
            saveHdrImage(frame, proceduralSkyEquirect(sequenceSunDirection(i, frames), width));
            if (!existed) made.push_back(frame);
        }
    } catch (...) {
        for (const auto& frame : made) std::filesystem::remove(frame, ec);
        throw;
    }
}

}  // namespace skygraph::app
