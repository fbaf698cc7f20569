// printableName: what every message and log line shows of a name or path, whatever bytes it
// holds. Control characters are escaped as JSON writes them, and bytes that are not valid
// UTF-8 as \xNN, so that a terminal or a UTF-8 reader of the log sees each one.
#include "printable_name.hpp"

#include <gtest/gtest.h>

namespace skygraph::test {
namespace {

TEST(PrintableName, KeepsPrintableTextAndValidUtf8AsItIs) {
    EXPECT_EQ(printableName("hdr_color"), "hdr_color");
    EXPECT_EQ(printableName("h\xc3\xa9llo \xe2\x82\xac \xf0\x9f\x8c\x85"), "h\xc3\xa9llo \xe2\x82\xac \xf0\x9f\x8c\x85");
    EXPECT_EQ(printableName(""), "");
}

TEST(PrintableName, EscapesControlCharactersAsJsonDoes) {
    EXPECT_EQ(printableName("sky\a.hdr"), "sky\\u0007.hdr");
    EXPECT_EQ(printableName(std::string("a\0b", 3)), "a\\u0000b");
    EXPECT_EQ(printableName("line\nbreak\x7f"), "line\\u000abreak\\u007f");
}

// Format characters that print as nothing or reorder the text after them, so that two names
// differing by one would print alike and a message could read otherwise than it is.
TEST(PrintableName, EscapesInvisibleFormatCharacters) {
    EXPECT_EQ(printableName("hdr\u200bcolor"), "hdr\\u200bcolor");       // zero-width space
    EXPECT_EQ(printableName("\u202eevil"), "\\u202eevil");                // right-to-left override
    EXPECT_EQ(printableName("a\u2066b\u2069"), "a\\u2066b\\u2069");      // an isolate and its end
    EXPECT_EQ(printableName("soft\u00adhyphen\ufeff"), "soft\\u00adhyphen\\ufeff");
    EXPECT_EQ(printableName("\u200e\u200f\u061c\u180e\u2060"), "\\u200e\\u200f\\u061c\\u180e\\u2060");
    // Their neighbours in the tables print as they are.
    EXPECT_EQ(printableName("\u200a\u2010\u2029\u2030\u205f\u2065\u206a\ufefe\u00ac\u00ae"),
              "\u200a\u2010\u2029\u2030\u205f\u2065\u206a\ufefe\u00ac\u00ae");
    EXPECT_EQ(firstInvisibleCharacter("plain \u00e9"), 0u);
    EXPECT_EQ(firstInvisibleCharacter("x\u200dy\u202e"), 0x200du);
}

TEST(PrintableName, EscapesEveryByteThatIsNotValidUtf8) {
    EXPECT_EQ(printableName("t\xff"), "t\\xff");
    EXPECT_EQ(printableName("\x80stray"), "\\x80stray");                      // a lone continuation byte
    EXPECT_EQ(printableName("\xc0\xaf"), "\\xc0\\xaf");                        // an overlong '/'
    EXPECT_EQ(printableName("\xe0\x80\xaf"), "\\xe0\\x80\\xaf");               // an overlong three-byte form
    EXPECT_EQ(printableName("\xed\xa0\x80"), "\\xed\\xa0\\x80");               // a UTF-16 surrogate
    EXPECT_EQ(printableName("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");      // past U+10FFFF
    EXPECT_EQ(printableName("cut \xe2\x82"), "cut \\xe2\\x82");                // a sequence cut short
    EXPECT_EQ(printableName("\xf4\x8f\xbf\xbf"), "\xf4\x8f\xbf\xbf") << "U+10FFFF itself is valid";
}

}  // namespace
}  // namespace skygraph::test
