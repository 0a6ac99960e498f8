// Tests for semgraph/semantics/operations.h: for every operation, one test per precondition (each
// breaks exactly that precondition and checks the whole Mismatch), the precondition order (when
// two fail, the first in the documented order is reported), and acceptance tests that check every
// field of the result semantics, in both coordinate forms where an operation has two.
#include "semgraph/semantics/operations.h"

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
constexpr RelationKind kLin = RelationKind::kLinearVelocity;
constexpr RelationKind kAng = RelationKind::kAngularVelocity;
constexpr RelationKind kTwist = RelationKind::kTwist;
constexpr CoordinateForm kChain = CoordinateForm::kChain;
constexpr CoordinateForm kSameFrame = CoordinateForm::kSameFrame;

// Shared names for every fixture below.
//
// C, D, E: bodies (C: the body a relation is of; D: its reference body; E: a third body);
//          F: a body that no valid operand mentions.
// e, e2 on C; f, f2 on D; g on E: points; x: a point that no valid operand mentions.
// [a], [a2] on C; [b], [b2] on D; [c] on E: orientation frames; [x]: one no valid operand mentions.
// [r], [s]: coordinate frames (orientation frames; a coordinate frame carries no body).
//
// Variables are Drake monograms. Relations between bodies use body letters: p_DC is
// PositionCoord(e|C, f|D, [r]) (from D's point to C's point), R_DC an orientation of C's frame
// in D's, X_DC a pose, v_DC, w_DC, V_DC the velocities of C measured in D; composing p_DC with
// p_ED gives p_EC. Relations inside one body and coordinate changes use point and frame letters:
// p_ee2 is PositionCoord(e2|C, e|C, [r]) (from e to e2), R_aa2 is [a2] in [a], R_sr is [r] in
// [s] (the R[s<-r] that re-expresses from [r] into [s]). A trailing _b, _r, ... names the
// coordinate frame where a test depends on it.
class Semantics : public ::testing::Test {
 protected:
  NameTable names_;
  const Body C = Intern<Body>("C"), D = Intern<Body>("D"), E = Intern<Body>("E"),
             F = Intern<Body>("F");
  const Point e = Intern<Point>("e"), e2 = Intern<Point>("e2"), f = Intern<Point>("f"),
              f2 = Intern<Point>("f2"), g = Intern<Point>("g"), x = Intern<Point>("x");
  const OrientationFrame a = Intern<OrientationFrame>("a"), a2 = Intern<OrientationFrame>("a2"),
                         b = Intern<OrientationFrame>("b"), b2 = Intern<OrientationFrame>("b2"),
                         c = Intern<OrientationFrame>("c"), ox = Intern<OrientationFrame>("x"),
                         r = Intern<OrientationFrame>("r"), s = Intern<OrientationFrame>("s");

  template <class P>
  P Intern(std::string_view name) {
    return P(*names_.Intern(name));
  }

  /// The frame {o}: origin point o and orientation frame [o].
  static Frame FrameOf(OrientationFrame o) { return Frame(o.id()); }

  /// One side of an expected Mismatch; `body` is left invalid for body and coordinate-frame
  /// fields, as operations.cc does.
  template <class N>
  static MismatchSide Side(Operand operand, RelationKind relation, Field field, N name,
                           Body body = Body()) {
    return {operand, relation, field, name.id(), body.id()};
  }

  std::string Text(const MismatchSide& side) const {
    return std::string(names_.name(side.name)) + "|" + std::string(names_.name(side.body)) +
           " (operand " + std::to_string(static_cast<int>(side.operand)) + ", relation " +
           std::to_string(static_cast<int>(side.relation)) + ", field " +
           std::to_string(static_cast<int>(side.field)) + ")";
  }

  /// Success when `result` is the Mismatch {kSemanticMismatch, op, lhs, rhs, coordinate_forms}.
  template <class T>
  ::testing::AssertionResult Refused(const Checked<T>& result, Operation op,
                                     const MismatchSide& lhs, const MismatchSide& rhs,
                                     bool coordinate_forms = false) const {
    if (result.has_value()) return ::testing::AssertionFailure() << "the operation succeeded";
    const Mismatch& m = result.error();
    const auto same = [](const MismatchSide& p, const MismatchSide& q) {
      return p.operand == q.operand && p.relation == q.relation && p.field == q.field &&
             p.name == q.name && p.body == q.body;
    };
    if (m.code == ErrorCode::kSemanticMismatch && m.operation == op && same(m.lhs, lhs) &&
        same(m.rhs, rhs) && m.coordinate_forms == coordinate_forms) {
      return ::testing::AssertionSuccess();
    }
    const Mismatch expected{ErrorCode::kSemanticMismatch, op, lhs, rhs, coordinate_forms};
    return ::testing::AssertionFailure()
           << "\n  got:      " << ToString(m.code) << ": " << Describe(m, names_)
           << "\n            " << Text(m.lhs) << " / " << Text(m.rhs)
           << " forms=" << m.coordinate_forms << "\n  expected: " << Describe(expected, names_)
           << "\n            " << Text(lhs) << " / " << Text(rhs) << " forms=" << coordinate_forms;
  }

  template <class S>
  ::testing::AssertionResult Is(const S& actual, const S& expected) const {
    if (actual == expected) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "\n  got:      " << Describe(actual, names_)
                                         << "\n  expected: " << Describe(expected, names_);
  }

  template <class S>
  ::testing::AssertionResult Gives(const Checked<S>& result, const S& expected) const {
    if (!result.has_value()) {
      return ::testing::AssertionFailure() << "refused: " << Describe(result.error(), names_);
    }
    return Is(*result, expected);
  }

  template <class S>
  ::testing::AssertionResult Gives(const Checked<Composition<S>>& result, const S& expected,
                                   CoordinateForm form) const {
    if (!result.has_value()) {
      return ::testing::AssertionFailure() << "refused: " << Describe(result.error(), names_);
    }
    if (result->form != form) {
      return ::testing::AssertionFailure() << "form " << static_cast<int>(result->form)
                                           << ", expected " << static_cast<int>(form);
    }
    return Is(result->result, expected);
  }

  /// A relation of each kind between C and D, expressed in `cf`.
  template <class S>
  S Sample(OrientationFrame cf) const {
    if constexpr (std::is_same_v<S, PositionSemantics>) {
      return {e, C, f, D, cf};
    } else if constexpr (std::is_same_v<S, OrientationSemantics>) {
      return {a, C, b, D, cf};
    } else if constexpr (std::is_same_v<S, PoseSemantics>) {
      return {e, a, C, f, b, D, cf};
    } else if constexpr (std::is_same_v<S, LinearVelocitySemantics>) {
      return {e, C, D, cf};
    } else if constexpr (std::is_same_v<S, AngularVelocitySemantics>) {
      return {C, D, cf};
    } else {
      static_assert(std::is_same_v<S, TwistSemantics>);
      return {e, C, D, cf};
    }
  }
};

template <class S>
constexpr RelationKind kKindOf = std::is_same_v<S, PositionSemantics>          ? kPos
                                 : std::is_same_v<S, OrientationSemantics>     ? kOri
                                 : std::is_same_v<S, PoseSemantics>            ? kPose
                                 : std::is_same_v<S, LinearVelocitySemantics>  ? kLin
                                 : std::is_same_v<S, AngularVelocitySemantics> ? kAng
                                                                               : kTwist;

// One fixture name per operation, so that test names read "PoseCompose.RefusesMismatchedRefPoint".
class PositionInverse : public Semantics {};
class PositionCompose : public Semantics {};
class PositionChangePoint : public Semantics {};
class PositionChangeRefPoint : public Semantics {};
class OrientationInverse : public Semantics {};
class OrientationInverseInNewRef : public Semantics {};
class OrientationCompose : public Semantics {};
class OrientationChangeOrientationFrame : public Semantics {};
class OrientationChangeRefOrientationFrame : public Semantics {};
class PoseInverse : public Semantics {};
class PoseInverseInNewRef : public Semantics {};
class PoseCompose : public Semantics {};
class PoseChangePoint : public Semantics {};
class PoseChangeRefPoint : public Semantics {};
class PoseChangeOrientationFrame : public Semantics {};
class PoseChangeRefOrientationFrame : public Semantics {};
class PoseParts : public Semantics {};
class PoseCombine : public Semantics {};
class LinearVelocityInverse : public Semantics {};
class LinearVelocityCompose : public Semantics {};
class AngularVelocityInverse : public Semantics {};
class AngularVelocityCompose : public Semantics {};
class TwistInverse : public Semantics {};
class TwistCompose : public Semantics {};
class TwistChangePoint : public Semantics {};
class TwistScrewTransform : public Semantics {};
class TwistParts : public Semantics {};
class TwistCombine : public Semantics {};
class RelationForms : public Semantics {};

// ================================================================ Position

TEST_F(PositionInverse, SwapsPointAndReferenceKeepingTheCoordinateFrame) {
  const PositionSemantics p_DC{e, C, f, D, r};
  EXPECT_TRUE(Is(Inverse(p_DC),
                 PositionSemantics{
                     .point = f, .body = D, .ref_point = e, .ref_body = C, .coordinate_frame = r}));
}

TEST_F(PositionCompose, ChainsFirstRelativeToSecondInNaturalOrder) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ED{f, D, g, E, r};
  EXPECT_TRUE(
      Gives(Compose(p_DC, p_ED),
            PositionSemantics{
                .point = e, .body = C, .ref_point = g, .ref_body = E, .coordinate_frame = r}));
}

TEST_F(PositionCompose, RefusesMatrixOrder) {
  // D1: only the natural order Compose(e wrt f, f wrt g) is provided.
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ED{f, D, g, E, r};
  EXPECT_TRUE(Refused(Compose(p_ED, p_DC), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefPoint, g, E),
                      Side(kSecond, kPos, Field::kPoint, e, C)));
}

TEST_F(PositionCompose, ComposesARelationWithItsInverseInBothNaturalOrders) {
  // The case that makes a matrix-order compose ambiguous (D1): both orders match, with
  // different results.
  const PositionSemantics p_DC{e, C, f, D, r};
  EXPECT_TRUE(Gives(Compose(p_DC, Inverse(p_DC)), PositionSemantics{e, C, e, C, r}));
  EXPECT_TRUE(Gives(Compose(Inverse(p_DC), p_DC), PositionSemantics{f, D, f, D, r}));
}

TEST_F(PositionCompose, RefusesMismatchedRefPoint) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ED{x, D, g, E, r};  // x != f
  EXPECT_TRUE(Refused(Compose(p_DC, p_ED), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefPoint, f, D),
                      Side(kSecond, kPos, Field::kPoint, x, D)));
}

TEST_F(PositionCompose, RefusesMismatchedRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_EF{f, F, g, E, r};  // F != D
  EXPECT_TRUE(Refused(Compose(p_DC, p_EF), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefBody, D),
                      Side(kSecond, kPos, Field::kBody, F)));
}

TEST_F(PositionCompose, RefusesMismatchedCoordinateFrames) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_ED_s{f, D, g, E, s};
  EXPECT_TRUE(Refused(Compose(p_DC_r, p_ED_s), Operation::kCompose,
                      Side(kFirst, kPos, Field::kCoordinateFrame, r),
                      Side(kSecond, kPos, Field::kCoordinateFrame, s)));
}

TEST_F(PositionCompose, ChecksRefPointBeforeRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_EF{x, F, g, E, r};
  EXPECT_TRUE(Refused(Compose(p_DC, p_EF), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefPoint, f, D),
                      Side(kSecond, kPos, Field::kPoint, x, F)));
}

TEST_F(PositionCompose, ChecksRefBodyBeforeCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_EF_s{f, F, g, E, s};
  EXPECT_TRUE(Refused(Compose(p_DC_r, p_EF_s), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefBody, D),
                      Side(kSecond, kPos, Field::kBody, F)));
}

TEST_F(PositionCompose, ChecksRefPointBeforeCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_ED_s{x, D, g, E, s};
  EXPECT_TRUE(Refused(Compose(p_DC_r, p_ED_s), Operation::kCompose,
                      Side(kFirst, kPos, Field::kRefPoint, f, D),
                      Side(kSecond, kPos, Field::kPoint, x, D)));
}

// ---------------------------------------------------------------- Position ChangePoint

TEST_F(PositionChangePoint, ReplacesThePointWithTheArgumentsPoint) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ee2{e2, C, e, C, r};  // new point e2 wrt old point e, both on C
  EXPECT_TRUE(
      Gives(ChangePoint(p_DC, p_ee2),
            PositionSemantics{
                .point = e2, .body = C, .ref_point = f, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(PositionChangePoint, RefusesAnArgumentNotRelativeToTheOldPoint) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_xe2{e2, C, x, C, r};
  EXPECT_TRUE(Refused(ChangePoint(p_DC, p_xe2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefPoint, x, C),
                      Side(kSubject, kPos, Field::kPoint, e, C)));
}

TEST_F(PositionChangePoint, RefusesAnArgumentWhoseRefBodyIsNotTheBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ee2{e2, C, e, F, r};
  EXPECT_TRUE(Refused(ChangePoint(p_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPos, Field::kBody, C)));
}

TEST_F(PositionChangePoint, RefusesAnArgumentWhoseBodyIsNotTheBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ee2{e2, F, e, C, r};
  EXPECT_TRUE(Refused(ChangePoint(p_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPos, Field::kBody, C)));
}

TEST_F(PositionChangePoint, RefusesAnArgumentInAnotherCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_ee2_s{e2, C, e, C, s};
  EXPECT_TRUE(Refused(ChangePoint(p_DC_r, p_ee2_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kPos, Field::kCoordinateFrame, r)));
}

TEST_F(PositionChangePoint, ChecksRefPointBeforeRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_xe2{e2, C, x, F, r};
  EXPECT_TRUE(Refused(ChangePoint(p_DC, p_xe2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefPoint, x, F),
                      Side(kSubject, kPos, Field::kPoint, e, C)));
}

TEST_F(PositionChangePoint, ChecksRefBodyBeforeBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ee2{e2, E, e, F, r};
  EXPECT_TRUE(Refused(ChangePoint(p_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPos, Field::kBody, C)));
}

TEST_F(PositionChangePoint, ChecksBodyBeforeCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_ee2_s{e2, F, e, C, s};
  EXPECT_TRUE(Refused(ChangePoint(p_DC_r, p_ee2_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPos, Field::kBody, C)));
}

// ---------------------------------------------------------------- Position ChangeRefPoint

TEST_F(PositionChangeRefPoint, ReplacesTheRefPointWithTheArgumentsRefPoint) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2f{f, D, f2, D, r};  // old ref f wrt new ref f2, both on D
  EXPECT_TRUE(
      Gives(ChangeRefPoint(p_DC, p_f2f),
            PositionSemantics{
                .point = e, .body = C, .ref_point = f2, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(PositionChangeRefPoint, RefusesAnArgumentNotOfTheOldRefPoint) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2x{x, D, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC, p_f2x), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kPoint, x, D),
                      Side(kSubject, kPos, Field::kRefPoint, f, D)));
}

TEST_F(PositionChangeRefPoint, RefusesAnArgumentWhoseBodyIsNotTheRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2f{f, F, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPos, Field::kRefBody, D)));
}

TEST_F(PositionChangeRefPoint, RefusesAnArgumentWhoseRefBodyIsNotTheRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2f{f, D, f2, F, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPos, Field::kRefBody, D)));
}

TEST_F(PositionChangeRefPoint, RefusesAnArgumentInAnotherCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_f2f_s{f, D, f2, D, s};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC_r, p_f2f_s), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kPos, Field::kCoordinateFrame, r)));
}

TEST_F(PositionChangeRefPoint, ChecksPointBeforeBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2x{x, F, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC, p_f2x), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kPoint, x, F),
                      Side(kSubject, kPos, Field::kRefPoint, f, D)));
}

TEST_F(PositionChangeRefPoint, ChecksBodyBeforeRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_f2f{f, F, f2, E, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPos, Field::kRefBody, D)));
}

TEST_F(PositionChangeRefPoint, ChecksRefBodyBeforeCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_f2f_s{f, D, f2, F, s};
  EXPECT_TRUE(Refused(ChangeRefPoint(p_DC_r, p_f2f_s), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPos, Field::kRefBody, D)));
}

// ================================================================ Orientation

TEST_F(OrientationInverse, SwapsFramesAndBodiesKeepingTheCoordinateFrame) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  EXPECT_TRUE(Is(Inverse(R_DC_r), OrientationSemantics{.orientation = b,
                                                       .body = D,
                                                       .ref_orientation = a,
                                                       .ref_body = C,
                                                       .coordinate_frame = r}));
}

TEST_F(OrientationInverseInNewRef, ExpressesTheInverseInTheNewReferenceFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  EXPECT_TRUE(Gives(InverseInNewRef(R_DC_b), OrientationSemantics{.orientation = b,
                                                                  .body = D,
                                                                  .ref_orientation = a,
                                                                  .ref_body = C,
                                                                  .coordinate_frame = a}));
}

TEST_F(OrientationInverseInNewRef, RefusesAnOrientationNotExpressedInItsReferenceFrame) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  EXPECT_TRUE(Refused(InverseInNewRef(R_DC_r), Operation::kInverseInNewRef,
                      Side(kSubject, kOri, Field::kCoordinateFrame, r),
                      Side(kSubject, kOri, Field::kRefOrientation, b, D)));
}

TEST_F(OrientationInverseInNewRef, RefusesAnOrientationExpressedInItsOwnFrame) {
  // Expressed in [a] the operator has the same value as in [b], but the inverse in the new
  // reference frame is defined for the rotation-matrix view, [r] = [b], only.
  const OrientationSemantics R_DC_a{a, C, b, D, a};
  EXPECT_TRUE(Refused(InverseInNewRef(R_DC_a), Operation::kInverseInNewRef,
                      Side(kSubject, kOri, Field::kCoordinateFrame, a),
                      Side(kSubject, kOri, Field::kRefOrientation, b, D)));
}

// ---------------------------------------------------------------- Orientation Compose

TEST_F(OrientationCompose, UsesTheChainFormWhenEachIsInItsReferenceFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};  // R[b<-a]
  const OrientationSemantics R_ED_c{b, D, c, E, c};  // R[c<-b]
  EXPECT_TRUE(Gives(
      Compose(R_DC_b, R_ED_c),
      OrientationSemantics{
          .orientation = a, .body = C, .ref_orientation = c, .ref_body = E, .coordinate_frame = c},
      kChain));
}

TEST_F(OrientationCompose, UsesTheSameFrameFormWhenBothShareACoordinateFrame) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  const OrientationSemantics R_ED_r{b, D, c, E, r};
  EXPECT_TRUE(Gives(
      Compose(R_DC_r, R_ED_r),
      OrientationSemantics{
          .orientation = a, .body = C, .ref_orientation = c, .ref_body = E, .coordinate_frame = r},
      kSameFrame));
}

TEST_F(OrientationCompose, UsesTheSameFrameFormWhenOnlyTheFirstIsInItsReferenceFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_b{b, D, c, E, b};
  EXPECT_TRUE(Gives(Compose(R_DC_b, R_ED_b), OrientationSemantics{a, C, c, E, b}, kSameFrame));
}

TEST_F(OrientationCompose, PrefersTheChainFormWhenBothFormsApply) {
  // [b] wrt [b] on another body: the second is in its reference frame [b], which is also the
  // first's coordinate frame.
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_b{b, D, b, E, b};
  EXPECT_TRUE(Gives(Compose(R_DC_b, R_ED_b), OrientationSemantics{a, C, b, E, b}, kChain));
}

TEST_F(OrientationCompose, RefusesMismatchedRefOrientation) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_c{ox, D, c, E, c};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_ED_c), Operation::kCompose,
                      Side(kFirst, kOri, Field::kRefOrientation, b, D),
                      Side(kSecond, kOri, Field::kOrientation, ox, D)));
}

TEST_F(OrientationCompose, RefusesMismatchedRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_EF_c{b, F, c, E, c};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_EF_c), Operation::kCompose,
                      Side(kFirst, kOri, Field::kRefBody, D),
                      Side(kSecond, kOri, Field::kBody, F)));
}

TEST_F(OrientationCompose, RefusesOperandsInNeitherCoordinateForm) {
  // The first is in its reference frame [b], the second in [r]: neither the chain nor one frame.
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_r{b, D, c, E, r};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_ED_r), Operation::kCompose,
                      Side(kFirst, kOri, Field::kCoordinateFrame, b),
                      Side(kSecond, kOri, Field::kCoordinateFrame, r),
                      /*coordinate_forms=*/true));
}

TEST_F(OrientationCompose, RefusesTwoDifferentArbitraryCoordinateFrames) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  const OrientationSemantics R_ED_s{b, D, c, E, s};
  EXPECT_TRUE(Refused(Compose(R_DC_r, R_ED_s), Operation::kCompose,
                      Side(kFirst, kOri, Field::kCoordinateFrame, r),
                      Side(kSecond, kOri, Field::kCoordinateFrame, s),
                      /*coordinate_forms=*/true));
}

TEST_F(OrientationCompose, RefusesAChainWhoseFirstIsExpressedInItsOwnFrame) {
  // R_DC in [a] has the value of R[b<-a], yet the chain needs it labelled [b]: no silent fix.
  const OrientationSemantics R_DC_a{a, C, b, D, a};
  const OrientationSemantics R_ED_c{b, D, c, E, c};
  EXPECT_TRUE(Refused(Compose(R_DC_a, R_ED_c), Operation::kCompose,
                      Side(kFirst, kOri, Field::kCoordinateFrame, a),
                      Side(kSecond, kOri, Field::kCoordinateFrame, c),
                      /*coordinate_forms=*/true));
}

TEST_F(OrientationCompose, ChecksRefOrientationBeforeRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_EF_c{ox, F, c, E, c};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_EF_c), Operation::kCompose,
                      Side(kFirst, kOri, Field::kRefOrientation, b, D),
                      Side(kSecond, kOri, Field::kOrientation, ox, F)));
}

TEST_F(OrientationCompose, ChecksRefBodyBeforeCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_EF_r{b, F, c, E, r};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_EF_r), Operation::kCompose,
                      Side(kFirst, kOri, Field::kRefBody, D),
                      Side(kSecond, kOri, Field::kBody, F)));
}

TEST_F(OrientationCompose, ChecksRefOrientationBeforeCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_r{ox, D, c, E, r};
  EXPECT_TRUE(Refused(Compose(R_DC_b, R_ED_r), Operation::kCompose,
                      Side(kFirst, kOri, Field::kRefOrientation, b, D),
                      Side(kSecond, kOri, Field::kOrientation, ox, D)));
}

// ------------------------------------------------------ Orientation ChangeOrientationFrame

TEST_F(OrientationChangeOrientationFrame, UsesTheChainForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};    // R[b<-a]
  const OrientationSemantics R_aa2_a{a2, C, a, C, a};  // R[a<-a2]
  EXPECT_TRUE(Gives(
      ChangeOrientationFrame(R_DC_b, R_aa2_a),
      OrientationSemantics{
          .orientation = a2, .body = C, .ref_orientation = b, .ref_body = D, .coordinate_frame = b},
      kChain));
}

TEST_F(OrientationChangeOrientationFrame, UsesTheSameFrameForm) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  const OrientationSemantics R_aa2_r{a2, C, a, C, r};
  EXPECT_TRUE(Gives(
      ChangeOrientationFrame(R_DC_r, R_aa2_r),
      OrientationSemantics{
          .orientation = a2, .body = C, .ref_orientation = b, .ref_body = D, .coordinate_frame = r},
      kSameFrame));
}

TEST_F(OrientationChangeOrientationFrame, RefusesAnArgumentNotRelativeToTheOldFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_xa2_x{a2, C, ox, C, ox};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_xa2_x), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefOrientation, ox, C),
                      Side(kSubject, kOri, Field::kOrientation, a, C)));
}

TEST_F(OrientationChangeOrientationFrame, RefusesAnArgumentWhoseRefBodyIsNotTheBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_aa2_a{a2, C, a, F, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefBody, F),
                      Side(kSubject, kOri, Field::kBody, C)));
}

TEST_F(OrientationChangeOrientationFrame, RefusesAnArgumentWhoseBodyIsNotTheBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_aa2_a{a2, F, a, C, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kOri, Field::kBody, C)));
}

TEST_F(OrientationChangeOrientationFrame, RefusesOperandsInNeitherCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_aa2_s{a2, C, a, C, s};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_aa2_s), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kCoordinateFrame, s),
                      Side(kSubject, kOri, Field::kCoordinateFrame, b),
                      /*coordinate_forms=*/true));
}

TEST_F(OrientationChangeOrientationFrame, ChecksRefOrientationBeforeRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_xa2{a2, C, ox, F, ox};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_xa2), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefOrientation, ox, F),
                      Side(kSubject, kOri, Field::kOrientation, a, C)));
}

TEST_F(OrientationChangeOrientationFrame, ChecksRefBodyBeforeBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_aa2_a{a2, E, a, F, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefBody, F),
                      Side(kSubject, kOri, Field::kBody, C)));
}

TEST_F(OrientationChangeOrientationFrame, ChecksBodyBeforeCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_aa2_s{a2, F, a, C, s};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(R_DC_b, R_aa2_s), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kOri, Field::kBody, C)));
}

// --------------------------------------------------- Orientation ChangeRefOrientationFrame

TEST_F(OrientationChangeRefOrientationFrame, UsesTheChainFormAndMovesTheCoordinateFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};      // R[b<-a]
  const OrientationSemantics R_b2b_b2{b, D, b2, D, b2};  // R[b2<-b]
  EXPECT_TRUE(Gives(ChangeRefOrientationFrame(R_DC_b, R_b2b_b2),
                    OrientationSemantics{.orientation = a,
                                         .body = C,
                                         .ref_orientation = b2,
                                         .ref_body = D,
                                         .coordinate_frame = b2},
                    kChain));
}

TEST_F(OrientationChangeRefOrientationFrame, UsesTheSameFrameForm) {
  const OrientationSemantics R_DC_r{a, C, b, D, r};
  const OrientationSemantics R_b2b_r{b, D, b2, D, r};
  EXPECT_TRUE(Gives(
      ChangeRefOrientationFrame(R_DC_r, R_b2b_r),
      OrientationSemantics{
          .orientation = a, .body = C, .ref_orientation = b2, .ref_body = D, .coordinate_frame = r},
      kSameFrame));
}

TEST_F(OrientationChangeRefOrientationFrame, RefusesAnArgumentNotOfTheOldRefFrame) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2x{ox, D, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(R_DC_b, R_b2x),
                      Operation::kChangeRefOrientationFrame,
                      Side(kArgument, kOri, Field::kOrientation, ox, D),
                      Side(kSubject, kOri, Field::kRefOrientation, b, D)));
}

TEST_F(OrientationChangeRefOrientationFrame, RefusesAnArgumentWhoseBodyIsNotTheRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2b{b, F, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(R_DC_b, R_b2b),
                      Operation::kChangeRefOrientationFrame, Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kOri, Field::kRefBody, D)));
}

TEST_F(OrientationChangeRefOrientationFrame, RefusesAnArgumentWhoseRefBodyIsNotTheRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2b{b, D, b2, F, b2};
  EXPECT_TRUE(
      Refused(ChangeRefOrientationFrame(R_DC_b, R_b2b), Operation::kChangeRefOrientationFrame,
              Side(kArgument, kOri, Field::kRefBody, F), Side(kSubject, kOri, Field::kRefBody, D)));
}

TEST_F(OrientationChangeRefOrientationFrame, RefusesOperandsInNeitherCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2b_s{b, D, b2, D, s};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(R_DC_b, R_b2b_s),
                      Operation::kChangeRefOrientationFrame,
                      Side(kSubject, kOri, Field::kCoordinateFrame, b),
                      Side(kArgument, kOri, Field::kCoordinateFrame, s),
                      /*coordinate_forms=*/true));
}

TEST_F(OrientationChangeRefOrientationFrame, ChecksOrientationBeforeBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2x{ox, F, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(R_DC_b, R_b2x),
                      Operation::kChangeRefOrientationFrame,
                      Side(kArgument, kOri, Field::kOrientation, ox, F),
                      Side(kSubject, kOri, Field::kRefOrientation, b, D)));
}

TEST_F(OrientationChangeRefOrientationFrame, ChecksBodyBeforeRefBody) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2b{b, F, b2, E, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(R_DC_b, R_b2b),
                      Operation::kChangeRefOrientationFrame, Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kOri, Field::kRefBody, D)));
}

TEST_F(OrientationChangeRefOrientationFrame, ChecksRefBodyBeforeCoordinateForm) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_b2b_s{b, D, b2, F, s};
  EXPECT_TRUE(
      Refused(ChangeRefOrientationFrame(R_DC_b, R_b2b_s), Operation::kChangeRefOrientationFrame,
              Side(kArgument, kOri, Field::kRefBody, F), Side(kSubject, kOri, Field::kRefBody, D)));
}

// ================================================================ Pose

TEST_F(PoseInverse, SwapsBothSidesKeepingTheCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  EXPECT_TRUE(Is(Inverse(X_DC_r), PoseSemantics{.point = f,
                                                .orientation = b,
                                                .body = D,
                                                .ref_point = e,
                                                .ref_orientation = a,
                                                .ref_body = C,
                                                .coordinate_frame = r}));
}

TEST_F(PoseInverseInNewRef, ExpressesTheInverseInTheNewReferenceFrame) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  EXPECT_TRUE(Gives(InverseInNewRef(X_DC_b), PoseSemantics{.point = f,
                                                           .orientation = b,
                                                           .body = D,
                                                           .ref_point = e,
                                                           .ref_orientation = a,
                                                           .ref_body = C,
                                                           .coordinate_frame = a}));
}

TEST_F(PoseInverseInNewRef, InvertsAnEdgeIntoAnEdge) {
  const PoseSemantics X_ba = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, b);
  EXPECT_TRUE(
      Gives(InverseInNewRef(X_ba), PoseSemantics::OfFrame(FrameOf(b), D, FrameOf(a), C, a)));
}

TEST_F(PoseInverseInNewRef, RefusesAPoseNotExpressedInItsReferenceFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  EXPECT_TRUE(Refused(InverseInNewRef(X_DC_r), Operation::kInverseInNewRef,
                      Side(kSubject, kPose, Field::kCoordinateFrame, r),
                      Side(kSubject, kPose, Field::kRefOrientation, b, D)));
}

// ---------------------------------------------------------------- Pose Compose

TEST_F(PoseCompose, UsesTheChainFormWhenEachIsInItsReferenceFrame) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_c{f, b, D, g, c, E, c};
  EXPECT_TRUE(Gives(Compose(X_DC_b, X_ED_c),
                    PoseSemantics{.point = e,
                                  .orientation = a,
                                  .body = C,
                                  .ref_point = g,
                                  .ref_orientation = c,
                                  .ref_body = E,
                                  .coordinate_frame = c},
                    kChain));
}

TEST_F(PoseCompose, UsesTheSameFrameFormWhenBothShareACoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const PoseSemantics X_ED_r{f, b, D, g, c, E, r};
  EXPECT_TRUE(Gives(Compose(X_DC_r, X_ED_r),
                    PoseSemantics{.point = e,
                                  .orientation = a,
                                  .body = C,
                                  .ref_point = g,
                                  .ref_orientation = c,
                                  .ref_body = E,
                                  .coordinate_frame = r},
                    kSameFrame));
}

TEST_F(PoseCompose, PrefersTheChainFormWhenBothFormsApply) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_b{f, b, D, g, b, E, b};
  EXPECT_TRUE(Gives(Compose(X_DC_b, X_ED_b), PoseSemantics{e, a, C, g, b, E, b}, kChain));
}

TEST_F(PoseCompose, ComposesEdgesInNaturalOrder) {
  // X_EC = Compose(X_DC, X_ED); in matrix notation X_EC = X_ED * X_DC.
  const PoseSemantics X_DC = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, b);
  const PoseSemantics X_ED = PoseSemantics::OfFrame(FrameOf(b), D, FrameOf(c), E, c);
  EXPECT_TRUE(
      Gives(Compose(X_DC, X_ED), PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(c), E, c), kChain));
}

TEST_F(PoseCompose, RefusesMatrixOrder) {
  const PoseSemantics X_DC = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, b);
  const PoseSemantics X_ED = PoseSemantics::OfFrame(FrameOf(b), D, FrameOf(c), E, c);
  EXPECT_TRUE(Refused(Compose(X_ED, X_DC), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefPoint, FrameOf(c).origin(), E),
                      Side(kSecond, kPose, Field::kPoint, FrameOf(a).origin(), C)));
}

TEST_F(PoseCompose, RefusesMismatchedRefPoint) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_c{x, b, D, g, c, E, c};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_ED_c), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefPoint, f, D),
                      Side(kSecond, kPose, Field::kPoint, x, D)));
}

TEST_F(PoseCompose, RefusesMismatchedRefOrientation) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_c{f, ox, D, g, c, E, c};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_ED_c), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefOrientation, b, D),
                      Side(kSecond, kPose, Field::kOrientation, ox, D)));
}

TEST_F(PoseCompose, RefusesMismatchedRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_EF_c{f, b, F, g, c, E, c};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_EF_c), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefBody, D),
                      Side(kSecond, kPose, Field::kBody, F)));
}

TEST_F(PoseCompose, RefusesOperandsInNeitherCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_r{f, b, D, g, c, E, r};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_ED_r), Operation::kCompose,
                      Side(kFirst, kPose, Field::kCoordinateFrame, b),
                      Side(kSecond, kPose, Field::kCoordinateFrame, r),
                      /*coordinate_forms=*/true));
}

TEST_F(PoseCompose, ChecksRefPointBeforeRefOrientation) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_ED_c{x, ox, D, g, c, E, c};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_ED_c), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefPoint, f, D),
                      Side(kSecond, kPose, Field::kPoint, x, D)));
}

TEST_F(PoseCompose, ChecksRefOrientationBeforeRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_EF_c{f, ox, F, g, c, E, c};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_EF_c), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefOrientation, b, D),
                      Side(kSecond, kPose, Field::kOrientation, ox, F)));
}

TEST_F(PoseCompose, ChecksRefBodyBeforeCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_EF_r{f, b, F, g, c, E, r};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_EF_r), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefBody, D),
                      Side(kSecond, kPose, Field::kBody, F)));
}

TEST_F(PoseCompose, ReportsTheRefPointWhenEverythingFails) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const PoseSemantics X_EF_r{x, ox, F, g, c, E, r};
  EXPECT_TRUE(Refused(Compose(X_DC_b, X_EF_r), Operation::kCompose,
                      Side(kFirst, kPose, Field::kRefPoint, f, D),
                      Side(kSecond, kPose, Field::kPoint, x, F)));
}

// ---------------------------------------------------------------- Pose ChangePoint

TEST_F(PoseChangePoint, ReplacesThePointAndKeepsTheOrientation) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2{e2, C, e, C, r};
  EXPECT_TRUE(Gives(ChangePoint(X_DC, p_ee2), PoseSemantics{.point = e2,
                                                            .orientation = a,
                                                            .body = C,
                                                            .ref_point = f,
                                                            .ref_orientation = b,
                                                            .ref_body = D,
                                                            .coordinate_frame = r}));
}

TEST_F(PoseChangePoint, RefusesAnArgumentNotRelativeToTheOldPoint) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_xe2{e2, C, x, C, r};
  EXPECT_TRUE(Refused(ChangePoint(X_DC, p_xe2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefPoint, x, C),
                      Side(kSubject, kPose, Field::kPoint, e, C)));
}

TEST_F(PoseChangePoint, RefusesAnArgumentWhoseRefBodyIsNotTheBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2{e2, C, e, F, r};
  EXPECT_TRUE(Refused(ChangePoint(X_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangePoint, RefusesAnArgumentWhoseBodyIsNotTheBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2{e2, F, e, C, r};
  EXPECT_TRUE(Refused(ChangePoint(X_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangePoint, RefusesAnArgumentInAnotherCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2_s{e2, C, e, C, s};
  EXPECT_TRUE(Refused(ChangePoint(X_DC_r, p_ee2_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kPose, Field::kCoordinateFrame, r)));
}

TEST_F(PoseChangePoint, ChecksRefPointBeforeRefBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_xe2{e2, C, x, F, r};
  EXPECT_TRUE(Refused(ChangePoint(X_DC, p_xe2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefPoint, x, F),
                      Side(kSubject, kPose, Field::kPoint, e, C)));
}

TEST_F(PoseChangePoint, ChecksRefBodyBeforeBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2{e2, E, e, F, r};
  EXPECT_TRUE(Refused(ChangePoint(X_DC, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangePoint, ChecksBodyBeforeCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const PositionSemantics p_ee2_s{e2, F, e, C, s};
  EXPECT_TRUE(Refused(ChangePoint(X_DC_r, p_ee2_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

// ---------------------------------------------------------------- Pose ChangeRefPoint

TEST_F(PoseChangeRefPoint, ReplacesTheRefPointAndKeepsTheOrientation) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f{f, D, f2, D, r};
  EXPECT_TRUE(Gives(ChangeRefPoint(X_DC, p_f2f), PoseSemantics{.point = e,
                                                               .orientation = a,
                                                               .body = C,
                                                               .ref_point = f2,
                                                               .ref_orientation = b,
                                                               .ref_body = D,
                                                               .coordinate_frame = r}));
}

TEST_F(PoseChangeRefPoint, RefusesAnArgumentNotOfTheOldRefPoint) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2x{x, D, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC, p_f2x), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kPoint, x, D),
                      Side(kSubject, kPose, Field::kRefPoint, f, D)));
}

TEST_F(PoseChangeRefPoint, RefusesAnArgumentWhoseBodyIsNotTheRefBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f{f, F, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefPoint, RefusesAnArgumentWhoseRefBodyIsNotTheRefBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f{f, D, f2, F, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefPoint, RefusesAnArgumentInAnotherCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f_s{f, D, f2, D, s};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC_r, p_f2f_s), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kPose, Field::kCoordinateFrame, r)));
}

TEST_F(PoseChangeRefPoint, ChecksPointBeforeBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2x{x, F, f2, D, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC, p_f2x), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kPoint, x, F),
                      Side(kSubject, kPose, Field::kRefPoint, f, D)));
}

TEST_F(PoseChangeRefPoint, ChecksBodyBeforeRefBody) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f{f, F, f2, E, r};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC, p_f2f), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefPoint, ChecksRefBodyBeforeCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const PositionSemantics p_f2f_s{f, D, f2, F, s};
  EXPECT_TRUE(Refused(ChangeRefPoint(X_DC_r, p_f2f_s), Operation::kChangeRefPoint,
                      Side(kArgument, kPos, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

// ---------------------------------------------------------- Pose ChangeOrientationFrame

TEST_F(PoseChangeOrientationFrame, UsesTheChainFormAndKeepsThePosition) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_a{a2, C, a, C, a};
  EXPECT_TRUE(Gives(ChangeOrientationFrame(X_DC_b, R_aa2_a),
                    PoseSemantics{.point = e,
                                  .orientation = a2,
                                  .body = C,
                                  .ref_point = f,
                                  .ref_orientation = b,
                                  .ref_body = D,
                                  .coordinate_frame = b},
                    kChain));
}

TEST_F(PoseChangeOrientationFrame, UsesTheSameFrameForm) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const OrientationSemantics R_aa2_r{a2, C, a, C, r};
  EXPECT_TRUE(Gives(ChangeOrientationFrame(X_DC_r, R_aa2_r),
                    PoseSemantics{.point = e,
                                  .orientation = a2,
                                  .body = C,
                                  .ref_point = f,
                                  .ref_orientation = b,
                                  .ref_body = D,
                                  .coordinate_frame = r},
                    kSameFrame));
}

TEST_F(PoseChangeOrientationFrame, RefusesAnArgumentNotRelativeToTheOldFrame) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_xa2{a2, C, ox, C, ox};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_xa2), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefOrientation, ox, C),
                      Side(kSubject, kPose, Field::kOrientation, a, C)));
}

TEST_F(PoseChangeOrientationFrame, RefusesAnArgumentWhoseRefBodyIsNotTheBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_a{a2, C, a, F, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangeOrientationFrame, RefusesAnArgumentWhoseBodyIsNotTheBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_a{a2, F, a, C, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangeOrientationFrame, RefusesOperandsInNeitherCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_s{a2, C, a, C, s};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_aa2_s), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kCoordinateFrame, s),
                      Side(kSubject, kPose, Field::kCoordinateFrame, b),
                      /*coordinate_forms=*/true));
}

TEST_F(PoseChangeOrientationFrame, ChecksRefOrientationBeforeRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_xa2{a2, C, ox, F, ox};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_xa2), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefOrientation, ox, F),
                      Side(kSubject, kPose, Field::kOrientation, a, C)));
}

TEST_F(PoseChangeOrientationFrame, ChecksRefBodyBeforeBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_a{a2, E, a, F, a};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_aa2_a), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kRefBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

TEST_F(PoseChangeOrientationFrame, ChecksBodyBeforeCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_aa2_s{a2, F, a, C, s};
  EXPECT_TRUE(Refused(ChangeOrientationFrame(X_DC_b, R_aa2_s), Operation::kChangeOrientationFrame,
                      Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kPose, Field::kBody, C)));
}

// ------------------------------------------------------- Pose ChangeRefOrientationFrame

TEST_F(PoseChangeRefOrientationFrame, UsesTheChainFormAndReexpressesInTheNewRefFrame) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b_b2{b, D, b2, D, b2};
  EXPECT_TRUE(Gives(ChangeRefOrientationFrame(X_DC_b, R_b2b_b2),
                    PoseSemantics{.point = e,
                                  .orientation = a,
                                  .body = C,
                                  .ref_point = f,
                                  .ref_orientation = b2,
                                  .ref_body = D,
                                  .coordinate_frame = b2},
                    kChain));
}

TEST_F(PoseChangeRefOrientationFrame, UsesTheSameFrameFormAndKeepsTheCoordinateFrame) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  const OrientationSemantics R_b2b_r{b, D, b2, D, r};
  EXPECT_TRUE(Gives(ChangeRefOrientationFrame(X_DC_r, R_b2b_r),
                    PoseSemantics{.point = e,
                                  .orientation = a,
                                  .body = C,
                                  .ref_point = f,
                                  .ref_orientation = b2,
                                  .ref_body = D,
                                  .coordinate_frame = r},
                    kSameFrame));
}

TEST_F(PoseChangeRefOrientationFrame, RefusesAnArgumentNotOfTheOldRefFrame) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2x{ox, D, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(X_DC_b, R_b2x),
                      Operation::kChangeRefOrientationFrame,
                      Side(kArgument, kOri, Field::kOrientation, ox, D),
                      Side(kSubject, kPose, Field::kRefOrientation, b, D)));
}

TEST_F(PoseChangeRefOrientationFrame, RefusesAnArgumentWhoseBodyIsNotTheRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b{b, F, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(X_DC_b, R_b2b),
                      Operation::kChangeRefOrientationFrame, Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefOrientationFrame, RefusesAnArgumentWhoseRefBodyIsNotTheRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b{b, D, b2, F, b2};
  EXPECT_TRUE(Refused(
      ChangeRefOrientationFrame(X_DC_b, R_b2b), Operation::kChangeRefOrientationFrame,
      Side(kArgument, kOri, Field::kRefBody, F), Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefOrientationFrame, RefusesOperandsInNeitherCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b_s{b, D, b2, D, s};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(X_DC_b, R_b2b_s),
                      Operation::kChangeRefOrientationFrame,
                      Side(kSubject, kPose, Field::kCoordinateFrame, b),
                      Side(kArgument, kOri, Field::kCoordinateFrame, s),
                      /*coordinate_forms=*/true));
}

TEST_F(PoseChangeRefOrientationFrame, ChecksOrientationBeforeBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2x{ox, F, b2, D, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(X_DC_b, R_b2x),
                      Operation::kChangeRefOrientationFrame,
                      Side(kArgument, kOri, Field::kOrientation, ox, F),
                      Side(kSubject, kPose, Field::kRefOrientation, b, D)));
}

TEST_F(PoseChangeRefOrientationFrame, ChecksBodyBeforeRefBody) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b{b, F, b2, E, b2};
  EXPECT_TRUE(Refused(ChangeRefOrientationFrame(X_DC_b, R_b2b),
                      Operation::kChangeRefOrientationFrame, Side(kArgument, kOri, Field::kBody, F),
                      Side(kSubject, kPose, Field::kRefBody, D)));
}

TEST_F(PoseChangeRefOrientationFrame, ChecksRefBodyBeforeCoordinateForm) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_b2b_s{b, D, b2, F, s};
  EXPECT_TRUE(Refused(
      ChangeRefOrientationFrame(X_DC_b, R_b2b_s), Operation::kChangeRefOrientationFrame,
      Side(kArgument, kOri, Field::kRefBody, F), Side(kSubject, kPose, Field::kRefBody, D)));
}

// ---------------------------------------------------------------- Pose parts and Combine

TEST_F(PoseParts, PositionOfKeepsPointsBodiesAndCoordinateFrame) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  EXPECT_TRUE(Is(PositionOf(X_DC),
                 PositionSemantics{
                     .point = e, .body = C, .ref_point = f, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(PoseParts, OrientationOfKeepsFramesBodiesAndCoordinateFrame) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  EXPECT_TRUE(Is(OrientationOf(X_DC), OrientationSemantics{.orientation = a,
                                                           .body = C,
                                                           .ref_orientation = b,
                                                           .ref_body = D,
                                                           .coordinate_frame = r}));
}

TEST_F(PoseCombine, JoinsAPositionAndAnOrientation) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const OrientationSemantics R_DC{a, C, b, D, r};
  EXPECT_TRUE(Gives(Combine(p_DC, R_DC), PoseSemantics{.point = e,
                                                       .orientation = a,
                                                       .body = C,
                                                       .ref_point = f,
                                                       .ref_orientation = b,
                                                       .ref_body = D,
                                                       .coordinate_frame = r}));
}

TEST_F(PoseCombine, UndoesTakingTheParts) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  EXPECT_TRUE(Gives(Combine(PositionOf(X_DC), OrientationOf(X_DC)), X_DC));
}

TEST_F(PoseCombine, RefusesDifferentBodies) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const OrientationSemantics R_DF{a, F, b, D, r};
  EXPECT_TRUE(Refused(Combine(p_DC, R_DF), Operation::kCombine, Side(kFirst, kPos, Field::kBody, C),
                      Side(kSecond, kOri, Field::kBody, F)));
}

TEST_F(PoseCombine, RefusesDifferentRefBodies) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const OrientationSemantics R_FC{a, C, b, F, r};
  EXPECT_TRUE(Refused(Combine(p_DC, R_FC), Operation::kCombine,
                      Side(kFirst, kPos, Field::kRefBody, D),
                      Side(kSecond, kOri, Field::kRefBody, F)));
}

TEST_F(PoseCombine, RefusesDifferentCoordinateFrames) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const OrientationSemantics R_DC_s{a, C, b, D, s};
  EXPECT_TRUE(Refused(Combine(p_DC_r, R_DC_s), Operation::kCombine,
                      Side(kFirst, kPos, Field::kCoordinateFrame, r),
                      Side(kSecond, kOri, Field::kCoordinateFrame, s)));
}

TEST_F(PoseCombine, ChecksBodyBeforeRefBody) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const OrientationSemantics R_FE{a, E, b, F, r};
  EXPECT_TRUE(Refused(Combine(p_DC, R_FE), Operation::kCombine, Side(kFirst, kPos, Field::kBody, C),
                      Side(kSecond, kOri, Field::kBody, E)));
}

TEST_F(PoseCombine, ChecksRefBodyBeforeCoordinateFrame) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const OrientationSemantics R_FC_s{a, C, b, F, s};
  EXPECT_TRUE(Refused(Combine(p_DC_r, R_FC_s), Operation::kCombine,
                      Side(kFirst, kPos, Field::kRefBody, D),
                      Side(kSecond, kOri, Field::kRefBody, F)));
}

// ================================================================ Linear velocity

TEST_F(LinearVelocityInverse, KeepsThePointAndSwapsTheBodies) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  EXPECT_TRUE(Is(Inverse(v_DCe), LinearVelocitySemantics{
                                     .point = e, .body = D, .ref_body = C, .coordinate_frame = r}));
}

TEST_F(LinearVelocityCompose, ChainsBodiesAtOnePoint) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const LinearVelocitySemantics v_EDe{e, D, E, r};  // e|D: the point of D at e
  EXPECT_TRUE(
      Gives(Compose(v_DCe, v_EDe),
            LinearVelocitySemantics{.point = e, .body = C, .ref_body = E, .coordinate_frame = r}));
}

TEST_F(LinearVelocityCompose, RefusesDifferentPoints) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const LinearVelocitySemantics v_EDx{x, D, E, r};
  EXPECT_TRUE(Refused(Compose(v_DCe, v_EDx), Operation::kCompose,
                      Side(kFirst, kLin, Field::kPoint, e, C),
                      Side(kSecond, kLin, Field::kPoint, x, D)));
}

TEST_F(LinearVelocityCompose, RefusesMismatchedRefBody) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const LinearVelocitySemantics v_EFe{e, F, E, r};
  EXPECT_TRUE(Refused(Compose(v_DCe, v_EFe), Operation::kCompose,
                      Side(kFirst, kLin, Field::kRefBody, D),
                      Side(kSecond, kLin, Field::kBody, F)));
}

TEST_F(LinearVelocityCompose, RefusesMismatchedCoordinateFrames) {
  const LinearVelocitySemantics v_DCe_r{e, C, D, r};
  const LinearVelocitySemantics v_EDe_s{e, D, E, s};
  EXPECT_TRUE(Refused(Compose(v_DCe_r, v_EDe_s), Operation::kCompose,
                      Side(kFirst, kLin, Field::kCoordinateFrame, r),
                      Side(kSecond, kLin, Field::kCoordinateFrame, s)));
}

TEST_F(LinearVelocityCompose, ChecksPointBeforeRefBody) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const LinearVelocitySemantics v_EFx{x, F, E, r};
  EXPECT_TRUE(Refused(Compose(v_DCe, v_EFx), Operation::kCompose,
                      Side(kFirst, kLin, Field::kPoint, e, C),
                      Side(kSecond, kLin, Field::kPoint, x, F)));
}

TEST_F(LinearVelocityCompose, ChecksRefBodyBeforeCoordinateFrame) {
  const LinearVelocitySemantics v_DCe_r{e, C, D, r};
  const LinearVelocitySemantics v_EFe_s{e, F, E, s};
  EXPECT_TRUE(Refused(Compose(v_DCe_r, v_EFe_s), Operation::kCompose,
                      Side(kFirst, kLin, Field::kRefBody, D),
                      Side(kSecond, kLin, Field::kBody, F)));
}

// ================================================================ Angular velocity

TEST_F(AngularVelocityInverse, SwapsTheBodies) {
  const AngularVelocitySemantics w_DC{C, D, r};
  EXPECT_TRUE(
      Is(Inverse(w_DC), AngularVelocitySemantics{.body = D, .ref_body = C, .coordinate_frame = r}));
}

TEST_F(AngularVelocityCompose, ChainsBodies) {
  const AngularVelocitySemantics w_DC{C, D, r};
  const AngularVelocitySemantics w_ED{D, E, r};
  EXPECT_TRUE(Gives(Compose(w_DC, w_ED),
                    AngularVelocitySemantics{.body = C, .ref_body = E, .coordinate_frame = r}));
}

TEST_F(AngularVelocityCompose, RefusesMismatchedRefBody) {
  const AngularVelocitySemantics w_DC{C, D, r};
  const AngularVelocitySemantics w_EF{F, E, r};
  EXPECT_TRUE(Refused(Compose(w_DC, w_EF), Operation::kCompose,
                      Side(kFirst, kAng, Field::kRefBody, D),
                      Side(kSecond, kAng, Field::kBody, F)));
}

TEST_F(AngularVelocityCompose, RefusesMismatchedCoordinateFrames) {
  const AngularVelocitySemantics w_DC_r{C, D, r};
  const AngularVelocitySemantics w_ED_s{D, E, s};
  EXPECT_TRUE(Refused(Compose(w_DC_r, w_ED_s), Operation::kCompose,
                      Side(kFirst, kAng, Field::kCoordinateFrame, r),
                      Side(kSecond, kAng, Field::kCoordinateFrame, s)));
}

TEST_F(AngularVelocityCompose, ChecksRefBodyBeforeCoordinateFrame) {
  const AngularVelocitySemantics w_DC_r{C, D, r};
  const AngularVelocitySemantics w_EF_s{F, E, s};
  EXPECT_TRUE(Refused(Compose(w_DC_r, w_EF_s), Operation::kCompose,
                      Side(kFirst, kAng, Field::kRefBody, D),
                      Side(kSecond, kAng, Field::kBody, F)));
}

// ================================================================ Twist

TEST_F(TwistInverse, KeepsThePointAndSwapsTheBodies) {
  const TwistSemantics V_DCe{e, C, D, r};
  EXPECT_TRUE(Is(Inverse(V_DCe),
                 TwistSemantics{.point = e, .body = D, .ref_body = C, .coordinate_frame = r}));
}

TEST_F(TwistCompose, ChainsBodiesAtOnePoint) {
  const TwistSemantics V_DCe{e, C, D, r};
  const TwistSemantics V_EDe{e, D, E, r};
  EXPECT_TRUE(Gives(Compose(V_DCe, V_EDe),
                    TwistSemantics{.point = e, .body = C, .ref_body = E, .coordinate_frame = r}));
}

TEST_F(TwistCompose, RefusesDifferentPoints) {
  const TwistSemantics V_DCe{e, C, D, r};
  const TwistSemantics V_EDx{x, D, E, r};
  EXPECT_TRUE(Refused(Compose(V_DCe, V_EDx), Operation::kCompose,
                      Side(kFirst, kTwist, Field::kPoint, e, C),
                      Side(kSecond, kTwist, Field::kPoint, x, D)));
}

TEST_F(TwistCompose, RefusesMismatchedRefBody) {
  const TwistSemantics V_DCe{e, C, D, r};
  const TwistSemantics V_EFe{e, F, E, r};
  EXPECT_TRUE(Refused(Compose(V_DCe, V_EFe), Operation::kCompose,
                      Side(kFirst, kTwist, Field::kRefBody, D),
                      Side(kSecond, kTwist, Field::kBody, F)));
}

TEST_F(TwistCompose, RefusesMismatchedCoordinateFrames) {
  const TwistSemantics V_DCe_r{e, C, D, r};
  const TwistSemantics V_EDe_s{e, D, E, s};
  EXPECT_TRUE(Refused(Compose(V_DCe_r, V_EDe_s), Operation::kCompose,
                      Side(kFirst, kTwist, Field::kCoordinateFrame, r),
                      Side(kSecond, kTwist, Field::kCoordinateFrame, s)));
}

TEST_F(TwistCompose, ChecksPointBeforeRefBody) {
  const TwistSemantics V_DCe{e, C, D, r};
  const TwistSemantics V_EFx{x, F, E, r};
  EXPECT_TRUE(Refused(Compose(V_DCe, V_EFx), Operation::kCompose,
                      Side(kFirst, kTwist, Field::kPoint, e, C),
                      Side(kSecond, kTwist, Field::kPoint, x, F)));
}

TEST_F(TwistCompose, ChecksRefBodyBeforeCoordinateFrame) {
  const TwistSemantics V_DCe_r{e, C, D, r};
  const TwistSemantics V_EFe_s{e, F, E, s};
  EXPECT_TRUE(Refused(Compose(V_DCe_r, V_EFe_s), Operation::kCompose,
                      Side(kFirst, kTwist, Field::kRefBody, D),
                      Side(kSecond, kTwist, Field::kBody, F)));
}

// ---------------------------------------------------------------- Twist ChangePoint

TEST_F(TwistChangePoint, MovesTheReferencePointToTheArgumentsRefPoint) {
  const TwistSemantics V_DCe{e, C, D, r};
  const PositionSemantics p_e2e{e, C, e2, C, r};  // old point e wrt new point e2
  EXPECT_TRUE(Gives(ChangePoint(V_DCe, p_e2e),
                    TwistSemantics{.point = e2, .body = C, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(TwistChangePoint, DoesNotCheckTheBodiesOfThePosition) {
  // D3: the vector from g to e at this instant is the same whichever bodies e and g are fixed
  // to; the result's point g is read as the point of C coinciding with g.
  const TwistSemantics V_DCe{e, C, D, r};
  const PositionSemantics p_ge{e, E, g, F, r};
  EXPECT_TRUE(Gives(ChangePoint(V_DCe, p_ge),
                    TwistSemantics{.point = g, .body = C, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(TwistChangePoint, RefusesAnArgumentNotOfTheOldPoint) {
  // Also what happens when the argument is given the wrong way round (new wrt old).
  const TwistSemantics V_DCe{e, C, D, r};
  const PositionSemantics p_ee2{e2, C, e, C, r};
  EXPECT_TRUE(Refused(ChangePoint(V_DCe, p_ee2), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kPoint, e2, C),
                      Side(kSubject, kTwist, Field::kPoint, e, C)));
}

TEST_F(TwistChangePoint, RefusesAnArgumentInAnotherCoordinateFrame) {
  const TwistSemantics V_DCe_r{e, C, D, r};
  const PositionSemantics p_e2e_s{e, C, e2, C, s};
  EXPECT_TRUE(Refused(ChangePoint(V_DCe_r, p_e2e_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kCoordinateFrame, s),
                      Side(kSubject, kTwist, Field::kCoordinateFrame, r)));
}

TEST_F(TwistChangePoint, ChecksPointBeforeCoordinateFrame) {
  const TwistSemantics V_DCe_r{e, C, D, r};
  const PositionSemantics p_e2x_s{x, C, e2, C, s};
  EXPECT_TRUE(Refused(ChangePoint(V_DCe_r, p_e2x_s), Operation::kChangePoint,
                      Side(kArgument, kPos, Field::kPoint, x, C),
                      Side(kSubject, kTwist, Field::kPoint, e, C)));
}

// ---------------------------------------------------------------- Twist ScrewTransform

TEST_F(TwistScrewTransform, MovesAScrewTwistAlongAnEdge) {
  // Pose-twist constraint (paper, example 3): TwistCoord(a|C, D, [a]) by PoseCoord({a}|C,
  // {b}|C, [b]) gives TwistCoord(b|C, D, [b]).
  const TwistSemantics V_DCa_a{FrameOf(a).origin(), C, D, a};
  const PoseSemantics X_ba = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), C, b);
  EXPECT_TRUE(
      Gives(ScrewTransform(V_DCa_a, X_ba),
            TwistSemantics{
                .point = FrameOf(b).origin(), .body = C, .ref_body = D, .coordinate_frame = b}));
}

TEST_F(TwistScrewTransform, AcceptsAnyPoseExpressedInItsReferenceFrame) {
  // D7: point e and orientation [a] need not be one frame.
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ea{e, a, C, f, b, C, b};
  EXPECT_TRUE(Gives(ScrewTransform(V_DCe_a, X_fb_ea),
                    TwistSemantics{.point = f, .body = C, .ref_body = D, .coordinate_frame = b}));
}

TEST_F(TwistScrewTransform, DoesNotCheckTheBodiesOfThePose) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ea{e, a, E, f, b, F, b};
  EXPECT_TRUE(Gives(ScrewTransform(V_DCe_a, X_fb_ea), TwistSemantics{f, C, D, b}));
}

TEST_F(TwistScrewTransform, RefusesAPoseOfAnotherPoint) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_xa{x, a, C, f, b, C, b};
  EXPECT_TRUE(Refused(ScrewTransform(V_DCe_a, X_fb_xa), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kPoint, x, C),
                      Side(kSubject, kTwist, Field::kPoint, e, C)));
}

TEST_F(TwistScrewTransform, RefusesAPoseWhoseOrientationIsNotTheTwistsCoordinateFrame) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ex{e, ox, C, f, b, C, b};
  EXPECT_TRUE(Refused(ScrewTransform(V_DCe_a, X_fb_ex), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kOrientation, ox, C),
                      Side(kSubject, kTwist, Field::kCoordinateFrame, a)));
}

TEST_F(TwistScrewTransform, RefusesAPoseNotExpressedInItsReferenceFrame) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ea_r{e, a, C, f, b, C, r};
  EXPECT_TRUE(Refused(ScrewTransform(V_DCe_a, X_fb_ea_r), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kCoordinateFrame, r),
                      Side(kArgument, kPose, Field::kRefOrientation, b, C)));
}

TEST_F(TwistScrewTransform, ChecksPointBeforeOrientation) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_xx{x, ox, C, f, b, C, b};
  EXPECT_TRUE(Refused(ScrewTransform(V_DCe_a, X_fb_xx), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kPoint, x, C),
                      Side(kSubject, kTwist, Field::kPoint, e, C)));
}

TEST_F(TwistScrewTransform, ChecksOrientationBeforeThePosesCoordinateFrame) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ex_r{e, ox, C, f, b, C, r};
  EXPECT_TRUE(Refused(ScrewTransform(V_DCe_a, X_fb_ex_r), Operation::kScrewTransform,
                      Side(kArgument, kPose, Field::kOrientation, ox, C),
                      Side(kSubject, kTwist, Field::kCoordinateFrame, a)));
}

// ---------------------------------------------------------------- Twist parts and Combine

TEST_F(TwistParts, LinearOfKeepsPointBodiesAndCoordinateFrame) {
  const TwistSemantics V_DCe{e, C, D, r};
  EXPECT_TRUE(
      Is(LinearOf(V_DCe),
         LinearVelocitySemantics{.point = e, .body = C, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(TwistParts, AngularOfKeepsBodiesAndCoordinateFrame) {
  const TwistSemantics V_DCe{e, C, D, r};
  EXPECT_TRUE(Is(AngularOf(V_DCe),
                 AngularVelocitySemantics{.body = C, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(TwistCombine, JoinsALinearAndAnAngularVelocity) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const AngularVelocitySemantics w_DC{C, D, r};
  EXPECT_TRUE(Gives(Combine(v_DCe, w_DC),
                    TwistSemantics{.point = e, .body = C, .ref_body = D, .coordinate_frame = r}));
}

TEST_F(TwistCombine, UndoesTakingTheParts) {
  const TwistSemantics V_DCe{e, C, D, r};
  EXPECT_TRUE(Gives(Combine(LinearOf(V_DCe), AngularOf(V_DCe)), V_DCe));
}

TEST_F(TwistCombine, RefusesDifferentBodies) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const AngularVelocitySemantics w_DF{F, D, r};
  EXPECT_TRUE(Refused(Combine(v_DCe, w_DF), Operation::kCombine,
                      Side(kFirst, kLin, Field::kBody, C), Side(kSecond, kAng, Field::kBody, F)));
}

TEST_F(TwistCombine, RefusesDifferentRefBodies) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const AngularVelocitySemantics w_FC{C, F, r};
  EXPECT_TRUE(Refused(Combine(v_DCe, w_FC), Operation::kCombine,
                      Side(kFirst, kLin, Field::kRefBody, D),
                      Side(kSecond, kAng, Field::kRefBody, F)));
}

TEST_F(TwistCombine, RefusesDifferentCoordinateFrames) {
  const LinearVelocitySemantics v_DCe_r{e, C, D, r};
  const AngularVelocitySemantics w_DC_s{C, D, s};
  EXPECT_TRUE(Refused(Combine(v_DCe_r, w_DC_s), Operation::kCombine,
                      Side(kFirst, kLin, Field::kCoordinateFrame, r),
                      Side(kSecond, kAng, Field::kCoordinateFrame, s)));
}

TEST_F(TwistCombine, ChecksBodyBeforeRefBody) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const AngularVelocitySemantics w_FE{E, F, r};
  EXPECT_TRUE(Refused(Combine(v_DCe, w_FE), Operation::kCombine,
                      Side(kFirst, kLin, Field::kBody, C), Side(kSecond, kAng, Field::kBody, E)));
}

TEST_F(TwistCombine, ChecksRefBodyBeforeCoordinateFrame) {
  const LinearVelocitySemantics v_DCe_r{e, C, D, r};
  const AngularVelocitySemantics w_FC_s{C, F, s};
  EXPECT_TRUE(Refused(Combine(v_DCe_r, w_FC_s), Operation::kCombine,
                      Side(kFirst, kLin, Field::kRefBody, D),
                      Side(kSecond, kAng, Field::kRefBody, F)));
}

// ================================================================ Every relation kind

// ChangeCoordinateFrame and Inverse exist for all six relations: one typed suite.
template <class S>
class EveryRelation : public Semantics {};

struct RelationName {
  template <class S>
  static std::string GetName(int) {
    if constexpr (std::is_same_v<S, PositionSemantics>)
      return "Position";
    else if constexpr (std::is_same_v<S, OrientationSemantics>)
      return "Orientation";
    else if constexpr (std::is_same_v<S, PoseSemantics>)
      return "Pose";
    else if constexpr (std::is_same_v<S, LinearVelocitySemantics>)
      return "LinearVelocity";
    else if constexpr (std::is_same_v<S, AngularVelocitySemantics>)
      return "AngularVelocity";
    else
      return "Twist";
  }
};

using AllRelations =
    ::testing::Types<PositionSemantics, OrientationSemantics, PoseSemantics,
                     LinearVelocitySemantics, AngularVelocitySemantics, TwistSemantics>;
TYPED_TEST_SUITE(EveryRelation, AllRelations, RelationName);

TYPED_TEST(EveryRelation, InverseIsAnInvolution) {
  const TypeParam X = this->template Sample<TypeParam>(this->r);
  EXPECT_TRUE(this->Is(Inverse(Inverse(X)), X));
  static_assert(noexcept(Inverse(X)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameAcceptsAnArgumentExpressedInTheOldFrame) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sr_r{this->r, this->D, this->s, this->E, this->r};
  EXPECT_TRUE(
      this->Gives(ChangeCoordinateFrame(X_r, R_sr_r), this->template Sample<TypeParam>(this->s)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameAcceptsAnArgumentExpressedInTheNewFrame) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sr_s{this->r, this->D, this->s, this->E, this->s};
  EXPECT_TRUE(
      this->Gives(ChangeCoordinateFrame(X_r, R_sr_s), this->template Sample<TypeParam>(this->s)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameDoesNotCheckTheArgumentBodies) {
  // D4: a coordinate frame carries no body.
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sr_s{this->r, this->F, this->s, this->F, this->s};
  EXPECT_TRUE(
      this->Gives(ChangeCoordinateFrame(X_r, R_sr_s), this->template Sample<TypeParam>(this->s)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameAcceptsTheIdentity) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_rr_r{this->r, this->C, this->r, this->C, this->r};
  EXPECT_TRUE(this->Gives(ChangeCoordinateFrame(X_r, R_rr_r), X_r));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameRefusesAnArgumentNotOfTheOldFrame) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sx_s{this->ox, this->D, this->s, this->E, this->s};
  EXPECT_TRUE(
      this->Refused(ChangeCoordinateFrame(X_r, R_sx_s), Operation::kChangeCoordinateFrame,
                    this->Side(kArgument, kOri, Field::kOrientation, this->ox, this->D),
                    this->Side(kSubject, kKindOf<TypeParam>, Field::kCoordinateFrame, this->r)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameRefusesAnArgumentExpressedInAThirdFrame) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sr_c{this->r, this->D, this->s, this->E, this->c};
  EXPECT_TRUE(this->Refused(ChangeCoordinateFrame(X_r, R_sr_c), Operation::kChangeCoordinateFrame,
                            this->Side(kArgument, kOri, Field::kCoordinateFrame, this->c),
                            this->Side(kArgument, kOri, Field::kRefOrientation, this->s, this->E)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameChecksTheOrientationBeforeTheArgumentFrame) {
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_sx_c{this->ox, this->D, this->s, this->E, this->c};
  EXPECT_TRUE(
      this->Refused(ChangeCoordinateFrame(X_r, R_sx_c), Operation::kChangeCoordinateFrame,
                    this->Side(kArgument, kOri, Field::kOrientation, this->ox, this->D),
                    this->Side(kSubject, kKindOf<TypeParam>, Field::kCoordinateFrame, this->r)));
}

TYPED_TEST(EveryRelation, ChangeCoordinateFrameRefusesTheArgumentTheWrongWayRound) {
  // [s] wrt [r] given where [r] wrt [s] is needed: its orientation is not the old frame.
  const TypeParam X_r = this->template Sample<TypeParam>(this->r);
  const OrientationSemantics R_rs_r{this->s, this->D, this->r, this->E, this->r};
  EXPECT_TRUE(
      this->Refused(ChangeCoordinateFrame(X_r, R_rs_r), Operation::kChangeCoordinateFrame,
                    this->Side(kArgument, kOri, Field::kOrientation, this->s, this->D),
                    this->Side(kSubject, kKindOf<TypeParam>, Field::kCoordinateFrame, this->r)));
}

// ================================================================ Forms and values

TEST_F(RelationForms, OfFrameUsesTheFrameNameForPointAndOrientation) {
  const PoseSemantics X_ba = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, r);
  EXPECT_TRUE(Is(X_ba, PoseSemantics{.point = Point(a.id()),
                                     .orientation = a,
                                     .body = C,
                                     .ref_point = Point(b.id()),
                                     .ref_orientation = b,
                                     .ref_body = D,
                                     .coordinate_frame = r}));
  EXPECT_TRUE(X_ba.is_frame_form());
  EXPECT_FALSE(X_ba.is_edge_form());
}

TEST_F(RelationForms, EdgeFormIsTheFrameFormExpressedInTheReferenceFrame) {
  EXPECT_TRUE(PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, b).is_edge_form());
  EXPECT_FALSE(PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, a).is_edge_form());
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  EXPECT_FALSE(X_DC_b.is_frame_form());
  EXPECT_FALSE(X_DC_b.is_edge_form());
}

TEST_F(RelationForms, ScrewTwistIsAtTheOriginOfItsCoordinateFrame) {
  EXPECT_TRUE((TwistSemantics{FrameOf(a).origin(), C, D, a}.is_screw_twist()));
  EXPECT_FALSE((TwistSemantics{FrameOf(a).origin(), C, D, b}.is_screw_twist()));
  EXPECT_FALSE((TwistSemantics{e, C, D, a}.is_screw_twist()));
}

TEST_F(RelationForms, ResultsAndMismatchesAreSmallValues) {
  static_assert(std::is_trivially_copyable_v<Mismatch>);
  static_assert(sizeof(Mismatch) <= 32);
  static_assert(std::is_trivially_copyable_v<PoseSemantics>);
  static_assert(std::is_trivially_copyable_v<Composition<PoseSemantics>>);
  static_assert(Mismatch{}.code == ErrorCode::kSemanticMismatch);
  const PoseSemantics X{e, a, C, f, b, D, b};
  const OrientationSemantics R{a, C, b, D, b};
  const PositionSemantics p{e, C, f, D, b};
  const TwistSemantics V{e, C, D, a};
  static_assert(noexcept(Compose(X, X)));
  static_assert(noexcept(InverseInNewRef(X)));
  static_assert(noexcept(ChangePoint(X, p)));
  static_assert(noexcept(ChangeRefPoint(X, p)));
  static_assert(noexcept(ChangeOrientationFrame(X, R)));
  static_assert(noexcept(ChangeRefOrientationFrame(X, R)));
  static_assert(noexcept(ChangeCoordinateFrame(X, R)));
  static_assert(noexcept(ChangePoint(V, p)));
  static_assert(noexcept(ScrewTransform(V, X)));
  static_assert(noexcept(Combine(p, R)));
  SUCCEED();
}

}  // namespace
}  // namespace semgraph::semantics
