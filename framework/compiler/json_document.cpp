#include "json_document.hpp"

#include "json_document_builder.hpp"
#include "integer_hint.hpp"
#include "printable_name.hpp"

#include <cmath>
#include <algorithm>
#include <bit>
#include <cstring>
#include <iterator>

namespace skygraph {

using Node = JsonValue::Node;
using Kind = JsonValue::Kind;

namespace {

/// nlohmann reads the text through this iterator, which writes down how far it has read:
/// nlohmann's SAX events come without their place in the text, and a string's place is what
/// lets the document view it where it is written rather than copy it.
class TrackedChar {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    TrackedChar(const char* at, const char** published) : at_(at), published_(published) {}
    reference operator*() const { return *at_; }
    TrackedChar& operator++() {
        *published_ = ++at_;
        return *this;
    }
    bool operator==(const TrackedChar& o) const { return at_ == o.at_; }
    bool operator!=(const TrackedChar& o) const { return at_ != o.at_; }

private:
    const char* at_;
    const char** published_;
};

// nlohmann's SAX events, for the builder. Each arrives just after its token is read: the
// parser's place then is the token's end (one byte later for a number, whose end nlohmann
// finds by reading the byte after it).
class SaxEvents {
public:
    SaxEvents(JsonDocumentBuilder& b, std::string_view text) : b_(b), text_(text), read_(text.data()) {}
    const char** readUpTo() { return &read_; }

    bool null() { return b_.add(Kind::Null, 0, here()); }
    bool boolean(bool v) { return b_.add(Kind::Boolean, v ? 1 : 0, here()); }
    bool number_integer(int64_t v) { return b_.add(Kind::Integer, std::bit_cast<uint64_t>(v), numberEnd()); }
    bool number_unsigned(uint64_t v) { return b_.add(Kind::Unsigned, v, numberEnd()); }
    bool number_float(double v, const std::string&) {
        return b_.add(Kind::Float, std::bit_cast<uint64_t>(v), numberEnd());
    }
    bool string(std::string& v) { return b_.add(Kind::String, stringRef(v), here()); }
    bool binary(nlohmann::json::binary_t&) { return b_.add(Kind::Null, 0, here()); }  // JSON text has none
    bool start_object(size_t) { return b_.open(false, here() - 1); }
    bool start_array(size_t) { return b_.open(true, here() - 1); }
    bool key(std::string& k) {
        b_.key(stringRef(k));
        return true;
    }
    bool end_object() { return b_.close(Kind::Object, here()); }
    bool end_array() { return b_.close(Kind::Array, here()); }
    bool parse_error(size_t position, const std::string&, const nlohmann::detail::exception& ex) {
        b_.errorByte = position;
        b_.error = printableName(ex.what());  // its "last read" shows the bytes as they are
        // A number too large for a double (nlohmann's out_of_range.406) is a bad value, not
        // bad structure: its path names the value itself, the element or member being read.
        constexpr int kNumberOverflow = 406;
        b_.errorPath = ex.id == kNumberOverflow ? b_.valuePath() : b_.currentPath();
        return false;
    }

private:
    [[nodiscard]] size_t here() const { return static_cast<size_t>(read_ - text_.data()); }
    /// A number's last byte is a digit; the byte nlohmann read after it (if any) is not.
    [[nodiscard]] size_t numberEnd() const {
        const size_t at = here();
        return text_[at - 1] >= '0' && text_[at - 1] <= '9' ? at : at - 1;
    }
    /// The string just read, as the document keeps it: viewed in the text where it is
    /// written without escapes, else a decoded copy. Its closing quote is the last byte read.
    /// Without escapes, it is the `v.size()` bytes before that quote, after an opening quote.
    /// With any, it is longer than its value (an escape is longer than what it stands for),
    /// so those bytes are only its end: they hold a backslash, or the byte before them is in
    /// the string, and a quote in a string is the escape \".
    uint64_t stringRef(const std::string& v) {
        const size_t quote = here() - 1;
        if (quote > v.size()) {
            const size_t start = quote - v.size();
            if (text_[start - 1] == '"' && std::memchr(text_.data() + start, '\\', v.size()) == nullptr)
                return JsonDocumentBuilder::inText(start, v.size());
        }
        return b_.decoded(v);
    }

    JsonDocumentBuilder& b_;
    std::string_view text_;
    const char* read_;  ///< Where nlohmann's input is.
};

}  // namespace

JsonRead readJson(std::string_view text, JsonListener* listener) {
    JsonRead result;
    // Offsets into the text and its decoded strings are 32-bit.
    if (text.size() > (uint64_t(1) << 31)) {
        result.error = "the text is larger than 2 GiB, more than a JSON file here may be";
        result.line = 1;
        result.column = 1;
        return result;
    }
    // nlohmann's lexer takes a NUL byte for the end of the text, so what follows one would go
    // unread (and a file of NULs would read as empty).
    if (const void* nul = std::memchr(text.data(), '\0', text.size())) {
        const auto at = static_cast<size_t>(static_cast<const char*>(nul) - text.data());
        JsonSyntaxError e = describeJsonError(
            text, at + 1, "a NUL byte (U+0000), which JSON has only inside a string, written \\u0000", false);
        result.error = std::move(e.message);
        result.line = e.line;
        result.column = e.column;
        return result;
    }
    JsonDocumentBuilder builder(result.document, text, listener);
    SaxEvents events(builder, text);
    bool ok = false;
    try {
        ok = nlohmann::json::sax_parse(TrackedChar(text.data(), events.readUpTo()),
                                       TrackedChar(text.data() + text.size(), events.readUpTo()), &events);
    } catch (const std::exception& e) {  // not expected: errors arrive through parse_error
        builder.error = e.what();
    }
    result.duplicateKeys = builder.takeDuplicates();
    if (ok && builder.error.empty()) return result;
    JsonSyntaxError e = describeJsonError(text, builder.errorByte, builder.error, builder.tooDeep);
    result.error = std::move(e.message);
    result.errorPath = std::move(builder.errorPath);
    result.line = e.line;
    result.column = e.column;
    result.document = JsonDocument();
    return result;
}

// ---- reading ----------------------------------------------------------------------------

bool JsonValue::equals(int64_t n) const noexcept {
    switch (node_->kind) {
        case Kind::Integer: return asInt64() == n;
        case Kind::Unsigned: return static_cast<int64_t>(node_->payload) == n;
        case Kind::Float: return asDouble() == static_cast<double>(n);
        default: return false;
    }
}

JsonValue JsonValue::find(std::string_view key) const noexcept {
    const Node* first = children();
    const size_t n = size();
    auto keyOf = [&](const Node& m) { return std::string_view(doc_->at(m.keyOffset), m.keyLength); };
    if (n <= 8) {
        for (const Node* m = first; m != first + n; ++m)
            if (m->keyLength == key.size() && sameKey(keyOf(*m), key)) return {doc_, m};
        return {};
    }
    const Node* it = std::lower_bound(first, first + n, key, [&](const Node& m, std::string_view k) {
        return json_detail::keyLess(keyOf(m), k);
    });
    if (it != first + n && sameKey(keyOf(*it), key)) return {doc_, it};
    return {};
}

nlohmann::json JsonValue::toJson() const {
    switch (node_->kind) {
        case Kind::Null: return nullptr;
        case Kind::Boolean: return boolean();
        case Kind::Integer: return asInt64();
        case Kind::Unsigned: return node_->payload;
        case Kind::Float: return asDouble();
        case Kind::String: return std::string(string());
        case Kind::Object: {
            nlohmann::json object = nlohmann::json::object();
            auto& map = object.get_ref<nlohmann::json::object_t&>();
            for (const auto& [key, value] : members()) map.emplace_hint(map.end(), key, value.toJson());
            return object;
        }
        case Kind::Array: {
            nlohmann::json array = nlohmann::json::array();
            auto& elements = array.get_ref<nlohmann::json::array_t&>();
            elements.reserve(size());
            for (const auto& e : this->elements()) elements.push_back(e.value.toJson());
            return array;
        }
    }
    return nullptr;
}

std::string JsonValue::dump() const { return toJson().dump(); }

std::string JsonValue::integerHint(double lowest, double highest) const {
    return kind() == Kind::Float ? skygraph::integerHint(number<double>(), lowest, highest) : "";
}

std::string JsonValue::integersHint(double lowest, double highest) const {
    if (!isArray()) return {};
    std::string hint;
    for (size_t i = 0; i < size(); ++i) {
        const JsonValue element = (*this)[i];
        if (element.isInteger() && element.number<double>() >= lowest && element.number<double>() <= highest) continue;
        hint = element.integerHint(lowest, highest);
        if (hint.empty()) return {};
    }
    return hint;
}

}  // namespace skygraph