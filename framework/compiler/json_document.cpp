#include "json_document.hpp"

#include "json_document_builder.hpp"
#include "json_fast_reader.hpp"

#include <algorithm>
#include <bit>

namespace skygraph {

using Node = JsonValue::Node;
using Kind = JsonValue::Kind;

namespace {

// nlohmann's SAX events, for the builder. Strings arrive decoded, without their place in the
// text: they are copied.
class SaxEvents {
public:
    explicit SaxEvents(JsonDocumentBuilder& b) : b_(b) {}
    bool null() { return b_.add(Kind::Null, 0); }
    bool boolean(bool v) { return b_.add(Kind::Boolean, v ? 1 : 0); }
    bool number_integer(int64_t v) { return b_.add(Kind::Integer, std::bit_cast<uint64_t>(v)); }
    bool number_unsigned(uint64_t v) { return b_.add(Kind::Unsigned, v); }
    bool number_float(double v, const std::string&) { return b_.add(Kind::Float, std::bit_cast<uint64_t>(v)); }
    bool string(std::string& v) { return b_.add(Kind::String, b_.decoded(v)); }
    bool binary(nlohmann::json::binary_t&) { return b_.add(Kind::Null, 0); }  // JSON text has none
    bool start_object(size_t) { return b_.open(false); }
    bool start_array(size_t) { return b_.open(true); }
    bool key(std::string& k) {
        b_.key(b_.decoded(k));
        return true;
    }
    bool end_object() { return b_.close(Kind::Object); }
    bool end_array() { return b_.close(Kind::Array); }
    bool parse_error(size_t position, const std::string&, const nlohmann::detail::exception& ex) {
        b_.errorByte = position;
        b_.error = ex.what();
        b_.errorPath = b_.currentPath();
        return false;
    }

private:
    JsonDocumentBuilder& b_;
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
    {
        JsonDocumentBuilder builder(result.document, text, listener);
        if (readJsonFast(text, builder)) {
            result.duplicateKeys = builder.takeDuplicates();
            result.listened = listener != nullptr;
            return result;
        }
    }
    result.document = JsonDocument();
    JsonDocumentBuilder builder(result.document, text, nullptr);
    SaxEvents events(builder);
    bool ok = false;
    try {
        ok = nlohmann::json::sax_parse(text.begin(), text.end(), &events);
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

}  // namespace skygraph