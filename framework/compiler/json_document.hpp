// A JSON text parsed by nlohmann's SAX parser into a compact, read-only tree: every value in
// one array, strings viewed in the text itself (only those with escapes are decoded, into one
// buffer). The graph loader reads files through it rather than through nlohmann::json, whose
// tree allocates per value: on a large graph building and freeing that tree costs several
// times the parse, and more per byte the larger the file.
//
// Objects read as nlohmann::json's do: members sorted by key (byte order), a repeated key
// keeping its last value. Numbers keep the kind nlohmann gives them (integer, unsigned,
// float), so conversions and printed values (dump) are nlohmann's. Errors, their positions
// and repeated keys are reported as parseJsonWithPositions reports them.
#pragma once

#include "json_positions.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

class JsonDocument;
class JsonChildren;

/// One value of a JsonDocument, or none (what find() returns for a missing member; false in
/// a condition). Two pointers: pass by value. Valid while its document and text live.
class JsonValue {
public:
    enum class Kind : uint8_t { Null, Boolean, Integer, Unsigned, Float, String, Object, Array };

    /// How a value is stored: 24 bytes, the children of a container side by side.
    struct Node {
        uint32_t keyOffset = 0;  ///< An object member's key (see JsonDocument::text).
        uint32_t keyLength = 0;
        /// By kind: the bool, the int64 or double's bits, the uint64, a string's offset (low
        /// half) and length, or a container's first child (low half) and child count.
        uint64_t payload = 0;
        Kind kind = Kind::Null;
        uint32_t keyOrder = 0;  ///< How many keys the text has before this member's.
    };

    JsonValue() = default;
    JsonValue(const JsonDocument* document, const Node* node) noexcept : doc_(document), node_(node) {}

    /// Whether there is a value (a JSON null is one).
    explicit operator bool() const noexcept { return node_ != nullptr; }

    [[nodiscard]] Kind kind() const noexcept { return node_->kind; }
    [[nodiscard]] bool isNull() const noexcept { return node_->kind == Kind::Null; }
    [[nodiscard]] bool isBoolean() const noexcept { return node_->kind == Kind::Boolean; }
    [[nodiscard]] bool isString() const noexcept { return node_->kind == Kind::String; }
    [[nodiscard]] bool isObject() const noexcept { return node_->kind == Kind::Object; }
    [[nodiscard]] bool isArray() const noexcept { return node_->kind == Kind::Array; }
    [[nodiscard]] bool isNumber() const noexcept {
        return node_->kind == Kind::Integer || node_->kind == Kind::Unsigned || node_->kind == Kind::Float;
    }
    /// Integer or unsigned, as nlohmann's is_number_integer.
    [[nodiscard]] bool isInteger() const noexcept {
        return node_->kind == Kind::Integer || node_->kind == Kind::Unsigned;
    }
    /// A non-negative integer as written (nlohmann's is_number_unsigned).
    [[nodiscard]] bool isUnsigned() const noexcept { return node_->kind == Kind::Unsigned; }

    [[nodiscard]] bool boolean() const noexcept { return node_->payload != 0; }
    [[nodiscard]] std::string_view string() const noexcept;
    /// The number converted as nlohmann's get<T>() converts it (static_cast from the stored kind).
    template <typename T>
    [[nodiscard]] T number() const noexcept {
        switch (node_->kind) {
            case Kind::Integer: return static_cast<T>(asInt64());
            case Kind::Unsigned: return static_cast<T>(node_->payload);
            default: return static_cast<T>(asDouble());
        }
    }
    /// Whether it equals integer `n` as nlohmann's operator== compares a value with one.
    [[nodiscard]] bool equals(int64_t n) const noexcept;

    /// Containers: members or elements.
    [[nodiscard]] size_t size() const noexcept { return static_cast<size_t>(node_->payload >> 32); }
    /// Arrays: element `i` (< size()).
    [[nodiscard]] JsonValue operator[](size_t i) const noexcept { return {doc_, children() + i}; }
    /// Objects: the member `key`, or none.
    [[nodiscard]] JsonValue find(std::string_view key) const noexcept;
    [[nodiscard]] bool contains(std::string_view key) const noexcept { return static_cast<bool>(find(key)); }
    /// Objects: members in key order. Arrays: elements in order (with empty keys).
    [[nodiscard]] JsonChildren members() const noexcept;
    [[nodiscard]] JsonChildren elements() const noexcept;

    /// The value as nlohmann::json (e.g. a pass's params), built on demand.
    [[nodiscard]] nlohmann::json toJson() const;
    /// nlohmann's compact text of the value, for messages.
    [[nodiscard]] std::string dump() const;
    /// For messages where an integer in [lowest, highest] is wanted: " (write it as an
    /// integer)" when the value is a whole number in that range written with a fraction or an
    /// exponent (`4.0`, `2.56e2`), which the loader does not take as an integer and the schema
    /// cannot tell apart; otherwise empty.
    [[nodiscard]] std::string integerHint(double lowest, double highest) const;
    /// The same for an array where integers are wanted: when every element is a whole number
    /// in range and some is written with a fraction (`[8, 8.0]`), not when one is not (`[0.5, 1.0]`).
    [[nodiscard]] std::string integersHint(double lowest, double highest) const;

private:
    [[nodiscard]] const Node* children() const noexcept;
    [[nodiscard]] int64_t asInt64() const noexcept {
        int64_t v;
        std::memcpy(&v, &node_->payload, sizeof v);
        return v;
    }
    [[nodiscard]] double asDouble() const noexcept {
        double v;
        std::memcpy(&v, &node_->payload, sizeof v);
        return v;
    }

    const JsonDocument* doc_ = nullptr;
    const Node* node_ = nullptr;
};

struct JsonMember {
    std::string_view key;
    JsonValue value;
};

/// A container's children, to iterate.
class JsonChildren {
public:
    class iterator {
    public:
        iterator(const JsonDocument* d, const JsonValue::Node* n) noexcept : doc_(d), node_(n) {}
        JsonMember operator*() const noexcept;
        iterator& operator++() noexcept {
            ++node_;
            return *this;
        }
        bool operator!=(const iterator& o) const noexcept { return node_ != o.node_; }

    private:
        const JsonDocument* doc_;
        const JsonValue::Node* node_;
    };
    JsonChildren(const JsonDocument* d, const JsonValue::Node* first, size_t n) noexcept
        : doc_(d), first_(first), n_(n) {}
    [[nodiscard]] iterator begin() const noexcept { return {doc_, first_}; }
    [[nodiscard]] iterator end() const noexcept { return {doc_, first_ + n_}; }

private:
    const JsonDocument* doc_;
    const JsonValue::Node* first_;
    size_t n_;
};

/// Whether two keys are equal. Keys are short and most differ in their first byte, which is
/// compared inline (a call to memcmp costs more than the comparison).
[[nodiscard]] inline bool sameKey(std::string_view a, std::string_view b) noexcept {
    return a.size() == b.size() &&
           (a.empty() || (a[0] == b[0] && std::memcmp(a.data(), b.data(), a.size()) == 0));
}

/// The members of an object whose keys a reader knows, by their key's place in `keys` (none
/// where missing), read in one walk over the object; and whether it has other keys.
template <size_t N>
struct JsonFields {
    std::array<JsonValue, N> values{};
    bool unknownKeys = false;
    [[nodiscard]] JsonValue operator[](size_t i) const noexcept { return values[i]; }
};

template <size_t N>
[[nodiscard]] JsonFields<N> fieldsOf(JsonValue object, const std::array<std::string_view, N>& keys);

/// The parsed text. It views the text: the text must outlive it and its values. Not copyable
/// (values point into it); movable only before values are taken.
class JsonDocument {
public:
    JsonDocument() = default;
    JsonDocument(const JsonDocument&) = delete;
    JsonDocument& operator=(const JsonDocument&) = delete;
    JsonDocument(JsonDocument&&) = default;
    JsonDocument& operator=(JsonDocument&&) = default;

    [[nodiscard]] JsonValue root() const noexcept { return {this, &root_}; }

private:
    friend class JsonValue;
    friend class JsonChildren;
    friend class JsonDocumentBuilder;

    /// Strings are offsets into the text, or past its end into `decoded_`.
    [[nodiscard]] const char* at(uint32_t offset) const noexcept {
        return offset < text_.size() ? text_.data() + offset : decoded_.data() + (offset - text_.size());
    }

    std::string_view text_;
    std::string decoded_;                 ///< Strings with escapes, decoded, end to end.
    std::vector<JsonValue::Node> nodes_;  ///< Every container's children, each container's together.
    JsonValue::Node root_;
};

/// Told of parts of the document as they are read: what lets a reader of a large file use
/// each element of a long array as it arrives, then drop it (readJson).
class JsonListener {
public:
    /// The root object's member `key` is complete (for an array it streamed: with no elements).
    virtual void rootMember(std::string_view key, JsonValue value) = 0;
    /// The root object's member `key` is an array, beginning at byte `offset` of the text:
    /// whether to hand its elements to element() as each is complete, leaving them out of the
    /// document.
    virtual bool streamArray(std::string_view key, size_t offset) = 0;
    /// Element `index` of the array being streamed, which ends before byte `end` of the text.
    /// The value is valid during the call only.
    virtual void element(size_t index, JsonValue value, size_t end) = 0;

protected:
    ~JsonListener() = default;
};

struct JsonRead {
    JsonDocument document;  ///< Complete only when `error` is empty.
    std::string error;      ///< Empty on success; otherwise as JsonParseResult::error.
    std::string errorPath;
    int line = 0;
    int column = 0;
    std::vector<DuplicateKey> duplicateKeys;  ///< In the order they appear in the text.
};

/// Never throws. The text must outlive the document. nlohmann's SAX parser reads the text, so
/// what it accepts, its values and its messages are nlohmann's. On success `listener` has
/// been told of the whole document; on an error, of the part before it, to be forgotten.
[[nodiscard]] JsonRead readJson(std::string_view text, JsonListener* listener = nullptr);

inline std::string_view JsonValue::string() const noexcept {
    return {doc_->at(static_cast<uint32_t>(node_->payload)), static_cast<size_t>(node_->payload >> 32)};
}

inline const JsonValue::Node* JsonValue::children() const noexcept {
    return doc_->nodes_.data() + static_cast<uint32_t>(node_->payload);
}

inline JsonMember JsonChildren::iterator::operator*() const noexcept {
    return {{doc_->at(node_->keyOffset), node_->keyLength}, JsonValue(doc_, node_)};
}

inline JsonChildren JsonValue::members() const noexcept { return {doc_, children(), size()}; }
inline JsonChildren JsonValue::elements() const noexcept { return {doc_, children(), size()}; }

template <size_t N>
JsonFields<N> fieldsOf(JsonValue object, const std::array<std::string_view, N>& keys) {
    JsonFields<N> f;
    for (const auto& [key, value] : object.members()) {
        size_t i = 0;
        while (i < N && !sameKey(key, keys[i])) ++i;
        if (i < N) f.values[i] = value;
        else f.unknownKeys = true;
    }
    return f;
}

}  // namespace skygraph
