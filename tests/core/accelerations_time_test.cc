// Stamped accelerations (docs/dynamics.md "Stamped accelerations"; accelerations.cc,
// acceleration_query.cc, timed_read.h): samples of analytic motions, checked against
//   - finite differences over time of the timed twist queries (the composed acceleration of a
//     two-edge chain at stamps, and between them), with a naive sum (Coriolis dropped) shown far
//     from the truth so the comparison is sensitive;
//   - the linear interpolation of two samples, by hand;
//   - a stamped acceleration given on its own in another frame, converted with the pose at its
//     stamp (not the newest);
//   - the policies (latest, latest common, at with and beyond the horizon, stale), a sample
//     without an acceleration (never an implicit zero), and every error with the graph unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "time_motions.h"

namespace semgraph::core {
namespace {

using time_motions::Orbit;
using time_motions::Rz;
using time_motions::S;
using time_motions::ScrewMotion;
using Vec = Eigen::Vector3d;
using G = SceneGraph<coord::QuaternionBackend>;

constexpr double kDt = 1e-3;  // sample spacing, s
constexpr int kSamples = 1001;

// The orbit's edge-form acceleration at s: classical acceleration of c's origin and the angular
// acceleration of C wrt W, both in [c].
AccelerationInput OrbitAcceleration(const Orbit& o, double s) {
  const Vec p_dd = -o.rho * o.a * o.a * Vec(std::cos(o.a * s), std::sin(o.a * s), 0);
  const Vec alpha_W = o.a * o.b * Vec(-std::sin(o.a * s), std::cos(o.a * s), 0);
  const Eigen::Quaterniond q = o.q(s).conjugate();
  return {q * p_dd, q * alpha_W};
}
// The screw motion's: constant twist, a = w^2 (c_x, c_y, 0) in [d], alpha = 0.
AccelerationInput ScrewAcceleration(const ScrewMotion& m) {
  return {m.w * m.w * Vec(m.c.x(), m.c.y(), 0), Vec::Zero()};
}

// w -> c (orbit, body C), c -> d (screw, body D); twist edges W -> {c}|C and C -> {d}|D, all
// stamped at k kDt, the twists with their accelerations.
class StampedChain : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(g.AddBody("W"));
    ASSERT_TRUE(g.AddFrame("w", "W"));
    for (int k = 0; k < kSamples; ++k) {
      const double s = k * kDt;
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of("c", "C").RelativeTo("w", "W"), orbit.q(s), orbit.p(s), S(s)));
      ASSERT_TRUE(g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c"), orbit.v(s),
                             orbit.omega(s), S(s), OrbitAcceleration(orbit, s)));
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of("d", "D").RelativeTo("c", "C"), screw.q(s), screw.p(s), S(s)));
      ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "D").RelativeTo("C").ExpressedIn("d"), screw.v(),
                             screw.omega(), S(s), ScrewAcceleration(screw)));
    }
  }
  // (dV/dt) of the twist of D's point at d wrt W in [w], by central differences of timed twist
  // queries at t +- h.
  void DifferenceOfTwists(double t, double h, Vec& a, Vec& alpha) const {
    const TwistSpec tip = TwistSpec::Of("d", "D").RelativeTo("W").ExpressedIn("w");
    auto before = g.GetTwist(tip, At{S(t - h)});
    auto after = g.GetTwist(tip, At{S(t + h)});
    ASSERT_TRUE(before && after);
    a = (after->value.linear - before->value.linear) / (2 * h);
    alpha = (after->value.angular - before->value.angular) / (2 * h);
  }
  G g;
  Orbit orbit;
  ScrewMotion screw;
};

TEST_F(StampedChain, ComposedAccelerationAtStampsIsTheDerivativeOfTheTwist) {
  const TwistSpec tip = TwistSpec::Of("d", "D").RelativeTo("W").ExpressedIn("w");
  double worst = 0, naive_best = 1e9;
  for (int k = 50; k < kSamples - 50; k += 97) {
    const double t = k * kDt;
    Vec a_fd, alpha_fd;
    DifferenceOfTwists(t, kDt, a_fd, alpha_fd);
    auto A = g.GetAcceleration(tip, At{S(t)});
    ASSERT_TRUE(A) << g.Describe(A.error(), tip);
    EXPECT_EQ(A->time.time, S(t));
    worst =
        std::max({worst, (A->value.linear - a_fd).norm(), (A->value.angular - alpha_fd).norm()});
    // The naive sum of the two edges' accelerations at d in [w] (Coriolis 2 w x v and w x w
    // dropped) must be far from the truth, or this comparison could not catch that mistake.
    auto A1 = g.GetAcceleration(TwistSpec::Of("d", "C").RelativeTo("W").ExpressedIn("w"), At{S(t)});
    auto A2 = g.GetAcceleration(TwistSpec::Of("d", "D").RelativeTo("C").ExpressedIn("w"), At{S(t)});
    ASSERT_TRUE(A1 && A2);
    naive_best = std::min(naive_best, (A1->value.linear + A2->value.linear - a_fd).norm());
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(naive_best, 1e-2);
}

TEST_F(StampedChain, BetweenStampsTheAccelerationFollowsTheDerivativeToTheSampleSpacing) {
  const TwistSpec tip = TwistSpec::Of("d", "D").RelativeTo("W").ExpressedIn("w");
  for (double t : {0.1234, 0.5005, 0.8888}) {
    Vec a_fd, alpha_fd;
    DifferenceOfTwists(t, 5 * kDt, a_fd, alpha_fd);
    auto A = g.GetAcceleration(tip, At{S(t)});
    ASSERT_TRUE(A);
    EXPECT_LT((A->value.linear - a_fd).norm(), 1e-3) << t;
    EXPECT_LT((A->value.angular - alpha_fd).norm(), 1e-3) << t;
  }
}

TEST_F(StampedChain, OneEdgeBetweenTwoSamplesIsTheirLinearInterpolation) {
  const TwistSpec edge = TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c");
  const int k = 321;
  const double lambda = 0.37, t = (k + lambda) * kDt;
  const AccelerationInput A0 = OrbitAcceleration(orbit, k * kDt),
                          A1 = OrbitAcceleration(orbit, (k + 1) * kDt);
  auto A = g.GetAcceleration(edge, At{S(t)});
  ASSERT_TRUE(A);
  EXPECT_LT((A->value.linear - ((1 - lambda) * A0.linear + lambda * A1.linear)).norm(), 1e-12);
  EXPECT_LT((A->value.angular - ((1 - lambda) * A0.angular + lambda * A1.angular)).norm(), 1e-12);
  EXPECT_EQ(A->time.oldest, S(k * kDt));
  EXPECT_EQ(A->time.newest, S((k + 1) * kDt));
  // The compiled query at the same policy: the same numbers.
  auto compiled = g.CompileAcceleration(edge);
  ASSERT_TRUE(compiled);
  Vec a, alpha;
  TimeReport report;
  ASSERT_EQ(compiled->Evaluate(a, alpha, At{S(t)}, report), ErrorCode::kOk);
  EXPECT_EQ(a, A->value.linear);
  EXPECT_EQ(alpha, A->value.angular);
  EXPECT_EQ(report.time, S(t));
}

TEST_F(StampedChain, Policies) {
  const TwistSpec edge = TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c");
  const double last = (kSamples - 1) * kDt;
  const AccelerationInput newest = OrbitAcceleration(orbit, last);
  auto latest = g.GetAcceleration(edge, Latest{});
  ASSERT_TRUE(latest);
  EXPECT_LT((latest->value.linear - newest.linear).norm(), 1e-12);
  EXPECT_EQ(latest->time.newest, S(last));
  // The untimed query reads the newest sample too.
  auto untimed = g.GetAcceleration(edge);
  ASSERT_TRUE(untimed);
  EXPECT_LT((untimed->linear - newest.linear).norm(), 1e-12);
  // Latest common: one edge a sample ahead; the answer is at the others' newest stamp.
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "D").RelativeTo("C").ExpressedIn("d"), screw.v(),
                         screw.omega(), S(last + kDt), ScrewAcceleration(screw)));
  const TwistSpec tip = TwistSpec::Of("d", "D").RelativeTo("W").ExpressedIn("w");
  auto common = g.GetAcceleration(tip, LatestCommon{});
  auto at_last = g.GetAcceleration(tip, At{S(last)});
  ASSERT_TRUE(common && at_last);
  EXPECT_EQ(common->time.time, S(last));
  EXPECT_EQ(common->value.linear, at_last->value.linear);
  // Past the samples within the horizon: the nearest sample held (extrapolated); beyond: refused.
  auto held = g.GetAcceleration(edge, At{S(last + 0.05), Duration::Milliseconds(100)});
  ASSERT_TRUE(held) << g.Describe(held.error(), edge);
  EXPECT_TRUE(held->time.extrapolated);
  EXPECT_LT((held->value.linear - newest.linear).norm(), 1e-12);
  auto beyond = g.GetAcceleration(edge, At{S(last + 0.2), Duration::Milliseconds(100)});
  ASSERT_FALSE(beyond);
  EXPECT_EQ(beyond.error().code, ErrorCode::kExtrapolation);
  auto stale = g.GetAcceleration(edge, Latest{S(last + 1)});
  ASSERT_FALSE(stale);
  EXPECT_EQ(stale.error().code, ErrorCode::kStale);
  auto linear = g.GetLinearAcceleration(edge, At{S(0.5)});
  auto angular =
      g.GetAngularAcceleration(TwistSpec::Of("", "C").RelativeTo("W").ExpressedIn("c"), At{S(0.5)});
  ASSERT_TRUE(linear && angular);
  EXPECT_LT((linear->value.value - OrbitAcceleration(orbit, 0.5).linear).norm(), 1e-12);
  EXPECT_LT((angular->value.value - OrbitAcceleration(orbit, 0.5).angular).norm(), 1e-12);
}

// w -> e rotating about z (stamped at 0, 1, 2, 3 s); twist edge W -> {e}|E stamped at 0, 1, 2
// with or without accelerations; a timeless twist edge W -> {f}|F.
class SampleAccelerations : public ::testing::Test {
 protected:
  void Build(G& graph) {
    ASSERT_TRUE(graph.AddBody("W"));
    ASSERT_TRUE(graph.AddFrame("w", "W"));
    for (int k = 0; k <= 3; ++k) {
      ASSERT_TRUE(graph.AddPose(PoseSpec::Of("e", "E").RelativeTo("w", "W"), Rz(0.5 * k),
                                Vec(k, 0, 0), S(k)));
    }
    ASSERT_TRUE(graph.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(0),
                               AccelerationInput{Vec(1, 2, 3), Vec(0.1, 0.2, 0.3)}));
    ASSERT_TRUE(graph.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(1)));  // none
    ASSERT_TRUE(graph.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(2),
                               AccelerationInput{Vec(3, 2, 1), Vec(0.3, 0.2, 0.1)}));
    ASSERT_TRUE(graph.AddPose(PoseSpec::Of("f", "F").RelativeTo("w", "W"), Rz(0), Vec(0, 1, 0)));
    ASSERT_TRUE(graph.AddTwist(TwistSpec::Of("f", "F").RelativeTo("W").ExpressedIn("f"),
                               Vec(0, 1, 0), Vec::Zero()));
  }
  void SetUp() override { Build(g); }
  ErrorCode At(const G& graph, double t, Vec* a = nullptr) const {
    auto A = graph.GetAcceleration(edge, core::At{S(t)});
    if (!A) return A.error().code;
    if (a) *a = A->value.linear;
    return ErrorCode::kOk;
  }
  const TwistSpec edge = TwistSpec::Of("e", "E").RelativeTo("W").ExpressedIn("e");
  G g;
};

TEST_F(SampleAccelerations, ASampleWithoutOneGivesNoAcceleration) {
  Vec a;
  EXPECT_EQ(At(g, 0, &a), ErrorCode::kOk);
  EXPECT_EQ(a, Vec(1, 2, 3));
  EXPECT_EQ(At(g, 2, &a), ErrorCode::kOk);
  EXPECT_EQ(a, Vec(3, 2, 1));
  for (double t : {0.5, 1.0, 1.5}) EXPECT_EQ(At(g, t), ErrorCode::kNoAcceleration) << t;
  auto missing = g.GetAcceleration(edge, core::At{S(1)});
  ASSERT_FALSE(missing);
  EXPECT_NE(g.Describe(missing.error(), edge).find("e"), std::string::npos);
  // The compiled query says the same.
  auto compiled = g.CompileAcceleration(edge);
  ASSERT_TRUE(compiled);
  TimeReport report;
  EXPECT_EQ(compiled->Evaluate(a, a, core::At{S(1)}, report), ErrorCode::kNoAcceleration);
  // A twist given again at a stamp without its acceleration clears that sample's.
  ASSERT_TRUE(g.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(0)));
  EXPECT_EQ(At(g, 0), ErrorCode::kNoAcceleration);
}

TEST_F(SampleAccelerations, OnItsOwnAtAStampConvertedWithThePoseAtThatStamp) {
  // Given at e in [w] at stamp 1: the edge form is R_EW(1) a, with e rotated by 0.5 rad then
  // (the newest pose, 1.5 rad, would give another vector).
  const Vec a_w(0.4, -1.1, 0.7), alpha_w(0.2, 0.3, -0.5);
  ASSERT_TRUE(g.AddAcceleration(TwistSpec::Of("e", "E").RelativeTo("W").ExpressedIn("w"), a_w,
                                alpha_w, S(1)));
  auto A = g.GetAcceleration(edge, core::At{S(1)});
  ASSERT_TRUE(A);
  EXPECT_LT((A->value.linear - Rz(0.5).conjugate() * a_w).norm(), 1e-12);
  EXPECT_LT((A->value.angular - Rz(0.5).conjugate() * alpha_w).norm(), 1e-12);
  // Now every bracket around 1 carries one: 0.5 is the interpolation of samples 0 and 1.
  Vec a;
  ASSERT_EQ(At(g, 0.5, &a), ErrorCode::kOk);
  EXPECT_LT((a - 0.5 * (Vec(1, 2, 3) + Rz(0.5).conjugate() * a_w)).norm(), 1e-12);
  // The real-time update at a stamp, in the edge form.
  auto h = g.FindTwistEdge("e", "W");
  ASSERT_TRUE(h);
  EXPECT_EQ(g.SetAcceleration(*h, Vec(5, 5, 5), Vec::Zero(), S(2)), ErrorCode::kOk);
  ASSERT_EQ(At(g, 2, &a), ErrorCode::kOk);
  EXPECT_EQ(a, Vec(5, 5, 5));
  // The newest sample's acceleration is the untimed readers' value.
  EXPECT_EQ(g.GetAcceleration(edge)->linear, Vec(5, 5, 5));
  EXPECT_EQ(g.SetAcceleration(*h, Vec(1, 1, 1), Vec::Zero(), S(1.5)), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetAcceleration(*h, Vec(1, 1, 1), Vec::Zero()), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetAcceleration(*h, Vec(std::nan(""), 1, 1), Vec::Zero(), S(2)),
            ErrorCode::kInvalidNumber);
  ASSERT_EQ(At(g, 2, &a), ErrorCode::kOk);
  EXPECT_EQ(a, Vec(5, 5, 5));
}

TEST_F(SampleAccelerations, ErrorsLeaveTheGraphUnchanged) {
  // A twist sample at 3 s, past the pose samples? No: poses run to 3 s; one at 4 s is past them.
  ASSERT_TRUE(g.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(4)));
  const auto snapshot = [&] {
    std::string s;
    for (double t : {0.0, 0.5, 1.0, 2.0, 4.0}) {
      Vec a = Vec::Zero();
      s += std::to_string(static_cast<int>(At(g, t, &a))) + ":" + std::to_string(a.x()) + "," +
           std::to_string(a.y()) + "," + std::to_string(a.z()) + ";";
    }
    return s;
  };
  const std::string before = snapshot();
  const TwistSpec in_w = TwistSpec::Of("e", "E").RelativeTo("W").ExpressedIn("w");
  const struct {
    const char* what;
    BuildResult result;
    ErrorCode code;
  } cases[] = {
      {"no stamp on a stamped edge", g.AddAcceleration(edge, Vec(1, 0, 0), Vec::Zero()),
       ErrorCode::kStampMismatch},
      {"a stamp on a timeless edge",
       g.AddAcceleration(TwistSpec::Of("f", "F").RelativeTo("W").ExpressedIn("f"), Vec(1, 0, 0),
                         Vec::Zero(), S(1)),
       ErrorCode::kStampMismatch},
      {"no twist sample at the stamp", g.AddAcceleration(edge, Vec(1, 0, 0), Vec::Zero(), S(0.5)),
       ErrorCode::kAccelerationNotConvertible},
      {"no pose at the stamp", g.AddAcceleration(in_w, Vec(1, 0, 0), Vec::Zero(), S(4)),
       ErrorCode::kAccelerationNotConvertible},
      {"not a number", g.AddAcceleration(edge, Vec(1, std::nan(""), 0), Vec::Zero(), S(1)),
       ErrorCode::kInvalidNumber},
      {"not a number with a twist",
       g.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(3),
                  AccelerationInput{Vec(INFINITY, 0, 0), Vec::Zero()}),
       ErrorCode::kInvalidNumber},
  };
  for (const auto& c : cases) {
    ASSERT_FALSE(c.result) << c.what;
    EXPECT_EQ(c.result.error().code, c.code) << c.what << ": " << c.result.error().message;
    EXPECT_EQ(snapshot(), before) << c.what;
  }
  EXPECT_NE(cases[2].result.error().message.find("no twist sample"), std::string::npos);
  // Under the reject policy, another acceleration on a sample that has one is a duplicate; the
  // same one again is accepted and changes nothing.
  TimeOptions options;
  options.duplicate_stamp = DuplicatePolicy::kReject;
  auto strict = G::Create(options);
  ASSERT_TRUE(strict);
  Build(*strict);
  auto dup = strict->AddAcceleration(edge, Vec(9, 9, 9), Vec::Zero(), S(0));
  ASSERT_FALSE(dup);
  EXPECT_EQ(dup.error().code, ErrorCode::kDuplicateStamp);
  EXPECT_TRUE(strict->AddAcceleration(edge, Vec(1, 2, 3), Vec(0.1, 0.2, 0.3), S(0)));
  auto twist_dup = strict->AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.5), S(0));  // without it
  ASSERT_FALSE(twist_dup);
  EXPECT_EQ(twist_dup.error().code, ErrorCode::kDuplicateStamp);
  Vec a;
  ASSERT_EQ(At(*strict, 0, &a), ErrorCode::kOk);
  EXPECT_EQ(a, Vec(1, 2, 3));
}

}  // namespace
}  // namespace semgraph::core
