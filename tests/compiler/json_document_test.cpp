// The JSON reader the loader uses (framework/compiler/json_document.hpp): it gives the values
// and repeated keys nlohmann's parser gives, whether it reads a text itself or leaves it to
// nlohmann, and a listener is told of a streamed array's elements as each is complete.
#include "json_document.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <bit>
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

// A byte-order mark makes the reader leave the text to nlohmann: both ways of reading find the
// same repeated keys, in the order the text has them (one of them written with an escape).
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
    EXPECT_TRUE(read.listened);
    EXPECT_EQ(r.events, (std::vector<std::string>{
                            "member head {\"a\":1}", "array items at 28", "element 0 {\"b\":[2]} ends 39",
                            "element 1 3 ends 42", "element 2 [4] ends 47", "member items []", "member tail \"t\"",
                            "array more at 71", "member more [5]"}));
    // The document keeps the rest; the streamed array is left empty.
    EXPECT_EQ(read.document.root().dump(), R"({"head":{"a":1},"items":[],"more":[5],"tail":"t"})");
}

TEST(JsonDocument, AListenerIsNotToldOfATextLeftToNlohmann) {
    Recorder r;
    const JsonRead read = readJson("\xef\xbb\xbf{\"items\": [1, 2]}", &r);
    ASSERT_EQ(read.error, "");
    EXPECT_FALSE(read.listened);
    EXPECT_TRUE(r.events.empty());
    EXPECT_EQ(read.document.root().dump(), R"({"items":[1,2]})");  // whole, as without a listener
    // A malformed text: the listener may have been told of its start, but not that it was whole.
    Recorder partial;
    const JsonRead bad = readJson(R"({"items": [1, 2], "x": })", &partial);
    EXPECT_NE(bad.error, "");
    EXPECT_FALSE(bad.listened);
    EXPECT_FALSE(partial.events.empty());
}

}  // namespace
}  // namespace skygraph
