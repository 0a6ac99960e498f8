// Tests for semgraph/semantics/names.h: interning, lookup without insertion, and the spec's name
// rule ("non-empty, printable, at most 255 bytes"), byte by byte.
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
  ExpectAccepted("caf\xC3\xA9");                 // U+00E9, 2 bytes
  ExpectAccepted("\xC2\xA0");                    // U+00A0, first code point after C1
  ExpectAccepted("\xDF\xBF");                    // U+07FF, largest 2-byte
  ExpectAccepted("\xE0\xA0\x80");                // U+0800, smallest 3-byte
  ExpectAccepted("\xE4\xB8\xAD\xE6\x96\x87");    // U+4E2D U+6587
  ExpectAccepted("\xED\x9F\xBF");                // U+D7FF, just below the surrogates
  ExpectAccepted("\xEE\x80\x80");                // U+E000, just above the surrogates
  ExpectAccepted("\xEF\xBF\xBD");                // U+FFFD
  ExpectAccepted("\xF0\x90\x80\x80");            // U+10000, smallest 4-byte
  ExpectAccepted("robot_\xF0\x9F\xA4\x96");      // U+1F916
  ExpectAccepted("\xF4\x8F\xBF\xBF");            // U+10FFFF, largest code point
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
  ExpectRejected("\xC3" "a", NameProblem::kNotUtf8, 0);
  ExpectRejected("\xE4\xB8" "a", NameProblem::kNotUtf8, 0);
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
  ExpectRejected("\xED\xA0\x80", NameProblem::kNotUtf8, 0);  // U+D800
  ExpectRejected("a\xED\xB2\x80", NameProblem::kNotUtf8, 1);  // U+DC80
  ExpectRejected("\xED\xBF\xBF", NameProblem::kNotUtf8, 0);  // U+DFFF
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
}

}  // namespace
}  // namespace semgraph::semantics
