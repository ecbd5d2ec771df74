// common/utf8.h: what counts as UTF-8 (no overlong forms, no surrogates, no truncated
// sequences), and the lossy copy our own text takes into JSON.
#include "common/utf8.h"

#include <gtest/gtest.h>

namespace rtsim {
namespace {

TEST(Utf8, ValidTextPassesAndEveryMalformedSequenceIsCaught) {
  EXPECT_TRUE(is_utf8(""));
  EXPECT_TRUE(is_utf8("run.lvb"));
  EXPECT_TRUE(is_utf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"));  // 2, 3 and 4 bytes
  EXPECT_FALSE(is_utf8("run.lv\xdb"));                                // a lead byte, then nothing
  EXPECT_FALSE(is_utf8("\xe2\x82"));                                  // truncated
  EXPECT_FALSE(is_utf8("\xc0\xaf"));                                  // overlong '/'
  EXPECT_FALSE(is_utf8("\xed\xa0\x80"));                              // a surrogate
  EXPECT_FALSE(is_utf8("\xf4\x90\x80\x80"));                          // above U+10FFFF
  EXPECT_FALSE(is_utf8("\x80"));                                      // a continuation byte
}

TEST(Utf8, TheLossyCopyReplacesOnlyTheBadBytes) {
  EXPECT_EQ(utf8_lossy("a\xdb"
                       "b\xe2\x82\xac"),
            "a?b\xe2\x82\xac");
  EXPECT_EQ(utf8_lossy("found '1\xc3"
                       "6'"),
            "found '1?6'");
  EXPECT_TRUE(is_utf8(utf8_lossy("\xff\xfe\xc0\xaf ok")));
  EXPECT_EQ(utf8_lossy("plain"), "plain");
}

}  // namespace
}  // namespace rtsim
