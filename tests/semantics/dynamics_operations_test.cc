// Tests for semgraph/semantics/dynamics_operations.h: every operation on accelerations and
// wrenches, one test per precondition (each breaks exactly that precondition and checks the
// whole Mismatch: operation, operands, relations, fields, names), the precondition order, and
// every field of the result semantics.
#include "semgraph/semantics/dynamics_operations.h"

#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#include "semgraph/semantics/describe.h"

namespace semgraph::semantics {
namespace {

constexpr Operand kFirst = Operand::kFirst;
constexpr Operand kSecond = Operand::kSecond;
constexpr Operand kSubject = Operand::kSubject;
constexpr Operand kArgument = Operand::kArgument;
constexpr RelationKind kPos = RelationKind::kPosition;
constexpr RelationKind kOri = RelationKind::kOrientation;
constexpr RelationKind kPose = RelationKind::kPose;
constexpr RelationKind kAng = RelationKind::kAngularVelocity;
constexpr RelationKind kTwist = RelationKind::kTwist;
constexpr RelationKind kAcc = RelationKind::kAcceleration;
constexpr RelationKind kWr = RelationKind::kWrench;

// Names. Bodies: C (the body moving / acted on), B (an intermediate body), M (the reference of a
// composition), D (the reference / the body acting), E, F (bodies no valid operand mentions).
// Points: e, q on C; x a point no valid operand mentions. Orientation frames: [a] on C, [b] on
// D; [r], [s] coordinate frames; [x] one no valid operand mentions.
// Variables are Drake monograms: A_BCe the acceleration of C relative to B at e, V_BCe the
// twist, w_MB the angular velocity of B in M, p_qe the position of e relative to q, F_DCe the
// wrench on C by D about e (F_Ce a net wrench on C, by several bodies); a trailing _r / _s names
// the coordinate frame where a test depends on it.
class Dyn : public ::testing::Test {
 protected:
  NameTable names_;
  const Body B = Intern<Body>("B"), C = Intern<Body>("C"), D = Intern<Body>("D"),
             E = Intern<Body>("E"), F = Intern<Body>("F"), M = Intern<Body>("M");
  const Point e = Intern<Point>("e"), q = Intern<Point>("q"), x = Intern<Point>("x");
  const OrientationFrame a = Intern<OrientationFrame>("a"), b = Intern<OrientationFrame>("b"),
                         r = Intern<OrientationFrame>("r"), s = Intern<OrientationFrame>("s"),
                         ox = Intern<OrientationFrame>("x");

  template <class P>
  P Intern(std::string_view name) {
    return P(*names_.Intern(name));
  }
  template <class N>
  static MismatchSide Side(Operand operand, RelationKind relation, Field field, N name,
                           Body body = Body()) {
    return {operand, relation, field, name.id(), body.id()};
  }
  static MismatchSide Several(Operand operand) {
    return {operand, kWr, Field::kRefBody, NameId(), NameId()};
  }

  template <class T>
  ::testing::AssertionResult Refused(const Checked<T>& result, Operation op,
                                     const MismatchSide& lhs, const MismatchSide& rhs) const {
    if (result.has_value()) return ::testing::AssertionFailure() << "the operation succeeded";
    const Mismatch& m = result.error();
    const auto same = [](const MismatchSide& p, const MismatchSide& o) {
      return p.operand == o.operand && p.relation == o.relation && p.field == o.field &&
             p.name == o.name && p.body == o.body;
    };
    if (m.code == ErrorCode::kSemanticMismatch && m.operation == op && same(m.lhs, lhs) &&
        same(m.rhs, rhs) && !m.coordinate_forms) {
      return ::testing::AssertionSuccess();
    }
    const Mismatch expected{ErrorCode::kSemanticMismatch, op, lhs, rhs, false};
    return ::testing::AssertionFailure() << "\n  got:      " << Describe(m, names_)
                                         << "\n  expected: " << Describe(expected, names_);
  }

  template <class S>
  ::testing::AssertionResult Gives(const Checked<S>& result, const S& expected) const {
    if (!result.has_value()) {
      return ::testing::AssertionFailure() << "refused: " << Describe(result.error(), names_);
    }
    if (*result == expected) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "\n  got:      " << Describe(*result, names_)
                                         << "\n  expected: " << Describe(expected, names_);
  }
};

class AccelerationInverse : public Dyn {};
class AccelerationCompose : public Dyn {};
class AccelerationChangePoint : public Dyn {};
class AccelerationChangeCoordinateFrame : public Dyn {};
class WrenchChangePoint : public Dyn {};
class WrenchChangeCoordinateFrame : public Dyn {};
class WrenchScrewTransform : public Dyn {};
class WrenchReaction : public Dyn {};
class WrenchSum : public Dyn {};
class WrenchPower : public Dyn {};
class DynamicsForms : public Dyn {};

// ================================================================ Acceleration Inverse

TEST_F(AccelerationInverse, SwapsTheBodiesAtThePointInTheFrame) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_TRUE(Gives(Inverse(A_DCe, VelocityOf(A_DCe)), AccelerationSemantics{e, D, C, r}));
}

TEST_F(AccelerationInverse, RefusesATwistAtAnotherPoint) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe, TwistSemantics{x, C, D, r}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kPoint, x, C),
                      Side(kSubject, kAcc, Field::kPoint, e, C)));
}

TEST_F(AccelerationInverse, RefusesTheTwistOfAnotherBody) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe, TwistSemantics{e, F, D, r}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kBody, F),
                      Side(kSubject, kAcc, Field::kBody, C)));
}

TEST_F(AccelerationInverse, RefusesTheTwistOfTheInverseRelation) {
  // The classic slip: the twist of D relative to C, already inverted.
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe, TwistSemantics{e, D, C, r}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kBody, D),
                      Side(kSubject, kAcc, Field::kBody, C)));
}

TEST_F(AccelerationInverse, RefusesATwistRelativeToAnotherBody) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe, TwistSemantics{e, C, F, r}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kRefBody, F),
                      Side(kSubject, kAcc, Field::kRefBody, D)));
}

TEST_F(AccelerationInverse, RefusesATwistInAnotherFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe_r, TwistSemantics{e, C, D, s}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kCoordinateFrame, s),
                      Side(kSubject, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationInverse, ChecksPointBeforeBodiesBeforeFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  EXPECT_TRUE(Refused(Inverse(A_DCe_r, TwistSemantics{x, F, E, s}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kPoint, x, F),
                      Side(kSubject, kAcc, Field::kPoint, e, C)));
  EXPECT_TRUE(Refused(Inverse(A_DCe_r, TwistSemantics{e, F, E, s}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kBody, F),
                      Side(kSubject, kAcc, Field::kBody, C)));
  EXPECT_TRUE(Refused(Inverse(A_DCe_r, TwistSemantics{e, C, E, s}), Operation::kInverse,
                      Side(kArgument, kTwist, Field::kRefBody, E),
                      Side(kSubject, kAcc, Field::kRefBody, D)));
}

// ================================================================ Acceleration Compose

TEST_F(AccelerationCompose, ChainsBodiesAtOnePoint) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(
      Gives(Compose(A_BCe, A_MBe, TwistSemantics{e, C, B, r}, AngularVelocitySemantics{B, M, r}),
            AccelerationSemantics{e, C, M, r}));
}

TEST_F(AccelerationCompose, RefusesDifferentPoints) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBx{x, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBx, VelocityOf(A_BCe), {B, M, r}), Operation::kCompose,
                      Side(kFirst, kAcc, Field::kPoint, e, C),
                      Side(kSecond, kAcc, Field::kPoint, x, B)));
}

TEST_F(AccelerationCompose, RefusesMismatchedRefBody) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MFe{e, F, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MFe, VelocityOf(A_BCe), {F, M, r}), Operation::kCompose,
                      Side(kFirst, kAcc, Field::kRefBody, B),
                      Side(kSecond, kAcc, Field::kBody, F)));
}

TEST_F(AccelerationCompose, RefusesDifferentCoordinateFrames) {
  const AccelerationSemantics A_BCe_r{e, C, B, r};
  const AccelerationSemantics A_MBe_s{e, B, M, s};
  EXPECT_TRUE(Refused(Compose(A_BCe_r, A_MBe_s, VelocityOf(A_BCe_r), {B, M, s}),
                      Operation::kCompose, Side(kFirst, kAcc, Field::kCoordinateFrame, r),
                      Side(kSecond, kAcc, Field::kCoordinateFrame, s)));
}

TEST_F(AccelerationCompose, RefusesATwistOfTheFirstAtAnotherPoint) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, TwistSemantics{x, C, B, r}, {B, M, r}),
                      Operation::kCompose, Side(kArgument, kTwist, Field::kPoint, x, C),
                      Side(kFirst, kAcc, Field::kPoint, e, C)));
}

TEST_F(AccelerationCompose, RefusesTheTwistOfTheSecondInPlaceOfTheFirst) {
  // Coriolis needs v_BCe, the velocity of C's point relative to B, not that of B relative to M.
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, VelocityOf(A_MBe), {B, M, r}), Operation::kCompose,
                      Side(kArgument, kTwist, Field::kBody, B),
                      Side(kFirst, kAcc, Field::kBody, C)));
}

TEST_F(AccelerationCompose, RefusesATwistOfTheFirstRelativeToAnotherBody) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, TwistSemantics{e, C, M, r}, {B, M, r}),
                      Operation::kCompose, Side(kArgument, kTwist, Field::kRefBody, M),
                      Side(kFirst, kAcc, Field::kRefBody, B)));
}

TEST_F(AccelerationCompose, RefusesATwistOfTheFirstInAnotherFrame) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, TwistSemantics{e, C, B, s}, {B, M, r}),
                      Operation::kCompose, Side(kArgument, kTwist, Field::kCoordinateFrame, s),
                      Side(kFirst, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationCompose, RefusesTheAngularVelocityOfTheFirstInPlaceOfTheSecond) {
  // The Coriolis term is w_MB x v_BCe: w_BC in its place is the classic mix-up.
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, VelocityOf(A_BCe), {C, B, r}), Operation::kCompose,
                      Side(kArgument, kAng, Field::kBody, C),
                      Side(kSecond, kAcc, Field::kBody, B)));
}

TEST_F(AccelerationCompose, RefusesAnAngularVelocityRelativeToAnotherBody) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, VelocityOf(A_BCe), {B, F, r}), Operation::kCompose,
                      Side(kArgument, kAng, Field::kRefBody, F),
                      Side(kSecond, kAcc, Field::kRefBody, M)));
}

TEST_F(AccelerationCompose, RefusesAnAngularVelocityInAnotherFrame) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, VelocityOf(A_BCe), {B, M, s}), Operation::kCompose,
                      Side(kArgument, kAng, Field::kCoordinateFrame, s),
                      Side(kSecond, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationCompose, ChecksTheAccelerationsBeforeTheTwistBeforeTheAngularVelocity) {
  const AccelerationSemantics A_BCe{e, C, B, r};
  const AccelerationSemantics A_MFe{e, F, M, r};
  const AccelerationSemantics A_MBe{e, B, M, r};
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MFe, TwistSemantics{x, E, E, s}, {E, E, s}),
                      Operation::kCompose, Side(kFirst, kAcc, Field::kRefBody, B),
                      Side(kSecond, kAcc, Field::kBody, F)));
  EXPECT_TRUE(Refused(Compose(A_BCe, A_MBe, TwistSemantics{e, C, B, s}, {E, E, s}),
                      Operation::kCompose, Side(kArgument, kTwist, Field::kCoordinateFrame, s),
                      Side(kFirst, kAcc, Field::kCoordinateFrame, r)));
}

// ================================================================ Acceleration ChangePoint

TEST_F(AccelerationChangePoint, MovesThePointToTheArgumentsRefPoint) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_qe{e, C, q, C, r};  // old point e wrt new point q
  EXPECT_TRUE(Gives(ChangePoint(A_DCe, p_qe, {C, D, r}), AccelerationSemantics{q, C, D, r}));
}

TEST_F(AccelerationChangePoint, DoesNotCheckTheBodiesOfThePosition) {
  // As for twists (D3): the vector between two points at an instant has no body.
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_xe{e, E, x, F, r};
  EXPECT_TRUE(Gives(ChangePoint(A_DCe, p_xe, {C, D, r}), AccelerationSemantics{x, C, D, r}));
}

TEST_F(AccelerationChangePoint, RefusesAnArgumentNotOfTheOldPoint) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_eq{q, C, e, C, r};  // new wrt old: the wrong way round
  EXPECT_TRUE(Refused(ChangePoint(A_DCe, p_eq, {C, D, r}), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kPoint, q, C),
                      Side(kSubject, kAcc, Field::kPoint, e, C)));
}

TEST_F(AccelerationChangePoint, RefusesAnArgumentInAnotherFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  const PositionSemantics p_qe_s{e, C, q, C, s};
  EXPECT_TRUE(Refused(ChangePoint(A_DCe_r, p_qe_s, {C, D, r}), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationChangePoint, RefusesTheAngularVelocityOfAnotherBody) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_qe{e, C, q, C, r};
  EXPECT_TRUE(Refused(ChangePoint(A_DCe, p_qe, {D, C, r}), Operation::kChangePoint,
                      Side(kArgument, kAng, Field::kBody, D),
                      Side(kSubject, kAcc, Field::kBody, C)));
}

TEST_F(AccelerationChangePoint, RefusesAnAngularVelocityRelativeToAnotherBody) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_qe{e, C, q, C, r};
  EXPECT_TRUE(Refused(ChangePoint(A_DCe, p_qe, {C, E, r}), Operation::kChangePoint,
                      Side(kArgument, kAng, Field::kRefBody, E),
                      Side(kSubject, kAcc, Field::kRefBody, D)));
}

TEST_F(AccelerationChangePoint, RefusesAnAngularVelocityInAnotherFrame) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_qe{e, C, q, C, r};
  EXPECT_TRUE(Refused(ChangePoint(A_DCe, p_qe, {C, D, s}), Operation::kChangePoint,
                      Side(kArgument, kAng, Field::kCoordinateFrame, s),
                      Side(kSubject, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationChangePoint, ChecksThePositionBeforeTheAngularVelocity) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  const PositionSemantics p_qe_s{e, C, q, C, s};
  EXPECT_TRUE(Refused(ChangePoint(A_DCe, p_qe_s, {E, E, s}), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kAcc, Field::kCoordinateFrame, r)));
}

// ================================================================ Acceleration coordinate frame

TEST_F(AccelerationChangeCoordinateFrame, ReexpressesInTheNewFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  const OrientationSemantics R_sr_s{r, E, s, E, s};
  const OrientationSemantics R_sr_r{r, E, s, E, r};
  EXPECT_TRUE(Gives(ChangeCoordinateFrame(A_DCe_r, R_sr_s), AccelerationSemantics{e, C, D, s}));
  EXPECT_TRUE(Gives(ChangeCoordinateFrame(A_DCe_r, R_sr_r), AccelerationSemantics{e, C, D, s}));
}

TEST_F(AccelerationChangeCoordinateFrame, RefusesAnOrientationNotOfTheOldFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  const OrientationSemantics R_sx{ox, E, s, E, s};
  EXPECT_TRUE(Refused(ChangeCoordinateFrame(A_DCe_r, R_sx), Operation::kChangeCoordinateFrame,
                      Side(kArgument, kOri, Field::kOrientation, ox, E),
                      Side(kSubject, kAcc, Field::kCoordinateFrame, r)));
}

TEST_F(AccelerationChangeCoordinateFrame, RefusesAnOrientationExpressedInAThirdFrame) {
  const AccelerationSemantics A_DCe_r{e, C, D, r};
  const OrientationSemantics R_sr_x{r, E, s, E, ox};
  EXPECT_TRUE(Refused(ChangeCoordinateFrame(A_DCe_r, R_sr_x), Operation::kChangeCoordinateFrame,
                      Side(kArgument, kOri, Field::kCoordinateFrame, ox),
                      Side(kArgument, kOri, Field::kRefOrientation, s, E)));
}

// ================================================================ Wrench ChangePoint

TEST_F(WrenchChangePoint, MovesTheMomentPointToTheArgumentsRefPoint) {
  const WrenchSemantics F_DCe{e, C, D, r};
  const PositionSemantics p_qe{e, C, q, C, r};
  EXPECT_TRUE(Gives(ChangePoint(F_DCe, p_qe), WrenchSemantics{q, C, D, r}));
}

TEST_F(WrenchChangePoint, KeepsASumBySeveralBodies) {
  const WrenchSemantics F_Ce{e, C, Body(), r, true};
  const PositionSemantics p_qe{e, D, q, E, r};
  EXPECT_TRUE(Gives(ChangePoint(F_Ce, p_qe), WrenchSemantics{q, C, Body(), r, true}));
}

TEST_F(WrenchChangePoint, RefusesAnArgumentNotOfTheOldPoint) {
  const WrenchSemantics F_DCe{e, C, D, r};
  const PositionSemantics p_eq{q, C, e, C, r};
  EXPECT_TRUE(Refused(ChangePoint(F_DCe, p_eq), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kPoint, q, C),
                      Side(kSubject, kWr, Field::kPoint, e, C)));
}

TEST_F(WrenchChangePoint, RefusesAnArgumentInAnotherFrame) {
  // A wrench rotated where only its lever arm should change (or the other way round) shows up
  // as a frame mismatch here.
  const WrenchSemantics F_DCe_r{e, C, D, r};
  const PositionSemantics p_qe_s{e, C, q, C, s};
  EXPECT_TRUE(Refused(ChangePoint(F_DCe_r, p_qe_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kWr, Field::kCoordinateFrame, r)));
}

// ================================================================ Wrench coordinate frame

TEST_F(WrenchChangeCoordinateFrame, ReexpressesKeepingThePoint) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  const OrientationSemantics R_sr{r, E, s, E, s};
  EXPECT_TRUE(Gives(ChangeCoordinateFrame(F_DCe_r, R_sr), WrenchSemantics{e, C, D, s}));
}

TEST_F(WrenchChangeCoordinateFrame, RefusesAnOrientationNotOfTheOldFrame) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  const OrientationSemantics R_rs{s, E, r, E, r};  // the inverse rotation
  EXPECT_TRUE(Refused(ChangeCoordinateFrame(F_DCe_r, R_rs), Operation::kChangeCoordinateFrame,
                      Side(kArgument, kOri, Field::kOrientation, s, E),
                      Side(kSubject, kWr, Field::kCoordinateFrame, r)));
}

// ================================================================ Wrench ScrewTransform

TEST_F(WrenchScrewTransform, MovesAWrenchAlongAFramePose) {
  const Frame fa = Frame(a.id()), fb = Frame(b.id());
  const WrenchSemantics F_DCa{fa.origin(), C, D, a};
  const PoseSemantics X_ba = PoseSemantics::OfFrame(fa, C, fb, D, b);
  EXPECT_TRUE(Gives(ScrewTransform(F_DCa, X_ba), WrenchSemantics{fb.origin(), C, D, b}));
}

TEST_F(WrenchScrewTransform, RefusesAPoseOfAnotherPoint) {
  const WrenchSemantics F_DCe{e, C, D, a};
  const PoseSemantics X{x, a, C, q, b, D, b};
  EXPECT_TRUE(Refused(ScrewTransform(F_DCe, X), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kPoint, x, C),
                      Side(kSubject, kWr, Field::kPoint, e, C)));
}

TEST_F(WrenchScrewTransform, RefusesAPoseWhoseOrientationIsNotTheWrenchsFrame) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  const PoseSemantics X{e, a, C, q, b, D, b};
  EXPECT_TRUE(Refused(ScrewTransform(F_DCe_r, X), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kOrientation, a, C),
                      Side(kSubject, kWr, Field::kCoordinateFrame, r)));
}

TEST_F(WrenchScrewTransform, RefusesAPoseNotExpressedInItsReferenceFrame) {
  const WrenchSemantics F_DCe{e, C, D, a};
  const PoseSemantics X{e, a, C, q, b, D, s};
  EXPECT_TRUE(Refused(ScrewTransform(F_DCe, X), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kCoordinateFrame, s),
                      Side(kArgument, kPose, Field::kRefOrientation, b, D)));
}

// ================================================================ Wrench Reaction

TEST_F(WrenchReaction, SwapsOnAndByAtThePointInTheFrame) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Gives(Reaction(F_DCe), WrenchSemantics{e, D, C, r}));
  EXPECT_TRUE(Gives(Reaction(*Reaction(F_DCe)), F_DCe));
}

TEST_F(WrenchReaction, RefusesASumBySeveralBodies) {
  const WrenchSemantics F_Ce{e, C, Body(), r, true};
  EXPECT_TRUE(Refused(Reaction(F_Ce), Operation::kReaction, Several(kSubject),
                      Side(kSubject, kWr, Field::kBody, C)));
}

// ================================================================ Wrench Sum

TEST_F(WrenchSum, OfTwoPartsOfOneInteractionIsByThatBody) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Gives(Sum(F_DCe, F_DCe), F_DCe));
}

TEST_F(WrenchSum, ByDifferentBodiesIsBySeveral) {
  const WrenchSemantics F_DCe{e, C, D, r};
  const WrenchSemantics F_ECe{e, C, E, r};
  const WrenchSemantics net{e, C, Body(), r, true};
  EXPECT_TRUE(Gives(Sum(F_DCe, F_ECe), net));
  EXPECT_TRUE(Gives(Sum(net, F_DCe), net));
  EXPECT_TRUE(Gives(Sum(F_DCe, net), net));
  EXPECT_TRUE(Gives(Sum(net, net), net));
}

TEST_F(WrenchSum, RefusesWrenchesOnDifferentBodies) {
  // The sensor's wrench by the tool (on the sensor) added to a wrench on the tool.
  const WrenchSemantics F_DCe{e, C, D, r};
  const WrenchSemantics F_CDe{e, D, C, r};
  EXPECT_TRUE(Refused(Sum(F_DCe, F_CDe), Operation::kSum, Side(kFirst, kWr, Field::kBody, C),
                      Side(kSecond, kWr, Field::kBody, D)));
}

TEST_F(WrenchSum, RefusesMomentsAboutDifferentPoints) {
  const WrenchSemantics F_DCe{e, C, D, r};
  const WrenchSemantics F_ECq{q, C, E, r};
  EXPECT_TRUE(Refused(Sum(F_DCe, F_ECq), Operation::kSum, Side(kFirst, kWr, Field::kPoint, e, C),
                      Side(kSecond, kWr, Field::kPoint, q, C)));
}

TEST_F(WrenchSum, RefusesDifferentFrames) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  const WrenchSemantics F_ECe_s{e, C, E, s};
  EXPECT_TRUE(Refused(Sum(F_DCe_r, F_ECe_s), Operation::kSum,
                      Side(kFirst, kWr, Field::kCoordinateFrame, r),
                      Side(kSecond, kWr, Field::kCoordinateFrame, s)));
}

TEST_F(WrenchSum, ChecksBodyBeforePointBeforeFrame) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  EXPECT_TRUE(Refused(Sum(F_DCe_r, WrenchSemantics{q, D, E, s}), Operation::kSum,
                      Side(kFirst, kWr, Field::kBody, C), Side(kSecond, kWr, Field::kBody, D)));
  EXPECT_TRUE(Refused(Sum(F_DCe_r, WrenchSemantics{q, C, E, s}), Operation::kSum,
                      Side(kFirst, kWr, Field::kPoint, e, C),
                      Side(kSecond, kWr, Field::kPoint, q, C)));
}

// ================================================================ Power

TEST_F(WrenchPower, OfAWrenchWithTheTwistOfItsRelation) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Gives(PowerOf(F_DCe, TwistSemantics{e, C, D, r}), PowerSemantics{C, D}));
}

TEST_F(WrenchPower, RefusesATwistAtAnotherPoint) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(PowerOf(F_DCe, TwistSemantics{q, C, D, r}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kPoint, q, C),
                      Side(kSubject, kWr, Field::kPoint, e, C)));
}

TEST_F(WrenchPower, RefusesTheTwistOfTheBodyActing) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(PowerOf(F_DCe, TwistSemantics{e, D, C, r}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kBody, D),
                      Side(kSubject, kWr, Field::kBody, C)));
}

TEST_F(WrenchPower, RefusesATwistRelativeToAnotherBodyThanTheOneActing) {
  // Power relative to the world is not the power D delivers to C when D moves.
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_TRUE(Refused(PowerOf(F_DCe, TwistSemantics{e, C, M, r}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kRefBody, M),
                      Side(kSubject, kWr, Field::kRefBody, D)));
}

TEST_F(WrenchPower, RefusesASumBySeveralBodies) {
  const WrenchSemantics F_Ce{e, C, Body(), r, true};
  EXPECT_TRUE(Refused(PowerOf(F_Ce, TwistSemantics{e, C, D, r}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kRefBody, D), Several(kSubject)));
}

TEST_F(WrenchPower, RefusesATwistInAnotherFrame) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  EXPECT_TRUE(Refused(PowerOf(F_DCe_r, TwistSemantics{e, C, D, s}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kCoordinateFrame, s),
                      Side(kSubject, kWr, Field::kCoordinateFrame, r)));
}

TEST_F(WrenchPower, ChecksPointBeforeBodiesBeforeFrame) {
  const WrenchSemantics F_DCe_r{e, C, D, r};
  EXPECT_TRUE(Refused(PowerOf(F_DCe_r, TwistSemantics{q, D, M, s}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kPoint, q, D),
                      Side(kSubject, kWr, Field::kPoint, e, C)));
  EXPECT_TRUE(Refused(PowerOf(F_DCe_r, TwistSemantics{e, C, M, s}), Operation::kPower,
                      Side(kArgument, kTwist, Field::kRefBody, M),
                      Side(kSubject, kWr, Field::kRefBody, D)));
}

// ================================================================ Forms

TEST_F(DynamicsForms, VelocityOfAndAccelerationOfKeepEveryField) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_EQ(VelocityOf(A_DCe), (TwistSemantics{e, C, D, r}));
  EXPECT_EQ(AccelerationOf(VelocityOf(A_DCe)), A_DCe);
}

TEST_F(DynamicsForms, AreSmallNoexceptValues) {
  static_assert(std::is_trivially_copyable_v<AccelerationSemantics>);
  static_assert(std::is_trivially_copyable_v<WrenchSemantics>);
  static_assert(sizeof(WrenchSemantics) <= 20);
  static_assert(sizeof(Mismatch) <= 32);
  const AccelerationSemantics A{e, C, D, r};
  const WrenchSemantics W{e, C, D, r};
  const PositionSemantics p{e, C, q, C, r};
  const OrientationSemantics O{r, E, s, E, s};
  static_assert(noexcept(Inverse(A, VelocityOf(A))));
  static_assert(noexcept(Compose(A, A, VelocityOf(A), AngularVelocitySemantics{})));
  static_assert(noexcept(ChangePoint(A, p, AngularVelocitySemantics{})));
  static_assert(noexcept(ChangeCoordinateFrame(A, O)));
  static_assert(noexcept(ChangePoint(W, p)));
  static_assert(noexcept(ChangeCoordinateFrame(W, O)));
  static_assert(noexcept(Reaction(W)));
  static_assert(noexcept(Sum(W, W)));
  static_assert(noexcept(PowerOf(W, VelocityOf(A))));
  SUCCEED();
}

}  // namespace
}  // namespace semgraph::semantics
