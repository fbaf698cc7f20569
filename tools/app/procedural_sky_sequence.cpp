// sequenceSunDirection and writeProceduralSkySequence: see procedural_environment.hpp.
#include "procedural_environment.hpp"

#include "printable_name.hpp"
#include "replace_file.hpp"

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
    std::vector<std::filesystem::path> files(frames);
    std::error_code ec;
    for (uint32_t i = 0; i < frames; ++i) {
        files[i] = sequenceFrameFile(pattern, i);
        if (std::filesystem::is_directory(files[i], ec)) throw ImageError(files[i], "cannot write: it is a folder");
    }
    // One frame replacing another would leave the sequence a frame short.
    if (const auto two = files::twoNamesOfOneFile(files))
        throw ImageError(files[two->second], "cannot write: it is the same file as '" +
                                                 printableName(files[two->first].string()) +
                                                 "', another frame of this sequence");
    // A sequence cut short by a failure is no sequence: all frames are replaced, or none (one
    // frame's pixels are held at a time).
    try {
        files::replaceFilesContents(files, [&](size_t i) {
            return encodeHdrImage(files[i], proceduralSkyEquirect(sequenceSunDirection(uint32_t(i), frames), width));
        });
    } catch (const std::filesystem::filesystem_error& e) {
        throw ImageError(e.path1(), "cannot write: " + files::whyNotWritten(e));
    }
}

}  // namespace skygraph::app
