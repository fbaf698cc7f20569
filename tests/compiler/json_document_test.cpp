// The JSON reader the loader uses (framework/compiler/json_document.hpp): the document it
// builds from nlohmann's SAX events holds the values nlohmann::json::parse gives, in the same
// order, with strings viewed in the text or decoded as they are written; repeated keys are
// found; a listener is told of a streamed array's elements as each is complete.
#include "json_document.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <bit>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace skygraph {
namespace {

/// Whether `a` and `b` are the same value with the same types all through: nlohmann's ==
/// takes 1 and 1.0, or 0.0 and -0.0, for equal.
bool same(const nlohmann::json& a, const nlohmann::json& b) {
    if (a.type() != b.type()) return false;
    if (a.is_object() || a.is_array()) {
        if (a.size() != b.size()) return false;
        for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j)
            if ((a.is_object() && i.key() != j.key()) || !same(*i, *j)) return false;
        return true;
    }
    if (a.is_number_float())
        return std::bit_cast<uint64_t>(a.get<double>()) == std::bit_cast<uint64_t>(b.get<double>());
    return a == b;
}

// Numbers of every kind and size (integers too long for 64 bits become floats, as nlohmann
// makes them), escapes and UTF-8, whitespace, nesting, repeated keys, a byte-order mark.
const std::vector<std::string> kTexts{
    R"({"a": 1, "b": -1, "c": 0, "d": -0, "e": 1.0, "f": -0.0, "g": 1e5, "h": 1E-5, "i": 2.5e+3})",
    R"([999999999999999999, -999999999999999999, 9999999999999999999, 18446744073709551615,
        18446744073709551616, -9223372036854775808, -9223372036854775809, 123456789012345678901234567890])",
    R"([1e-320, 4.9e-324, 1e-400, 1.7976931348623157e308, 0.1, 0.30000000000000004, 123.456e-7])",
    R"(["", "plain", "tab\tquote\"backslash\\slash\/", "\b\f\n\r", "\u00e9\u20ac\ud83d\ude00", "\u0000x"])",
    "[\"caf\xc3\xa9\", \"\xe2\x82\xac\", \"\xf0\x9f\x98\x80\", \"\xf4\x8f\xbf\xbf\", \"\x7f\"]",
    "\xef\xbb\xbf{\"bom\": true}",
    " \t\r\n[ true , false , null ] \n",
    R"({"z": 1, "a": {"y": [], "b": {}}, "m": [[], [{}]], "": 0})",
    R"({"k": 1, "k": 2, "j": {"x": 1, "x": [3]}})",
    R"({"\u0041": 1, "A": 2, "B\u0041": 3, "\u00e9": 4})",
    "3",
    "\"only a string\"",
};

TEST(JsonDocument, ReadsTheValuesNlohmannReads) {
    for (const auto& text : kTexts) {
        const JsonRead read = readJson(text);
        ASSERT_EQ(read.error, "") << text;
        const nlohmann::json expected = nlohmann::json::parse(text);
        EXPECT_TRUE(same(read.document.root().toJson(), expected))
            << text << "\nread " << read.document.root().dump() << "\nnlohmann " << expected.dump();
    }
}

TEST(JsonDocument, ObjectsAreSortedAndTheLastOfARepeatedKeyWins) {
    const JsonRead read = readJson(R"({"b": 1, "a": {"y": 2, "x": 3}, "b": 4, "c\u0000": 5, "c": 6})");
    ASSERT_EQ(read.error, "");
    std::vector<std::string> keys;
    for (const auto& [key, value] : read.document.root().members()) keys.emplace_back(key);
    EXPECT_EQ(keys, (std::vector<std::string>{"a", "b", "c", std::string("c\0", 2)}));
    EXPECT_EQ(read.document.root().find("b").number<int>(), 4);
    EXPECT_FALSE(read.document.root().find("d"));
    ASSERT_EQ(read.duplicateKeys.size(), 1u);
    EXPECT_EQ(read.duplicateKeys[0].path, "b");
}

// A large object (a graph's resources) is sorted another way than a small one: by its keys'
// first 8 bytes, then whole keys. Keys that share those bytes, are shorter, hold a NUL or an
// escape, or repeat must still come in nlohmann's order, the last of a repeat winning.
TEST(JsonDocument, ALargeObjectIsInKeyOrder) {
    const std::vector<std::string> stems{"res", "resource_", "resource", "r", "", "a\u0000", "shared_prefix_", "z"};
    std::string text = "{";
    for (int i = 0; i < 300; ++i)
        text += (i ? ", \"" : "\"") + stems[size_t(i * 7 + i / 5) % stems.size()] + std::to_string(i % 41) +
                "\": " + std::to_string(i);
    text += "}";
    const JsonRead read = readJson(text);
    ASSERT_EQ(read.error, "");
    const nlohmann::json expected = nlohmann::json::parse(text);
    std::vector<std::pair<std::string, int>> got, want;
    for (const auto& [key, value] : read.document.root().members()) got.emplace_back(key, value.number<int>());
    for (const auto& [key, value] : expected.items()) want.emplace_back(key, value.get<int>());
    EXPECT_EQ(got, want);
    EXPECT_GT(read.duplicateKeys.size(), 0u);
}

// Repeated keys in the order the text has them (one of them written with an escape), with or
// without a byte-order mark (which moves every string's place in the text).
TEST(JsonDocument, RepeatedKeysAreTheSameEitherWay) {
    const std::string text =
        R"({ "a": { "x": 1, "\u0078": 2 }, "b": [ {}, { "y": 1, "z": 2, "y": 3 } ], "a": 0 })";
    for (const std::string& t : {text, "\xef\xbb\xbf" + text}) {
        const JsonRead read = readJson(t);
        ASSERT_EQ(read.error, "");
        ASSERT_EQ(read.duplicateKeys.size(), 3u) << t;
        EXPECT_EQ(read.duplicateKeys[0].path, "a.x");
        EXPECT_EQ(read.duplicateKeys[1].path, "b[1].y");
        EXPECT_EQ(read.duplicateKeys[2].path, "a");
    }
}

TEST(JsonDocument, NumbersConvertAsNlohmannConvertsThem) {
    const JsonRead read = readJson(R"([1, -1, 2.9, 18446744073709551615, 1.0])");
    ASSERT_EQ(read.error, "");
    const JsonValue a = read.document.root();
    EXPECT_TRUE(a[0].isUnsigned());
    EXPECT_TRUE(a[1].isInteger() && !a[1].isUnsigned());
    EXPECT_FALSE(a[2].isInteger());
    EXPECT_EQ(a[1].number<uint32_t>(), nlohmann::json(-1).get<uint32_t>());
    EXPECT_EQ(a[2].number<int>(), 2);
    EXPECT_EQ(a[3].number<int64_t>(), -1);  // wraps, as get<int64_t>()
    EXPECT_TRUE(a[4].equals(1));            // as nlohmann's 1.0 == 1
    EXPECT_FALSE(a[2].equals(2));
    EXPECT_EQ(a[2].dump(), "2.9");
}

/// Writes down what it is told.
struct Recorder final : JsonListener {
    std::vector<std::string> events;
    void rootMember(std::string_view key, JsonValue value) override {
        events.push_back("member " + std::string(key) + " " + value.dump());
    }
    bool streamArray(std::string_view key, size_t offset) override {
        events.push_back("array " + std::string(key) + " at " + std::to_string(offset));
        return key == "items";
    }
    void element(size_t index, JsonValue value, size_t end) override {
        events.push_back("element " + std::to_string(index) + " " + value.dump() + " ends " + std::to_string(end));
    }
};

TEST(JsonDocument, AListenerIsToldOfAStreamedArraysElementsAsTheyComplete) {
    const std::string text = R"({"head": {"a": 1}, "items": [{"b": [2]}, 3, [4]], "tail": "t", "more": [5]})";
    Recorder r;
    const JsonRead read = readJson(text, &r);
    ASSERT_EQ(read.error, "");
    EXPECT_EQ(r.events, (std::vector<std::string>{
                            "member head {\"a\":1}", "array items at 28", "element 0 {\"b\":[2]} ends 39",
                            "element 1 3 ends 42", "element 2 [4] ends 47", "member items []", "member tail \"t\"",
                            "array more at 71", "member more [5]"}));
    // The document keeps the rest; the streamed array is left empty.
    EXPECT_EQ(read.document.root().dump(), R"({"head":{"a":1},"items":[],"more":[5],"tail":"t"})");
}

TEST(JsonDocument, AListenerCountsOffsetsFromTheTextsFirstByte) {
    Recorder r;
    const JsonRead read = readJson("\xef\xbb\xbf{\"items\": [1, 22]}", &r);
    ASSERT_EQ(read.error, "");
    EXPECT_EQ(r.events, (std::vector<std::string>{"array items at 13", "element 0 1 ends 15",
                                                  "element 1 22 ends 19", "member items []"}));
}

TEST(JsonDocument, AListenerOfAMalformedTextIsToldOfItsStartOnly) {
    Recorder r;
    const JsonRead bad = readJson(R"({"items": [1, 2], "x": })", &r);
    EXPECT_NE(bad.error, "");
    EXPECT_EQ(r.events, (std::vector<std::string>{"array items at 10", "element 0 1 ends 12",
                                                  "element 1 2 ends 15", "member items []"}));
}

/// Keeps the views of the streamed elements' strings, as the graph loader keeps pass names.
struct ViewKeeper final : JsonListener {
    std::vector<std::string_view> views;
    std::vector<std::string> copies;
    void rootMember(std::string_view, JsonValue) override {}
    bool streamArray(std::string_view key, size_t) override { return key == "items"; }
    void element(size_t, JsonValue value, size_t) override {
        views.push_back(value.string());
        copies.emplace_back(value.string());
    }
};

TEST(JsonDocument, ViewsOfDecodedStringsStayInPlaceWhileLaterOnesAreDecoded) {
    // Strings with escapes are decoded into one buffer; the first must not be moved by the
    // later ones, though it alone fits in an empty std::string's own few bytes.
    std::string text = R"({"items": ["\u0061b")";
    for (int i = 0; i < 40; ++i) text += R"(, "escaped \"string\" number )" + std::to_string(i) + R"( is long enough")";
    text += "]}";
    ViewKeeper k;
    const JsonRead read = readJson(text, &k);
    ASSERT_EQ(read.error, "");
    ASSERT_EQ(k.views.size(), 41u);
    EXPECT_EQ(k.copies[0], "ab");
    EXPECT_EQ(k.copies[40], R"(escaped "string" number 39 is long enough)");
    // All views are in one buffer, end to end, in order: none was left behind by a move.
    for (size_t i = 1; i < k.views.size(); ++i)
        EXPECT_EQ(k.views[i].data(), k.views[i - 1].data() + k.views[i - 1].size()) << i;
    for (size_t i = 0; i < k.views.size(); ++i) EXPECT_EQ(k.views[i], k.copies[i]) << i;
}

// ---- against nlohmann::json::parse ------------------------------------------------------

/// Random texts, valid and broken, built from the pieces that test the builder: strings with
/// and without escapes (an escaped quote or backslash just inside a quote, where a view of
/// the text could be taken for the value), keys likewise, small and large objects (sorted two
/// ways) with repeated and prefix-sharing keys, numbers of every kind, deep nesting.
class RandomJson {
public:
    explicit RandomJson(uint64_t seed) : rng_(seed) {}

    std::string text() {
        std::string t = value(0);
        if (pick(3) == 0)
            for (size_t m = 1 + pick(3); m-- > 0 && !t.empty();) mutate(t);
        if (pick(8) == 0) t = " \n\t" + t + "\r\n";
        if (pick(40) == 0) t = "\xef\xbb\xbf" + t;
        return t;
    }

private:
    size_t pick(size_t n) { return static_cast<size_t>(rng_() % n); }
    template <size_t N>
    const char* oneOf(const std::array<const char*, N>& choices) { return choices[pick(N)]; }

    std::string string() {
        static constexpr std::array<const char*, 26> kParts{
            "a", "Z", "res", "ource", " ", "\\\"", "\\\\", "\\/", "\\b", "\\f", "\\n", "\\r", "\\t",
            "\\u0041", "\\u00e9", "\\u20ac", "\\ud83d\\ude00", "\\u0000", "\xc3\xa9", "\xe2\x82\xac",
            "\xf0\x9f\x98\x80", "\x7f", "\\\"\\\"", "\"", "\\", "\\u"};
        std::string s = "\"";
        // The last three parts break a string: rarely, as the numbers that do.
        for (size_t n = pick(5); n-- > 0;) s += pick(50) ? kParts[pick(kParts.size() - 3)] : oneOf(kParts);
        return s + "\"";
    }
    std::string number() {
        static constexpr std::array<const char*, 24> kNumbers{
            "0", "-0", "7", "-1", "0.5", "-0.0", "1e5", "1E-5", "2.5e+3", "999999999999999999",
            "-999999999999999999", "9999999999999999999", "18446744073709551615", "18446744073709551616",
            "-9223372036854775808", "-9223372036854775809", "1e-320", "4.9e-324", "1.7976931348623157e308",
            "0.1", "123456789012345678901234567890", "3.14159265358979323846264338327950288", "1e309", "01"};
        return pick(50) ? kNumbers[pick(kNumbers.size() - 2)] : oneOf(kNumbers);  // the last two break it
    }
    std::string key(size_t members) {
        if (pick(3) == 0) return string();
        static constexpr std::array<const char*, 6> kStems{"k", "key_", "shared_prefix_", "", "a\\u0000", "\\u006b"};
        return "\"" + std::string(oneOf(kStems)) + std::to_string(pick(members + 1)) + "\"";
    }
    std::string value(int depth) {
        size_t kind = pick(depth > 5 ? 6 : 9);
        if (depth == 0 && pick(3) == 0) kind = 9;  // a large object: at the root only
        switch (kind) {
            case 0: return "null";
            case 1: return pick(2) ? "true" : "false";
            case 2: case 3: return number();
            case 4: case 5: return string();
            case 6: case 7: return container(depth, '[', ']', pick(5));
            case 8: return container(depth, '{', '}', pick(6));
            default: return container(depth, '{', '}', 17 + pick(40));
        }
    }
    std::string container(int depth, char open, char close, size_t n) {
        std::string s(1, open);
        for (size_t i = 0; i < n; ++i) {
            if (i) s += pick(4) ? "," : " ,\n ";
            if (open == '{') s += key(n) + (pick(2) ? ":" : " : ");
            s += value(depth + 1);
        }
        return s + close;
    }
    void mutate(std::string& t) {
        static constexpr std::array<const char*, 16> kPieces{"{", "}", "[", "]", ",", ":", "\"", "\\", "1",
                                                             "tru", "nul", "\xff", "\x01", "\xc3", "-", "e"};
        const size_t at = pick(t.size() + 1);
        switch (pick(3)) {
            case 0: t.insert(at, oneOf(kPieces)); break;
            case 1: t.erase(at, 1 + pick(3)); break;
            default: if (at < t.size()) t[at] = oneOf(kPieces)[0]; break;
        }
    }

    std::mt19937_64 rng_;
};

/// Whether the document's containers hold their members in nlohmann's order (same() compares
/// through toJson, which could reorder them).
bool sameOrder(JsonValue v, const nlohmann::json& j) {
    if (v.kind() != JsonValue::Kind::Object && v.kind() != JsonValue::Kind::Array) return true;
    if (v.size() != j.size()) return false;
    auto it = j.begin();
    for (const auto& [key, child] : v.members()) {
        if ((v.isObject() && key != it.key()) || !sameOrder(child, *it)) return false;
        ++it;
    }
    return true;
}

/// Streams every array of the root object, keeping the elements of each key's last value.
struct Collector final : JsonListener {
    std::map<std::string, std::vector<nlohmann::json>, std::less<>> streamed;
    void rootMember(std::string_view key, JsonValue) override {
        if (key != streaming) streamed.erase(std::string(key));  // repeated with another value
        streaming.reset();
    }
    bool streamArray(std::string_view key, size_t) override {
        streaming = key;
        streamed[*streaming].clear();
        return true;
    }
    void element(size_t index, JsonValue value, size_t) override {
        auto& elements = streamed[*streaming];
        EXPECT_EQ(index, elements.size());
        elements.push_back(value.toJson());
    }
    std::optional<std::string> streaming;
};

TEST(JsonDocument, AgreesWithNlohmannOnRandomTexts) {
    RandomJson random(20261201);
    size_t accepted = 0, refused = 0, streamedArrays = 0;
    for (int n = 0; n < 30000; ++n) {
        const std::string text = random.text();
        const JsonRead read = readJson(text);
        nlohmann::json expected;
        bool parses = true;
        try {
            expected = nlohmann::json::parse(text);
        } catch (const nlohmann::json::exception&) {
            parses = false;
        }
        ASSERT_EQ(read.error.empty(), parses) << text << "\n" << read.error;
        if (!parses) {
            ++refused;
            continue;
        }
        ++accepted;
        ASSERT_TRUE(same(read.document.root().toJson(), expected))
            << text << "\nread     " << read.document.root().dump() << "\nnlohmann " << expected.dump();
        ASSERT_TRUE(sameOrder(read.document.root(), expected)) << text;

        // Read again streaming the root's arrays: their elements arrive as nlohmann has them,
        // the rest of the document is as before, and the repeated keys are the same.
        if (!expected.is_object()) continue;
        Collector c;
        const JsonRead streamed = readJson(text, &c);
        ASSERT_EQ(streamed.error, "") << text;
        nlohmann::json rest = expected;
        for (auto& [key, elements] : c.streamed) {
            ASSERT_TRUE(expected.contains(key) && expected[key].is_array()) << text;
            ASSERT_TRUE(same(nlohmann::json(elements), expected[key])) << text << "\n" << key;
            rest[key] = nlohmann::json::array();
            ++streamedArrays;
        }
        ASSERT_TRUE(same(streamed.document.root().toJson(), rest)) << text;
        ASSERT_EQ(streamed.duplicateKeys.size(), read.duplicateKeys.size()) << text;
    }
    // The texts reach both outcomes and the listener, often.
    EXPECT_GT(accepted, 10000u);
    EXPECT_GT(refused, 5000u);
    EXPECT_GT(streamedArrays, 1000u);
}

}  // namespace
}  // namespace skygraph
