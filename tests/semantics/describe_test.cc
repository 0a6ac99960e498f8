// Tests for semgraph/semantics/describe.h: the exact text of every semantics in the paper's
// notation and of the Mismatch messages the operations produce.
#include "semgraph/semantics/describe.h"

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "semgraph/semantics/dynamics_operations.h"
#include "semgraph/semantics/operations.h"

namespace semgraph::semantics {
namespace {

// C, D, E: bodies; F: a body no valid operand mentions.
// e, e2 on C; f on D; g on D (second operand of a compose); x: points.
// [a] on C; [b] on D; [c] on E; [x]: orientation frames; [r], [s]: coordinate frames.
// Variables are Drake monograms over bodies (p_DC: position of C's point relative to D's
// point), or over points/frames for relations inside one body (p_ee2: e2 relative to e).
class Describing : public ::testing::Test {
 protected:
  NameTable names_;
  const Body C = Intern<Body>("C"), D = Intern<Body>("D"), E = Intern<Body>("E"),
             F = Intern<Body>("F");
  const Point e = Intern<Point>("e"), e2 = Intern<Point>("e2"), f = Intern<Point>("f"),
              g = Intern<Point>("g"), x = Intern<Point>("x");
  const OrientationFrame a = Intern<OrientationFrame>("a"), b = Intern<OrientationFrame>("b"),
                         c = Intern<OrientationFrame>("c"), ox = Intern<OrientationFrame>("x"),
                         r = Intern<OrientationFrame>("r"), s = Intern<OrientationFrame>("s");

  template <class P>
  P Intern(std::string_view name) {
    return P(*names_.Intern(name));
  }
  static Frame FrameOf(OrientationFrame o) { return Frame(o.id()); }

  /// The message of a refused operation ("<accepted>" if it was not refused).
  template <class T>
  std::string Message(const Checked<T>& result) const {
    return result.has_value() ? "<accepted>" : Describe(result.error(), names_);
  }
};

class DescribeSemantics : public Describing {};
class DescribeMismatch : public Describing {};

// ================================================================ Semantics

TEST_F(DescribeSemantics, WritesAPositionInThePapersNotation) {
  const PositionSemantics p_DC{e, C, f, D, r};
  EXPECT_EQ(Describe(p_DC, names_), "PositionCoord(e|C, f|D, [r])");
}

TEST_F(DescribeSemantics, WritesAnOrientationInThePapersNotation) {
  const OrientationSemantics R_DC{a, C, b, D, r};
  EXPECT_EQ(Describe(R_DC, names_), "OrientationCoord([a]|C, [b]|D, [r])");
}

TEST_F(DescribeSemantics, WritesAGeneralPoseWithPointAndOrientationFrame) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  EXPECT_EQ(Describe(X_DC, names_), "PoseCoord((e,[a])|C, (f,[b])|D, [r])");
}

TEST_F(DescribeSemantics, WritesAFramePoseWithBraces) {
  const PoseSemantics X_DC = PoseSemantics::OfFrame(FrameOf(a), C, FrameOf(b), D, b);
  EXPECT_EQ(Describe(X_DC, names_), "PoseCoord({a}|C, {b}|D, [b])");
}

TEST_F(DescribeSemantics, WritesEachSideOfAPoseInItsOwnForm) {
  const PoseSemantics X_DC{FrameOf(a).origin(), a, C, f, b, D, b};
  EXPECT_EQ(Describe(X_DC, names_), "PoseCoord({a}|C, (f,[b])|D, [b])");
  const PoseSemantics X_DC_r{e, a, C, FrameOf(b).origin(), b, D, r};
  EXPECT_EQ(Describe(X_DC_r, names_), "PoseCoord((e,[a])|C, {b}|D, [r])");
}

TEST_F(DescribeSemantics, WritesALinearVelocity) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  EXPECT_EQ(Describe(v_DCe, names_), "LinearVelocityCoord(e|C, D, [r])");
}

TEST_F(DescribeSemantics, WritesAnAngularVelocity) {
  const AngularVelocitySemantics w_DC{C, D, r};
  EXPECT_EQ(Describe(w_DC, names_), "AngularVelocityCoord(C, D, [r])");
}

TEST_F(DescribeSemantics, WritesATwist) {
  const TwistSemantics V_DCe{e, C, D, r};
  EXPECT_EQ(Describe(V_DCe, names_), "TwistCoord(e|C, D, [r])");
}

TEST_F(DescribeSemantics, WritesUtf8NamesUnchanged) {
  NameTable names;
  const Body body(*names.Intern("K\xC3\xB6rper"));
  const Body ref_body(*names.Intern("\xE4\xB8\x96\xE7\x95\x8C"));
  const OrientationFrame frame(*names.Intern("\xCE\xB1"));
  const AngularVelocitySemantics w{body, ref_body, frame};
  EXPECT_EQ(Describe(w, names),
            "AngularVelocityCoord(K\xC3\xB6rper, \xE4\xB8\x96\xE7\x95\x8C, [\xCE\xB1])");
}

TEST_F(DescribeSemantics, MarksIdsTheTableDoesNotKnow) {
  EXPECT_EQ(Describe(PositionSemantics{}, names_),
            "PositionCoord(<invalid>|<invalid>, <invalid>|<invalid>, [<invalid>])");
  EXPECT_EQ(Describe(AngularVelocitySemantics{C, Body(NameId(999)), r}, names_),
            "AngularVelocityCoord(C, <invalid>, [r])");
}

// ================================================================ Operation names

TEST(DescribeOperation, NamesEveryOperationInSnakeCase) {
  EXPECT_EQ(ToString(Operation::kCompose), "compose");
  EXPECT_EQ(ToString(Operation::kInverseInNewRef), "inverse_in_new_ref");
  EXPECT_EQ(ToString(Operation::kChangePoint), "change_point");
  EXPECT_EQ(ToString(Operation::kChangeRefPoint), "change_ref_point");
  EXPECT_EQ(ToString(Operation::kChangeOrientationFrame), "change_orientation_frame");
  EXPECT_EQ(ToString(Operation::kChangeRefOrientationFrame), "change_ref_orientation_frame");
  EXPECT_EQ(ToString(Operation::kChangeCoordinateFrame), "change_coordinate_frame");
  EXPECT_EQ(ToString(Operation::kScrewTransform), "screw_transform");
  EXPECT_EQ(ToString(Operation::kCombine), "combine");
}

// ================================================================ Mismatch messages

TEST_F(DescribeMismatch, ComposeNamesTheRefPointAndThePointWithTheirBodies) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ED{g, D, x, E, r};  // g != f
  EXPECT_EQ(Message(Compose(p_DC, p_ED)),
            "compose: reference point f|D of the first does not match point g|D of the second");
}

TEST_F(DescribeMismatch, ComposeNamesTheRefOrientationAndTheOrientation) {
  const PoseSemantics X_DC{e, a, C, f, b, D, b};
  const PoseSemantics X_ED{f, c, D, g, c, E, c};
  EXPECT_EQ(Message(Compose(X_DC, X_ED)),
            "compose: reference orientation frame [b]|D of the first does not match orientation "
            "frame [c]|D of the second");
}

TEST_F(DescribeMismatch, ComposeNamesBodiesWithoutABar) {
  const AngularVelocitySemantics w_DC{C, D, r};
  const AngularVelocitySemantics w_FE{E, F, r};
  EXPECT_EQ(Message(Compose(w_DC, w_FE)),
            "compose: reference body D of the first does not match body E of the second");
}

TEST_F(DescribeMismatch, ComposeNamesTheCoordinateFrames) {
  const PositionSemantics p_DC_r{e, C, f, D, r};
  const PositionSemantics p_ED_s{f, D, g, E, s};
  EXPECT_EQ(Message(Compose(p_DC_r, p_ED_s)),
            "compose: coordinate frame [r] of the first does not match coordinate frame [s] of "
            "the second");
}

TEST_F(DescribeMismatch, ComposeExplainsTheCoordinateForms) {
  const OrientationSemantics R_DC_b{a, C, b, D, b};
  const OrientationSemantics R_ED_r{b, D, c, E, r};
  EXPECT_EQ(Message(Compose(R_DC_b, R_ED_r)),
            "compose: coordinate frame [b] of the first does not match coordinate frame [r] of "
            "the second, and the two are not each expressed in their own reference orientation "
            "frame");
}

TEST_F(DescribeMismatch, ComposeOfVelocitiesNamesThePoints) {
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const LinearVelocitySemantics v_EDx{x, D, E, r};
  EXPECT_EQ(Message(Compose(v_DCe, v_EDx)),
            "compose: point e|C of the first does not match point x|D of the second");
}

TEST_F(DescribeMismatch, InverseInNewRefNamesTheSubjectTwice) {
  const PoseSemantics X_DC_r{e, a, C, f, b, D, r};
  EXPECT_EQ(Message(InverseInNewRef(X_DC_r)),
            "inverse_in_new_ref: coordinate frame [r] of the pose does not match reference "
            "orientation frame [b]|D of the pose");
}

TEST_F(DescribeMismatch, ChangePointNamesTheArgumentPositionAndThePose) {
  const PoseSemantics X_DC{e, a, C, f, b, D, r};
  const PositionSemantics p_xe2{e2, C, x, C, r};
  EXPECT_EQ(Message(ChangePoint(X_DC, p_xe2)),
            "change_point: reference point x|C of the argument position does not match point e|C "
            "of the pose");
  const PositionSemantics p_ee2{e2, F, e, C, r};
  EXPECT_EQ(Message(ChangePoint(X_DC, p_ee2)),
            "change_point: body F of the argument position does not match body C of the pose");
}

TEST_F(DescribeMismatch, ChangeRefPointNamesTheArgumentPositionAndThePosition) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_gx{x, D, g, D, r};
  EXPECT_EQ(Message(ChangeRefPoint(p_DC, p_gx)),
            "change_ref_point: point x|D of the argument position does not match reference point "
            "f|D of the position");
}

TEST_F(DescribeMismatch, ChangeOrientationFrameNamesTheArgumentOrientation) {
  const OrientationSemantics R_DC{a, C, b, D, b};
  const OrientationSemantics R_xa{a, C, ox, C, ox};
  EXPECT_EQ(Message(ChangeOrientationFrame(R_DC, R_xa)),
            "change_orientation_frame: reference orientation frame [x]|C of the argument "
            "orientation does not match orientation frame [a]|C of the orientation");
}

TEST_F(DescribeMismatch, ChangeRefOrientationFrameExplainsTheCoordinateForms) {
  const PoseSemantics X_DC_b{e, a, C, f, b, D, b};
  const OrientationSemantics R_cb_s{b, D, c, D, s};
  EXPECT_EQ(Message(ChangeRefOrientationFrame(X_DC_b, R_cb_s)),
            "change_ref_orientation_frame: coordinate frame [b] of the pose does not match "
            "coordinate frame [s] of the argument orientation, and the two are not each expressed "
            "in their own reference orientation frame");
}

TEST_F(DescribeMismatch, ChangeCoordinateFrameNamesTheRelationKind) {
  const OrientationSemantics R_sx{ox, D, s, E, s};
  EXPECT_EQ(Message(ChangeCoordinateFrame(TwistSemantics{e, C, D, r}, R_sx)),
            "change_coordinate_frame: orientation frame [x]|D of the argument orientation does not "
            "match coordinate frame [r] of the twist");
  EXPECT_EQ(Message(ChangeCoordinateFrame(LinearVelocitySemantics{e, C, D, r}, R_sx)),
            "change_coordinate_frame: orientation frame [x]|D of the argument orientation does not "
            "match coordinate frame [r] of the linear velocity");
  EXPECT_EQ(Message(ChangeCoordinateFrame(AngularVelocitySemantics{C, D, r}, R_sx)),
            "change_coordinate_frame: orientation frame [x]|D of the argument orientation does not "
            "match coordinate frame [r] of the angular velocity");
}

TEST_F(DescribeMismatch, ChangeCoordinateFrameNamesAnArgumentInAThirdFrame) {
  const OrientationSemantics R_sr_c{r, D, s, E, c};
  EXPECT_EQ(Message(ChangeCoordinateFrame(PositionSemantics{e, C, f, D, r}, R_sr_c)),
            "change_coordinate_frame: coordinate frame [c] of the argument orientation does not "
            "match reference orientation frame [s]|E of the argument orientation");
}

TEST_F(DescribeMismatch, TwistChangePointNamesTheArgumentsPoint) {
  const TwistSemantics V_DCe{e, C, D, r};
  const PositionSemantics p_ee2{e2, C, e, C, r};  // the wrong way round
  EXPECT_EQ(Message(ChangePoint(V_DCe, p_ee2)),
            "change_point: point e2|C of the argument position does not match point e|C of the "
            "twist");
}

TEST_F(DescribeMismatch, ScrewTransformNamesThePoseAndTheTwist) {
  const TwistSemantics V_DCe_a{e, C, D, a};
  const PoseSemantics X_fb_ex{e, ox, C, f, b, C, b};
  EXPECT_EQ(Message(ScrewTransform(V_DCe_a, X_fb_ex)),
            "screw_transform: orientation frame [x]|C of the argument pose does not match "
            "coordinate frame [a] of the twist");
  const PoseSemantics X_fb_ea_r{e, a, C, f, b, C, r};
  EXPECT_EQ(Message(ScrewTransform(V_DCe_a, X_fb_ea_r)),
            "screw_transform: coordinate frame [r] of the argument pose does not match reference "
            "orientation frame [b]|C of the argument pose");
}

TEST_F(DescribeMismatch, CombineNamesFirstAndSecond) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const OrientationSemantics R_DF{a, F, b, D, r};
  EXPECT_EQ(Message(Combine(p_DC, R_DF)),
            "combine: body C of the first does not match body F of the second");
  const LinearVelocitySemantics v_DCe{e, C, D, r};
  const AngularVelocitySemantics w_FC{C, F, r};
  EXPECT_EQ(Message(Combine(v_DCe, w_FC)),
            "combine: reference body D of the first does not match reference body F of the second");
}

TEST_F(DescribeMismatch, WritesAHandMadeMismatch) {
  const Mismatch m{
      ErrorCode::kSemanticMismatch, Operation::kChangeRefPoint,
      MismatchSide{Operand::kArgument, RelationKind::kPosition, Field::kRefPoint, g.id(), E.id()},
      MismatchSide{Operand::kSubject, RelationKind::kTwist, Field::kRefBody, D.id(), NameId()},
      false};
  EXPECT_EQ(Describe(m, names_),
            "change_ref_point: reference point g|E of the argument position does not match "
            "reference body D of the twist");
}

TEST_F(DescribeMismatch, WritesOneSideOnItsOwn) {
  EXPECT_EQ(Describe(MismatchSide{Operand::kFirst, RelationKind::kPosition, Field::kRefPoint,
                                  f.id(), D.id()},
                     names_),
            "reference point f|D of the first");
  EXPECT_EQ(Describe(MismatchSide{Operand::kSecond, RelationKind::kPose, Field::kOrientation,
                                  a.id(), C.id()},
                     names_),
            "orientation frame [a]|C of the second");
  EXPECT_EQ(Describe(MismatchSide{Operand::kSubject, RelationKind::kLinearVelocity,
                                  Field::kCoordinateFrame, r.id(), NameId()},
                     names_),
            "coordinate frame [r] of the linear velocity");
  EXPECT_EQ(Describe(MismatchSide{Operand::kArgument, RelationKind::kOrientation,
                                  Field::kRefOrientation, b.id(), D.id()},
                     names_),
            "reference orientation frame [b]|D of the argument orientation");
  EXPECT_EQ(Describe(MismatchSide{Operand::kSubject, RelationKind::kAngularVelocity, Field::kBody,
                                  C.id(), NameId()},
                     names_),
            "body C of the angular velocity");
}

TEST_F(DescribeMismatch, AcceptedOperationsHaveNoMessage) {
  const PositionSemantics p_DC{e, C, f, D, r};
  const PositionSemantics p_ED{f, D, g, E, r};
  EXPECT_EQ(Message(Compose(p_DC, p_ED)), "<accepted>");
}

// ================================================================ Accelerations and wrenches

TEST_F(DescribeSemantics, WritesAnAcceleration) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_EQ(Describe(A_DCe, names_), "AccelerationCoord(e|C, D, [r])");
}

TEST_F(DescribeSemantics, WritesAWrenchOnItsBodyByTheOther) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_EQ(Describe(F_DCe, names_), "WrenchCoord(e|C, D, [r])");
  const WrenchSemantics F_Ce{e, C, Body(), r, true};
  EXPECT_EQ(Describe(F_Ce, names_), "WrenchCoord(e|C, several, [r])");
  EXPECT_EQ(Describe(PowerSemantics{C, D}, names_), "Power(C, D)");
}

TEST_F(DescribeMismatch, NamesTheTwistAnAccelerationOperationNeeds) {
  const AccelerationSemantics A_DCe{e, C, D, r};
  EXPECT_EQ(Message(Inverse(A_DCe, TwistSemantics{e, D, C, r})),
            "inverse: body D of the argument twist does not match body C of the acceleration");
  const AccelerationSemantics A_EDe{e, D, E, r};
  EXPECT_EQ(Message(Compose(A_DCe, A_EDe, VelocityOf(A_DCe), AngularVelocitySemantics{D, F, r})),
            "compose: reference body F of the argument angular velocity does not match reference "
            "body E of the second");
}

TEST_F(DescribeMismatch, NamesAWrenchsBodiesByTheirRoles) {
  const WrenchSemantics F_DCe{e, C, D, r};
  EXPECT_EQ(Message(PowerOf(F_DCe, TwistSemantics{e, C, E, r})),
            "power: reference body E of the argument twist does not match by body D of the wrench");
  EXPECT_EQ(Message(Sum(F_DCe, WrenchSemantics{e, D, C, r})),
            "sum: on body C of the first does not match on body D of the second");
  const WrenchSemantics F_Ce{e, C, Body(), r, true};
  EXPECT_EQ(Message(PowerOf(F_Ce, TwistSemantics{e, C, D, r})),
            "power: reference body D of the argument twist does not match by body (several "
            "bodies) of the wrench");
  EXPECT_EQ(Message(Reaction(F_Ce)),
            "reaction: the wrench on C is a sum of wrenches by several bodies, which has no single "
            "reaction");
}

}  // namespace
}  // namespace semgraph::semantics
