// The structural rules (topology/rules.h), on topology alone: for each rule a scene that breaks
// it (the code and the nodes the violation names) and a near miss that passes; then the order
// in which CheckNewPoseEdge / CheckNewTwistEdge report a scene that breaks several.
// Notation: {x}|X is frame x of body X; "x -> y" the pose edge with tail x, head y; "D -> {h}"
// the twist edge from body D into frame h. W2 (twist_same_body) is decided on names by the
// caller (rules.h): no check of this file's layer.
#include "semgraph/topology/rules.h"

#include <gtest/gtest.h>

#include <string_view>

#include "topology/scene_builder.h"

namespace semgraph::topology {
namespace {

using base::ErrorCode;
using testing::SceneBuilder;

void ExpectViolation(const std::optional<RuleViolation>& v, ErrorCode code, FrameIndex frame = {},
                     FrameIndex other = {}, BodyIndex body = {}) {
  ASSERT_TRUE(v.has_value()) << "no violation, expected code " << static_cast<int>(code);
  EXPECT_EQ(v->code, code);
  EXPECT_EQ(v->frame, frame);
  EXPECT_EQ(v->other, other);
  EXPECT_EQ(v->body, body);
}

// ---------------------------------------------------------------- existence and P4

TEST(Rules, PoseEdgeExistsOnlyInItsDirection) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  EXPECT_TRUE(PoseEdgeExists(s.t, w, a));
  EXPECT_FALSE(PoseEdgeExists(s.t, a, w));             // reversed
  EXPECT_FALSE(PoseEdgeExists(s.t, w, b));             // never linked
  EXPECT_FALSE(PoseEdgeExists(s.t, FrameIndex(), a));  // a frame not created yet
  EXPECT_FALSE(PoseEdgeExists(s.t, w, FrameIndex()));
}

TEST(Rules, P4AnEdgeIsConstantWhenItJoinsTwoFramesOfOneBody) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), a2 = s.Frame("a2", "A");
  s.Pose(w, a);
  s.Pose(a, a2);
  EXPECT_TRUE(IsConstantEdge(s.t, a, a2));
  // Near misses: an inter-body edge, the same pair reversed (no such edge), a frame not yet made.
  EXPECT_FALSE(IsConstantEdge(s.t, w, a));
  EXPECT_FALSE(IsConstantEdge(s.t, a2, a));
  EXPECT_FALSE(IsConstantEdge(s.t, a, FrameIndex()));
  // Two frames of one body without an edge between them: not an existing constant edge.
  const FrameIndex a3 = s.Frame("a3", "A");
  EXPECT_FALSE(IsConstantEdge(s.t, a, a3));
}

// ---------------------------------------------------------------- P1 multiple_pose_parents

TEST(Rules, P1AFrameHasAtMostOnePoseParent) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), x = s.Frame("x", "X");
  s.Pose(w, a);
  // x -> a: a already has the parent w, which the violation names.
  ExpectViolation(CheckP1(s.t, s.Edge(x, a)), ErrorCode::kMultiplePoseParents, w);
  // Near misses: into the root w; into a frame not created yet.
  EXPECT_FALSE(CheckP1(s.t, s.Edge(x, w)).has_value());
  EXPECT_FALSE(
      CheckP1(s.t, NewPoseEdge{x, FrameIndex(), s.t.body_of(x), s.Body("N"), false}).has_value());
}

// ---------------------------------------------------------------- P2 pose_cycle

TEST(Rules, P2AnEdgeNeverClosesACycle) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  s.Pose(a, b);
  // b -> w (w a root, b below it): a cycle; the violation names the tail's root.
  ExpectViolation(CheckP2(s.t, s.Edge(b, w)), ErrorCode::kPoseCycle, w);
  // After a reroot at b the root named is b.
  s.t.RerootPose(b);
  ExpectViolation(CheckP2(s.t, s.Edge(w, b)), ErrorCode::kPoseCycle, b);
  // Near misses: a tail in another tree; a new tail.
  const FrameIndex c = s.Frame("c", "C");
  EXPECT_FALSE(CheckP2(s.t, s.Edge(c, b)).has_value());
  EXPECT_FALSE(
      CheckP2(s.t, NewPoseEdge{FrameIndex(), b, s.Body("N"), s.t.body_of(b), false}).has_value());
}

// ---------------------------------------------------------------- P3 duplicate_pose_path

TEST(Rules, P3ABodyIsNotInTwoTreesThatAnEdgeWouldJoin) {
  SceneBuilder s;
  // Tree 1: w|W -> a|A. Tree 2: v|V -> a2|A (A has frames in both).
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A");
  const FrameIndex v = s.Frame("v", "V"), a2 = s.Frame("a2", "A");
  s.Pose(w, a);
  s.Pose(v, a2);
  // a -> v joins the trees: A would have two paths. Named: A's frame in each tree.
  ExpectViolation(CheckP3(s.t, s.Edge(a, v)), ErrorCode::kDuplicatePosePath, a, a2, s.Body("A"));
  ExpectViolation(CheckP3(s.t, s.Edge(w, v)), ErrorCode::kDuplicatePosePath, a, a2, s.Body("A"));
  // Near miss: two trees without a common body.
  const FrameIndex x = s.Frame("x", "X");
  EXPECT_FALSE(CheckP3(s.t, s.Edge(a, x)).has_value());
}

TEST(Rules, P3TheSameBodyEdgeThatJoinsABodysTwoTreesIsAllowed) {
  SceneBuilder s;
  // Tree 1: w|W -> a|A. Tree 2: a2|A -> v|V (a2 a root).
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A");
  const FrameIndex a2 = s.Frame("a2", "A"), v = s.Frame("v", "V");
  s.Pose(w, a);
  s.Pose(a2, v);
  // a -> a2 (a constant edge of A): allowed, A is the body it joins.
  EXPECT_FALSE(CheckP3(s.t, s.Edge(a, a2)).has_value());
  // ... unless another body is in both trees: W gets a frame in tree 2.
  const FrameIndex w2 = s.Frame("w2", "W");
  s.Pose(v, w2);
  ExpectViolation(CheckP3(s.t, s.Edge(a, a2)), ErrorCode::kDuplicatePosePath, w, w2, s.Body("W"));
}

TEST(Rules, P3WithAFrameNotCreatedYet) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A");
  s.Pose(w, a);
  const BodyIndex A = s.Body("A"), W = s.Body("W"), N = s.Body("N");
  // A new tail frame of A into a tree that has A: the new frame's tree is {A}.
  ExpectViolation(CheckP3(s.t, NewPoseEdge{FrameIndex(), w, A, W, false}),
                  ErrorCode::kDuplicatePosePath, FrameIndex(), a, A);
  // A new head frame of W under a (tree {W, A}).
  ExpectViolation(CheckP3(s.t, NewPoseEdge{a, FrameIndex(), A, W, false}),
                  ErrorCode::kDuplicatePosePath, w, FrameIndex(), W);
  // Near misses: a body not in the tree; a new frame of the tail's own body (a constant edge);
  // a body that does not exist yet.
  EXPECT_FALSE(CheckP3(s.t, NewPoseEdge{a, FrameIndex(), A, N, false}).has_value());
  EXPECT_FALSE(CheckP3(s.t, NewPoseEdge{a, FrameIndex(), A, A, true}).has_value());
  EXPECT_FALSE(CheckP3(s.t, NewPoseEdge{a, FrameIndex(), A, BodyIndex(), false}).has_value());
  EXPECT_FALSE(CheckP3(s.t, NewPoseEdge{FrameIndex(), a, BodyIndex(), A, false}).has_value());
}

// ---------------------------------------------------------------- W4 twist_merge_conflict

// Tree 1: a1|A -> a2|A with D -> {a1}, E -> {a2}: TG D - A - E. Tree 2: b1|B -> b2|B with
// D -> {b1}, and (when `closing`) E -> {b2}: TG D - B (- E). D and E have no frame anywhere.
struct MergeScene {
  SceneBuilder s;
  FrameIndex a1, a2, b1, b2;
  explicit MergeScene(bool closing) {
    a1 = s.Frame("a1", "A");
    a2 = s.Frame("a2", "A");
    b1 = s.Frame("b1", "B");
    b2 = s.Frame("b2", "B");
    s.Pose(a1, a2);
    s.Pose(b1, b2);
    s.Twist(s.Body("D"), a1);
    s.Twist(s.Body("E"), a2);
    s.Twist(s.Body("D"), b1);
    if (closing) s.Twist(s.Body("E"), b2);
  }
};

TEST(Rules, W4TheMergedTwistGraphMustStayAForest) {
  // Joining the trees would close D - A - E - B - D.
  MergeScene closing(true);
  ExpectViolation(CheckW4(closing.s.t, closing.s.Edge(closing.a2, closing.b1)),
                  ErrorCode::kTwistMergeConflict);
  ExpectViolation(CheckNewPoseEdge(closing.s.t, closing.s.Edge(closing.a1, closing.b1)),
                  ErrorCode::kTwistMergeConflict);
  // Near miss: without E -> {b2} the union D - A - E, D - B is a tree.
  MergeScene open(false);
  EXPECT_FALSE(CheckW4(open.s.t, open.s.Edge(open.a2, open.b1)).has_value());
  EXPECT_FALSE(CheckNewPoseEdge(open.s.t, open.s.Edge(open.a2, open.b1)).has_value());
  // A tree without twist edges, or a new frame, never conflicts.
  const FrameIndex x = closing.s.Frame("x", "X");
  EXPECT_FALSE(CheckW4(closing.s.t, closing.s.Edge(closing.a1, x)).has_value());
  EXPECT_FALSE(CheckW4(closing.s.t, NewPoseEdge{closing.a1, FrameIndex(), closing.s.Body("A"),
                                                closing.s.Body("N"), false})
                   .has_value());
}

// ---------------------------------------------------------------- W1, W3

TEST(Rules, W1AFrameHasAtMostOneTwistParent) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A");
  s.Pose(w, a);
  const BodyIndex W = s.Body("W"), X = s.Body("X"), A = s.Body("A");
  s.Twist(W, a);
  // X -> {a}: a already has the twist parent W, which the violation names.
  ExpectViolation(CheckW1(s.t, NewTwistEdge{X, a, A}), ErrorCode::kMultipleTwistParents, {}, {}, W);
  ExpectViolation(CheckW1(s.t, NewTwistEdge{BodyIndex(), a, A}), ErrorCode::kMultipleTwistParents,
                  {}, {}, W);
  // Near misses: W -> {a} again (a value update); into a frame without a twist edge; a new frame.
  EXPECT_FALSE(CheckW1(s.t, NewTwistEdge{W, a, A}).has_value());
  EXPECT_FALSE(CheckW1(s.t, NewTwistEdge{X, w, W}).has_value());
  EXPECT_FALSE(CheckW1(s.t, NewTwistEdge{X, FrameIndex(), A}).has_value());
}

TEST(Rules, W3TwoBodiesHaveAtMostOneTwistPathInATree) {
  SceneBuilder s;
  // One tree: w|W -> a|A, w -> b|B, b -> b2|B; twists D -> {a}, D -> {b}: TG A - D - B.
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B"),
                   b2 = s.Frame("b2", "B");
  s.Pose(w, a);
  s.Pose(w, b);
  s.Pose(b, b2);
  const BodyIndex A = s.Body("A"), B = s.Body("B"), D = s.Body("D"), E = s.Body("E");
  s.Twist(D, a);
  s.Twist(D, b);
  // A -> {b2}: A and B are joined through D already.
  ExpectViolation(CheckW3(s.t, NewTwistEdge{A, b2, B}), ErrorCode::kDuplicateTwistPath);
  ExpectViolation(CheckW3(s.t, NewTwistEdge{D, b2, B}), ErrorCode::kDuplicateTwistPath);
  // Near misses: from a body outside the TG; into a tree without a record; from a new body.
  EXPECT_FALSE(CheckW3(s.t, NewTwistEdge{E, b2, B}).has_value());
  EXPECT_FALSE(CheckW3(s.t, NewTwistEdge{A, s.Frame("lone", "L"), s.Body("L")}).has_value());
  EXPECT_FALSE(CheckW3(s.t, NewTwistEdge{BodyIndex(), b2, B}).has_value());
  // The same pair in another pose tree is another TG: no path there.
  const FrameIndex b3 = s.Frame("b3", "B3");
  const FrameIndex v = s.Frame("v", "V");
  s.Pose(v, b3);
  s.Twist(D, b3);
  EXPECT_FALSE(CheckW3(s.t, NewTwistEdge{A, v, s.Body("V")}).has_value());
}

// ---------------------------------------------------------------- order of the checks

TEST(Rules, APoseEdgeReportsTheFirstRuleItBreaks) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  s.Pose(a, b);
  // b -> a: P1 (a has a parent) and P2 (b is below a): P1.
  ASSERT_TRUE(CheckP2(s.t, NewPoseEdge{b, w, s.Body("B"), s.Body("W"), false}).has_value());
  ExpectViolation(CheckNewPoseEdge(s.t, s.Edge(b, a)), ErrorCode::kMultiplePoseParents, w);
  // b -> w: P2 and P3 (the tree has every body of itself): P2.
  ASSERT_TRUE(CheckP3(s.t, s.Edge(b, w)).has_value());
  ExpectViolation(CheckNewPoseEdge(s.t, s.Edge(b, w)), ErrorCode::kPoseCycle, w);
}

TEST(Rules, P3IsReportedBeforeW4) {
  MergeScene m(true);
  // Tree 2 gets a frame of A too (b2 -> {a3}|A): the edge a2 -> b1 breaks P3 and W4.
  const FrameIndex a3 = m.s.Frame("a3", "A");
  m.s.Pose(m.b2, a3);
  ASSERT_TRUE(CheckW4(m.s.t, m.s.Edge(m.a2, m.b1)).has_value());
  const BodyIndex A = m.s.Body("A");
  ExpectViolation(CheckNewPoseEdge(m.s.t, m.s.Edge(m.a2, m.b1)), ErrorCode::kDuplicatePosePath,
                  m.s.t.SomeFrameOfBodyInTree(A, m.a1), a3, A);
}

TEST(Rules, ATwistEdgeReportsW1BeforeW3) {
  SceneBuilder s;
  const FrameIndex w = s.Frame("w", "W"), a = s.Frame("a", "A"), b = s.Frame("b", "B");
  s.Pose(w, a);
  s.Pose(w, b);
  const BodyIndex A = s.Body("A"), B = s.Body("B"), D = s.Body("D");
  s.Twist(D, a);
  s.Twist(D, b);
  // B -> {a}: a has the twist parent D (W1) and A, B are joined (W3): W1.
  ASSERT_TRUE(CheckW3(s.t, NewTwistEdge{B, a, A}).has_value());
  ExpectViolation(CheckNewTwistEdge(s.t, NewTwistEdge{B, a, A}), ErrorCode::kMultipleTwistParents,
                  {}, {}, D);
  // Near miss A -> {w}: w has no twist parent and W is not in the TG. From B into a2|A, a frame
  // of A without a twist parent: W3 alone.
  EXPECT_FALSE(CheckNewTwistEdge(s.t, NewTwistEdge{A, w, s.Body("W")}).has_value());
  const FrameIndex a2 = s.Frame("a2", "A");
  s.Pose(a, a2);
  ExpectViolation(CheckNewTwistEdge(s.t, NewTwistEdge{B, a2, A}), ErrorCode::kDuplicateTwistPath);
}

// ---------------------------------------------------------------- joints
// The rules of a joint's edges (topology/rules.h CheckNewJointEdges): the pose rules first, then
// W1 for any twist edge into the child frame, then W3 in the union of the twist graphs of the
// two pose trees the joint's pose edge joins, where a twist path may alternate between them.
// Scenes are built on SceneTopology directly; the expected codes are worked out by hand.

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
