// Tests of the one UTF-8 decoder (base/utf8.h): hand-decoded sequences from Unicode's Table 3-7
// and its examples, every code point round-tripped through an encoder written here from the
// table's bit patterns, and every 1- and 2-byte input classified against the table's ranges.
#include "semgraph/base/utf8.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace semgraph::base {
namespace {

using namespace std::string_view_literals;

// The bit patterns of Table 3-6, independent of the decoder.
std::string Encode(std::uint32_t cp) {
  std::string s;
  if (cp < 0x80) {
    s += static_cast<char>(cp);
  } else if (cp < 0x800) {
    s += static_cast<char>(0xC0 | (cp >> 6));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    s += static_cast<char>(0xE0 | (cp >> 12));
    s += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (cp >> 18));
    s += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  }
  return s;
}

TEST(Utf8, DecodesKnownSequences) {
  struct Case {
    std::string_view bytes;
    std::size_t length;
    std::uint32_t code_point;
  };
  // Unicode 15 §3.9 examples and a few letters, decoded by hand.
  const Case cases[] = {
      {"A"sv, 1, 0x41},
      {"\x7F"sv, 1, 0x7F},
      {"\xC3\xA9"sv, 2, 0xE9},             // é
      {"\xD0\x96"sv, 2, 0x416},            // Ж
      {"\xE2\x82\xAC"sv, 3, 0x20AC},       // €
      {"\xE4\xBA\x8C"sv, 3, 0x4E8C},       // 二 (Unicode's Table 3-5 example)
      {"\xEF\xBF\xBF"sv, 3, 0xFFFF},       // a noncharacter: well-formed all the same
      {"\xF0\x90\x8C\x82"sv, 4, 0x10302},  // Table 3-5 example
      {"\xF4\x8F\xBF\xBF"sv, 4, 0x10FFFF},
      {"\x00"sv, 1, 0},
  };
  for (const Case& c : cases) {
    const Utf8Sequence d = DecodeUtf8(c.bytes, 0);
    EXPECT_EQ(d.length, c.length) << c.code_point;
    EXPECT_EQ(d.code_point, c.code_point);
    EXPECT_EQ(Utf8Length(c.bytes, 0), c.length);
  }
  // At an offset inside a longer text.
  EXPECT_EQ(DecodeUtf8("ab\xE2\x82\xAC"sv, 2).code_point, 0x20ACu);
}

TEST(Utf8, RejectsIllFormedSequences) {
  const std::string_view bad[] = {
      "\x80"sv,              // stray continuation byte
      "\xBF"sv,              // stray continuation byte
      "\xC0\x80"sv,          // overlong U+0000
      "\xC1\xBF"sv,          // overlong U+007F
      "\xE0\x80\x80"sv,      // overlong
      "\xE0\x9F\xBF"sv,      // overlong U+07FF
      "\xF0\x8F\xBF\xBF"sv,  // overlong U+FFFF
      "\xED\xA0\x80"sv,      // surrogate U+D800
      "\xED\xBF\xBF"sv,      // surrogate U+DFFF
      "\xF4\x90\x80\x80"sv,  // U+110000
      "\xF5\x80\x80\x80"sv,  // lead byte beyond U+10FFFF
      "\xFF"sv,
      "\xC3"sv,              // cut short by the end
      "\xE2\x82"sv,          // cut short by the end
      "\xF0\x90\x8C"sv,      // cut short by the end
      "\xC3\x41"sv,          // cut short by a byte that is not a continuation
      "\xE2\x82\xC3\xA9"sv,  // cut short by a lead byte
  };
  for (std::string_view b : bad) {
    EXPECT_EQ(Utf8Length(b, 0), 0u) << std::hex << int(static_cast<unsigned char>(b[0]));
  }
  // The end of the view ends the text, whatever follows in memory.
  EXPECT_EQ(Utf8Length(std::string_view("\xE2\x82\xAC", 2), 0), 0u);
}

TEST(Utf8, EveryScalarValueRoundTrips) {
  for (std::uint32_t cp = 0; cp <= 0x10FFFF; ++cp) {
    if (cp >= 0xD800 && cp <= 0xDFFF) continue;
    const std::string s = Encode(cp);
    const Utf8Sequence d = DecodeUtf8(s, 0);
    ASSERT_EQ(d.length, s.size()) << cp;
    ASSERT_EQ(d.code_point, cp);
  }
  for (std::uint32_t cp = 0xD800; cp <= 0xDFFF; ++cp)
    ASSERT_EQ(Utf8Length(Encode(cp), 0), 0u) << cp;
}

// Table 3-7: a 1-byte sequence is 00..7F; a 2-byte one is C2..DF then 80..BF. Every other one-
// or two-byte input is ill-formed (a longer lead byte is cut short by the end).
TEST(Utf8, EveryOneAndTwoByteInputIsClassifiedAsTable37Says) {
  for (int b0 = 0; b0 < 256; ++b0) {
    const std::string one(1, static_cast<char>(b0));
    EXPECT_EQ(Utf8Length(one, 0), b0 < 0x80 ? 1u : 0u) << b0;
    for (int b1 = 0; b1 < 256; ++b1) {
      const std::string two{static_cast<char>(b0), static_cast<char>(b1)};
      const std::size_t expected = b0 < 0x80                                                ? 1
                                   : (b0 >= 0xC2 && b0 <= 0xDF && b1 >= 0x80 && b1 <= 0xBF) ? 2
                                                                                            : 0;
      ASSERT_EQ(Utf8Length(two, 0), expected) << b0 << " " << b1;
    }
  }
}

static_assert(DecodeUtf8("\xE2\x82\xAC", 0).code_point == 0x20AC);  // usable at compile time

}  // namespace
}  // namespace semgraph::base
