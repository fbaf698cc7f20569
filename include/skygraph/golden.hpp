// Golden plans: a plan's text kept in a file that someone reviewed against the Vulkan spec, and
// the comparison of a freshly compiled plan with it. `skygraph check` and the GoogleTest
// helpers of skygraph::testing both read and write goldens through this header, so a golden
// written by one is read by the other. Device-free.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

/// The version of the golden text: its first line names it. A change to the plan text that
/// would make goldens differ raises it, so that an old golden is reported as written by
/// another version instead of as hundreds of differing lines.
inline constexpr uint32_t kGoldenFormatVersion = 2;

/// The text a golden file holds for `plan`: one header line naming the format version, then
/// planToText(plan). The caller owns the result.
[[nodiscard]] std::string goldenText(const Plan& plan);

/// "<graph file stem>.<feature>-on.<feature>-off....plan.txt", features in the order the graph
/// declares them; a graph without features gives "<stem>.plan.txt". The stem is the name of
/// `graph.file` without its extension, or `graph.name` for a graph not read from a file. In a
/// graph's and features' names, characters other than letters, digits, '-', '_' and '.' are
/// written as '_' (and '_' goes before a leading '.'), so that the name stays one file in the
/// goldens' folder; names that differ only there share a file.
[[nodiscard]] std::string goldenFileName(const GraphDesc& graph, const FeatureValues& features);

enum class GoldenStatus : uint8_t {
    Matches,       ///< The file holds exactly goldenText(plan).
    Differs,       ///< It holds another plan: GoldenComparison::diff says how.
    Missing,       ///< No such file (or no such directory).
    OtherVersion,  ///< Its header names another kGoldenFormatVersion, or none.
    Unreadable,    ///< It exists but could not be read.
    Unwritable,    ///< Writing it failed (`skygraph check --update`); the message says why.
};
/// e.g. "matches", "other version"; a view of static storage.
[[nodiscard]] std::string_view toString(GoldenStatus status) noexcept;

struct GoldenComparison {
    GoldenStatus status = GoldenStatus::Missing;
    std::filesystem::path file;
    /// For Differs: a unified diff from the golden to the plan ("--- <file>", "+++ compiled").
    std::string diff;
    /// One line for a person: what is wrong and what to do (empty when it matches).
    std::string message;
    [[nodiscard]] bool ok() const noexcept { return status == GoldenStatus::Matches; }
};

/// Compares `plan` with the golden file `golden`, read with CRLF line ends taken as LF (a
/// checkout that converted them). Never throws for a missing, unreadable or foreign file: the
/// status says which.
[[nodiscard]] GoldenComparison compareWithGolden(const Plan& plan, const std::filesystem::path& golden);

/// Writes goldenText(plan) to `golden` whole or not at all (a temporary file of this process
/// and thread, renamed over it); creates missing directories. Throws std::runtime_error naming
/// the file when it cannot. Writing different goldens from several threads is safe.
void writeGolden(const Plan& plan, const std::filesystem::path& golden);

/// A unified diff ("--- beforeName", "+++ afterName", "@@ -a,b +c,d @@" hunks with three lines
/// of context) turning `before` into `after`, compared line by line; a last line without its
/// newline is followed by "\ No newline at end of file". Empty when they are equal.
[[nodiscard]] std::string unifiedDiff(const std::string& before, const std::string& after,
                                      std::string_view beforeName, std::string_view afterName);

}  // namespace skygraph
