// The rules of a joint's edges (topology/rules.h CheckNewJointEdges): the pose rules first, then
// W1 for any twist edge into the child frame, then W3 in the union of the twist graphs of the
// two pose trees the joint's pose edge joins, where a twist path may alternate between them.
// Scenes are built on SceneTopology directly; the expected codes are worked out by hand.
#include "semgraph/topology/rules.h"

#include <gtest/gtest.h>

#include <string_view>

namespace semgraph::topology {
namespace {

using base::ErrorCode;

class JointRules : public ::testing::Test {
 protected:
  BodyIndex Body(std::string_view name) { return t_.CreateBody(*t_.mutable_names().Intern(name)); }
  FrameIndex Frame(std::string_view name, BodyIndex body) {
    return t_.CreateFrame(*t_.mutable_names().Intern(name), body);
  }
  // The twist edge tail -> {head}|body of head, as a screw twist at head.
  void Twist(BodyIndex tail, FrameIndex head) {
    const NameId h = t_.frame_name_id(head);
    t_.ReserveLinkTwist(head);
    (void)t_.LinkTwist(tail, head,
                       semantics::TwistSemantics{semantics::Point(h), t_.BodyOfSem(head),
                                                 t_.BodySem(tail), semantics::OrientationFrame(h)});
  }
  NewPoseEdge Joint(FrameIndex p, FrameIndex c) const {
    return NewPoseEdge{p, c, t_.body_of(p), t_.body_of(c), false};
  }
  ErrorCode Check(const NewPoseEdge& e) const {
    const auto v = CheckNewJointEdges(t_, e);
    return v ? v->code : ErrorCode::kOk;
  }

  SceneTopology t_;
};

// Tree 1: {p}|P with the twist X -> {p}|P. Tree 2: {c}|C -> {c2}|C with X -> {c2}|C. Neither
// twist graph joins P and C; their union does, through X: P - X - C.
TEST_F(JointRules, W3SeesAPathAlternatingBetweenTheTwoTrees) {
  const BodyIndex P = Body("P"), C = Body("C"), X = Body("X");
  const FrameIndex p = Frame("p", P), c = Frame("c", C), c2 = Frame("c2", C);
  t_.LinkPose(c, c2);
  Twist(X, c2);
  EXPECT_EQ(Check(Joint(p, c)), ErrorCode::kOk);  // tree 1 has no twist edge yet
  Twist(X, p);
  EXPECT_FALSE(t_.RecordOf(p)->twists.Connected(P, C));
  EXPECT_FALSE(t_.RecordOf(c)->twists.Connected(P, C));
  EXPECT_FALSE(CheckW4(t_, Joint(p, c)).has_value());  // the union is a forest
  EXPECT_EQ(Check(Joint(p, c)), ErrorCode::kDuplicateTwistPath);
}

TEST_F(JointRules, W3WithinOneTreeAndNotAcrossUnrelatedBodies) {
  const BodyIndex P = Body("P"), C = Body("C"), X = Body("X"), Y = Body("Y");
  const FrameIndex p = Frame("p", P), c = Frame("c", C), c2 = Frame("c2", C);
  t_.LinkPose(c, c2);
  Twist(P, c2);  // P - C in tree 2 alone
  EXPECT_EQ(Check(Joint(p, c)), ErrorCode::kDuplicateTwistPath);

  const FrameIndex q = Frame("q", X), d = Frame("d", Y), d2 = Frame("d2", Y);
  t_.LinkPose(d, d2);
  Twist(C, d2);  // Y - C: joins neither X nor Y to the joint's other end
  EXPECT_EQ(Check(Joint(q, d)), ErrorCode::kOk);
}

TEST_F(JointRules, W1RefusesAnyTwistEdgeIntoTheChildAfterThePoseRules) {
  const BodyIndex P = Body("P"), C = Body("C"), Q = Body("Q");
  const FrameIndex p = Frame("p", P), c = Frame("c", C), q = Frame("q", Q);
  Twist(P, c);  // even from the joint's own parent body: a joint's twist edge is new
  const auto v = CheckNewJointEdges(t_, Joint(p, c));
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->code, ErrorCode::kMultipleTwistParents);
  EXPECT_EQ(v->body, P);
  // The pose rules come first: with a pose parent already, P1 is reported.
  t_.LinkPose(q, c);
  EXPECT_EQ(Check(Joint(p, c)), ErrorCode::kMultiplePoseParents);
}

TEST_F(JointRules, NewFramesAndBodiesHaveNoTwistPath) {
  const BodyIndex P = Body("P"), X = Body("X");
  const FrameIndex p = Frame("p", P);
  Twist(X, p);
  // A child frame not created yet, on a body not created yet: nothing to join.
  EXPECT_EQ(Check(NewPoseEdge{p, FrameIndex(), P, BodyIndex(), false}), ErrorCode::kOk);
}

}  // namespace
}  // namespace semgraph::topology
