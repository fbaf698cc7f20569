// The JSON paths in messages: a key that a dot could not delimit is quoted in brackets, and
// the duplicate-key report reads the resource back out of such a path.
#include "json_path.hpp"

#include <skygraph/pass_registry.hpp>

#include <gtest/gtest.h>

namespace skygraph::test {
namespace {

TEST(JsonPath, PlainKeysFollowADot) {
    EXPECT_EQ(jsonPathMember("", "resources"), "resources");
    EXPECT_EQ(jsonPathMember("resources", "hdr_color"), "resources.hdr_color");
    EXPECT_EQ(jsonPathMember("passes[2].uses", "shadow-map_0"), "passes[2].uses.shadow-map_0");
    EXPECT_EQ(jsonPathMember("resources", "h\xc3\xa9lium"), "resources.h\xc3\xa9lium");  // UTF-8 is plain
}

TEST(JsonPath, KeysADotCouldNotDelimitAreQuotedInBrackets) {
    EXPECT_EQ(jsonPathMember("resources", "gbuffer.normal"), R"(resources["gbuffer.normal"])");
    EXPECT_EQ(jsonPathMember("resources", "a[0]"), R"(resources["a[0]"])");
    EXPECT_EQ(jsonPathMember("resources", "two words"), R"(resources["two words"])");
    EXPECT_EQ(jsonPathMember("resources", R"(say "hi" \o/)"), R"(resources["say \"hi\" \\o/"])");
    EXPECT_EQ(jsonPathMember("resources", ""), R"(resources[""])");
    EXPECT_EQ(jsonPathMember("", "a.b"), R"(["a.b"])");
    EXPECT_EQ(jsonPathMember(jsonPathMember("resources", "a.b"), "size"), R"(resources["a.b"].size)");
}

// What a pass type outside the project writes its params errors with: the same paths.
TEST(JsonPath, ParamErrorsQuoteKeysTheSameWay) {
    EXPECT_EQ(ParamError::forKey("strength", "m").path, "strength");
    EXPECT_EQ(ParamError::forKey("exposure.ev", "m").path, R"(["exposure.ev"])");
    EXPECT_EQ(ParamError::forKey("exposure.ev", "too bright").message, "too bright");
    EXPECT_EQ(ParamError::memberPath("tint", "r"), "tint.r");
    EXPECT_EQ(ParamError::memberPath(ParamError::memberPath("", "a b"), "c"), R"(["a b"].c)");
}

TEST(JsonPath, EveryMemberReadsBackAsItWasWritten) {
    for (const std::string key : {"hdr_color", "gbuffer.normal", "a[0]", "x\"]y", "back\\slash", "", "end\\"}) {
        const std::string path = jsonPathMember(jsonPathMember("resources", key), "size");
        size_t at = 9;
        const auto read = readPathMember(path, at);
        ASSERT_TRUE(read.has_value()) << path;
        EXPECT_EQ(*read, key) << path;
        EXPECT_EQ(path.substr(at), ".size") << path;
    }
}

TEST(JsonPath, WhatNamesNoMemberReadsAsNothing) {
    for (const std::string path : {"resources", "resources.", "resources[0]", R"(resources["open)", R"(resources["a"x)"}) {
        size_t at = 9;
        EXPECT_FALSE(readPathMember(path, at).has_value()) << path;
        EXPECT_EQ(at, 9u) << path;
    }
}

}  // namespace
}  // namespace skygraph::test
