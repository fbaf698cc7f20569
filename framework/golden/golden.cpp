#include <skygraph/golden.hpp>
#include <skygraph/plan_format.hpp>

#include <cctype>
#include <stdexcept>
#include <system_error>

#include "read_file.hpp"
#include "replace_file.hpp"

namespace skygraph {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHeaderPrefix = "# skygraph golden plan, format ";

std::string headerLine(uint32_t version) { return std::string(kHeaderPrefix) + std::to_string(version); }

/// `name` as one file name: a graph's name may hold any character, and "../x" or "a/b" would
/// place the golden outside its folder.
std::string asFileName(std::string name) {
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    if (name.empty() || name.front() == '.') name.insert(0, "_");
    return name;
}

}  // namespace

std::string goldenText(const Plan& plan) { return headerLine(kGoldenFormatVersion) + "\n" + planToText(plan); }

std::string goldenFileName(const GraphDesc& graph, const FeatureValues& features) {
    std::string name = graph.file.empty() || graph.file.front() == '<' ? asFileName(graph.name)
                                                                        : fs::path(graph.file).stem().string();
    for (const FeatureDecl& f : graph.features) {
        const auto it = features.find(f.name);
        const bool on = it != features.end() ? it->second : f.defaultValue;
        name += "." + asFileName(f.name) + (on ? "-on" : "-off");
    }
    return name + ".plan.txt";
}

std::string_view toString(GoldenStatus status) noexcept {
    switch (status) {
        case GoldenStatus::Matches: return "matches";
        case GoldenStatus::Differs: return "differs";
        case GoldenStatus::Missing: return "missing";
        case GoldenStatus::OtherVersion: return "other version";
        case GoldenStatus::Unreadable: return "unreadable";
        case GoldenStatus::Unwritable: return "unwritable";
    }
    return "unknown";
}

GoldenComparison compareWithGolden(const Plan& plan, const fs::path& golden) {
    GoldenComparison result;
    result.file = golden;
    std::error_code ec;
    if (!fs::exists(golden, ec)) {
        result.status = GoldenStatus::Missing;
        result.message = "no golden plan " + golden.string() +
                         (fs::exists(golden.parent_path(), ec) ? "" : " (its directory does not exist)") +
                         "; write it with --update (or SKYGRAPH_UPDATE_GOLDEN=1) and review it";
        return result;
    }
    std::optional<std::string> text = files::readFile(golden);
    if (!text) {  // a folder, a FIFO (whose read would wait for a writer), a file we may not read
        result.status = GoldenStatus::Unreadable;
        result.message = "cannot read the golden plan " + golden.string() +
                         (fs::is_regular_file(golden, ec) ? "" : ": it is not a regular file");
        return result;
    }
    std::string expected = std::move(*text);
    if (expected.find('\r') != std::string::npos) {
        std::string lf;
        for (size_t i = 0; i < expected.size(); ++i)
            if (!(expected[i] == '\r' && i + 1 < expected.size() && expected[i + 1] == '\n')) lf += expected[i];
        expected = std::move(lf);
    }
    const std::string firstLine = expected.substr(0, expected.find('\n'));
    if (firstLine != headerLine(kGoldenFormatVersion)) {
        result.status = GoldenStatus::OtherVersion;
        result.message = golden.string() + " was not written by this version's golden format (" +
                         headerLine(kGoldenFormatVersion).substr(2) + "): its first line is '" + firstLine.substr(0, 80) +
                         "'; rewrite it with --update and review the change";
        return result;
    }
    const std::string actual = goldenText(plan);
    if (expected == actual) {
        result.status = GoldenStatus::Matches;
        return result;
    }
    result.status = GoldenStatus::Differs;
    result.diff = unifiedDiff(expected, actual, golden.string(), "compiled");
    result.message = "the compiled plan differs from " + golden.string();
    return result;
}

void writeGolden(const Plan& plan, const fs::path& golden) {
    std::error_code ec;
    if (golden.has_parent_path()) fs::create_directories(golden.parent_path(), ec);
    if (ec) throw std::runtime_error("cannot create the directory of " + golden.string() + ": " + ec.message());
    try {
        files::replaceFileContents(golden, goldenText(plan));
    } catch (const fs::filesystem_error& e) {
        throw std::runtime_error("cannot write the golden plan " + golden.string() + ": " + files::whyNotWritten(e));
    }
}

}  // namespace skygraph
