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

}  // namespace skygraph
