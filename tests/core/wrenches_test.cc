// Wrenches in the scene graph (scene_graph.h "wrenches", wrenches.h, docs/dynamics.md), on a
// scene worked out by hand: two pushers push a box that rests on the ground.
//
//   {w}|G ground; {b}|Box at (1, 0, 0) in [w], rotated 90 deg about z ([b]'s x axis = [w]'s y);
//   {p1}|P1 at (1, 1, 0), {p2}|P2 at (1, -1, 0), both with [w]'s axes; {iso}|Iso alone.
//   Stored: on Box by P1: f = (5, 0, 0) about p1 in [w]; on Box by P2: f = (-3, 0, 0) about p2
//   in [w]; on G by Box: f = (0, 0, -20) about b in [w] (the box presses on the ground).
// By hand, about b in [w]: on Box by P1 (5,0,0), m = (0,1,0) x (5,0,0) = (0,0,-5); by P2
// (-3,0,0), m = (0,-1,0) x (-3,0,0) = (0,0,-3); the reaction of the wrench on G: on Box by G
// (0,0,20), m = 0. Net on Box: f = (2,0,20), m = (0,0,-8); in [b] (v_b = (v_y, -v_x, v_z)):
// f = (0,-2,20), m = (0,0,-8); about w in [w]: m = (0,0,-8) + (1,0,0) x (2,0,20) = (0,-20,-8).
// Also: every error in the rules' order with the graph unchanged (Dump before and after),
// updates, removal, handles, compiled queries, and power invariance with a twist edge.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "semgraph/coord/dynamics_operations.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::Near;
using Vec = Eigen::Vector3d;

template <class B>
class Wrenches : public ::testing::Test {
 protected:
  void SetUp() override {
    const Eigen::Quaterniond q90(Eigen::AngleAxisd(M_PI / 2, Vec::UnitZ()));
    const Eigen::Quaterniond id = Eigen::Quaterniond::Identity();
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "Box").RelativeTo("w", "G"), q90, Vec(1, 0, 0)));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("p1", "P1").RelativeTo("w", "G"), id, Vec(1, 1, 0)));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("p2", "P2").RelativeTo("w", "G"), id, Vec(1, -1, 0)));
    ASSERT_TRUE(g.AddBody("Iso"));
    ASSERT_TRUE(g.AddFrame("iso", "Iso"));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("Box").By("P1").At("p1").ExpressedIn("w"), Vec(5, 0, 0),
                            Vec::Zero()));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("Box").By("P2").At("p2").ExpressedIn("w"), Vec(-3, 0, 0),
                            Vec::Zero()));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("G").By("Box").At("b").ExpressedIn("w"), Vec(0, 0, -20),
                            Vec::Zero()));
  }
  coord::Wrench Get(const WrenchSpec& spec) {
    auto r = g.GetWrench(spec);
    if (!r) {
      ADD_FAILURE() << g.Describe(r.error(), spec);
      return {};
    }
    return *r;
  }
  ErrorCode QueryCode(const WrenchSpec& spec) {
    auto r = g.GetWrench(spec);
    return r ? ErrorCode::kOk : r.error().code;
  }
  // An add that must fail with `code` and leave the graph exactly as it was.
  void ExpectRejectedAdd(ErrorCode code, const WrenchSpec& spec, const Vec& f = Vec(1, 2, 3),
                         const Vec& m = Vec(4, 5, 6)) {
    const std::string before = Dump(g);
    auto r = g.AddWrench(spec, f, m);
    ASSERT_FALSE(r) << "accepted";
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(std::string(base::ToString(code))), std::string::npos)
        << r.error().message;
    EXPECT_EQ(Dump(g), before);
  }
  SceneGraph<B> g;
};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(Wrenches, Backends, BackendName);

TYPED_TEST(Wrenches, OneWrenchAndItsReactionByHand) {
  const coord::Wrench W = this->Get(WrenchSpec::On("Box").By("P1").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(W.force, Vec(5, 0, 0)));
  EXPECT_TRUE(Near(W.moment, Vec(0, 0, -5)));
  EXPECT_EQ(W.semantics.on, this->g.topology().BodySem(this->g.FindBody("Box")));
  EXPECT_EQ(W.semantics.by, this->g.topology().BodySem(this->g.FindBody("P1")));
  EXPECT_FALSE(W.semantics.by_several);
  const coord::Wrench R = this->Get(WrenchSpec::On("P1").By("Box").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(R.force, Vec(-5, 0, 0)));
  EXPECT_TRUE(Near(R.moment, Vec(0, 0, 5)));
  EXPECT_EQ(R.semantics.on, this->g.topology().BodySem(this->g.FindBody("P1")));
  // About p1 (its own point) in [b]: no moment; force (5,0,0) in [w] is (0,-5,0) in [b].
  const coord::Wrench P = this->Get(WrenchSpec::On("Box").By("P1").At("p1").ExpressedIn("b"));
  EXPECT_TRUE(Near(P.force, Vec(0, -5, 0)));
  EXPECT_TRUE(Near(P.moment, Vec::Zero()));
}

TYPED_TEST(Wrenches, NetWrenchSumsWrenchesOnAndReactionsOfWrenchesBy) {
  const coord::Wrench W = this->Get(WrenchSpec::On("Box").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(W.force, Vec(2, 0, 20)));
  EXPECT_TRUE(Near(W.moment, Vec(0, 0, -8)));
  EXPECT_TRUE(W.semantics.by_several);
  const coord::Wrench Wb = this->Get(WrenchSpec::On("Box").At("b"));
  EXPECT_TRUE(Near(Wb.force, Vec(0, -2, 20)));
  EXPECT_TRUE(Near(Wb.moment, Vec(0, 0, -8)));
  const coord::Wrench Ww = this->Get(WrenchSpec::On("Box").At("w"));
  EXPECT_TRUE(Near(Ww.force, Vec(2, 0, 20)));
  EXPECT_TRUE(Near(Ww.moment, Vec(0, -20, -8)));
  // Net on the ground: only the stored wrench on it (by Box), about w: (1,0,0) x (0,0,-20).
  const coord::Wrench G = this->Get(WrenchSpec::On("G").At("w"));
  EXPECT_TRUE(Near(G.force, Vec(0, 0, -20)));
  EXPECT_TRUE(Near(G.moment, Vec(0, 20, 0)));
  EXPECT_EQ(G.semantics.by, this->g.topology().BodySem(this->g.FindBody("Box")));
  EXPECT_FALSE(G.semantics.by_several);
}

TYPED_TEST(Wrenches, UpdateReplacesAndKeepsTheStorageFrame) {
  auto& g = this->g;
  // The same force given about w in [b] instead: (5,0,0)_w = (0,-5,0)_b about w; about p1 its
  // moment was 0, so about w: (p1 - w) x f = (1,1,0) x (5,0,0) = (0,0,-5).
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("Box").By("P1").At("w").ExpressedIn("b"), Vec(0, -7, 0),
                          Vec(0, 0, -7)));
  EXPECT_EQ(g.num_wrenches(), 3u);
  // Still stored in b, the frame the first add chose (neither p1 nor [w] is Box's: Box's
  // first frame in p1's tree).
  const coord::Wrench W = this->Get(WrenchSpec::On("Box").By("P1").At("w").ExpressedIn("w"));
  EXPECT_TRUE(Near(W.force, Vec(7, 0, 0)));
  EXPECT_TRUE(Near(W.moment, Vec(0, 0, -7)));
  auto h = g.FindWrench("Box", "P1");
  ASSERT_TRUE(h) << h.error().message;
  EXPECT_EQ(h->frame, g.FindFrame("b"));
}

TYPED_TEST(Wrenches, AddErrorsInTheRulesOrderLeaveTheGraphUnchanged) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto spec = [](std::string_view on, std::string_view by, std::string_view e,
                       std::string_view r) {
    return WrenchSpec::On(on).By(by).At(e).ExpressedIn(r);
  };
  // invalid_name (a missing by) before invalid_number.
  this->ExpectRejectedAdd(ErrorCode::kInvalidName, spec("Box", "", "b", "w"), Vec(nan, 0, 0));
  this->ExpectRejectedAdd(ErrorCode::kInvalidName, spec("Box", "P1", "", "w"));
  // invalid_number before node resolution.
  this->ExpectRejectedAdd(ErrorCode::kInvalidNumber, spec("Nobody", "P1", "nowhere", "w"),
                          Vec(0, nan, 0));
  this->ExpectRejectedAdd(ErrorCode::kInvalidNumber, spec("Box", "P1", "b", "w"), Vec::Zero(),
                          Vec(0, 0, 1e300));
  // unknown_frame before unknown_body; unknown_body before self_wrench.
  this->ExpectRejectedAdd(ErrorCode::kUnknownFrame, spec("Nobody", "P1", "nowhere", "w"));
  this->ExpectRejectedAdd(ErrorCode::kUnknownFrame, spec("Box", "P1", "b", "nowhere"));
  this->ExpectRejectedAdd(ErrorCode::kUnknownBody, spec("Nobody", "Nobody", "b", "w"));
  this->ExpectRejectedAdd(ErrorCode::kUnknownBody, spec("Box", "Nobody", "b", "w"));
  // self_wrench before wrench_not_convertible.
  this->ExpectRejectedAdd(ErrorCode::kSelfWrench, spec("Box", "Box", "iso", "w"));
  // wrench_not_convertible: point and frame in other trees than the storage frame, or no frame
  // of C in the point's tree; before duplicate_wrench.
  this->ExpectRejectedAdd(ErrorCode::kWrenchNotConvertible, spec("Box", "Iso", "iso", "w"));
  this->ExpectRejectedAdd(ErrorCode::kWrenchNotConvertible, spec("Iso", "Box", "b", "w"));
  this->ExpectRejectedAdd(ErrorCode::kWrenchNotConvertible, spec("P1", "Box", "iso", "iso"));
  // duplicate_wrench: the wrench on Box by P1 is stored; this would be its reaction.
  this->ExpectRejectedAdd(ErrorCode::kDuplicateWrench, spec("P1", "Box", "b", "w"));
}

TYPED_TEST(Wrenches, RemovalAndQueryErrorsInOrder) {
  auto& g = this->g;
  std::string before = Dump(g);
  auto r = g.RemoveWrench("P1", "Box");  // stored the other way round
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kNoWrench);
  EXPECT_EQ(g.RemoveWrench("Box", "Box").error().code, ErrorCode::kSelfWrench);
  EXPECT_EQ(g.RemoveWrench("Box", "Nobody").error().code, ErrorCode::kUnknownBody);
  EXPECT_EQ(g.RemoveWrench("", "P1").error().code, ErrorCode::kInvalidName);
  EXPECT_EQ(Dump(g), before);

  const auto q = [](std::string_view on, std::string_view by, std::string_view e,
                    std::string_view r) { return WrenchSpec::On(on).By(by).At(e).ExpressedIn(r); };
  EXPECT_EQ(this->QueryCode(q("", "P1", "nowhere", "w")), ErrorCode::kInvalidName);
  EXPECT_EQ(this->QueryCode(q("Nobody", "P1", "nowhere", "w")), ErrorCode::kUnknownFrame);
  EXPECT_EQ(this->QueryCode(q("Nobody", "Box", "b", "w")), ErrorCode::kUnknownBody);
  EXPECT_EQ(this->QueryCode(q("Box", "Box", "b", "w")), ErrorCode::kSelfWrench);
  EXPECT_EQ(this->QueryCode(q("Iso", "", "b", "w")), ErrorCode::kNoWrench);  // before no_pose_path
  EXPECT_EQ(this->QueryCode(q("P1", "P2", "b", "w")), ErrorCode::kNoWrench);
  EXPECT_EQ(this->QueryCode(q("Box", "", "iso", "w")), ErrorCode::kNoPosePath);
  EXPECT_EQ(this->QueryCode(q("Box", "P2", "b", "iso")), ErrorCode::kNoPosePath);
  auto e = g.GetWrench(q("Box", "", "iso", "w"));
  const std::string text = g.Describe(e.error(), q("Box", "", "iso", "w"));
  EXPECT_NE(text.find("no_pose_path"), std::string::npos) << text;
  EXPECT_NE(text.find("{iso}"), std::string::npos) << text;

  before = Dump(g);
  ASSERT_TRUE(g.RemoveWrench("G", "Box"));
  EXPECT_NE(Dump(g), before);
  EXPECT_EQ(g.num_wrenches(), 2u);
  const coord::Wrench W = this->Get(WrenchSpec::On("Box").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(W.force, Vec(2, 0, 0)));
  EXPECT_TRUE(Near(W.moment, Vec(0, 0, -8)));
  // The pair may now be given the other way round.
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("Box").By("G").At("b").ExpressedIn("w"), Vec(0, 0, 20),
                          Vec::Zero()));
  const coord::Wrench W2 = this->Get(WrenchSpec::On("Box").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(W2.force, Vec(2, 0, 20)));
}

TYPED_TEST(Wrenches, HandlesAndCompiledQueries) {
  auto& g = this->g;
  const WrenchSpec net = WrenchSpec::On("Box").At("w");
  auto compiled = g.CompileWrench(net);
  ASSERT_TRUE(compiled);
  EXPECT_EQ(compiled->num_terms(), 3u);
  Vec f, m;
  ASSERT_EQ(compiled->Evaluate(f, m), ErrorCode::kOk);
  EXPECT_TRUE(Near(f, Vec(2, 0, 20)));
  EXPECT_TRUE(Near(m, Vec(0, -20, -8)));
  // A new value by handle, in the storage frame: on Box by P1 is stored in [b] about b.
  auto h = g.FindWrench("Box", "P1");
  ASSERT_TRUE(h);
  ASSERT_EQ(h->frame, g.FindFrame("b"));
  ASSERT_EQ(g.SetWrench(*h, Vec(0, -1, 0), Vec(0, 0, 2)), ErrorCode::kOk);  // (1,0,0) in [w]
  // Net about b in [w]: (1,0,0) + (-3,0,0) + (0,0,20); m = (0,0,2) + (0,0,-3).
  const coord::Wrench W = this->Get(WrenchSpec::On("Box").At("b").ExpressedIn("w"));
  EXPECT_TRUE(Near(W.force, Vec(-2, 0, 20)));
  EXPECT_TRUE(Near(W.moment, Vec(0, 0, -1)));
  ASSERT_EQ(compiled->Evaluate(f, m), ErrorCode::kOk);
  auto one_shot = g.GetWrench(net);
  ASSERT_TRUE(one_shot);
  EXPECT_TRUE(Near(f, one_shot->force));
  EXPECT_TRUE(Near(m, one_shot->moment));
  // A pose change moves the compiled answer too.
  auto pose = g.FindPoseEdge("b", "w");
  ASSERT_TRUE(pose);
  ASSERT_EQ(g.SetPose(*pose, Eigen::Quaterniond::Identity(), Vec(2, 0, 0)), ErrorCode::kOk);
  ASSERT_EQ(compiled->Evaluate(f, m), ErrorCode::kOk);
  one_shot = g.GetWrench(net);
  ASSERT_TRUE(one_shot);
  EXPECT_TRUE(Near(f, one_shot->force));
  EXPECT_TRUE(Near(m, one_shot->moment));
  EXPECT_EQ(compiled->Evaluate()->semantics, one_shot->semantics);
  // Bad input: nothing written.
  const std::string before = Dump(g);
  UpdateError why;
  EXPECT_EQ(g.SetWrench(*h, Vec(std::nan(""), 0, 0), Vec::Zero(), &why), ErrorCode::kInvalidNumber);
  EXPECT_EQ(why.value.role, coord::ValueRole::kForce);
  WrenchHandle forged = *h;
  forged.graph = 0;
  EXPECT_EQ(g.SetWrench(forged, Vec::Zero(), Vec::Zero()), ErrorCode::kNoWrench);
  forged = *h;
  forged.slot = 99;
  EXPECT_EQ(g.SetWrench(forged, Vec::Zero(), Vec::Zero()), ErrorCode::kNoWrench);
  EXPECT_EQ(Dump(g), before);
  // Removal: the handle is refused and the compiled query invalidated, also after the slot is
  // reused by another pair.
  ASSERT_TRUE(g.RemoveWrench("Box", "P1"));
  EXPECT_EQ(g.SetWrench(*h, Vec::Zero(), Vec::Zero()), ErrorCode::kNoWrench);
  EXPECT_EQ(compiled->Evaluate(f, m), ErrorCode::kQueryInvalidated);
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("P1").By("Box").At("p1"), Vec(1, 1, 1), Vec::Zero()));
  EXPECT_EQ(g.SetWrench(*h, Vec::Zero(), Vec::Zero()), ErrorCode::kNoWrench);
  EXPECT_EQ(compiled->Evaluate(f, m), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(g.CompileWrench(WrenchSpec::On("Iso").At("iso")).error().code, ErrorCode::kNoWrench);
}

// Power f.v + m.w of the wrench on C by D with the twist of C relative to D is the same at every
// point and in every frame (docs/dynamics.md), and coord::PowerOf accepts the graph's answers.
TYPED_TEST(Wrenches, PowerIsInvariantWithTwistsFromTheGraph) {
  auto& g = this->g;
  // Box moves relative to G: the twist edge G -> {b}|Box, screw twist at b in [b].
  auto added = g.AddTwist(TwistSpec::Of("b", "Box").RelativeTo("G").ExpressedIn("b"),
                          Vec(0.3, -0.2, 0.5), Vec(0.1, 0.7, -0.4));
  ASSERT_TRUE(added) << added.error().message;
  ASSERT_TRUE(g.RemoveWrench("G", "Box"));
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("Box").By("G").At("p2").ExpressedIn("p1"), Vec(1, -2, 3),
                          Vec(-0.5, 0.25, 2)));
  const char* frames[] = {"w", "b", "p1", "p2"};
  double first = std::nan("");
  for (const char* e : frames) {
    for (const char* r : frames) {
      auto W = g.GetWrench(WrenchSpec::On("Box").By("G").At(e).ExpressedIn(r));
      auto V = g.GetTwist(TwistSpec::Of(e, "Box").RelativeTo("G").ExpressedIn(r));
      ASSERT_TRUE(W && V);
      auto P = coord::PowerOf(*W, *V);
      ASSERT_TRUE(P) << "semantics of the graph's wrench and twist do not match";
      if (std::isnan(first)) first = P->value;
      EXPECT_NEAR(P->value, first, 1e-9) << "at " << e << " in " << r;
      // The reaction with the inverse twist delivers the same power.
      auto Wr = g.GetWrench(WrenchSpec::On("G").By("Box").At(e).ExpressedIn(r));
      auto Vr = g.GetTwist(TwistSpec::Of(e, "G").RelativeTo("Box").ExpressedIn(r));
      ASSERT_TRUE(Wr && Vr);
      EXPECT_NEAR(coord::PowerOf(*Wr, *Vr)->value, first, 1e-9);
    }
  }
  EXPECT_NE(first, 0.0);
}

}  // namespace
}  // namespace semgraph::core
