// EnvironmentSequence's file names: see scene.hpp.
#include <skygraph/scene.hpp>

#include <cctype>

namespace skygraph {
namespace {

/// Where the number's conversion lies in a pattern: [begin, end), and its digit count (0: %d).
struct Conversion {
    size_t begin = std::string_view::npos, end = 0;
    int width = 0;
};

/// The first conversion at or after `from`, or one with begin npos; `bad` is set when a
/// '%' starts something other than %d or %0Nd.
Conversion findConversion(std::string_view pattern, size_t from, bool& bad) {
    Conversion c;
    const size_t at = pattern.find('%', from);
    if (at == std::string_view::npos) return c;
    size_t i = at + 1;
    int width = 0;
    if (i < pattern.size() && pattern[i] == '0') {
        ++i;
        if (i >= pattern.size() || pattern[i] < '1' || pattern[i] > '9') return bad = true, c;
        width = pattern[i++] - '0';
    }
    if (i >= pattern.size() || pattern[i] != 'd') return bad = true, c;
    return {at, i + 1, width};
}

}  // namespace

std::string sequencePatternProblem(std::string_view pattern) {
    bool bad = false;
    const Conversion c = findConversion(pattern, 0, bad);
    if (bad || c.begin == std::string_view::npos)
        return "must hold the frame number as %d or %0Nd (N from 1 to 9), e.g. frames/%04d.exr";
    if (const Conversion second = findConversion(pattern, c.end, bad); bad || second.begin != std::string_view::npos)
        return "must hold exactly one %d or %0Nd, and no other '%'";
    return {};
}

std::string formatSequenceFrame(std::string_view pattern, uint32_t number) {
    bool bad = false;
    const Conversion c = findConversion(pattern, 0, bad);
    if (bad || c.begin == std::string_view::npos) return std::string(pattern);
    std::string digits = std::to_string(number);
    if (digits.size() < size_t(c.width)) digits.insert(0, size_t(c.width) - digits.size(), '0');
    return std::string(pattern.substr(0, c.begin)) + digits + std::string(pattern.substr(c.end));
}

std::filesystem::path sequenceFrameFile(const std::filesystem::path& pattern, uint32_t number) {
    return pattern.parent_path() / formatSequenceFrame(pattern.filename().string(), number);
}

std::filesystem::path EnvironmentSequence::frame(uint32_t index) const {
    return sequenceFrameFile(pattern, first + index);
}

}  // namespace skygraph
