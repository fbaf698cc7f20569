// Feature conditions (docs/graph-format.md, "Features and conditions"): grammar, precedence,
// errors with columns, and limits that keep hostile input from exhausting the stack.
#include <skygraph/condition.hpp>

#include <gtest/gtest.h>

#include <string>

namespace skygraph {
namespace {

Condition parseOk(const std::string& text) {
    std::string error;
    auto c = Condition::parse(text, error);
    EXPECT_TRUE(c.has_value()) << "'" << text << "' failed: " << error;
    EXPECT_EQ(error, "") << text;
    return c ? *c : Condition();
}

std::string parseError(const std::string& text) {
    std::string error;
    auto c = Condition::parse(text, error);
    EXPECT_FALSE(c.has_value()) << "'" << text << "' parsed but should not";
    return error;
}

FeatureValues values(bool a, bool b, bool c) { return {{"a", a}, {"b", b}, {"c", c}}; }

TEST(Condition, DefaultIsAlwaysTrue) {
    Condition c;
    EXPECT_TRUE(c.evaluate({}));
    EXPECT_TRUE(c.evaluate({{"x", false}}));
    EXPECT_EQ(c.text(), "");
    EXPECT_TRUE(c.features().empty());
}

TEST(Condition, SingleFeature) {
    Condition c = parseOk("skybox");
    EXPECT_TRUE(c.evaluate({{"skybox", true}}));
    EXPECT_FALSE(c.evaluate({{"skybox", false}}));
    EXPECT_FALSE(c.evaluate({}));  // missing counts as off
    EXPECT_EQ(c.text(), "skybox");
    EXPECT_EQ(c.features(), std::vector<std::string>{"skybox"});
}

TEST(Condition, AndBindsTighterThanOrAndNotTighterThanAnd) {
    // a || b && !c  ==  a || (b && (!c))
    Condition c = parseOk("a || b && !c");
    for (int bits = 0; bits < 8; ++bits) {
        const bool a = bits & 1, b = bits & 2, cc = bits & 4;
        EXPECT_EQ(c.evaluate(values(a, b, cc)), a || (b && !cc)) << "a=" << a << " b=" << b << " c=" << cc;
    }
    // !a && b  ==  (!a) && b, not !(a && b)
    Condition d = parseOk("!a && b");
    EXPECT_TRUE(d.evaluate(values(false, true, false)));
    EXPECT_FALSE(d.evaluate(values(false, false, false)));  // !(a && b) would be true here
    // a && b || c  ==  (a && b) || c
    Condition e = parseOk("a && b || c");
    EXPECT_TRUE(e.evaluate(values(false, false, true)));  // a && (b || c) would be false
}

TEST(Condition, ParenthesesOverridePrecedence) {
    Condition c = parseOk("(a || b) && !c");
    for (int bits = 0; bits < 8; ++bits) {
        const bool a = bits & 1, b = bits & 2, cc = bits & 4;
        EXPECT_EQ(c.evaluate(values(a, b, cc)), (a || b) && !cc);
    }
    Condition d = parseOk("!(a && b)");
    EXPECT_TRUE(d.evaluate(values(true, false, false)));
    EXPECT_FALSE(d.evaluate(values(true, true, false)));
    Condition e = parseOk("((((a))))");
    EXPECT_TRUE(e.evaluate(values(true, false, false)));
    EXPECT_FALSE(e.evaluate(values(false, true, true)));
}

TEST(Condition, LongChainsEvaluateEveryTerm) {
    Condition c = parseOk("a && b && c");
    EXPECT_TRUE(c.evaluate(values(true, true, true)));
    EXPECT_FALSE(c.evaluate(values(true, true, false)));
    EXPECT_FALSE(c.evaluate(values(false, true, true)));
    Condition d = parseOk("a || b || c");
    EXPECT_FALSE(d.evaluate(values(false, false, false)));
    EXPECT_TRUE(d.evaluate(values(false, false, true)));
}

TEST(Condition, TrueAndFalseLiterals) {
    EXPECT_TRUE(parseOk("true").evaluate({}));
    EXPECT_FALSE(parseOk("false").evaluate({}));
    EXPECT_FALSE(parseOk("!true").evaluate({}));
    EXPECT_TRUE(parseOk("!false").evaluate({}));
    EXPECT_TRUE(parseOk("false || a").evaluate({{"a", true}}));
    EXPECT_FALSE(parseOk("true && a").evaluate({{"a", false}}));
    // Literals are not feature names; a longer name that starts with one is.
    EXPECT_TRUE(parseOk("true || false").features().empty());
    EXPECT_EQ(parseOk("trueish").features(), std::vector<std::string>{"trueish"});
}

TEST(Condition, WhitespaceAndNamesWithDigitsAndUnderscores) {
    Condition c = parseOk("  !\tdebug_view2 &&(\nssao_v1 )  ");
    EXPECT_TRUE(c.evaluate({{"debug_view2", false}, {"ssao_v1", true}}));
    EXPECT_FALSE(c.evaluate({{"debug_view2", true}, {"ssao_v1", true}}));
    EXPECT_EQ(c.features(), (std::vector<std::string>{"debug_view2", "ssao_v1"}));
}

TEST(Condition, FeaturesListedInOrderWithoutRepeats) {
    Condition c = parseOk("b && (a || b) && !c && a");
    EXPECT_EQ(c.features(), (std::vector<std::string>{"b", "a", "c"}));
}

TEST(Condition, ErrorsNameTheColumn) {
    EXPECT_EQ(parseError(""), "column 1: expected a feature name at the end");
    EXPECT_EQ(parseError("a &&"), "column 5: expected a feature name at the end");
    EXPECT_EQ(parseError("a && && b"), "column 6: expected a feature name, found '&& b'");
    EXPECT_EQ(parseError("a b"), "column 3: unexpected 'b'");
    EXPECT_EQ(parseError("(a || b"), "column 8: expected ')'");
    EXPECT_EQ(parseError("a)"), "column 2: unexpected ')'");
    EXPECT_EQ(parseError("a & b"), "column 3: unexpected '& b'");
    EXPECT_EQ(parseError("a | b"), "column 3: unexpected '| b'");
    EXPECT_EQ(parseError("2fast"), "column 1: expected a feature name, found '2fast'");
    EXPECT_EQ(parseError("!"), "column 2: expected a feature name at the end");
    EXPECT_EQ(parseError("()"), "column 2: expected a feature name, found ')'");
    EXPECT_EQ(parseError("a-b"), "column 2: unexpected '-b'");
    EXPECT_EQ(parseError("a && sky-box"), "column 9: unexpected '-box'");
}

TEST(Condition, ErrorsQuoteAndCountWholeCharacters) {
    // Three-byte characters: a quote cut after eight bytes would end inside the third.
    EXPECT_EQ(parseError("a && \u274c\u274c\u274c"), "column 6: expected a feature name, found '\u274c\u274c\u274c'");
    EXPECT_EQ(parseError("\u00e9\u00e9 || \u00e9\u00e9\u00e9\u00e9\u00e9\u00e9\u00e9\u00e9\u00e9"),
              "column 1: expected a feature name, found '\u00e9\u00e9 || \u00e9\u00e9'");
    EXPECT_EQ(parseError("a \u00e9"), "column 3: unexpected '\u00e9'");
}

TEST(Condition, DeepParenthesesAreRefusedNotFatal) {
    // 100000 '(' would overflow the stack of a naive recursive-descent parser.
    const std::string deep(100000, '(');
    const std::string error = parseError(deep + "a" + std::string(100000, ')'));
    EXPECT_NE(error.find("nested deeper than 256 levels"), std::string::npos) << error;
    EXPECT_EQ(error.rfind("column 257:", 0), 0u) << error;
    // Unbalanced too.
    EXPECT_NE(parseError(deep).find("nested deeper than"), std::string::npos);
}

TEST(Condition, DeepNegationIsRefusedNotFatal) {
    const std::string error = parseError(std::string(100000, '!') + "a");
    EXPECT_NE(error.find("nested deeper than 256 levels"), std::string::npos) << error;
}

TEST(Condition, NestingUpToTheLimitWorks) {
    const std::string text = std::string(256, '(') + "a" + std::string(256, ')');
    Condition c = parseOk(text);
    EXPECT_TRUE(c.evaluate({{"a", true}}));
    EXPECT_FALSE(c.evaluate({{"a", false}}));
    // 256 negations: even count, so the value is a's.
    Condition n = parseOk(std::string(256, '!') + "a");
    EXPECT_TRUE(n.evaluate({{"a", true}}));
    EXPECT_FALSE(n.evaluate({{"a", false}}));
    parseError(std::string(257, '!') + "a");
}

TEST(Condition, VeryLongChainsParseEvaluateAndDestroy) {
    // 100000 terms: a chain is flat, so neither evaluation nor destruction recurses deeply.
    std::string andChain = "a";
    std::string orChain = "x0";
    for (int i = 1; i < 100000; ++i) {
        andChain += " && a";
        orChain += " || x" + std::to_string(i);
    }
    {
        Condition c = parseOk(andChain);
        EXPECT_TRUE(c.evaluate({{"a", true}}));
        EXPECT_FALSE(c.evaluate({{"a", false}}));
        EXPECT_EQ(c.features().size(), 1u);
    }
    {
        Condition c = parseOk(orChain);
        EXPECT_EQ(c.features().size(), 100000u);
        EXPECT_EQ(c.features().back(), "x99999");
        EXPECT_FALSE(c.evaluate({}));
        EXPECT_TRUE(c.evaluate({{"x99999", true}}));
    }
}

TEST(Condition, CopiesShareTheTree) {
    Condition a = parseOk("a && !b");
    Condition b = a;
    EXPECT_EQ(b.text(), "a && !b");
    EXPECT_EQ(b.evaluate(values(true, false, false)), a.evaluate(values(true, false, false)));
    EXPECT_TRUE(b.evaluate(values(true, false, false)));
}

}  // namespace
}  // namespace skygraph
