// The numbers in the core's messages (core/src/describe.cc, coord::FormatNumber): every number
// is printed with the fewest digits that read back exactly, so a message never shows a rounded
// value that is not the offending or stored one.
//
// And the texts of core/src/describe.cc, checked word for word where a message was changed on
// purpose (docs/rules.md §8): a query error's text carries its snake_case code as a build
// error's does ("query failed (<code>): ..."); without the query's spec it never prints an
// empty name ("frame {}"); no_twist_path names the link of the pose path that no twist edge
// spans and suggests the zero twist of a static mount; duplicate_pose_path names both ways to
// the body that would be reachable twice. The scenes are built by hand: a camera C mounted on
// a robot base B, watching an object O1; an arm B - L1 - L2 with a tool T.
#include <gtest/gtest.h>

#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::core {
namespace {

using base::ErrorCode;
using Eigen::Quaterniond;
using Eigen::Vector3d;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Describe, ConstantPoseChangeShowsTheStoredPositionExactly) {
  SceneGraph<> g;
  const Vector3d p(0.1, 0.1 + 0.2, 1.0 / 3.0);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("a2", "A").RelativeTo("a", "A"), Quaterniond::Identity(), p));
  const auto r =
      g.AddPose(PoseSpec::Of("a2").RelativeTo("a"), Quaterniond::Identity(), Vector3d(1, 2, 3));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kConstantPoseChange);
  // Before: "[0.1, 0.3, 0.333333333]" (9 digits), which is not the stored value.
  EXPECT_TRUE(
      Contains(r.error().message, "(position [0.1, 0.30000000000000004, 0.3333333333333333])"))
      << r.error().message;
}

TEST(Describe, InvalidNumberShowsTheOffendingValueExactly) {
  SceneGraph<> g;
  const auto r = g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), Quaterniond::Identity(),
                           Vector3d(1000000000000.5, 0, 0));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidNumber);
  // Before: "position component 0 is 1e+12 (magnitude above 1e+12)".
  EXPECT_TRUE(Contains(r.error().message,
                       "position component 0 is 1000000000000.5 (magnitude above 1e+12)"))
      << r.error().message;
}

// {c}|C wrt {b}|B (the camera mount), {o1}|O1 wrt {c}|C (the object seen), and the object's
// twist relative to the camera. No twist relates C and B yet.
template <class G>
void BuildCameraScene(G& g) {
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), Quaterniond::Identity(),
                        Vector3d(1, 0, 0.5)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("o1", "O1").RelativeTo("c", "C"), Quaterniond::Identity(),
                        Vector3d(0, 0, 2)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("o1", "O1").RelativeTo("C").ExpressedIn("o1"),
                         Vector3d(0.1, 0, 0), Vector3d(0, 0, 0.2)));
}

TEST(DescribeQueryError, CarriesTheCodeLikeABuildError) {
  SceneGraph<> g;
  BuildCameraScene(g);
  const PoseSpec unknown = PoseSpec::Of("nowhere").RelativeTo("b");
  const auto r = g.GetPose(unknown);
  ASSERT_FALSE(r);
  EXPECT_EQ(g.Describe(r.error(), unknown),
            "query failed (unknown_frame): the point names frame {nowhere}, which does not exist");
  const PoseSpec wrong_body = PoseSpec::Of("c", "O1").RelativeTo("b");
  const auto m = g.GetPose(wrong_body);
  ASSERT_FALSE(m);
  EXPECT_EQ(g.Describe(m.error(), wrong_body),
            "query failed (frame_body_mismatch): the point {c} is attached to body C, not to body "
            "O1 named "
            "in the query");
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("y", "Y"), Quaterniond::Identity(),
                        Vector3d::Zero()));
  const PoseSpec apart = PoseSpec::Of("x").RelativeTo("b");
  const auto n = g.GetPose(apart);
  ASSERT_FALSE(n);
  EXPECT_EQ(g.Describe(n.error(), apart),
            "query failed (no_pose_path): {x} and {b} are in different pose trees: no pose path "
            "joins them");
  const PoseSpec empty = PoseSpec::Of("").RelativeTo("b");
  const auto e = g.GetPose(empty);
  ASSERT_FALSE(e);
  EXPECT_EQ(g.Describe(e.error(), empty),
            "query failed (invalid_name): the point name is missing or invalid");
  const PoseSpec bad = PoseSpec::Of("a\x01z").RelativeTo("b");
  const auto i = g.GetPose(bad);
  ASSERT_FALSE(i);
  EXPECT_EQ(g.Describe(i.error(), bad)
                .rfind("query failed (invalid_name): the point name is missing or invalid: ", 0),
            0u)
      << g.Describe(i.error(), bad);
  // The homogeneous representation refuses a pose in a third frame: the code leads too.
  SceneGraph<coord::HomogeneousBackend> h;
  BuildCameraScene(h);
  const PoseSpec third = PoseSpec::Of("o1").RelativeTo("c").ExpressedIn("b");
  const auto t = h.GetPose(third);
  ASSERT_FALSE(t);
  EXPECT_EQ(h.Describe(t.error(), third)
                .rfind("query failed (representation_constraint): the homogeneous", 0),
            0u)
      << h.Describe(t.error(), third);
}

TEST(DescribeQueryError, WithoutTheSpecNeverPrintsAnEmptyName) {
  SceneGraph<> g;
  BuildCameraScene(g);
  const auto frame = g.GetPose(PoseSpec::Of("c").RelativeTo("b").ExpressedIn("nowhere"));
  ASSERT_FALSE(frame);
  const std::string text = g.Describe(frame.error());
  EXPECT_EQ(text,
            "query failed (unknown_frame): the coordinate frame names a frame that does not exist "
            "(pass the "
            "query's spec to Describe for its name)");
  EXPECT_EQ(text.find("{}"), std::string::npos);
  const auto body = g.GetTwist(TwistSpec::Of("o1").RelativeTo("Nobody").ExpressedIn("o1"));
  ASSERT_FALSE(body);
  EXPECT_EQ(
      g.Describe(body.error()),
      "query failed (unknown_body): the reference body names a body that does not exist (pass the "
      "query's spec to Describe for its name)");
  const auto empty = g.GetPose(PoseSpec::Of("").RelativeTo("b"));
  ASSERT_FALSE(empty);
  EXPECT_EQ(g.Describe(empty.error()),
            "query failed (invalid_name): the point name is missing or invalid");
  // A name the graph knows (a body's, asked as a frame) is named even without the spec.
  const auto known = g.GetPose(PoseSpec::Of("C").RelativeTo("b"));
  ASSERT_FALSE(known);
  EXPECT_EQ(g.Describe(known.error()),
            "query failed (unknown_frame): the point names frame {C}, which does not exist");
}

TEST(DescribeQueryError, NoTwistPathNamesTheMountWithoutATwist) {
  SceneGraph<> g;
  BuildCameraScene(g);
  const TwistSpec spec = TwistSpec::Of("o1").RelativeTo("B").ExpressedIn("b");
  const auto r = g.GetTwist(spec);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kNoTwistPath);
  const std::string expected =
      "query failed (no_twist_path): no twist path joins body O1 and body B in the pose tree of "
      "{o1}|O1: no "
      "twist edge joins body C and body B (the mount {c}|C wrt {b}|B); add the twist of {c}|C wrt "
      "B, a zero "
      "twist if the mount is static";
  EXPECT_EQ(g.Describe(r.error(), spec), expected);
  EXPECT_EQ(g.Describe(r.error()), expected);  // the point travels in the error
  // Doing what it says answers the query: with the mount static, O1 moves relative to B as it
  // does relative to C (the frames are parallel), at {o1}.
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("c").RelativeTo("B").ExpressedIn("c"), Vector3d::Zero(),
                         Vector3d::Zero()));
  const auto V = g.GetTwist(spec);
  ASSERT_TRUE(V) << g.Describe(V.error(), spec);
  EXPECT_LT((V->linear - Vector3d(0.1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((V->angular - Vector3d(0, 0, 0.2)).norm(), 1e-15);
}

TEST(DescribeQueryError, NoTwistPathNamesTheFirstMissingLinkFromTheBody) {
  // B <- L1 <- L2 <- T on the pose path; twists L1 wrt B and T wrt L2, none between L2 and L1.
  SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("t", "T").RelativeTo("l2", "L2"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("l1").RelativeTo("B").ExpressedIn("l1"), Vector3d::Zero(),
                         Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("t").RelativeTo("L2").ExpressedIn("t"), Vector3d::Zero(),
                         Vector3d(1, 0, 0)));
  const TwistSpec spec = TwistSpec::Of("t").RelativeTo("B").ExpressedIn("b");
  const auto r = g.GetTwist(spec);
  ASSERT_FALSE(r);
  EXPECT_EQ(g.Describe(r.error(), spec),
            "query failed (no_twist_path): no twist path joins body T and body B in the pose tree "
            "of {t}|T: no "
            "twist edge joins body L2 and body L1 (the mount {l2}|L2 wrt {l1}|L1); add the twist "
            "of {l2}|L2 wrt "
            "L1, a zero twist if the mount is static");
  // The other way round: the first missing link from B's side is the same mount.
  const TwistSpec back = TwistSpec::Of("b").RelativeTo("T").ExpressedIn("b");
  const auto s = g.GetTwist(back);
  ASSERT_FALSE(s);
  EXPECT_NE(g.Describe(s.error(), back)
                .find("no twist edge joins body L2 and body L1 (the mount {l2}|L2 wrt "
                      "{l1}|L1)"),
            std::string::npos)
      << g.Describe(s.error(), back);
}

TEST(DescribeQueryError, NoTwistPathToABodyOutsideThePoseTree) {
  SceneGraph<> g;
  BuildCameraScene(g);
  ASSERT_TRUE(g.AddBody("Far"));
  const TwistSpec spec = TwistSpec::Of("o1").RelativeTo("Far").ExpressedIn("o1");
  const auto r = g.GetTwist(spec);
  ASSERT_FALSE(r);
  EXPECT_EQ(g.Describe(r.error(), spec),
            "query failed (no_twist_path): no twist path joins body O1 and body Far in the pose "
            "tree of {o1}|O1: "
            "body Far has no frame and no twist edge in that tree; a twist relates bodies of one "
            "pose tree only");
}

// A tool T hangs from link L2 by its flange {t}; its tip {tcp} is then attached to L1, the
// wrong link: T would be reached from {l1} both through L2 and through the new edge.
TEST(DescribeBuildError, DuplicatePosePathNamesBothWaysToTheBody) {
  SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l2", "L2").RelativeTo("l1", "L1"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("t", "T").RelativeTo("l2", "L2"), Quaterniond::Identity(),
                        Vector3d(0, 0, 0.1)));
  const std::string before = Dump(g);
  const auto r = g.AddPose(PoseSpec::Of("tcp", "T").RelativeTo("l1"), Quaterniond::Identity(),
                           Vector3d(0, 0, 1.2));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicatePosePath);
  EXPECT_EQ(r.error().message,
            "pose of {tcp}|T wrt {l1} rejected (duplicate_pose_path): body T would be reachable "
            "twice from "
            "{l1}|L1: through {l1}|L1 -> {l2}|L2 -> {t}|T, and through the new edge, {l1}|L1 -> "
            "{tcp}|T; the "
            "frames of one body may be joined only through that body's own frames. Give {tcp} its "
            "pose relative "
            "to a frame of T (such as {t}|T) instead, or remove one of the two paths first");
  EXPECT_EQ(Dump(g), before);
  // Doing what it says is accepted.
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("tcp", "T").RelativeTo("t"), Quaterniond::Identity(),
                        Vector3d(0, 0, 0.2)));
}

TEST(DescribeBuildError, DuplicatePosePathWhenJoiningTwoTrees) {
  // Tree 1: {b} -> {l1}|L1 -> {t}|T; tree 2: {tcp}|T -> {x}|X. Hanging tree 2 under {b} by {tcp}
  // (a root) would reach T from {b} twice.
  SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("l1", "L1").RelativeTo("b", "B"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("t", "T").RelativeTo("l1"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("tcp", "T"), Quaterniond::Identity(),
                        Vector3d(0, 0, 1)));
  const auto r =
      g.AddPose(PoseSpec::Of("tcp").RelativeTo("b"), Quaterniond::Identity(), Vector3d::Zero());
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "pose of {tcp} wrt {b} rejected (duplicate_pose_path): body T would be reachable twice "
            "from {b}|B: "
            "through {b}|B -> {l1}|L1 -> {t}|T, and through the new edge, {b}|B -> {tcp}|T; the "
            "frames of one "
            "body may be joined only through that body's own frames. Give {tcp} its pose relative "
            "to a frame of "
            "T (such as {t}|T) instead, or remove one of the two paths first");
}

}  // namespace
}  // namespace semgraph::core
