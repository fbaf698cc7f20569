// The line diff of golden plans and `compile --watch`: Debian's header-only dtl.
#include <skygraph/golden.hpp>

#include <dtl/dtl.hpp>

#include <sstream>
#include <vector>

namespace skygraph {
namespace {

/// A last line without its newline differs from the same line with one, and is printed
/// with diff's and git's marker after it: texts that differ only there get a hunk too.
std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    if (!text.empty() && text.back() != '\n') lines.back() += "\n\\ No newline at end of file";
    return lines;
}

}  // namespace

std::string unifiedDiff(const std::string& before, const std::string& after, std::string_view beforeName,
                        std::string_view afterName) {
    if (before == after) return {};
    const std::vector<std::string> a = splitLines(before), b = splitLines(after);
    dtl::Diff<std::string, std::vector<std::string>> diff(a, b);
    diff.compose();
    diff.composeUnifiedHunks();
    std::ostringstream out;
    out << "--- " << beforeName << "\n+++ " << afterName << "\n";
    diff.printUnifiedFormat(out);
    return out.str();
}

}  // namespace skygraph
