// Names end up in terminals, logs, text plans, DOT graphs and XML. A control character in one
// (a JSON "\u0007" or "\n") would ring, break a line or make a file invalid, and an invisible
// format character (a zero-width space, a right-to-left override) would make one name print
// like another or a line read otherwise than it is. The graph loader refuses such names in
// graph files, where a name is an identifier that plans and code must find again; names and
// paths from scene and glTF files are valid as they are, and every message and log line shows
// them escaped instead. Header-only, for the libraries and the tool; not installed.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace skygraph {

/// Why the loader refuses such names, for its messages.
inline constexpr const char* kPrintedNames = "names are printed in plans, DOT graphs and messages";

[[nodiscard]] constexpr bool isControlCharacter(char c) noexcept {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

[[nodiscard]] inline bool hasControlCharacter(std::string_view name) noexcept {
    for (const char c : name)
        if (isControlCharacter(c)) return true;
    return false;
}

/// The length of the valid UTF-8 sequence at the start of `text` (1 to 4), or 0 where its first
/// byte starts none: a stray continuation byte, an overlong form, a surrogate, past U+10FFFF,
/// or cut short.
[[nodiscard]] constexpr size_t utf8SequenceLength(std::string_view text) noexcept {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead < 0x80) return 1;
    const size_t length = lead >= 0xc2 && lead <= 0xdf ? 2 : lead >= 0xe0 && lead <= 0xef ? 3 : lead >= 0xf0 && lead <= 0xf4 ? 4 : 0;
    if (length == 0 || text.size() < length) return 0;
    for (size_t i = 1; i < length; ++i)
        if ((byte(i) & 0xc0) != 0x80) return 0;
    // The second byte's range rules out overlong forms, surrogates and code points past U+10FFFF.
    if ((lead == 0xe0 && byte(1) < 0xa0) || (lead == 0xed && byte(1) > 0x9f) || (lead == 0xf0 && byte(1) < 0x90) ||
        (lead == 0xf4 && byte(1) > 0x8f))
        return 0;
    return length;
}

/// The code point of the UTF-8 sequence `seq` (of utf8SequenceLength(seq) bytes) when it is a
/// format character that prints as nothing or reorders what follows it (a zero-width space or
/// joiner, a bidirectional embedding, override or isolate, a soft hyphen, a byte order mark),
/// else 0: two names that differ only by one look the same, and an override makes a message
/// read otherwise than it is.
[[nodiscard]] constexpr char32_t invisibleFormatCharacter(std::string_view seq) noexcept {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(seq[i]); };
    if (seq.size() >= 2 && byte(0) == 0xc2 && byte(1) == 0xad) return 0x00ad;
    if (seq.size() >= 2 && byte(0) == 0xd8 && byte(1) == 0x9c) return 0x061c;
    if (seq.size() < 3) return 0;
    if (byte(0) < 0xe0 || byte(0) > 0xef) return 0;
    const char32_t cp = char32_t(byte(0) & 0x0f) << 12 | char32_t(byte(1) & 0x3f) << 6 | char32_t(byte(2) & 0x3f);
    const bool invisible = cp == 0x180e || (cp >= 0x200b && cp <= 0x200f) || (cp >= 0x202a && cp <= 0x202e) ||
                           (cp >= 0x2060 && cp <= 0x2064) || (cp >= 0x2066 && cp <= 0x2069) || cp == 0xfeff;
    return invisible ? cp : 0;
}

/// The first invisible format character of valid UTF-8 `name` (invisibleFormatCharacter), or 0.
[[nodiscard]] inline char32_t firstInvisibleCharacter(std::string_view name) noexcept {
    for (size_t i = 0; i < name.size();) {
        const size_t length = utf8SequenceLength(name.substr(i));
        if (length == 0) return 0;  // not UTF-8: JSON text always is
        if (length > 1)
            if (const char32_t cp = invisibleFormatCharacter(name.substr(i, length))) return cp;
        i += length;
    }
    return 0;
}

/// Why the loader refuses `name` ("holds a control character; ...", "holds the invisible
/// character U+200B, ..."), or "" when it prints as it is.
[[nodiscard]] inline std::string unprintableNameProblem(std::string_view name) {
    if (hasControlCharacter(name)) return std::string("holds a control character; ") + kPrintedNames;
    const char32_t cp = firstInvisibleCharacter(name);
    if (cp == 0) return {};
    char code[16];
    std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(cp));
    return "holds the invisible character " + std::string(code) +
           ", which prints as nothing or reorders what follows it; " + kPrintedNames;
}

/// `name` with each control character and each invisible format character written as JSON
/// writes it (\u0007, \u200b), and each byte that is not part of valid UTF-8 as \xff, for
/// messages: a terminal or a reader of the log that decodes UTF-8 sees every byte, and two names
/// that differ only by a zero-width space do not print alike.
[[nodiscard]] inline std::string printableName(std::string_view name) {
    bool plain = true;
    for (const char c : name) plain = plain && !isControlCharacter(c) && static_cast<unsigned char>(c) < 0x80;
    if (plain) return std::string(name);
    std::string out;
    for (size_t i = 0; i < name.size();) {
        const char c = name[i];
        const size_t length = utf8SequenceLength(name.substr(i));
        char escaped[12];
        if (length == 0) {
            std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned char>(c));
            out += escaped;
            ++i;
        } else if (isControlCharacter(c)) {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
            out += escaped;
            ++i;
        } else if (const char32_t cp = length > 1 ? invisibleFormatCharacter(name.substr(i, length)) : 0) {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(cp));
            out += escaped;
            i += length;
        } else {
            out.append(name.substr(i, length));
            i += length;
        }
    }
    return out;
}

}  // namespace skygraph
