// Tests for semgraph/semantics/names.h: interning, lookup without insertion, and the name rule
// ("non-empty, printable, at most 255 bytes"; printable as defined in docs/rules.md §1), byte by
// byte and code point by code point.
#include "semgraph/semantics/names.h"

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace semgraph::semantics {
namespace {

using namespace std::string_view_literals;

// Expects `name` to be rejected for `problem` at `offset`, both by ValidateName and by Intern,
// and Intern to leave the table unchanged.
void ExpectRejected(std::string_view name, NameProblem problem, std::size_t offset) {
  SCOPED_TRACE(::testing::Message() << "name of " << name.size() << " bytes");
  const auto validated = ValidateName(name);
  ASSERT_FALSE(validated.has_value());
  EXPECT_EQ(validated.error().code, ErrorCode::kInvalidName);
  EXPECT_EQ(validated.error().problem, problem);
  EXPECT_EQ(validated.error().byte_offset, offset);

  NameTable names;
  ASSERT_TRUE(names.Intern("kept").has_value());
  const auto interned = names.Intern(name);
  ASSERT_FALSE(interned.has_value());
  EXPECT_EQ(interned.error().code, ErrorCode::kInvalidName);
  EXPECT_EQ(interned.error().problem, problem);
  EXPECT_EQ(interned.error().byte_offset, offset);
  EXPECT_EQ(names.size(), 1u);
  EXPECT_FALSE(names.Find(name).is_valid());
}

void ExpectAccepted(std::string_view name) {
  SCOPED_TRACE(::testing::Message() << "name of " << name.size() << " bytes");
  EXPECT_TRUE(ValidateName(name).has_value());
  NameTable names;
  const auto id = names.Intern(name);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(names.name(*id), name);
  EXPECT_EQ(names.Find(name), *id);
}

// ---------------------------------------------------------------- NameId

TEST(NameId, DefaultConstructedIsInvalid) {
  constexpr NameId id;
  static_assert(!id.is_valid());
  EXPECT_EQ(id.value(), NameId::kInvalid);
  EXPECT_EQ(id, NameId(NameId::kInvalid));
}

TEST(NameId, ComparesByValue) {
  static_assert(NameId(3) == NameId(3));
  static_assert(NameId(3) != NameId(4));
  static_assert(NameId(3) < NameId(4));
  static_assert(std::is_trivially_copyable_v<NameId>);
  static_assert(sizeof(NameId) == 4);
  EXPECT_TRUE(NameId(0).is_valid());
}

// ---------------------------------------------------------------- Interning

TEST(NameTable, StartsEmpty) {
  NameTable names;
  EXPECT_EQ(names.size(), 0u);
  EXPECT_FALSE(names.Find("a").is_valid());
}

TEST(NameTable, InternsOnce) {
  NameTable names;
  const auto a = names.Intern("a");
  ASSERT_TRUE(a.has_value());
  const auto again = names.Intern("a");
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(*again, *a);
  EXPECT_EQ(names.name(*a), "a");
  EXPECT_EQ(names.size(), 1u);
}

TEST(NameTable, GivesDenseIdsInOrderOfFirstInterning) {
  NameTable names;
  const std::vector<std::string_view> texts = {"C", "a", "D", "b", "world"};
  for (std::uint32_t i = 0; i < texts.size(); ++i) {
    const auto id = names.Intern(texts[i]);
    ASSERT_TRUE(id.has_value());
    EXPECT_EQ(id->value(), i);
  }
  // Interning again, in another order, neither renumbers nor grows.
  for (std::uint32_t i = static_cast<std::uint32_t>(texts.size()); i-- > 0;) {
    EXPECT_EQ(names.Intern(texts[i])->value(), i);
  }
  EXPECT_EQ(names.size(), texts.size());
}

TEST(NameTable, DistinguishesNamesThatDifferInOneByteOrInCase) {
  NameTable names;
  const NameId a = *names.Intern("frame_a");
  const NameId b = *names.Intern("frame_b");
  const NameId upper = *names.Intern("Frame_a");
  const NameId prefix = *names.Intern("frame_");
  EXPECT_NE(a, b);
  EXPECT_NE(a, upper);
  EXPECT_NE(a, prefix);
  EXPECT_EQ(names.size(), 4u);
}

TEST(NameTable, InternCopiesTheText) {
  NameTable names;
  std::string text = "gripper";
  const NameId id = *names.Intern(text);
  text = "changed";
  EXPECT_EQ(names.name(id), "gripper");
  EXPECT_EQ(names.Find("gripper"), id);
  EXPECT_FALSE(names.Find("changed").is_valid());
}

TEST(NameTable, KeepsEarlierNamesStableWhileGrowing) {
  NameTable names;
  const NameId first = *names.Intern("first");
  const std::string_view first_text = names.name(first);
  for (int i = 0; i < 5000; ++i) ASSERT_TRUE(names.Intern("n" + std::to_string(i)).has_value());
  EXPECT_EQ(first_text, "first");  // the view still points at live storage
  EXPECT_EQ(names.Find("first"), first);
  EXPECT_EQ(names.Find("n4999").value(), 5000u);
  EXPECT_EQ(names.size(), 5001u);
}

TEST(NameTable, SurvivesBeingMoved) {
  NameTable names;
  const NameId a = *names.Intern("a");
  const NameId b = *names.Intern("a long name that does not fit in a small string buffer");
  NameTable moved(std::move(names));
  EXPECT_EQ(moved.name(a), "a");
  EXPECT_EQ(moved.Find("a long name that does not fit in a small string buffer"), b);
  NameTable assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.Find("a"), a);
  EXPECT_EQ(assigned.name(b), "a long name that does not fit in a small string buffer");
  EXPECT_EQ(*assigned.Intern("c"), NameId(2));
}

TEST(NameTable, ReportsMoreBytesAsItGrows) {
  NameTable names;
  const std::size_t empty = names.ApproximateBytes();
  ASSERT_TRUE(names.Intern(std::string(100, 'x')).has_value());
  const std::size_t one = names.ApproximateBytes();
  EXPECT_GT(one, empty);
  EXPECT_GE(one - empty, 100u);
}

// ---------------------------------------------------------------- TruncateTo

TEST(NameTable, TruncateToForgetsLaterNamesOnly) {
  NameTable names;
  const NameId a = *names.Intern("a");
  const NameId b = *names.Intern("b");
  ASSERT_TRUE(names.Intern("c").has_value());
  ASSERT_TRUE(
      names.Intern("a name long enough to live on the heap, not in the string").has_value());
  names.TruncateTo(2);
  EXPECT_EQ(names.size(), 2u);
  EXPECT_EQ(names.Find("a"), a);
  EXPECT_EQ(names.Find("b"), b);
  EXPECT_EQ(names.name(b), "b");
  EXPECT_FALSE(names.Find("c").is_valid());
  EXPECT_FALSE(names.Find("a name long enough to live on the heap, not in the string").is_valid());
  EXPECT_EQ(names.name(NameId(2)), "<invalid>");
}

TEST(NameTable, TruncateToHandsForgottenIdsOutAgain) {
  NameTable names;
  ASSERT_TRUE(names.Intern("a").has_value());
  ASSERT_TRUE(names.Intern("rolled_back").has_value());
  names.TruncateTo(1);
  // A rejected operation rolled back: the next name takes the freed id, densely.
  EXPECT_EQ(names.Intern("other")->value(), 1u);
  EXPECT_EQ(names.Intern("rolled_back")->value(), 2u);
}

TEST(NameTable, TruncateToTheCurrentSizeOrMoreChangesNothing) {
  NameTable names;
  const NameId a = *names.Intern("a");
  names.TruncateTo(1);
  names.TruncateTo(10);
  EXPECT_EQ(names.size(), 1u);
  EXPECT_EQ(names.Find("a"), a);
  names.TruncateTo(0);
  EXPECT_EQ(names.size(), 0u);
  EXPECT_FALSE(names.Find("a").is_valid());
}

// ---------------------------------------------------------------- Find

TEST(NameTable, FindReturnsTheInternedId) {
  NameTable names;
  const NameId a = *names.Intern("a");
  const NameId b = *names.Intern("b");
  EXPECT_EQ(names.Find("a"), a);
  EXPECT_EQ(names.Find("b"), b);
}

TEST(NameTable, FindDoesNotInsert) {
  NameTable names;
  ASSERT_TRUE(names.Intern("a").has_value());
  EXPECT_FALSE(names.Find("b").is_valid());
  EXPECT_EQ(names.size(), 1u);
  // "b" was never inserted, so it takes the next id when interned.
  EXPECT_EQ(names.Intern("b")->value(), 1u);
}

TEST(NameTable, FindOfAnInvalidNameIsInvalid) {
  NameTable names;
  EXPECT_FALSE(names.Find("").is_valid());
  EXPECT_FALSE(names.Find("a\nb").is_valid());
  EXPECT_FALSE(names.Find(std::string(256, 'a')).is_valid());
  EXPECT_EQ(names.size(), 0u);
}

TEST(NameTable, NameOfAnInvalidOrUnknownIdIsMarked) {
  NameTable names;
  ASSERT_TRUE(names.Intern("a").has_value());
  EXPECT_EQ(names.name(NameId()), "<invalid>");
  EXPECT_EQ(names.name(NameId(1)), "<invalid>");
  EXPECT_EQ(names.name(NameId(12345)), "<invalid>");
}

// ---------------------------------------------------------------- Length

TEST(NameRule, RejectsTheEmptyName) { ExpectRejected("", NameProblem::kEmpty, 0); }

TEST(NameRule, AcceptsAOneByteName) { ExpectAccepted("a"); }

TEST(NameRule, AcceptsAName255BytesLong) { ExpectAccepted(std::string(255, 'a')); }

TEST(NameRule, RejectsAName256BytesLong) {
  ExpectRejected(std::string(256, 'a'), NameProblem::kTooLong, kMaxNameBytes);
}

TEST(NameRule, CountsBytesNotCharacters) {
  std::string name;
  for (int i = 0; i < 85; ++i) name += "\xE4\xB8\xAD";  // U+4E2D, 3 bytes each: 255 bytes
  ExpectAccepted(name);
  name += "a";  // 256 bytes, 86 characters
  ExpectRejected(name, NameProblem::kTooLong, kMaxNameBytes);
}

TEST(NameRule, ReportsLengthBeforeBadBytes) {
  ExpectRejected(std::string(300, '\n'), NameProblem::kTooLong, kMaxNameBytes);
}

// ---------------------------------------------------------------- ASCII

TEST(NameRule, AcceptsEveryPrintableAsciiCharacter) {
  for (int c = 0x20; c <= 0x7E; ++c) {
    SCOPED_TRACE(c);
    ExpectAccepted(std::string(1, static_cast<char>(c)));
  }
  ExpectAccepted("base_link/camera-optical.frame 2:{x}|[y]");
}

TEST(NameRule, RejectsEveryAsciiControlCharacter) {
  for (int c = 0x00; c < 0x20; ++c) {
    SCOPED_TRACE(c);
    std::string name = "ab";
    name += static_cast<char>(c);
    name += "cd";
    ExpectRejected(name, NameProblem::kNotPrintable, 2);
  }
}

TEST(NameRule, RejectsAnEmbeddedNul) {
  ExpectRejected("a\0b"sv, NameProblem::kNotPrintable, 1);
  ExpectRejected("\0"sv, NameProblem::kNotPrintable, 0);
}

TEST(NameRule, RejectsTabNewlineAndCarriageReturn) {
  ExpectRejected("a\tb", NameProblem::kNotPrintable, 1);
  ExpectRejected("a\n", NameProblem::kNotPrintable, 1);
  ExpectRejected("\ra", NameProblem::kNotPrintable, 0);
}

TEST(NameRule, RejectsDel) {
  ExpectRejected("\x7F", NameProblem::kNotPrintable, 0);
  ExpectRejected("abc\x7F", NameProblem::kNotPrintable, 3);
}

TEST(NameRule, ReportsTheFirstBadByte) {
  ExpectRejected("ab\x01\xFF", NameProblem::kNotPrintable, 2);
  ExpectRejected("ab\xFF\x01", NameProblem::kNotUtf8, 2);
}

// ---------------------------------------------------------------- UTF-8

TEST(NameRule, AcceptsValidUtf8OfEveryLength) {
  ExpectAccepted("caf\xC3\xA9");                   // U+00E9, 2 bytes
  ExpectAccepted("\xC2\xA1");                      // U+00A1, first printable after C1 and U+00A0
  ExpectAccepted("\xDF\xBF");                      // U+07FF, largest 2-byte
  ExpectAccepted("\xE0\xA0\x80");                  // U+0800, smallest 3-byte
  ExpectAccepted("\xE4\xB8\xAD\xE6\x96\x87");      // U+4E2D U+6587
  ExpectAccepted("\xED\x9F\xBF");                  // U+D7FF, just below the surrogates
  ExpectAccepted("\xEE\x80\x80");                  // U+E000, just above the surrogates
  ExpectAccepted("\xEF\xBF\xBD");                  // U+FFFD
  ExpectAccepted("\xF0\x90\x80\x80");              // U+10000, smallest 4-byte
  ExpectAccepted("robot_\xF0\x9F\xA4\x96");        // U+1F916
  ExpectAccepted("\xF4\x8F\xBF\xBD");              // U+10FFFD, largest printable code point
  ExpectAccepted("\xCE\xB1|\xCE\xB2 [\xCE\xB3]");  // Greek letters mixed with ASCII
}

TEST(NameRule, RejectsALoneContinuationByte) {
  ExpectRejected("\x80", NameProblem::kNotUtf8, 0);
  ExpectRejected("a\xBF", NameProblem::kNotUtf8, 1);
}

TEST(NameRule, RejectsATruncatedSequence) {
  ExpectRejected("a\xC3", NameProblem::kNotUtf8, 1);
  ExpectRejected("\xE4\xB8", NameProblem::kNotUtf8, 0);
  ExpectRejected("\xF0\x9F\xA4", NameProblem::kNotUtf8, 0);
}

TEST(NameRule, RejectsASequenceInterruptedByAsciiOrANewLeadByte) {
  ExpectRejected(
      "\xC3"
      "a",
      NameProblem::kNotUtf8, 0);
  ExpectRejected(
      "\xE4\xB8"
      "a",
      NameProblem::kNotUtf8, 0);
  ExpectRejected("\xE4\xC3\xA9", NameProblem::kNotUtf8, 0);
}

TEST(NameRule, RejectsBytesThatNeverOccurInUtf8) {
  for (int b : {0xF8, 0xFB, 0xFC, 0xFE, 0xFF}) {
    SCOPED_TRACE(b);
    std::string name = "x";
    name += static_cast<char>(b);
    name += "\x80\x80\x80\x80";
    ExpectRejected(name, NameProblem::kNotUtf8, 1);
  }
}

TEST(NameRule, RejectsOverlongEncodings) {
  ExpectRejected("\xC0\x80", NameProblem::kNotUtf8, 0);          // U+0000 in 2 bytes
  ExpectRejected("\xC0\xAF", NameProblem::kNotUtf8, 0);          // '/' in 2 bytes
  ExpectRejected("\xC1\xBF", NameProblem::kNotUtf8, 0);          // U+007F in 2 bytes
  ExpectRejected("\xE0\x80\x80", NameProblem::kNotUtf8, 0);      // U+0000 in 3 bytes
  ExpectRejected("\xE0\x82\x85", NameProblem::kNotUtf8, 0);      // U+0085 in 3 bytes
  ExpectRejected("\xE0\x9F\xBF", NameProblem::kNotUtf8, 0);      // U+07FF in 3 bytes
  ExpectRejected("\xF0\x80\x80\x80", NameProblem::kNotUtf8, 0);  // U+0000 in 4 bytes
  ExpectRejected("\xF0\x8F\xBF\xBF", NameProblem::kNotUtf8, 0);  // U+FFFF in 4 bytes
}

TEST(NameRule, RejectsSurrogates) {
  ExpectRejected("\xED\xA0\x80", NameProblem::kNotUtf8, 0);   // U+D800
  ExpectRejected("a\xED\xB2\x80", NameProblem::kNotUtf8, 1);  // U+DC80
  ExpectRejected("\xED\xBF\xBF", NameProblem::kNotUtf8, 0);   // U+DFFF
  // A CESU-8 style surrogate pair (U+1F916) is not UTF-8 either.
  ExpectRejected("\xED\xA0\xBE\xED\xB4\x96", NameProblem::kNotUtf8, 0);
}

TEST(NameRule, RejectsCodePointsAbove10FFFF) {
  ExpectRejected("\xF4\x90\x80\x80", NameProblem::kNotUtf8, 0);  // U+110000
  ExpectRejected("\xF5\x80\x80\x80", NameProblem::kNotUtf8, 0);
  ExpectRejected("\xF7\xBF\xBF\xBF", NameProblem::kNotUtf8, 0);
}

TEST(NameRule, RejectsC1ControlCharactersAsNotPrintable) {
  for (int second = 0x80; second <= 0x9F; ++second) {
    SCOPED_TRACE(second);
    std::string name = "ab\xC2";
    name += static_cast<char>(second);
    ExpectRejected(name, NameProblem::kNotPrintable, 2);
  }
}

// ---------------------------------------------------------------- Printable (docs/rules.md §1)

// UTF-8 of code point cp, encoded here independently of names.cc.
std::string Utf8(char32_t cp) {
  std::string out;
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
  return out;
}

// "x" + cp + "y" is refused at byte 1 as not printable, naming cp.
void ExpectNotPrintable(char32_t cp) {
  SCOPED_TRACE(::testing::Message() << "U+" << std::hex << static_cast<unsigned>(cp));
  const std::string name = "x" + Utf8(cp) + "y";
  ExpectRejected(name, NameProblem::kNotPrintable, 1);
  EXPECT_EQ(ValidateName(name).error().code_point, static_cast<std::uint32_t>(cp));
  // Also alone and at the end: the position is the character's first byte.
  ExpectRejected(Utf8(cp), NameProblem::kNotPrintable, 0);
  ExpectRejected("abc" + Utf8(cp), NameProblem::kNotPrintable, 3);
}
void ExpectPrintable(char32_t cp) {
  SCOPED_TRACE(::testing::Message() << "U+" << std::hex << static_cast<unsigned>(cp));
  ExpectAccepted("x" + Utf8(cp) + "y");
}
void ExpectRangeNotPrintable(char32_t first, char32_t last) {
  for (char32_t cp = first; cp <= last; ++cp) ExpectNotPrintable(cp);
}

// Before: U+200B, U+FEFF, U+2028, U+FFFE and U+00A0 were accepted, so "x" and U+200B "x" were
// two bodies that print alike.
TEST(NameRule, RefusesInvisibleAndFormattingCharacters) {
  ExpectNotPrintable(0x00AD);                 // soft hyphen
  ExpectRangeNotPrintable(0x200B, 0x200F);    // zero width space, (non-)joiner, LRM, RLM
  ExpectRangeNotPrintable(0x202A, 0x202E);    // bidi embeddings and overrides
  ExpectRangeNotPrintable(0x2060, 0x2064);    // word joiner, invisible operators
  ExpectRangeNotPrintable(0x2066, 0x2069);    // bidi isolates
  ExpectNotPrintable(0xFEFF);                 // byte-order mark / zero width no-break space
  ExpectRangeNotPrintable(0xE0000, 0xE007F);  // tag characters (and the reserved E0000)
  // The rest of Unicode's format characters and default-ignorable code points.
  ExpectNotPrintable(0x034F);               // combining grapheme joiner
  ExpectNotPrintable(0x061C);               // Arabic letter mark (a bidi control)
  ExpectRangeNotPrintable(0x115F, 0x1160);  // Hangul fillers
  ExpectNotPrintable(0x3164);
  ExpectNotPrintable(0xFFA0);
  ExpectRangeNotPrintable(0x180B, 0x180F);    // Mongolian variation selectors, vowel separator
  ExpectRangeNotPrintable(0xFE00, 0xFE0F);    // variation selectors
  ExpectRangeNotPrintable(0xFFF9, 0xFFFB);    // interlinear annotation
  ExpectRangeNotPrintable(0x13430, 0x1343F);  // Egyptian hieroglyph format controls
  ExpectRangeNotPrintable(0x1D173, 0x1D17A);  // musical symbol format controls
  ExpectNotPrintable(0xE0100);                // variation selector 17
  ExpectNotPrintable(0xE0FFF);
}

TEST(NameRule, RefusesLineAndParagraphSeparators) {
  ExpectNotPrintable(0x2028);
  ExpectNotPrintable(0x2029);
}

TEST(NameRule, RefusesNoncharactersInEveryPlane) {
  ExpectRangeNotPrintable(0xFDD0, 0xFDEF);
  for (char32_t plane = 0; plane <= 0x10; ++plane) {
    ExpectNotPrintable(plane * 0x10000 + 0xFFFE);
    ExpectNotPrintable(plane * 0x10000 + 0xFFFF);
    ExpectPrintable(plane * 0x10000 + 0xFFFD);  // the last character before them
  }
}

TEST(NameRule, RefusesEverySpaceButTheAsciiOne) {
  ExpectAccepted("a b");
  ExpectNotPrintable(0x00A0);               // no-break space
  ExpectNotPrintable(0x1680);               // ogham space mark
  ExpectRangeNotPrintable(0x2000, 0x200A);  // en quad .. hair space
  ExpectNotPrintable(0x202F);               // narrow no-break space
  ExpectNotPrintable(0x205F);               // medium mathematical space
  ExpectNotPrintable(0x3000);               // ideographic space
}

TEST(NameRule, AcceptsVisibleNeighboursOfTheRefusedCharacters) {
  for (char32_t cp :
       {0x00A1,     0x00AC,  0x00AE,  0x034E,  0x0350,  0x0600,  0x06DD,  0x070F, 0x08E2, 0x110BD,
        0x1680 - 1, 0x1681,  0x1FFF,  0x2010,  0x2027,  0x2025,  0x2030,  0x205E, 0x2070, 0x3001,
        0x3163,     0x3165,  0xFDCF,  0xFDF0,  0xFDFD,  0xFE10,  0xFEFE,  0xFF01, 0xFFFC, 0xFFFD,
        0x1342F,    0x13440, 0x1F600, 0xDFFFD, 0xE1000, 0xF0000, 0x10FFFD}) {
    ExpectPrintable(cp);
  }
  ExpectAccepted(
      "\xE4\xB8\xAD\xE6\x96\x87 caf\xC3\xA9 \xCE\xB1\xCE\xB2");  // letters of every script
}

TEST(NameRule, EveryCodePointIsClassifiedOnce) {
  // Exhaustive over Unicode: exactly the refused set is refused, by the classes above. The
  // count is the sum of the listed ranges (computed by hand from docs/rules.md §1).
  std::size_t refused = 0;
  for (char32_t cp = 0; cp <= 0x10FFFF; ++cp) {
    if (cp >= 0xD800 && cp <= 0xDFFF) continue;  // surrogates are not UTF-8
    const auto r = ValidateName(Utf8(cp));
    if (!r) {
      ASSERT_EQ(r.error().problem, NameProblem::kNotPrintable)
          << std::hex << static_cast<unsigned>(cp);
      ++refused;
    }
  }
  // controls 65 (0x00-0x1F, 0x7F-0x9F) + separators 2 + noncharacters 32 + 34 + spaces 16 +
  // invisible: 1 + 1 + 1 + 2 + 2 + 5 + 5 + 5 + 16 + 1 + 16 + 1 + 1 + 12 + 16 + 4 + 8 + 4096.
  EXPECT_EQ(refused,
            65u + 2u + 66u + 16u +
                (1 + 1 + 1 + 2 + 2 + 5 + 5 + 5 + 16 + 1 + 16 + 1 + 1 + 12 + 16 + 4 + 8 + 4096));
}

// ---------------------------------------------------------------- Messages

TEST(NameRule, DescribesEachProblem) {
  EXPECT_EQ(Describe(ValidateName("").error(), ""), "name is empty");
  const std::string long_name(300, 'a');
  EXPECT_EQ(Describe(ValidateName(long_name).error(), long_name),
            "name is 300 bytes long (at most 255)");
  EXPECT_EQ(Describe(ValidateName("abc\n").error(), "abc\n"),
            "byte 3 of the name is a control character");
  EXPECT_EQ(Describe(ValidateName("\xC2\x85").error(), "\xC2\x85"),
            "byte 0 of the name is a control character");
  EXPECT_EQ(Describe(ValidateName("ok\xFF").error(), "ok\xFF"),
            "byte 2 of the name is not valid UTF-8");
  EXPECT_EQ(Describe(ValidateName("\xE2\x80\x8Bx").error(), "\xE2\x80\x8Bx"),
            "byte 0 of the name is U+200B, an invisible or formatting character");
  EXPECT_EQ(Describe(ValidateName("a\xE2\x80\xA8").error(), "a\xE2\x80\xA8"),
            "byte 1 of the name is U+2028, a line or paragraph separator");
  EXPECT_EQ(Describe(ValidateName("a\xC2\xA0"
                                  "b")
                         .error(),
                     "a\xC2\xA0"
                     "b"),
            "byte 1 of the name is U+00A0, a space other than U+0020");
  EXPECT_EQ(Describe(ValidateName("\xF4\x8F\xBF\xBF").error(), "\xF4\x8F\xBF\xBF"),
            "byte 0 of the name is U+10FFFF, a noncharacter");
  EXPECT_EQ(Describe(ValidateName("\xF3\xA0\x80\x81").error(), "\xF3\xA0\x80\x81"),
            "byte 0 of the name is U+E0001, an invisible or formatting character");
}

}  // namespace
}  // namespace semgraph::semantics
