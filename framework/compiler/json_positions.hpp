// JSON parsing that keeps what nlohmann::json throws away: where a syntax error is (line and
// column) and which object keys were repeated (JSON keeps only the last silently).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

struct DuplicateKey {
    std::string path;  ///< JSON path of the repeated key, e.g. "resources.depth"
    std::string key;
};

struct JsonParseResult {
    nlohmann::json value;
    std::string error;      ///< Empty on success.
    std::string errorPath;  ///< Where the parser was when it failed, if known.
    int line = 0;
    int column = 0;
    std::vector<DuplicateKey> duplicateKeys;
};

/// Never throws. Nesting deeper than 256 levels is refused as an error (it would only come
/// from a fuzzer or a generator gone wrong, and deep recursion can exhaust the stack).
[[nodiscard]] JsonParseResult parseJsonWithPositions(std::string_view text);

/// The nesting limit of parseJsonWithPositions and readJson (json_document.hpp).
constexpr size_t kMaxJsonDepth = 256;

/// A failed parse as a diagnostic words it: nlohmann's message without its own position, and
/// the line and column of the token that broke the text.
struct JsonSyntaxError {
    std::string message;
    int line = 0;
    int column = 0;
};

/// `what` is nlohmann's exception text and `byte` its position (the 1-based offset of the
/// last character read), or, for `tooDeep`, the depth limit's message. Finds positions by
/// reading `text` again: only failed parses pay for it.
[[nodiscard]] JsonSyntaxError describeJsonError(std::string_view text, size_t byte, const std::string& what,
                                                bool tooDeep);

}  // namespace skygraph
