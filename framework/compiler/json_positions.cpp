#include "json_positions.hpp"

#include <set>

namespace skygraph {
namespace {

constexpr int kMaxDepth = 256;

// Tracks the JSON path during nlohmann's SAX-like callback parse.
struct PathTracker {
    struct Frame {
        bool isArray = false;
        std::string path;
        std::set<std::string> keys;
        long nextIndex = 0;
        std::string lastKey;
    };
    std::vector<Frame> stack;
    std::vector<DuplicateKey> duplicates;
    bool tooDeep = false;

    std::string childPath() {
        if (stack.empty()) return "";
        Frame& f = stack.back();
        std::string base = f.path;
        if (f.isArray) return base + "[" + std::to_string(f.nextIndex++) + "]";
        return base.empty() ? f.lastKey : base + "." + f.lastKey;
    }
    std::string currentPath() const { return stack.empty() ? "" : stack.back().path; }

    bool onEvent(int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using E = nlohmann::json::parse_event_t;
        if (depth > kMaxDepth) tooDeep = true;
        switch (event) {
            case E::object_start:
            case E::array_start: {
                Frame f;
                f.isArray = event == E::array_start;
                f.path = childPath();
                stack.push_back(std::move(f));
                break;
            }
            case E::object_end:
            case E::array_end:
                if (!stack.empty()) stack.pop_back();
                break;
            case E::key: {
                std::string key = parsed.get<std::string>();
                Frame& f = stack.back();
                f.lastKey = key;
                if (!f.keys.insert(key).second)
                    duplicates.push_back({f.path.empty() ? key : f.path + "." + key, key});
                break;
            }
            case E::value:
                if (!stack.empty() && stack.back().isArray) stack.back().nextIndex++;
                break;
        }
        return !tooDeep;
    }
};

}  // namespace

JsonParseResult parseJsonWithPositions(std::string_view text) {
    JsonParseResult result;
    PathTracker tracker;
    try {
        result.value = nlohmann::json::parse(
            text.begin(), text.end(),
            [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
                return tracker.onEvent(depth, event, parsed);
            });
        if (tracker.tooDeep) {
            result.error = "nesting deeper than " + std::to_string(kMaxDepth) + " levels";
            result.errorPath = tracker.currentPath();
        }
    } catch (const nlohmann::json::parse_error& e) {
        // e.byte is the 1-based offset of the character that made parsing fail.
        size_t end = std::min<size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
        result.line = 1;
        result.column = 1;
        for (size_t i = 0; i < end; ++i) {
            if (text[i] == '\n') {
                ++result.line;
                result.column = 1;
            } else {
                ++result.column;
            }
        }
        std::string what = e.what();
        // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 3, column 5: ".
        if (auto colon = what.find(": ", what.find("parse error")); colon != std::string::npos)
            what = what.substr(colon + 2);
        result.error = "malformed JSON: " + what;
        result.errorPath = tracker.currentPath();
    }
    result.duplicateKeys = std::move(tracker.duplicates);
    return result;
}

}  // namespace skygraph
