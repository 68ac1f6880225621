// base/text.hpp: names made printable and text made UTF-8 (src/base/text.hpp).
#include "base/text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using fdmsurf::detail::printable;
using fdmsurf::detail::utf8_sequence;
using fdmsurf::detail::valid_utf8;

TEST(Text, PrintableReplacesEveryControlCharacter) {
    EXPECT_EQ(printable("plain name.pdb"), "plain name.pdb");
    EXPECT_EQ(printable("a\nb\rc\td"), "a?b?c?d");
    EXPECT_EQ(printable("x\x1b[31my"), "x?[31my");  // ESC
    EXPECT_EQ(printable("del\x7f"), "del?");
    EXPECT_EQ(printable("csi\xc2\x9b" "1m"), "csi?1m");  // C1 control U+009B
    EXPECT_EQ(printable("nbsp\xc2\xa0" "x"), "nbsp\xc2\xa0" "x");  // U+00A0 is no control
    EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x84\xab"), "caf\xc3\xa9 \xe2\x84\xab");  // é, Å
    EXPECT_EQ(printable("cr\xffn"), "cr?n");  // not UTF-8
    EXPECT_EQ(printable("\xe2\x84"), "??");   // a sequence cut short
}

TEST(Text, Utf8SequencesAreCheckedAsJsonNeedsThem) {
    EXPECT_EQ(utf8_sequence("\xc3\xa9", 0), 2u);
    EXPECT_EQ(utf8_sequence("\xf0\x9f\x98\x80", 0), 4u);
    EXPECT_EQ(utf8_sequence("\xc0\xaf", 0), 0u);          // overlong '/'
    EXPECT_EQ(utf8_sequence("\xed\xa0\x80", 0), 0u);      // surrogate
    EXPECT_EQ(utf8_sequence("\xf4\x90\x80\x80", 0), 0u);  // above U+10FFFF
    EXPECT_EQ(utf8_sequence("\x80", 0), 0u);              // lone continuation byte
    EXPECT_EQ(valid_utf8("ok \xc3\xa9"), "ok \xc3\xa9");
    EXPECT_EQ(valid_utf8("GL\xffY"), "GL\xef\xbf\xbdY");
    EXPECT_EQ(valid_utf8("\xed\xa0\x80"), "\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd");
}

}  // namespace
