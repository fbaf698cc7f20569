#include "json_positions.hpp"

#include "json_document.hpp"

#include <algorithm>
#include <cctype>

namespace skygraph {
namespace {

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
    // (A number too large for a double is nlohmann's out_of_range.406, whose message leads
    // with its id; a parse error's message may quote any text that was read.)
    const bool number = what.find("unexpected number literal") != std::string_view::npos ||
                        what.starts_with("[json.exception.out_of_range.406]");
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

/// Offset of the bracket that opens nesting level kMaxJsonDepth + 1, skipping strings.
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
            if (++depth > kMaxJsonDepth) return i;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return text.size();
}

}  // namespace

JsonSyntaxError describeJsonError(std::string_view text, size_t byte, const std::string& what,
                                  bool tooDeep) {
    JsonSyntaxError result;
    size_t start = text.size();
    std::string message = what;
    // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 3, column 5: ",
    // since the position is reported separately and more precisely.
    if (auto colon = message.find(": ", message.find("parse error"));
        message.starts_with("[json.exception.parse_error") && colon != std::string::npos)
        message = message.substr(colon + 2);
    else if (auto bracket = message.find("] "); message.starts_with("[json.exception.") && bracket != std::string::npos)
        message = message.substr(bracket + 2);
    // nlohmann quotes what it read with control characters as <U+000A>; messages here write
    // them as JSON does, \u000a.
    for (size_t at = message.find("<U+"); at != std::string::npos; at = message.find("<U+", at + 1))
        if (at + 8 <= message.size() && message[at + 7] == '>' &&
            std::all_of(message.begin() + at + 3, message.begin() + at + 7,
                        [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; }))
            message.replace(at, 8, "\\u" + message.substr(at + 3, 4));
    if (tooDeep) {
        result.message = what;
        start = tooDeepOffset(text);
    } else {
        result.message = "malformed JSON: " + (message.empty() ? std::string("unreadable") : message);
        if (byte > 0) start = tokenStart(text, byte, what);
    }
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
    return result;
}

JsonParseResult parseJsonWithPositions(std::string_view text) {
    JsonRead read = readJson(text);
    JsonParseResult result;
    result.error = std::move(read.error);
    result.errorPath = std::move(read.errorPath);
    result.line = read.line;
    result.column = read.column;
    result.duplicateKeys = std::move(read.duplicateKeys);
    if (result.error.empty()) result.value = read.document.root().toJson();
    return result;
}

}  // namespace skygraph
