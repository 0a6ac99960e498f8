// Accelerations on twist edges (scene_graph.h "accelerations", accelerations.h,
// docs/dynamics.md §7), on a scene worked out by hand: a disc spinning on the ground with a
// slider running outwards along one of its spokes.
//
//   {w}|G ground; {d}|Disc at w's origin, rotated 90 deg about z ([d]'s x axis = [w]'s y);
//   twist G -> {d}|Disc: omega = (0, 0, W), v = 0; acceleration alpha = (0, 0, beta), a = 0.
//   {p}|Disc fixed at (R, 0, 0) in [d]; {s}|Slider at (R, 0, 0) in [d], axes of [d];
//   twist Disc -> {s}|Slider: v = (u, 0, 0), omega = 0, no acceleration of its own (a = 0).
//   {iso}|Iso alone.
// By hand (W = 2, beta = 0.5, R = 3, u = 0.7), in [d]:
//   p|Disc wrt G: alpha x r + w x (w x r) = (0, beta R, 0) + (-W^2 R, 0, 0) = (-12, 1.5, 0);
//     in [w] (x_d = y_w, y_d = -x_w): (-1.5, -12, 0).
//   the inverse, G wrt Disc at p (a point of the ground seen from the spinning disc):
//     (-beta) z x r + (-W z) x ((-W z) x r) = (-W^2 R, -beta R, 0) = (-12, -1.5, 0).
//   s|Slider wrt G: centripetal and tangential as p, plus Coriolis 2 w x v = (0, 2 W u, 0):
//     (-12, 1.5 + 2.8, 0) = (-12, 4.3, 0); alpha = (0, 0, beta).
// Also: every add error in the rules' order with the graph unchanged (Dump), the acceleration
// cleared by a later twist without one (never stale), no_acceleration naming the edge, zero for
// C == D, and the errors' order against the twist queries'.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::Near;
using Vec = Eigen::Vector3d;

constexpr double kW = 2.0, kBeta = 0.5, kR = 3.0, kU = 0.7;

template <class B>
class Accelerations : public ::testing::Test {
 protected:
  void SetUp() override {
    const Eigen::Quaterniond q90(Eigen::AngleAxisd(M_PI / 2, Vec::UnitZ()));
    const Eigen::Quaterniond id = Eigen::Quaterniond::Identity();
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "Disc").RelativeTo("w", "G"), q90, Vec::Zero()));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("p", "Disc").RelativeTo("d", "Disc"), id, Vec(kR, 0, 0)));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("s", "Slider").RelativeTo("d", "Disc"), id, Vec(kR, 0, 0)));
    ASSERT_TRUE(g.AddBody("Iso"));
    ASSERT_TRUE(g.AddFrame("iso", "Iso"));
    ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                           Vec(0, 0, kW), AccelerationInput{Vec::Zero(), Vec(0, 0, kBeta)}));
    ASSERT_TRUE(g.AddTwist(TwistSpec::Of("s", "Slider").RelativeTo("Disc").ExpressedIn("s"),
                           Vec(kU, 0, 0), Vec::Zero(),
                           AccelerationInput{Vec::Zero(), Vec::Zero()}));
  }
  coord::Acceleration Get(const TwistSpec& spec) {
    auto r = g.GetAcceleration(spec);
    if (!r) {
      ADD_FAILURE() << g.Describe(r.error(), spec);
      return {};
    }
    return *r;
  }
  ErrorCode QueryCode(const TwistSpec& spec) {
    auto r = g.GetAcceleration(spec);
    return r ? ErrorCode::kOk : r.error().code;
  }
  // An add that must fail with `code` and leave the graph exactly as it was.
  void ExpectRejected(ErrorCode code, const TwistSpec& spec, const Vec& a = Vec(1, 2, 3)) {
    const std::string before = Dump(g);
    auto r = g.AddAcceleration(spec, a, Vec(4, 5, 6));
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
TYPED_TEST_SUITE(Accelerations, Backends, BackendName);

TYPED_TEST(Accelerations, SpinningDiscByHand) {
  const coord::Acceleration A =
      this->Get(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("d"));
  EXPECT_TRUE(Near(A.linear, Vec(-kW * kW * kR, kBeta * kR, 0)));
  EXPECT_TRUE(Near(A.angular, Vec(0, 0, kBeta)));
  const auto& t = this->g.topology();
  EXPECT_EQ(A.semantics,
            (semantics::AccelerationSemantics{
                t.FrameSem(this->g.FindFrame("p")).origin(), t.BodySem(this->g.FindBody("Disc")),
                t.BodySem(this->g.FindBody("G")), t.FrameSem(this->g.FindFrame("d")).axes()}));
  const coord::Acceleration Aw =
      this->Get(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("w"));
  EXPECT_TRUE(Near(Aw.linear, Vec(-kBeta * kR, -kW * kW * kR, 0)));
  // At the disc's centre: no acceleration of the point, the same angular acceleration.
  const coord::Acceleration Ad =
      this->Get(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("w"));
  EXPECT_TRUE(Near(Ad.linear, Vec::Zero()));
  EXPECT_TRUE(Near(Ad.angular, Vec(0, 0, kBeta)));
}

TYPED_TEST(Accelerations, InverseIsNotTheNegation) {
  const coord::Acceleration A =
      this->Get(TwistSpec::Of("p", "G").RelativeTo("Disc").ExpressedIn("d"));
  EXPECT_TRUE(Near(A.linear, Vec(-kW * kW * kR, -kBeta * kR, 0)));
  EXPECT_TRUE(Near(A.angular, Vec(0, 0, -kBeta)));
}

TYPED_TEST(Accelerations, CoriolisOfTheSlider) {
  const coord::Acceleration A =
      this->Get(TwistSpec::Of("s", "Slider").RelativeTo("G").ExpressedIn("d"));
  EXPECT_TRUE(Near(A.linear, Vec(-kW * kW * kR, kBeta * kR + 2 * kW * kU, 0)));
  EXPECT_TRUE(Near(A.angular, Vec(0, 0, kBeta)));
  auto lin =
      this->g.GetLinearAcceleration(TwistSpec::Of("s", "Slider").RelativeTo("G").ExpressedIn("d"));
  ASSERT_TRUE(lin);
  EXPECT_TRUE(Near(lin->value, A.linear));
  auto ang =
      this->g.GetAngularAcceleration(TwistSpec::Of("", "Slider").RelativeTo("G").ExpressedIn("w"));
  ASSERT_TRUE(ang);
  EXPECT_TRUE(Near(ang->value, Vec(0, 0, kBeta)));
  // Relative to the disc, the slider does not accelerate (constant radial speed).
  const coord::Acceleration S =
      this->Get(TwistSpec::Of("s", "Slider").RelativeTo("Disc").ExpressedIn("w"));
  EXPECT_TRUE(Near(S.linear, Vec::Zero()));
}

TYPED_TEST(Accelerations, AddAccelerationAtAnotherPointAndFrameIsConverted) {
  auto& g = this->g;
  // The disc's acceleration restated at p in [w] (by hand above): stored at d as a = 0.
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("w"),
                                Vec(-kBeta * kR, -kW * kW * kR, 0), Vec(0, 0, kBeta)));
  const auto stored = g.acceleration_value(g.FindFrame("d"));
  ASSERT_TRUE(stored);
  EXPECT_TRUE(Near(stored->linear, Vec::Zero()));
  EXPECT_TRUE(Near(stored->angular, Vec(0, 0, kBeta)));
  // A new value: 1 m/s^2 along [w]'s x at p, no angular acceleration: at d the same (alpha = 0
  // and the centripetal term -w x (w x r) of moving back to d cancels +W^2 R of p).
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("w"),
                                Vec(1, 0, 0), Vec::Zero()));
  const coord::Acceleration A =
      this->Get(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("w"));
  EXPECT_TRUE(Near(A.linear, Vec(1, 0, 0)));
  EXPECT_TRUE(Near(A.angular, Vec::Zero()));
  EXPECT_EQ(CheckInvariants(g), "");
}

TYPED_TEST(Accelerations, AddAccelerationAgainstTheEdgeIsTheInverseRelation) {
  auto& g = this->g;
  // The ground relative to the disc at p in [d] (by hand above: (-12, -1.5, 0), alpha = -beta z)
  // is the disc's own acceleration inverted: stored at d as a = 0, alpha = beta z.
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("p", "G").RelativeTo("Disc").ExpressedIn("d"),
                                Vec(-kW * kW * kR, -kBeta * kR, 0), Vec(0, 0, -kBeta)));
  const auto stored = g.acceleration_value(g.FindFrame("d"));
  ASSERT_TRUE(stored);
  EXPECT_TRUE(Near(stored->linear, Vec::Zero()));
  EXPECT_TRUE(Near(stored->angular, Vec(0, 0, kBeta)));
  // The disc relative to the slider at s, in [w], with the slider moving: Disc wrt Slider has
  // w = 0 and v = -(u, 0, 0); given a = (0, 2, 0) in [w] = (2, 0, 0) in [d] = [s] and alpha = 0,
  // the slider's own acceleration is its negation (w = 0: no Coriolis term), (-2, 0, 0) in [s].
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("s", "Disc").RelativeTo("Slider").ExpressedIn("w"),
                                Vec(0, 2, 0), Vec::Zero()));
  const auto slider = g.acceleration_value(g.FindFrame("s"));
  ASSERT_TRUE(slider);
  EXPECT_TRUE(Near(slider->linear, Vec(-2, 0, 0)));
  EXPECT_TRUE(Near(slider->angular, Vec::Zero()));
  // The slider wrt G at s, composed from both (hand: centripetal and tangential of p, Coriolis
  // 2 W u, and the slider's own -2 along [d]'s x): (-12 - 2, 1.5 + 2.8, 0) in [d].
  const coord::Acceleration A =
      this->Get(TwistSpec::Of("s", "Slider").RelativeTo("G").ExpressedIn("d"));
  EXPECT_TRUE(Near(A.linear, Vec(-kW * kW * kR - 2, kBeta * kR + 2 * kW * kU, 0)));
  EXPECT_TRUE(Near(A.angular, Vec(0, 0, kBeta)));
  EXPECT_EQ(CheckInvariants(g), "");
}

TYPED_TEST(Accelerations, AddErrorsInTheRulesOrderLeaveTheGraphUnchanged) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto spec = [](std::string_view e, std::string_view C, std::string_view D,
                       std::string_view r) {
    return TwistSpec::Of(e, C).RelativeTo(D).ExpressedIn(r);
  };
  // invalid_name before invalid_number, before unknown names.
  this->ExpectRejected(ErrorCode::kInvalidName, spec("", "Disc", "G", "w"), Vec(nan, 0, 0));
  this->ExpectRejected(ErrorCode::kInvalidName, spec("p", "Disc", "", "w"));
  this->ExpectRejected(ErrorCode::kInvalidName, spec("p", "Disc", "G", ""));
  // invalid_number before node resolution.
  this->ExpectRejected(ErrorCode::kInvalidNumber, spec("nope", "Disc", "G", "w"), Vec(nan, 0, 0));
  this->ExpectRejected(ErrorCode::kUnknownFrame, spec("nope", "Nobody", "G", "w"));
  this->ExpectRejected(ErrorCode::kUnknownFrame, spec("p", "Nobody", "G", "nope"));
  this->ExpectRejected(ErrorCode::kUnknownBody, spec("p", "Nobody", "Nobody", "w"));
  this->ExpectRejected(ErrorCode::kUnknownBody, spec("p", "Disc", "Nobody", "w"));
  // no_such_edge: no twist edge between G and Slider (a path, not an edge), in either direction;
  // a body of another tree; C == D.
  this->ExpectRejected(ErrorCode::kNoSuchEdge, spec("s", "Slider", "G", "iso"));
  this->ExpectRejected(ErrorCode::kNoSuchEdge, spec("s", "G", "Slider", "iso"));
  this->ExpectRejected(ErrorCode::kNoSuchEdge, spec("p", "Disc", "Iso", "w"));
  this->ExpectRejected(ErrorCode::kNoSuchEdge, spec("p", "Disc", "Disc", "w"));
  // acceleration_not_convertible: [r] not in the edge's pose tree.
  this->ExpectRejected(ErrorCode::kAccelerationNotConvertible, spec("p", "Disc", "G", "iso"));
  // AddTwist with an invalid acceleration: invalid_number, unchanged.
  const std::string before = Dump(this->g);
  auto r = this->g.AddTwist(spec("d", "Disc", "G", "d"), Vec::Zero(), Vec(0, 0, 1),
                            AccelerationInput{Vec(0, nan, 0), Vec::Zero()});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidNumber) << r.error().message;
  EXPECT_EQ(Dump(this->g), before);
  EXPECT_EQ(CheckInvariants(this->g), "");
}

TYPED_TEST(Accelerations, ATwistWithoutAnAccelerationLeavesNone) {
  auto& g = this->g;
  const TwistSpec slider = TwistSpec::Of("s", "Slider").RelativeTo("G").ExpressedIn("d");
  ASSERT_EQ(this->QueryCode(slider), ErrorCode::kOk);
  // A new twist of the disc, given without an acceleration: the old one is gone.
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                         Vec(0, 0, 3)));
  EXPECT_FALSE(g.acceleration_value(g.FindFrame("d")));
  auto r = g.GetAcceleration(slider);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kNoAcceleration);
  const std::string text = g.Describe(r.error(), slider);
  EXPECT_NE(text.find("no_acceleration"), std::string::npos) << text;
  EXPECT_NE(text.find("G -> {d}"), std::string::npos) << text;
  // The twist itself still answers.
  EXPECT_TRUE(g.GetTwist(slider));
  // Given again; then a real-time SetTwist clears it too.
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"),
                                Vec::Zero(), Vec(0, 0, 1)));
  ASSERT_EQ(this->QueryCode(slider), ErrorCode::kOk);
  auto h = g.FindTwistEdge("s", "Disc");
  ASSERT_TRUE(h);
  ASSERT_EQ(g.SetTwist(*h, Vec(1, 0, 0), Vec::Zero()), ErrorCode::kOk);
  EXPECT_EQ(this->QueryCode(slider), ErrorCode::kNoAcceleration);
  // Removed and re-added: none.
  ASSERT_TRUE(g.RemoveTwist("d", "G"));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                         Vec(0, 0, 3)));
  EXPECT_FALSE(g.acceleration_value(g.FindFrame("d")));
  EXPECT_EQ(CheckInvariants(g), "");
}

TYPED_TEST(Accelerations, QueryErrorsAndZero) {
  // C == D: zero, with no twist edge needed.
  const coord::Acceleration Z =
      this->Get(TwistSpec::Of("iso", "Iso").RelativeTo("Iso").ExpressedIn("iso"));
  EXPECT_EQ(Z.linear, Vec::Zero());
  EXPECT_EQ(Z.angular, Vec::Zero());
  // The twist query's errors first.
  EXPECT_EQ(this->QueryCode(TwistSpec::Of("iso", "Iso").RelativeTo("G").ExpressedIn("iso")),
            ErrorCode::kNoTwistPath);
  EXPECT_EQ(this->QueryCode(TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("iso")),
            ErrorCode::kNoPosePath);
  EXPECT_EQ(this->QueryCode(TwistSpec::Of("nope", "Disc").RelativeTo("G").ExpressedIn("w")),
            ErrorCode::kUnknownFrame);
  EXPECT_EQ(this->QueryCode(TwistSpec::Of("p", "Disc").RelativeTo("").ExpressedIn("w")),
            ErrorCode::kInvalidName);
}

}  // namespace
}  // namespace semgraph::core
