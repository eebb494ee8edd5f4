// JsonWriter: whatever bytes it is given, the document is valid JSON and says what they were.
#include "core/util/json_writer.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace pushpin::util {
namespace {

std::string jsonOf(std::string_view s) {
    JsonWriter w(0);
    w.value(s);
    return w.str();
}

TEST(JsonWriter, EscapesQuotesBackslashesAndControlCharacters) {
    EXPECT_EQ(jsonOf("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(jsonOf("l1\nl2\tx\r"), "\"l1\\nl2\\tx\\r\"");
    EXPECT_EQ(jsonOf(std::string("a\x01z\x7f", 4)), "\"a\\u0001z\\u007f\"");
}

TEST(JsonWriter, PassesValidUtf8Through) {
    EXPECT_EQ(jsonOf("St\xc3\xbctzen"), "\"St\xc3\xbctzen\"");        // ü, two bytes
    EXPECT_EQ(jsonOf("\xe2\x82\xac"), "\"\xe2\x82\xac\"");              // €, three bytes
    EXPECT_EQ(jsonOf("\xf0\x9f\x93\x8c"), "\"\xf0\x9f\x93\x8c\"");      // 📌, four bytes
}

// A Latin-1 name from an older Maya file ("Stützen" with ü as the single byte 0xFC) is escaped as
// the Latin-1 character, byte for byte, and never merged into a neighbouring sequence.
TEST(JsonWriter, EscapesBytesThatAreNotUtf8AsLatin1) {
    EXPECT_EQ(jsonOf("St\xfctzen"), "\"St\\u00fctzen\"");
    EXPECT_EQ(jsonOf("Erschlie\xdf" "ung"), "\"Erschlie\\u00dfung\"");
    EXPECT_EQ(jsonOf("\xc3"), "\"\\u00c3\"");              // a lead byte cut off at the end
    EXPECT_EQ(jsonOf("\xc3x"), "\"\\u00c3x\"");            // a lead byte without its continuation
    EXPECT_EQ(jsonOf("\x80\xbf"), "\"\\u0080\\u00bf\"");   // continuation bytes alone
    EXPECT_EQ(jsonOf("\xc0\xaf"), "\"\\u00c0\\u00af\"");   // an overlong form is not UTF-8
}

TEST(JsonWriter, NonFiniteNumbersBecomeNull) {
    JsonWriter w(0);
    w.beginArray().value(std::numeric_limits<double>::quiet_NaN()).value(std::numeric_limits<double>::infinity()).value(1.5).endArray();
    EXPECT_EQ(w.str(), "[null,null,1.5]");
}

}  // namespace
}  // namespace pushpin::util
