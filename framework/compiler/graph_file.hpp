// What the loader's parts share: the graph file format's limits (graph_limits.hpp), where each problem found in
// a file goes, and the check for keys that an entry of the file does not have.
#pragma once

#include "graph_limits.hpp"
#include "json_document.hpp"
#include "json_path.hpp"

#include <skygraph/diagnostics.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

/// `names` as a message lists what was declared: "a, b, c", or "none".
[[nodiscard]] inline std::string joinNames(const std::vector<std::string>& names) {
    if (names.empty()) return "none";
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

/// The keys an entry of the file may have, in the order messages list them.
template <size_t N>
using Keys = std::array<std::string_view, N>;

/// Where `key` is in `keys`; for constants (a key not in the list does not compile).
template <size_t N>
constexpr size_t keyIndex(const Keys<N>& keys, std::string_view key) {
    for (size_t i = 0; i < N; ++i)
        if (keys[i] == key) return i;
    throw "not a key of the list";
}

/// The problems found in a graph file, each added to the list of the part of the file being
/// loaded (into()).
class FileProblems {
public:
    using Part = std::vector<Diagnostic>;

    explicit FileProblems(std::string file) : file_(std::move(file)) {}

    void into(Part& part) noexcept { part_ = &part; }

    /// The problem as a diagnostic of this file.
    [[nodiscard]] Diagnostic diagnostic(const std::string& path, std::string_view pass, std::string_view resource,
                                        const std::string& message) const {
        return {file_, path, std::string(pass), std::string(resource), message};
    }
    void operator()(const std::string& path, std::string_view pass, std::string_view resource,
                    const std::string& message) {
        part_->push_back(diagnostic(path, pass, resource, message));
    }

    /// Every key of `object` (read into `fields`) that is not in `keys`, in key order. `path`
    /// gives the object's JSON path; it is called only when there is something to report.
    template <size_t N, typename Path>
    void unknownKeys(JsonValue object, const JsonFields<N>& fields, Path&& path, const Keys<N>& keys,
                     std::string_view pass = "", std::string_view resource = "") {
        if (!fields.unknownKeys) return;
        std::string list;
        for (auto k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
        for (const auto& [key, _] : object.members()) {
            if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
            (*this)(jsonPathMember(path(), key), pass, resource,
                    "unknown key '" + std::string(key) + "'; expected one of: " + list);
        }
    }

private:
    std::string file_;
    Part* part_ = nullptr;
};

}  // namespace skygraph
