// Handles that cannot lie (core/src/realtime.cc): SetPose/SetTwist accept only a handle made by
// this graph's FindPoseEdge/FindTwistEdge for an edge that still exists and may change. Forged
// (hand-made, wrong kind, out of range, root frame, constant same-body edge, free twist slot),
// foreign (another graph's, a moved-from graph's) and stale (edge removed since) handles all
// return a code and write nothing: the graph's Dump() (names, topology and every stored value)
// is compared before and after each attempt.
//
// Scene: bodies B, E, G. {b}|B root; {e}|E wrt {b} (variable); {e2}|E wrt {e} (constant,
// same body); {g}|G wrt {e2} (variable); twist edges B -> {e} and E -> {g}.
#include <gtest/gtest.h>

#include <utility>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::core {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

template <class B>
void BuildScene(SceneGraph<B>& g) {
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"), Quaterniond::Identity(),
                        Vector3d(1, 0, 0)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("e2", "E").RelativeTo("e", "E"), Quaterniond::Identity(),
                        Vector3d(0, 2, 0)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("g", "G").RelativeTo("e2", "E"), Quaterniond::Identity(),
                        Vector3d(0, 0, 3)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"),
                         Vector3d(1, 0, 0), Vector3d::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("g", "G").RelativeTo("E").ExpressedIn("g"),
                         Vector3d(0, 1, 0), Vector3d::Zero()));
}

template <class B>
class HandleTest : public ::testing::Test {
 protected:
  void SetUp() override { BuildScene(graph_); }
  // A value every refused call tries to write: visibly different from every stored one.
  const Quaterniond q_ = Quaterniond(Eigen::AngleAxisd(0.5, Vector3d::UnitZ()));
  const Vector3d p_ = Vector3d(7, 8, 9);
  // SetPose with both rotation forms and SetPoseUnchecked; expects `code` from each and an
  // unchanged graph.
  void ExpectPoseRefused(const PoseHandle& h, ErrorCode code) {
    const std::string before = Dump(graph_);
    EXPECT_EQ(graph_.SetPose(h, q_, p_), code);
    EXPECT_EQ(graph_.SetPose(h, q_.toRotationMatrix(), p_), code);
    EXPECT_EQ(graph_.SetPoseUnchecked(h, q_, p_), code);
    EXPECT_EQ(Dump(graph_), before);
    EXPECT_EQ(CheckInvariants(graph_), "");
  }
  void ExpectTwistRefused(const TwistHandle& h) {
    const std::string before = Dump(graph_);
    EXPECT_EQ(graph_.SetTwist(h, p_, p_), ErrorCode::kNoSuchEdge);
    EXPECT_EQ(Dump(graph_), before);
  }
  FrameIndex frame(const char* name) const { return graph_.FindFrame(name); }
  SceneGraph<B> graph_;
};

using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(HandleTest, Backends);

TYPED_TEST(HandleTest, AGenuineHandleWritesItsEdge) {
  auto h = this->graph_.FindPoseEdge("g", "e2");
  ASSERT_TRUE(h);
  EXPECT_EQ(*h, *this->graph_.FindPoseEdge("g", "e2"));  // a handle is a value: found again, equal
  ASSERT_EQ(this->graph_.SetPose(*h, this->q_, this->p_), ErrorCode::kOk);
  // X_E2G = (q_, p_): the position of {g} in {b} is p_BE + p_EE2 + R p_ (identity above g).
  auto X = this->graph_.GetPosition(PoseSpec::Of("g").RelativeTo("b"));
  ASSERT_TRUE(X);
  EXPECT_LT((X->value - (Vector3d(1, 2, 0) + this->p_)).norm(), 1e-12);
  auto t = this->graph_.FindTwistEdge("g", "E");
  ASSERT_TRUE(t);
  ASSERT_EQ(this->graph_.SetTwist(*t, Vector3d(4, 5, 6), Vector3d(0, 0, 1)), ErrorCode::kOk);
  EXPECT_EQ(this->graph_.twist_value(this->frame("g"))->linear, Vector3d(4, 5, 6));
  static_assert(noexcept(this->graph_.SetPose(*h, this->q_, this->p_)));
  static_assert(noexcept(this->graph_.SetTwist(*t, this->p_, this->p_)));
}

TYPED_TEST(HandleTest, FindingAnEdgeChecksNamesFirst) {
  // Before: FindPoseEdge("", "") said unknown_frame. Order: invalid_name -> unknown_frame ->
  // (unknown_body) -> no_such_edge -> constant_pose_change.
  const std::string before = Dump(this->graph_);
  for (auto [of, wrt] :
       {std::pair{"", ""}, std::pair{"g", ""}, std::pair{"", "e2"}, std::pair{"g\x01", "zz"}}) {
    auto pose = this->graph_.FindPoseEdge(of, wrt);
    ASSERT_FALSE(pose);
    EXPECT_EQ(pose.error().code, ErrorCode::kInvalidName) << of << " " << wrt;
    auto twist = this->graph_.FindTwistEdge(of, wrt);
    ASSERT_FALSE(twist);
    EXPECT_EQ(twist.error().code, ErrorCode::kInvalidName) << of << " " << wrt;
  }
  const auto empty = this->graph_.FindPoseEdge("", "");
  EXPECT_NE(empty.error().message.find("invalid_name): name is empty"), std::string::npos)
      << empty.error().message;
  EXPECT_EQ(this->graph_.FindPoseEdge("zz", "e2").error().code, ErrorCode::kUnknownFrame);
  EXPECT_EQ(this->graph_.FindTwistEdge("g", "ZZ").error().code, ErrorCode::kUnknownBody);
  EXPECT_EQ(this->graph_.FindPoseEdge("g", "b").error().code, ErrorCode::kNoSuchEdge);
  EXPECT_EQ(this->graph_.FindTwistEdge("g", "B").error().code, ErrorCode::kNoSuchEdge);
  EXPECT_EQ(Dump(this->graph_), before);
}

TYPED_TEST(HandleTest, HandMadeAndDefaultHandlesAreRefused) {
  const FrameIndex g = this->frame("g");
  this->ExpectPoseRefused(PoseHandle{}, ErrorCode::kNoSuchEdge);
  // The fields of a genuine handle except its graph and kind: refused.
  this->ExpectPoseRefused(PoseHandle{g, 0}, ErrorCode::kNoSuchEdge);
  auto genuine = this->graph_.FindPoseEdge("g", "e2");
  ASSERT_TRUE(genuine);
  PoseHandle wrong_kind = *genuine;
  wrong_kind.kind = EdgeKind::kTwist;
  this->ExpectPoseRefused(wrong_kind, ErrorCode::kNoSuchEdge);
  PoseHandle out_of_range = *genuine;
  out_of_range.child = FrameIndex(static_cast<std::uint32_t>(this->graph_.num_frames()));
  this->ExpectPoseRefused(out_of_range, ErrorCode::kNoSuchEdge);
  out_of_range.child = FrameIndex();
  this->ExpectPoseRefused(out_of_range, ErrorCode::kNoSuchEdge);
  PoseHandle wrong_epoch = *genuine;
  wrong_epoch.epoch += 1;
  this->ExpectPoseRefused(wrong_epoch, ErrorCode::kNoSuchEdge);
}

TYPED_TEST(HandleTest, AForgedHandleOfARootFrameIsRefused) {
  // Before: epoch 0 matched and the root's identity was overwritten, moving its whole tree.
  auto genuine = this->graph_.FindPoseEdge("e", "b");
  ASSERT_TRUE(genuine);
  PoseHandle root = *genuine;
  root.child = this->frame("b");
  root.epoch = 0;
  this->ExpectPoseRefused(root, ErrorCode::kNoSuchEdge);
}

TYPED_TEST(HandleTest, AForgedHandleOfAConstantSameBodyEdgeIsRefused) {
  EXPECT_EQ(this->graph_.FindPoseEdge("e2", "e").error().code, ErrorCode::kConstantPoseChange);
  auto genuine = this->graph_.FindPoseEdge("g", "e2");
  ASSERT_TRUE(genuine);
  PoseHandle constant = *genuine;
  constant.child = this->frame("e2");
  constant.epoch = 0;
  this->ExpectPoseRefused(constant, ErrorCode::kConstantPoseChange);
}

TYPED_TEST(HandleTest, AnotherGraphsHandleIsRefusedEvenWhenTheGraphsAreAlike) {
  using B = TypeParam;
  SceneGraph<B> other;
  BuildScene(other);
  ASSERT_EQ(Dump(other), Dump(this->graph_));  // same names, ids, epochs and values
  auto foreign_pose = other.FindPoseEdge("g", "e2");
  auto foreign_twist = other.FindTwistEdge("g", "E");
  ASSERT_TRUE(foreign_pose && foreign_twist);
  this->ExpectPoseRefused(*foreign_pose, ErrorCode::kNoSuchEdge);
  this->ExpectTwistRefused(*foreign_twist);
  EXPECT_EQ(other.SetPose(*foreign_pose, this->q_, this->p_),
            ErrorCode::kOk);  // still good at home
}

TYPED_TEST(HandleTest, HandlesFollowAMovedGraphAndNotItsEmptiedSource) {
  using B = TypeParam;
  auto pose = this->graph_.FindPoseEdge("g", "e2");
  auto twist = this->graph_.FindTwistEdge("g", "E");
  ASSERT_TRUE(pose && twist);
  SceneGraph<B> moved = std::move(this->graph_);
  EXPECT_EQ(moved.SetPose(*pose, this->q_, this->p_), ErrorCode::kOk);
  EXPECT_EQ(moved.SetTwist(*twist, this->p_, this->p_), ErrorCode::kOk);
  // The moved-from object, rebuilt alike, is another graph: the old handles do not apply.
  this->graph_ = SceneGraph<B>();
  BuildScene(this->graph_);
  this->ExpectPoseRefused(*pose, ErrorCode::kNoSuchEdge);
  this->ExpectTwistRefused(*twist);
  // Move assignment: the target takes the source's handles, its own old ones stop working.
  auto old_target = this->graph_.FindPoseEdge("g", "e2");
  ASSERT_TRUE(old_target);
  this->graph_ = std::move(moved);
  EXPECT_EQ(this->graph_.SetPose(*pose, this->q_, this->p_), ErrorCode::kOk);
  this->ExpectPoseRefused(*old_target, ErrorCode::kNoSuchEdge);
}

TYPED_TEST(HandleTest, StaleHandlesAreRefusedAfterRemovalAndReAdd) {
  auto pose = this->graph_.FindPoseEdge("g", "e2");
  auto twist = this->graph_.FindTwistEdge("g", "E");
  ASSERT_TRUE(pose && twist);
  ASSERT_TRUE(this->graph_.RemovePose("g", "e2"));
  this->ExpectPoseRefused(*pose, ErrorCode::kNoSuchEdge);  // {g} is a root now
  ASSERT_TRUE(this->graph_.AddPose(PoseSpec::Of("g").RelativeTo("e"), Quaterniond::Identity(),
                                   Vector3d::Zero()));
  this->ExpectPoseRefused(*pose, ErrorCode::kNoSuchEdge);  // another edge into {g}
  ASSERT_TRUE(this->graph_.RemoveTwist("g", "E"));
  this->ExpectTwistRefused(*twist);
  // A forged twist handle naming the free slot at its current epoch.
  TwistHandle free_slot = *twist;
  free_slot.epoch += 1;
  this->ExpectTwistRefused(free_slot);
  // The slot reused by a new edge: the old handle still does not apply.
  ASSERT_TRUE(this->graph_.AddTwist(TwistSpec::Of("g", "G").RelativeTo("B").ExpressedIn("g"),
                                    Vector3d::Zero(), Vector3d::Zero()));
  this->ExpectTwistRefused(*twist);
  auto fresh = this->graph_.FindTwistEdge("g", "B");
  ASSERT_TRUE(fresh);
  EXPECT_EQ(fresh->slot, twist->slot);
  EXPECT_EQ(this->graph_.SetTwist(*fresh, this->p_, this->p_), ErrorCode::kOk);
}

TYPED_TEST(HandleTest, HandMadeTwistHandlesAreRefused) {
  this->ExpectTwistRefused(TwistHandle{});
  auto genuine = this->graph_.FindTwistEdge("g", "E");
  ASSERT_TRUE(genuine);
  this->ExpectTwistRefused(TwistHandle{genuine->slot, genuine->epoch});  // no graph, no kind
  TwistHandle wrong_kind = *genuine;
  wrong_kind.kind = EdgeKind::kPose;
  this->ExpectTwistRefused(wrong_kind);
  TwistHandle out_of_range = *genuine;
  out_of_range.slot =
      TwistEdgeIndex(static_cast<std::uint32_t>(this->graph_.num_twist_edges() + 5));
  this->ExpectTwistRefused(out_of_range);
}

}  // namespace
}  // namespace semgraph::core
