#include "json_fast_reader.hpp"

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

namespace skygraph {
namespace {

using Kind = JsonValue::Kind;

// Reads a JSON text straight from its bytes, for the builder: strings without escapes are
// viewed where they are. It accepts a subset of what nlohmann accepts, with the same values
// (numbers convert exactly: integers of up to 18 digits, and floats correctly rounded, as
// strtod rounds them). At anything else (every error, a byte-order mark, a longer integer,
// a float out of range, nesting past the limit) it gives up, and the text is read by nlohmann.
class FastReader {
    /// Bytes that end the plain run of a string: the quote, a backslash, control characters
    /// (an error) and the bytes of multi-byte UTF-8 sequences (to be checked).
    static constexpr auto kStringStop = [] {
        std::array<bool, 256> stop{};
        for (int c = 0; c < 0x20; ++c) stop[c] = true;
        for (int c = 0x80; c < 0x100; ++c) stop[c] = true;
        stop['"'] = stop['\\'] = true;
        return stop;
    }();

public:
    FastReader(std::string_view text, JsonDocumentBuilder& b)
        : begin_(text.data()), p_(text.data()), end_(text.data() + text.size()), b_(b) {}

    /// Whether the whole text was read.
    bool read() {
        skipSpace();
        if (!value()) return false;
        skipSpace();
        return p_ == end_;
    }

private:
    static bool digit(char c) { return c >= '0' && c <= '9'; }
    void skipSpace() {
        while (p_ != end_ && (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) ++p_;
    }

    bool value() {
        if (p_ == end_) return false;
        switch (*p_) {
            case '{': return object();
            case '[': return array();
            case '"': {
                uint64_t ref = 0;
                return string(ref) && add(Kind::String, ref);
            }
            case 't': return literal("true") && add(Kind::Boolean, 1);
            case 'f': return literal("false") && add(Kind::Boolean, 0);
            case 'n': return literal("null") && add(Kind::Null, 0);
            default: return number();
        }
    }

    bool add(Kind kind, uint64_t payload) {
        b_.position = size_t(p_ - begin_);
        return b_.add(kind, payload);
    }
    bool open(bool array) {
        b_.position = size_t(p_ - begin_);
        return b_.open(array);
    }
    bool close(Kind kind) {
        ++p_;
        b_.position = size_t(p_ - begin_);
        return b_.close(kind);
    }

    bool literal(std::string_view word) {
        if (size_t(end_ - p_) < word.size() || std::string_view(p_, word.size()) != word) return false;
        p_ += word.size();
        return true;
    }

    bool object() {
        if (!open(false)) return false;
        ++p_;
        skipSpace();
        if (p_ != end_ && *p_ == '}') return close(Kind::Object);
        for (;;) {
            uint64_t key = 0;
            if (p_ == end_ || *p_ != '"' || !string(key)) return false;
            b_.key(key);
            skipSpace();
            if (p_ == end_ || *p_ != ':') return false;
            ++p_;
            skipSpace();
            if (!value()) return false;
            skipSpace();
            if (p_ == end_) return false;
            if (*p_ == '}') return close(Kind::Object);
            if (*p_ != ',') return false;
            ++p_;
            skipSpace();
        }
    }

    bool array() {
        if (!open(true)) return false;
        ++p_;
        skipSpace();
        if (p_ != end_ && *p_ == ']') return close(Kind::Array);
        for (;;) {
            if (!value()) return false;
            skipSpace();
            if (p_ == end_) return false;
            if (*p_ == ']') return close(Kind::Array);
            if (*p_ != ',') return false;
            ++p_;
            skipSpace();
        }
    }

    bool number() {
        const char* start = p_;
        const bool negative = *p_ == '-';
        if (negative) ++p_;
        if (p_ == end_) return false;
        if (*p_ == '0') {
            ++p_;
        } else if (*p_ >= '1' && *p_ <= '9') {
            while (p_ != end_ && digit(*p_)) ++p_;
        } else {
            return false;
        }
        bool isFloat = false;
        if (p_ != end_ && *p_ == '.') {
            isFloat = true;
            if (++p_ == end_ || !digit(*p_)) return false;
            while (p_ != end_ && digit(*p_)) ++p_;
        }
        if (p_ != end_ && (*p_ == 'e' || *p_ == 'E')) {
            isFloat = true;
            if (++p_ != end_ && (*p_ == '+' || *p_ == '-')) ++p_;
            if (p_ == end_ || !digit(*p_)) return false;
            while (p_ != end_ && digit(*p_)) ++p_;
        }
        if (!isFloat) {
            const char* digits = start + (negative ? 1 : 0);
            if (p_ - digits > 18) return false;  // might not fit: nlohmann decides (it may make it a float)
            uint64_t v = 0;
            for (const char* d = digits; d != p_; ++d) v = v * 10 + uint64_t(*d - '0');
            if (negative) return add(Kind::Integer, std::bit_cast<uint64_t>(-static_cast<int64_t>(v)));
            return add(Kind::Unsigned, v);
        }
        double v = 0;
        const auto [ptr, ec] = std::from_chars(start, p_, v);
        if (ec != std::errc() || ptr != p_ || !std::isfinite(v)) return false;
        return add(Kind::Float, std::bit_cast<uint64_t>(v));
    }

    /// A string at the quote `p_` points to: its place in the text, or (with escapes) its
    /// decoded copy. UTF-8 is checked as nlohmann checks it.
    bool string(uint64_t& ref) {
        const char* start = ++p_;
        while (p_ != end_ && !kStringStop[static_cast<unsigned char>(*p_)]) ++p_;
        if (p_ != end_ && *p_ == '"') {
            ref = JsonDocumentBuilder::inText(size_t(start - begin_), size_t(p_ - start));
            ++p_;
            return true;
        }
        bool escaped = false;
        while (p_ != end_) {
            const auto c = static_cast<unsigned char>(*p_);
            if (c == '"') break;
            if (c < 0x20) return false;
            if (c == '\\') {
                escaped = true;
                break;
            }
            if (c < 0x80) {
                ++p_;
            } else if (!utf8()) {
                return false;
            }
        }
        if (p_ == end_) return false;
        if (!escaped) {
            ref = JsonDocumentBuilder::inText(size_t(start - begin_), size_t(p_ - start));
            ++p_;
            return true;
        }
        // Escapes: decoded from the start again.
        scratch_.assign(start, p_);
        while (p_ != end_) {
            const auto c = static_cast<unsigned char>(*p_);
            if (c == '"') {
                ref = b_.decoded(scratch_);
                ++p_;
                return true;
            }
            if (c < 0x20) return false;
            if (c == '\\') {
                if (!escape()) return false;
            } else if (c < 0x80) {
                scratch_ += *p_++;
            } else {
                const char* from = p_;
                if (!utf8()) return false;
                scratch_.append(from, p_);
            }
        }
        return false;
    }

    /// One UTF-8 sequence at p_, well-formed by the ranges nlohmann accepts (RFC 3629).
    bool utf8() {
        const auto c = static_cast<unsigned char>(*p_);
        auto in = [&](size_t i, unsigned char lo, unsigned char hi) {
            if (size_t(end_ - p_) <= i) return false;
            const auto b = static_cast<unsigned char>(p_[i]);
            return b >= lo && b <= hi;
        };
        size_t n = 0;
        if (c >= 0xC2 && c <= 0xDF) n = in(1, 0x80, 0xBF) ? 2 : 0;
        else if (c == 0xE0) n = in(1, 0xA0, 0xBF) && in(2, 0x80, 0xBF) ? 3 : 0;
        else if ((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF)
            n = in(1, 0x80, 0xBF) && in(2, 0x80, 0xBF) ? 3 : 0;
        else if (c == 0xED) n = in(1, 0x80, 0x9F) && in(2, 0x80, 0xBF) ? 3 : 0;
        else if (c == 0xF0) n = in(1, 0x90, 0xBF) && in(2, 0x80, 0xBF) && in(3, 0x80, 0xBF) ? 4 : 0;
        else if (c >= 0xF1 && c <= 0xF3) n = in(1, 0x80, 0xBF) && in(2, 0x80, 0xBF) && in(3, 0x80, 0xBF) ? 4 : 0;
        else if (c == 0xF4) n = in(1, 0x80, 0x8F) && in(2, 0x80, 0xBF) && in(3, 0x80, 0xBF) ? 4 : 0;
        p_ += n;
        return n != 0;
    }

    /// Four hex digits after "\u", or -1.
    int hex4() {
        if (end_ - p_ < 4) return -1;
        int v = 0;
        for (int i = 0; i < 4; ++i) {
            const char c = *p_++;
            v <<= 4;
            if (c >= '0' && c <= '9') v |= c - '0';
            else if (c >= 'a' && c <= 'f') v |= c - 'a' + 10;
            else if (c >= 'A' && c <= 'F') v |= c - 'A' + 10;
            else return -1;
        }
        return v;
    }

    /// The escape at p_ (a backslash), decoded onto scratch_ as nlohmann decodes it.
    bool escape() {
        if (++p_ == end_) return false;
        const char c = *p_++;
        switch (c) {
            case '"': scratch_ += '"'; return true;
            case '\\': scratch_ += '\\'; return true;
            case '/': scratch_ += '/'; return true;
            case 'b': scratch_ += '\b'; return true;
            case 'f': scratch_ += '\f'; return true;
            case 'n': scratch_ += '\n'; return true;
            case 'r': scratch_ += '\r'; return true;
            case 't': scratch_ += '\t'; return true;
            case 'u': break;
            default: return false;
        }
        int cp = hex4();
        if (cp < 0 || (cp >= 0xDC00 && cp <= 0xDFFF)) return false;
        if (cp >= 0xD800 && cp <= 0xDBFF) {  // a high surrogate: its low one must follow
            if (end_ - p_ < 2 || p_[0] != '\\' || p_[1] != 'u') return false;
            p_ += 2;
            const int low = hex4();
            if (low < 0xDC00 || low > 0xDFFF) return false;
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
        }
        auto put = [&](int byte) { scratch_ += static_cast<char>(byte); };
        if (cp < 0x80) {
            put(cp);
        } else if (cp <= 0x7FF) {
            put(0xC0 | (cp >> 6));
            put(0x80 | (cp & 0x3F));
        } else if (cp <= 0xFFFF) {
            put(0xE0 | (cp >> 12));
            put(0x80 | ((cp >> 6) & 0x3F));
            put(0x80 | (cp & 0x3F));
        } else {
            put(0xF0 | (cp >> 18));
            put(0x80 | ((cp >> 12) & 0x3F));
            put(0x80 | ((cp >> 6) & 0x3F));
            put(0x80 | (cp & 0x3F));
        }
        return true;
    }

    const char* begin_;
    const char* p_;
    const char* end_;
    JsonDocumentBuilder& b_;
    std::string scratch_;
};

}  // namespace

bool readJsonFast(std::string_view text, JsonDocumentBuilder& builder) { return FastReader(text, builder).read(); }

}  // namespace skygraph
