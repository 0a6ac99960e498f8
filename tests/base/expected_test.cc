// Tests for semgraph/base/expected.h: Expected<T, E> holds exactly one alternative, copies
// and moves it correctly (also across alternatives), constructs and destroys each alternative
// exactly once, and aborts on access to the wrong alternative.
#include "semgraph/base/expected.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "semgraph/base/error_code.h"

namespace semgraph::base {
namespace {

struct SmallError {
  ErrorCode code = ErrorCode::kOk;
  int detail = 0;
};

// Counts live instances, so that a leak or a double destruction shows.
struct Tracked {
  static inline int live = 0;
  std::string text;
  explicit Tracked(std::string t) : text(std::move(t)) { ++live; }
  Tracked(const Tracked& other) : text(other.text) { ++live; }
  Tracked(Tracked&& other) noexcept : text(std::move(other.text)) { ++live; }
  Tracked& operator=(const Tracked&) = default;
  Tracked& operator=(Tracked&&) = default;
  ~Tracked() { --live; }
};

using Trivial = Expected<int, SmallError>;
using WithString = Expected<std::string, SmallError>;
using BothTracked = Expected<Tracked, Tracked>;

// ---------------------------------------------------------------- Type properties

TEST(Expected, MovesWithoutThrowingWhenBothAlternativesDo) {
  // (Copy, move and destruction are user-provided even for trivial alternatives: clang 14 has no
  // conditionally trivial special members. So only the noexcept guarantees are asserted here.)
  static_assert(std::is_nothrow_move_constructible_v<Trivial>);
  static_assert(std::is_nothrow_move_assignable_v<Trivial>);
  static_assert(std::is_nothrow_destructible_v<Trivial>);
  static_assert(std::is_copy_constructible_v<Trivial>);
  static_assert(std::is_copy_assignable_v<Trivial>);
  static_assert(std::is_nothrow_move_constructible_v<WithString>);
  static_assert(std::is_copy_constructible_v<WithString>);
  static_assert(std::is_nothrow_move_constructible_v<Expected<Ok, ErrorCode>>);
  SUCCEED();
}

TEST(Expected, IsMoveOnlyWhenAnAlternativeIs) {
  using MoveOnly = Expected<std::unique_ptr<int>, SmallError>;
  static_assert(std::is_move_constructible_v<MoveOnly>);
  static_assert(std::is_nothrow_move_constructible_v<MoveOnly>);
  MoveOnly a(std::make_unique<int>(1));
  MoveOnly b(std::move(a));
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(**b, 1);
}

TEST(Expected, AccessIsNoexcept) {
  Trivial e = 1;
  static_assert(noexcept(e.has_value()));
  static_assert(noexcept(e.value()));
  static_assert(noexcept(*e));
  static_assert(noexcept(static_cast<bool>(e)));
  EXPECT_TRUE(e.has_value());
}

// ---------------------------------------------------------------- Value

TEST(Expected, HoldsAValue) {
  const Trivial e = 42;
  EXPECT_TRUE(e.has_value());
  EXPECT_TRUE(static_cast<bool>(e));
  EXPECT_EQ(e.value(), 42);
  EXPECT_EQ(*e, 42);
}

TEST(Expected, GivesMemberAccessThroughArrow) {
  WithString e = std::string("frame");
  EXPECT_EQ(e->size(), 5u);
  e->append("_a");
  EXPECT_EQ(*e, "frame_a");
  const WithString& c = e;
  EXPECT_EQ(c->front(), 'f');
}

TEST(Expected, ValueIsMutableThroughAReference) {
  Trivial e = 1;
  e.value() = 2;
  EXPECT_EQ(*e, 2);
  *e = 3;
  EXPECT_EQ(e.value(), 3);
}

TEST(Expected, MovesTheValueOutOfAnRvalue) {
  WithString e = std::string(64, 'x');
  std::string taken = std::move(e).value();
  EXPECT_EQ(taken, std::string(64, 'x'));
}

TEST(Expected, ConstructsFromAMovedValue) {
  auto owned = std::make_unique<int>(7);
  Expected<std::unique_ptr<int>, SmallError> e(std::move(owned));
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(**e, 7);
  EXPECT_EQ(owned, nullptr);
}

// ---------------------------------------------------------------- Error

TEST(Expected, HoldsAnError) {
  const Trivial e = Unexpected{SmallError{ErrorCode::kPoseCycle, 3}};
  EXPECT_FALSE(e.has_value());
  EXPECT_FALSE(static_cast<bool>(e));
  EXPECT_EQ(e.error().code, ErrorCode::kPoseCycle);
  EXPECT_EQ(e.error().detail, 3);
}

TEST(Expected, ConvertsAnUnexpectedOfAnotherType) {
  // Unexpected<ErrorCode> converts into an Expected whose error type is constructible from it.
  const Expected<int, SmallError> e = Unexpected{SmallError{ErrorCode::kNoPosePath, 0}};
  EXPECT_EQ(e.error().code, ErrorCode::kNoPosePath);
  const Expected<int, long> widened = Unexpected{5};
  EXPECT_EQ(widened.error(), 5L);
}

TEST(Expected, ErrorIsMutableAndMovable) {
  Expected<int, std::string> e = Unexpected{std::string("first")};
  e.error() += " and second";
  EXPECT_EQ(e.error(), "first and second");
  std::string taken = std::move(e).error();
  EXPECT_EQ(taken, "first and second");
}

TEST(Expected, OkCarriesNothing) {
  const Expected<Ok, ErrorCode> success = Ok{};
  const Expected<Ok, ErrorCode> failure = Unexpected{ErrorCode::kSelfEdge};
  EXPECT_TRUE(success.has_value());
  EXPECT_FALSE(failure.has_value());
  EXPECT_EQ(failure.error(), ErrorCode::kSelfEdge);
}

// ---------------------------------------------------------------- Copy and move

TEST(Expected, CopiesEitherAlternative) {
  const WithString value = std::string("a long string that is heap allocated for sure");
  const WithString error = Unexpected{SmallError{ErrorCode::kUnknownFrame, 1}};
  const WithString value_copy(value);
  const WithString error_copy(error);
  EXPECT_EQ(*value_copy, *value);
  EXPECT_EQ(error_copy.error().code, ErrorCode::kUnknownFrame);
}

TEST(Expected, AssignsAcrossAlternatives) {
  WithString e = std::string("value");
  const WithString error = Unexpected{SmallError{ErrorCode::kNoTwistPath, 2}};
  e = error;
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().detail, 2);
  e = WithString(std::string("again"));
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(*e, "again");
}

TEST(Expected, SurvivesSelfAssignment) {
  WithString e = std::string("self");
  WithString& alias = e;
  e = alias;
  EXPECT_EQ(*e, "self");
  e = std::move(alias);
  EXPECT_EQ(*e, "self");
}

TEST(Expected, CopiesTrivialAlternativesAcrossAssignments) {
  Trivial a = 5;
  Trivial b = Unexpected{SmallError{ErrorCode::kInvalidName, 9}};
  b = a;
  EXPECT_EQ(*b, 5);
  a = Trivial(Unexpected{SmallError{ErrorCode::kInvalidNumber, 1}});
  EXPECT_EQ(a.error().code, ErrorCode::kInvalidNumber);
  EXPECT_EQ(*b, 5);
}

TEST(Expected, ConstructsAndDestroysExactlyOnce) {
  ASSERT_EQ(Tracked::live, 0);
  {
    BothTracked value = Tracked("v");
    BothTracked error = Unexpected{Tracked("e")};
    EXPECT_EQ(Tracked::live, 2);
    BothTracked copy(value);
    BothTracked moved(std::move(error));
    EXPECT_EQ(Tracked::live, 4);
    copy = moved;  // value -> error: destroys one, constructs one
    EXPECT_EQ(Tracked::live, 4);
    EXPECT_EQ(copy.error().text, "e");
    value = std::move(copy);
    EXPECT_EQ(Tracked::live, 4);
    EXPECT_FALSE(value.has_value());
  }
  EXPECT_EQ(Tracked::live, 0);
}

// ---------------------------------------------------------------- Wrong alternative

TEST(ExpectedDeathTest, ValueOfAnErrorAborts) {
  const Trivial e = Unexpected{SmallError{}};
  EXPECT_DEATH((void)e.value(), "internal check failed");
}

TEST(ExpectedDeathTest, ErrorOfAValueAborts) {
  const Trivial e = 1;
  EXPECT_DEATH((void)e.error(), "internal check failed");
}

TEST(ExpectedDeathTest, DemandNamesTheFailedCondition) {
  EXPECT_DEATH(SEMGRAPH_DEMAND(1 + 1 == 3), "1 \\+ 1 == 3");
}

}  // namespace
}  // namespace semgraph::base
