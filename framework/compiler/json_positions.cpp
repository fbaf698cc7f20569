#include "json_positions.hpp"

#include <cctype>

namespace skygraph {
namespace {

using nlohmann::json;

constexpr size_t kMaxDepth = 256;

// Builds the document through nlohmann's SAX interface while tracking the JSON path, repeated
// keys and the nesting depth. (nlohmann's parse callback would do too, but its DOM builder
// rescans every parent on each end of object, which is quadratic in a graph's passes.)
class Builder final : public nlohmann::json_sax<json> {
public:
    json root;
    std::vector<DuplicateKey> duplicates;
    std::string error;      ///< Set by parse_error or the depth limit.
    size_t errorByte = 0;   ///< nlohmann's position for parse errors (1-based, last read).
    bool tooDeep = false;
    std::string errorPath;

    bool null() override { return place(json(nullptr)); }
    bool boolean(bool v) override { return place(json(v)); }
    bool number_integer(number_integer_t v) override { return place(json(v)); }
    bool number_unsigned(number_unsigned_t v) override { return place(json(v)); }
    bool number_float(number_float_t v, const string_t&) override { return place(json(v)); }
    bool string(string_t& v) override { return place(json(std::move(v))); }
    bool binary(binary_t& v) override { return place(json::binary(std::move(v))); }

    bool start_object(std::size_t) override { return open(json::object(), false); }
    bool start_array(std::size_t) override { return open(json::array(), true); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }

    bool key(string_t& k) override {
        Frame& f = frames_.back();
        if (f.value->contains(k)) {
            std::string path = currentPath();
            duplicates.push_back({path.empty() ? k : path + "." + k, k});
        }
        f.key = std::move(k);
        return true;
    }

    bool parse_error(std::size_t position, const std::string&,
                     const nlohmann::detail::exception& ex) override {
        errorByte = position;
        error = ex.what();
        errorPath = currentPath();
        return false;
    }

    /// Path of the innermost open container.
    std::string currentPath() const { return path(false); }

private:
    struct Frame {
        json* value = nullptr;
        std::string key;     ///< Objects: the current key (of the open child or the next value).
        size_t next = 0;     ///< Arrays: index of the next element.
    };

    /// Paths are built only when needed (errors, repeated keys): each open container's place
    /// in its parent is the parent's current key or last index. With `pending`, the path
    /// continues to where the next value will go.
    std::string path(bool pending) const {
        std::string out;
        for (size_t i = 0; i < frames_.size(); ++i) {
            const bool last = i + 1 == frames_.size();
            if (last && !pending) break;
            const Frame& f = frames_[i];
            if (f.value->is_array()) {
                out += "[" + std::to_string(last ? f.next : f.next - 1) + "]";
            } else {
                if (!out.empty()) out += ".";
                out += f.key;
            }
        }
        return out;
    }
    std::string childPath() const { return path(true); }

    /// Stores `v` where the parser is: the root, the next array element, or the current key
    /// (the last of repeated keys wins, as in nlohmann). Parents do not change while a child
    /// container is open, so the pointers in frames_ stay valid.
    json* store(json&& v) {
        if (frames_.empty()) {
            root = std::move(v);
            return &root;
        }
        Frame& f = frames_.back();
        if (f.value->is_array()) {
            ++f.next;
            f.value->push_back(std::move(v));
            return &f.value->back();
        }
        json& slot = (*f.value)[f.key];
        slot = std::move(v);
        return &slot;
    }
    bool place(json&& v) {
        store(std::move(v));
        return true;
    }
    bool open(json&& container, bool) {
        if (frames_.size() >= kMaxDepth) {
            tooDeep = true;
            error = "nesting deeper than " + std::to_string(kMaxDepth) + " levels";
            errorPath = childPath();
            return false;  // stops the parse
        }
        json* value = store(std::move(container));
        frames_.push_back({value, {}, 0});
        return true;
    }
    bool close() {
        frames_.pop_back();
        return true;
    }

    std::vector<Frame> frames_;
};

/// Offset of the first character of the token that made parsing fail. nlohmann reports
/// `byte`, the 1-based offset of the last character it read, which for a multi-character
/// token is its end; users expect to be pointed at its start.
size_t tokenStart(std::string_view text, size_t byte, std::string_view what) {
    if (byte == 0) return 0;
    const size_t end = byte - 1;  // 0-based offset of the last character read
    if (end >= text.size()) return text.size();  // unexpected end of input
    auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
    // A misspelt literal ("tru}", "nulll"): nlohmann stops at the first character that does
    // not fit, which may be the one after the word. (Its "last read" text cannot be used: for
    // literals it also holds the tokens before.)
    if (what.find("invalid literal") != std::string_view::npos) {
        size_t i = end;
        if (!word(text[i]) && i > 0 && word(text[i - 1])) --i;
        while (i > 0 && word(text[i - 1])) --i;
        return i;
    }
    // A parser error names the whole token that was unexpected; it ends at `end`.
    if (what.find("unexpected string literal") != std::string_view::npos && text[end] == '"') {
        for (size_t i = end; i-- > 0;) {
            if (text[i] != '"') continue;
            size_t backslashes = 0;
            while (i > backslashes && text[i - 1 - backslashes] == '\\') ++backslashes;
            if (backslashes % 2 == 0) return i;
        }
        return end;
    }
    auto partOf = [](char c, std::string_view extra) {
        return std::isalnum(static_cast<unsigned char>(c)) || extra.find(c) != std::string_view::npos;
    };
    const bool number = what.find("unexpected number literal") != std::string_view::npos;
    const bool literal = what.find("unexpected true literal") != std::string_view::npos ||
                         what.find("unexpected false literal") != std::string_view::npos ||
                         what.find("unexpected null literal") != std::string_view::npos;
    if (number || literal) {
        size_t i = end;
        while (i > 0 && partOf(text[i - 1], number ? "+-." : "")) --i;
        return i;
    }
    return end;
}

/// Offset of the bracket that opens nesting level kMaxDepth + 1, skipping strings.
size_t tooDeepOffset(std::string_view text) {
    size_t depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxDepth) return i;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return text.size();
}

}  // namespace

JsonParseResult parseJsonWithPositions(std::string_view text) {
    JsonParseResult result;
    Builder builder;
    bool ok = false;
    try {
        ok = json::sax_parse(text.begin(), text.end(), &builder);
    } catch (const std::exception& e) {  // not expected: errors arrive through parse_error
        builder.error = e.what();
    }
    if (ok && builder.error.empty()) {
        result.value = std::move(builder.root);
        result.duplicateKeys = std::move(builder.duplicates);
        return result;
    }
    result.duplicateKeys = std::move(builder.duplicates);
    result.errorPath = builder.errorPath;
    size_t start = text.size();
    std::string what = builder.error;
    // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 3, column 5: ",
    // since the position is reported separately and more precisely.
    if (auto colon = what.find(": ", what.find("parse error")); what.starts_with("[json.exception.parse_error") &&
                                                                 colon != std::string::npos)
        what = what.substr(colon + 2);
    else if (auto bracket = what.find("] "); what.starts_with("[json.exception.") && bracket != std::string::npos)
        what = what.substr(bracket + 2);
    if (builder.tooDeep) {
        result.error = builder.error;
        start = tooDeepOffset(text);
    } else {
        result.error = "malformed JSON: " + (what.empty() ? std::string("unreadable") : what);
        if (builder.errorByte > 0) start = tokenStart(text, builder.errorByte, builder.error);
    }
    {
        result.line = 1;
        result.column = 1;
        for (size_t i = 0; i < start; ++i) {
            if (text[i] == '\n') {
                ++result.line;
                result.column = 1;
            } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
                ++result.column;  // columns count characters, not UTF-8 continuation bytes
            }
        }
    }
    return result;
}

}  // namespace skygraph
