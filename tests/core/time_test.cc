// Time (docs/time.md): stamped edges, interpolation modes, extrapolation with the measured
// twist, differentiation (twist source poses), time travel, policies, every time error with the
// graph unchanged, window / capacity / duplicates / out-of-order samples, stamps from seconds.
//
// Ground truth is analytic or built independently:
//   ScrewMotion   a body spinning at rate w about the z axis through the point c of its parent
//                 while sliding along it at h: X(s) = (Rz(w s), c - Rz(w s) c + h s z), whose
//                 screw twist (at the body's origin, in its frame) is (c x w z + h z, w z),
//                 constant
//   Orbit         a body on a circle of radius rho about its parent's z axis, spinning about its
//                 own x axis: X(s) = (Rz(a s) Rx(b s), rho (cos a s, sin a s, 0))
//   at a sample stamp: the same graph built with those values and no time at all
//   derivatives of composed motions: central differences of the analytic composed pose
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"
#include "time_motions.h"

namespace semgraph::core {
namespace {

using semgraph::testing::ExpectNear;
using Graph = SceneGraph<coord::QuaternionBackend>;

using namespace time_motions;  // S, Rz, Rx, ScrewMotion, Orbit

const PoseSpec kOinW = PoseSpec::Of("o").RelativeTo("w");

// W (world) <- {o}|O moving with ScrewMotion, sampled every `dt` from 0 to 1 s.
Graph ScrewGraph(Interpolation mode, double dt = 0.1, bool with_twist = false) {
  TimeOptions options;
  options.interpolation = mode;
  Graph g = *Graph::Create(options);
  const ScrewMotion m;
  EXPECT_TRUE(g.AddBody("W").has_value());
  EXPECT_TRUE(g.AddFrame("w", "W").has_value());
  const int n = static_cast<int>(std::lround(1.0 / dt));
  for (int i = 0; i <= n; ++i) {
    const double s = i * dt;
    EXPECT_TRUE(
        g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), m.q(s), m.p(s), S(s)).has_value());
  }
  if (with_twist) {
    // The measured twist of O wrt W at o in [o], sampled at the same stamps.
    for (int i = 0; i <= n; ++i) {
      EXPECT_TRUE(g.AddTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), m.v(), m.omega(),
                             S(i * dt))
                      .has_value());
    }
  }
  return g;
}

TEST(TimeTest, ScrewModeReproducesAConstantScrewMotionBetweenSamples) {
  const Graph g = ScrewGraph(Interpolation::kScrew);
  const ScrewMotion m;
  for (double s : {0.0, 0.05, 0.333, 0.5, 0.71, 0.999, 1.0}) {
    auto X = g.GetPose(kOinW, At{S(s)});
    ASSERT_TRUE(X.has_value()) << s;
    ExpectNear(X->value.value.rotation, m.q(S(s).seconds()), 1e-12);
    ExpectNear(X->value.value.translation, m.p(S(s).seconds()), 1e-12);
    ASSERT_TRUE(X->time.time.has_value());
    EXPECT_EQ(*X->time.time, S(s));
    EXPECT_FALSE(X->time.extrapolated);
  }
  // Between samples both bracketing stamps are reported; at a stamp, only it.
  auto X = g.GetPose(kOinW, At{S(0.35)});
  EXPECT_EQ(*X->time.oldest, S(0.3));
  EXPECT_EQ(*X->time.newest, S(0.4));
  X = g.GetPose(kOinW, At{S(0.4)});
  EXPECT_EQ(*X->time.oldest, S(0.4));
  EXPECT_EQ(*X->time.newest, S(0.4));
}

TEST(TimeTest, LinearModeConvergesToTheMotionAsSamplesGetDenser) {
  const ScrewMotion m;
  double previous = 1e9;
  for (double dt : {0.1, 0.05, 0.025, 0.0125}) {
    const Graph g = ScrewGraph(Interpolation::kLinear, dt);
    double worst = 0;
    for (double s = 0.013; s < 1.0; s += 0.071) {
      auto X = g.GetPose(kOinW, At{S(s)});
      ASSERT_TRUE(X.has_value());
      worst = std::max(worst, (X->value.value.translation - m.p(S(s).seconds())).norm());
    }
    EXPECT_GT(worst, 0.0);
    EXPECT_LT(worst, previous / 3.0);  // second order: error / 4 per halving
    previous = worst;
  }
}

TEST(TimeTest, AnOrbitConvergesInBothModes) {
  const Orbit o;
  for (Interpolation mode : {Interpolation::kScrew, Interpolation::kLinear}) {
    TimeOptions options;
    options.interpolation = mode;
    Graph g = *Graph::Create(options);
    ASSERT_TRUE(g.AddBody("W").has_value());
    ASSERT_TRUE(g.AddFrame("w", "W").has_value());
    for (int i = 0; i <= 400; ++i) {
      ASSERT_TRUE(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), o.q(i * 0.0025),
                            o.p(i * 0.0025), S(i * 0.0025))
                      .has_value());
    }
    for (double s = 0.01; s < 1.0; s += 0.0917) {
      auto X = g.GetPose(kOinW, At{S(s)});
      ASSERT_TRUE(X.has_value());
      ExpectNear(X->value.value.translation, o.p(S(s).seconds()), 2e-6);
      ExpectNear(X->value.value.rotation, o.q(S(s).seconds()), 2e-6);
    }
  }
}

TEST(TimeTest, ExtrapolationIntegratesTheMeasuredTwistAndSaysSo) {
  const Graph g = ScrewGraph(Interpolation::kScrew, 0.1, /*with_twist=*/true);
  const ScrewMotion m;
  // Without a horizon: refused, naming the edge and its range.
  auto refused = g.GetPose(kOinW, At{S(1.2)});
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().code, ErrorCode::kExtrapolation);
  EXPECT_EQ(g.Describe(refused.error(), kOinW),
            "query failed (extrapolation): pose of {o}|O wrt {w}|W has samples in [0.000, 1.000] "
            "s; asked 1.200 s");
  // Within the horizon: X(1) Exp(0.2 xi) = the analytic motion at 1.2 (forwards and backwards).
  for (double s : {1.2, 1.5, -0.3}) {
    auto X = g.GetPose(kOinW, At{S(s), Duration::Milliseconds(500)});
    ASSERT_TRUE(X.has_value()) << s;
    EXPECT_TRUE(X->time.extrapolated);
    ExpectNear(X->value.value.rotation, m.q(s), 1e-12);
    ExpectNear(X->value.value.translation, m.p(s), 1e-12);
  }
  // Beyond the horizon.
  EXPECT_EQ(g.GetPose(kOinW, At{S(1.6), Duration::Milliseconds(500)}).error().code,
            ErrorCode::kExtrapolation);
  // A twist edge holds its nearest sample within the horizon.
  auto V = g.GetTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"),
                      At{S(1.3), Duration::Milliseconds(500)});
  ASSERT_TRUE(V.has_value());
  EXPECT_TRUE(V->time.extrapolated);
  ExpectNear(V->value.linear, m.v(), 1e-15);
  // No twist path: extrapolation is refused even with a horizon.
  const Graph no_twist = ScrewGraph(Interpolation::kScrew);
  EXPECT_EQ(no_twist.GetPose(kOinW, At{S(1.2), Duration::Seconds(1)}).error().code,
            ErrorCode::kExtrapolation);
  // A negative horizon is invalid_number, after invalid_name.
  EXPECT_EQ(g.GetPose(kOinW, At{S(0.5), Duration::Nanoseconds(-1)}).error().code,
            ErrorCode::kInvalidNumber);
  EXPECT_EQ(g.GetPose(PoseSpec::Of("").RelativeTo("w"), At{S(0.5), Duration::Nanoseconds(-1)})
                .error()
                .code,
            ErrorCode::kInvalidName);
  EXPECT_EQ(g.GetPose(PoseSpec::Of("nope").RelativeTo("w"), At{S(0.5), Duration::Nanoseconds(-1)})
                .error()
                .code,
            ErrorCode::kInvalidNumber);
}

TEST(TimeTest, TwistFromPosesEqualsTheAnalyticTwistAndTheTwistEdges) {
  for (Interpolation mode : {Interpolation::kScrew, Interpolation::kLinear}) {
    const Graph g = ScrewGraph(mode, 0.1, /*with_twist=*/true);
    const ScrewMotion m;
    const TwistSpec at_o = TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o");
    for (double s : {0.05, 0.3, 0.55, 1.0}) {
      auto from_poses = g.GetTwist(at_o, At{S(s)}, TwistSource::kPoses);
      ASSERT_TRUE(from_poses.has_value());
      auto from_twists = g.GetTwist(at_o, At{S(s)}, TwistSource::kTwists);
      ASSERT_TRUE(from_twists.has_value());
      if (mode == Interpolation::kScrew) {
        ExpectNear(from_poses->value.angular, m.omega(), 1e-12);
        ExpectNear(from_poses->value.linear, m.v(), 1e-12);
        ExpectNear(from_poses->value.linear, from_twists->value.linear, 1e-12);
      } else {
        // lerp/slerp: the chord's velocity R(s)^T (p1 - p0) / dt, with R(s) the motion's own
        // rotation (slerp about a fixed axis is exact); the rotation rate is exact.
        const double s0 = s == 1.0 ? 0.9 : std::floor(s * 10 + 1e-9) / 10, s1 = s0 + 0.1;
        ExpectNear(from_poses->value.angular, m.omega(), 1e-12);
        ExpectNear(from_poses->value.linear,
                   Eigen::Vector3d(m.q(s).conjugate() * ((m.p(s1) - m.p(s0)) / 0.1)), 1e-9);
      }
    }
    // Expressed in the world at the world's origin: the analytic spatial twist.
    auto Vw = g.GetTwist(TwistSpec::Of("w", "O").RelativeTo("W").ExpressedIn("w"), At{S(0.45)},
                         TwistSource::kPoses);
    ASSERT_TRUE(Vw.has_value());
    const Eigen::Vector3d w_world = m.q(0.45) * m.omega();
    if (mode == Interpolation::kScrew) {
      // v at w's origin = R v_body + p x w (p of o in w).
      ExpectNear(Vw->value.linear, Eigen::Vector3d(m.q(0.45) * m.v() + m.p(0.45).cross(w_world)),
                 1e-12);
    }
    ExpectNear(Vw->value.angular, w_world, 1e-12);
  }
}

TEST(TimeTest, TwistFromPosesOfAChainOfTwoMovingBodies) {
  // W <- {a}|A (Orbit) <- {b}|B (ScrewMotion): the twist of B wrt W at b in [w] is the
  // derivative of X_WB(s) = X_WA(s) X_AB(s); checked against central differences of the
  // analytic product, dense samples in screw mode, at a segment's midpoint (where the segment's
  // constant twist is second-order accurate).
  const Orbit o;
  const ScrewMotion m;
  Graph g;
  ASSERT_TRUE(g.AddBody("W").has_value());
  ASSERT_TRUE(g.AddFrame("w", "W").has_value());
  for (int i = 0; i <= 1000; ++i) {
    const double s = i * 0.001;
    ASSERT_TRUE(
        g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w"), o.q(s), o.p(s), S(s)).has_value());
    ASSERT_TRUE(
        g.AddPose(PoseSpec::Of("b", "B").RelativeTo("a"), m.q(s), m.p(s), S(s)).has_value());
  }
  const auto X_WB = [&](double s, Eigen::Quaterniond& q, Eigen::Vector3d& p) {
    q = o.q(s) * m.q(s);
    p = o.q(s) * m.p(s) + o.p(s);
  };
  const double s = 0.4565, h = 1e-6;
  Eigen::Quaterniond q0, q1, q;
  Eigen::Vector3d p0, p1, p;
  X_WB(s - h, q0, p0);
  X_WB(s + h, q1, p1);
  X_WB(s, q, p);
  const Eigen::Vector3d v_truth = (p1 - p0) / (2 * h);  // velocity of b's origin in [w]
  const Eigen::Quaterniond dq(((q1.coeffs() - q0.coeffs()) / (2 * h)).eval());
  const Eigen::Vector3d w_truth = 2.0 * (dq * q.conjugate()).vec();  // spatial angular velocity
  auto V = g.GetTwist(TwistSpec::Of("b").RelativeTo("W").ExpressedIn("w"), At{S(s)},
                      TwistSource::kPoses);
  ASSERT_TRUE(V.has_value());
  ExpectNear(V->value.linear, v_truth, 1e-5);
  ExpectNear(V->value.angular, w_truth, 1e-5);
  // The pose itself, composed of two interpolated edges.
  auto X = g.GetPose(PoseSpec::Of("b").RelativeTo("w"), At{S(s)});
  ExpectNear(X->value.value.translation, p, 1e-6);
  // A single sample has no derivative.
  Graph one;
  ASSERT_TRUE(one.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), Rz(0.1),
                          Eigen::Vector3d::Zero(), S(1))
                  .has_value());
  auto e = one.GetTwist(TwistSpec::Of("b").RelativeTo("W").ExpressedIn("w"), Latest{},
                        TwistSource::kPoses);
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, ErrorCode::kExtrapolation);
  EXPECT_TRUE(e.error().time.single_sample);
}

// ---------------------------------------------------------------- at a sample == no time at all

TEST(TimeTest, AtASampleStampEveryAnswerEqualsTheTimelessGraph) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto rand_q = [&] {
    return Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
  };
  const auto rand_p = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  // A tree: frames f1..f7 on bodies B1..B7 (f0 on W), parent of fi = f(i/2); a twist edge per body.
  constexpr int kFrames = 8, kStamps = 5;
  struct Value {
    Eigen::Quaterniond q;
    Eigen::Vector3d p, v, w;
  };
  std::vector<std::vector<Value>> values(kFrames, std::vector<Value>(kStamps));
  for (auto& per_frame : values) {
    for (Value& x : per_frame) x = {rand_q(), rand_p(), rand_p(), rand_p()};
  }
  const auto name = [](int i) { return "f" + std::to_string(i); };
  const auto body = [](int i) { return i == 0 ? std::string("W") : "B" + std::to_string(i); };
  Graph stamped;
  ASSERT_TRUE(stamped.AddBody("W").has_value());
  ASSERT_TRUE(stamped.AddFrame("f0", "W").has_value());
  for (int k = 0; k < kStamps; ++k) {
    for (int i = 1; i < kFrames; ++i) {
      const std::string n = name(i), b = body(i), pn = name(i / 2), pb = body(i / 2);
      ASSERT_TRUE(stamped
                      .AddPose(PoseSpec::Of(n, b).RelativeTo(pn, pb), values[i][k].q,
                               values[i][k].p, S(k * 0.1))
                      .has_value());
      ASSERT_TRUE(stamped
                      .AddTwist(TwistSpec::Of(n, b).RelativeTo(pb).ExpressedIn(n), values[i][k].v,
                                values[i][k].w, S(k * 0.1))
                      .has_value());
    }
  }
  for (int k = 0; k < kStamps; ++k) {
    Graph plain;
    ASSERT_TRUE(plain.AddBody("W").has_value());
    ASSERT_TRUE(plain.AddFrame("f0", "W").has_value());
    for (int i = 1; i < kFrames; ++i) {
      const std::string n = name(i), b = body(i), pn = name(i / 2), pb = body(i / 2);
      ASSERT_TRUE(
          plain.AddPose(PoseSpec::Of(n, b).RelativeTo(pn, pb), values[i][k].q, values[i][k].p)
              .has_value());
      ASSERT_TRUE(plain
                      .AddTwist(TwistSpec::Of(n, b).RelativeTo(pb).ExpressedIn(n), values[i][k].v,
                                values[i][k].w)
                      .has_value());
    }
    for (int a = 0; a < kFrames; ++a) {
      for (int b = 0; b < kFrames; ++b) {
        const std::string na = name(a), nb = name(b), nr = name((a + b + k) % kFrames),
                          rb = body(b);
        PoseSpec ps = PoseSpec::Of(na).RelativeTo(nb).ExpressedIn(nr);
        auto X = stamped.GetPose(ps, At{S(k * 0.1)});
        auto Y = plain.GetPose(ps);
        ASSERT_TRUE(X.has_value() && Y.has_value());
        ExpectNear(X->value.value.rotation, Y->value.rotation, 1e-12);
        ExpectNear(X->value.value.translation, Y->value.translation, 1e-12);
        const TwistSpec ts = TwistSpec::Of(na).RelativeTo(rb).ExpressedIn(nr);
        auto V = stamped.GetTwist(ts, At{S(k * 0.1)});
        auto W = plain.GetTwist(ts);
        ASSERT_TRUE(V.has_value() && W.has_value());
        ExpectNear(V->value.linear, W->linear, 1e-12);
        ExpectNear(V->value.angular, W->angular, 1e-12);
        // The compiled query under the same policy.
        auto c = stamped.CompilePose(ps);
        ASSERT_TRUE(c.has_value());
        typename Graph::Backend::PoseCoords Z;
        TimeReport rep;
        ASSERT_EQ(c->Evaluate(Z, At{S(k * 0.1)}, rep), ErrorCode::kOk);
        ExpectNear(Z.translation, Y->value.translation, 1e-12);
      }
    }
    // Latest = the newest stamp's graph.
    if (k == kStamps - 1) {
      auto X = stamped.GetPose(PoseSpec::Of("f7").RelativeTo("f5"), Latest{});
      auto Y = plain.GetPose(PoseSpec::Of("f7").RelativeTo("f5"));
      ExpectNear(X->value.value.translation, Y->value.translation, 1e-12);
      EXPECT_EQ(*X->time.newest, S(0.4));
      EXPECT_FALSE(X->time.time.has_value());
    }
  }
}

// ---------------------------------------------------------------- errors, graph unchanged

class TimeErrorsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    TimeOptions o;
    o.duplicate_stamp = DuplicatePolicy::kReject;
    o.window = Duration::Seconds(1);
    g = *Graph::Create(o);
    ASSERT_TRUE(g.AddBody("W").has_value());
    ASSERT_TRUE(g.AddFrame("w", "W").has_value());
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("s", "S").RelativeTo("w"), Rz(0.1), Eigen::Vector3d(1, 0, 0))
                    .has_value());  // timeless
    ASSERT_TRUE(
        g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), Rz(0.2), Eigen::Vector3d(0, 1, 0), S(10))
            .has_value());
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), Rz(0.3), Eigen::Vector3d(0, 2, 0),
                          S(10.5))
                    .has_value());
    ASSERT_TRUE(g.AddTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"),
                           Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 1), S(10))
                    .has_value());
    ASSERT_TRUE(g.AddFrame("o2", "O").has_value());
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("o2").RelativeTo("o"), Rz(0.4), Eigen::Vector3d(0, 0, 1))
                    .has_value());  // constant
  }
  void ExpectRefused(const BuildResult& r, ErrorCode code, const std::string& before) {
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_EQ(Dump(g), before);
    EXPECT_EQ(CheckInvariants(g), "");
  }
  Graph g;
};

TEST_F(TimeErrorsTest, EveryAddErrorLeavesTheGraphUnchanged) {
  const std::string before = Dump(g);
  const Eigen::Quaterniond q = Rz(0.5);
  const Eigen::Vector3d p(1, 2, 3);
  // stamp_mismatch: a stamp for a timeless edge, none for a stamped edge.
  auto r = g.AddPose(PoseSpec::Of("s", "S").RelativeTo("w"), q, p, S(10));
  ExpectRefused(r, ErrorCode::kStampMismatch, before);
  EXPECT_NE(r.error().message.find("timeless"), std::string::npos) << r.error().message;
  ExpectRefused(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), q, p), ErrorCode::kStampMismatch,
                before);
  ExpectRefused(g.AddTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), p, p),
                ErrorCode::kStampMismatch, before);
  // stamp_too_old: older than newest (10.5) - window (1).
  r = g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), q, p, S(9.4));
  ExpectRefused(r, ErrorCode::kStampTooOld, before);
  EXPECT_NE(r.error().message.find("9.400 s"), std::string::npos) << r.error().message;
  // duplicate_stamp (policy reject): another value at 10.
  ExpectRefused(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), q, p, S(10)),
                ErrorCode::kDuplicateStamp, before);
  ExpectRefused(g.AddTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), p, p, S(10)),
                ErrorCode::kDuplicateStamp, before);
  // The same value again is a no-op.
  EXPECT_TRUE(
      g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), Rz(0.2), Eigen::Vector3d(0, 1, 1e-9), S(10))
          .has_value());
  EXPECT_EQ(Dump(g), before);
  // Order: the rules of the scene graph first (invalid_number before stamp_mismatch).
  ExpectRefused(
      g.AddPose(PoseSpec::Of("s", "S").RelativeTo("w"), q, Eigen::Vector3d(NAN, 0, 0), S(10)),
      ErrorCode::kInvalidNumber, before);
  // A conversion at a stamp with no values there: extrapolation (in the place of
  // pose_not_convertible).
  r = g.AddPose(PoseSpec::Of("x", "X").RelativeTo("w").ExpressedIn("o"), q, p, S(20));
  ExpectRefused(r, ErrorCode::kExtrapolation, before);
  EXPECT_NE(r.error().message.find("[10.000, 10.500] s"), std::string::npos) << r.error().message;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("y", "Y").RelativeTo("w"), q, p).has_value());
  const std::string with_y = Dump(g);
  ExpectRefused(g.AddTwist(TwistSpec::Of("y").RelativeTo("W").ExpressedIn("o"), p, p, S(20)),
                ErrorCode::kExtrapolation, with_y);
  // A stamped conversion within the samples works (and uses the interpolated value).
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("w").ExpressedIn("o"), q, p, S(10.25))
                  .has_value());
  // A constant edge with a stamp: validated, ignored.
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("o2").RelativeTo("o"), Rz(0.4), Eigen::Vector3d(0, 0, 1), S(3))
                  .has_value());
}

TEST_F(TimeErrorsTest, EveryRealTimeErrorLeavesTheGraphUnchanged) {
  auto po = g.FindPoseEdge("o", "w");
  auto ps = g.FindPoseEdge("s", "w");
  auto tw = g.FindTwistEdge("o", "W");
  ASSERT_TRUE(po && ps && tw);
  const std::string before = Dump(g);
  const Eigen::Vector3d p(1, 2, 3);
  EXPECT_EQ(g.SetPose(*ps, Rz(0.5), p, S(11)), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetPose(*po, Rz(0.5), p), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetPose(*po, Rz(0.5), p, S(9.0)), ErrorCode::kStampTooOld);
  EXPECT_EQ(g.SetPose(*po, Rz(0.5), p, S(10.5)), ErrorCode::kDuplicateStamp);
  EXPECT_EQ(g.SetTwist(*tw, p, p, S(10)), ErrorCode::kDuplicateStamp);
  EXPECT_EQ(g.SetTwist(*tw, p, p), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetPose(*po, Eigen::Quaterniond(2, 0, 0, 0), p, S(11)), ErrorCode::kInvalidRotation);
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(g.SetPose(*po, Rz(0.5), p, S(11)), ErrorCode::kOk);
  EXPECT_EQ(g.SetPose(*ps, Rz(0.5), p), ErrorCode::kOk);
}

TEST_F(TimeErrorsTest, QueryErrorsInOrder) {
  // stale: the twist edge's newest sample (10) is older than not_before.
  auto e = g.GetTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), Latest{S(10.2)});
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, ErrorCode::kStale);
  EXPECT_EQ(g.Describe(e.error()),
            "query failed (stale): twist of {o}|O wrt W is stale: its newest sample is at 10.000 "
            "s, older than not_before 10.200 s");
  EXPECT_TRUE(g.GetPose(kOinW, Latest{S(10.2)}).has_value());
  // extrapolation before stale.
  e = g.GetTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), At{S(12), {}, S(11)});
  EXPECT_EQ(e.error().code, ErrorCode::kExtrapolation);
  // no_pose_path before extrapolation.
  ASSERT_TRUE(g.AddFrame("z", "W").has_value());
  EXPECT_EQ(g.GetPose(PoseSpec::Of("o").RelativeTo("z"), At{S(99)}).error().code,
            ErrorCode::kNoPosePath);
  // Timeless edges have values at every time.
  auto s = g.GetPose(PoseSpec::Of("s").RelativeTo("w"), At{S(-1e9)});
  ASSERT_TRUE(s.has_value());
  EXPECT_FALSE(s->time.oldest.has_value());
  EXPECT_EQ(*s->time.time, S(-1e9));
}

TEST_F(TimeErrorsTest, LatestCommonTakesTheOldestNewestStamp) {
  // o has samples up to 10.5; x (made here) up to 10.25: latest common of x wrt o = 10.25.
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("x", "X").RelativeTo("w"), Rz(0), Eigen::Vector3d(5, 0, 0), S(10))
          .has_value());
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("x", "X").RelativeTo("w"), Rz(0), Eigen::Vector3d(6, 0, 0), S(10.25))
          .has_value());
  auto X = g.GetPose(PoseSpec::Of("x").RelativeTo("o"), LatestCommon{});
  ASSERT_TRUE(X.has_value());
  EXPECT_EQ(*X->time.time, S(10.25));
  auto Y = g.GetPose(PoseSpec::Of("x").RelativeTo("o"), At{S(10.25)});
  ExpectNear(X->value.value.translation, Y->value.value.translation, 0.0);
  // No stamped edge: as latest, no time.
  auto Z = g.GetPose(PoseSpec::Of("s").RelativeTo("w"), LatestCommon{});
  EXPECT_FALSE(Z->time.time.has_value());
  // Edges above the common ancestor are not used: o2 wrt o reads no sample.
  auto C = g.GetPose(PoseSpec::Of("o2").RelativeTo("o"), LatestCommon{});
  EXPECT_FALSE(C->time.oldest.has_value());
  // The diagnostic lists each edge with its samples.
  auto uses = g.ExplainPose(PoseSpec::Of("x").RelativeTo("o"), At{S(10.1)});
  ASSERT_TRUE(uses.has_value());
  ASSERT_EQ(uses->size(), 2u);
  for (const EdgeUse& u : *uses) {
    EXPECT_TRUE(u.stamped);
    EXPECT_EQ(u.relative_to, "w");
    EXPECT_EQ(*u.read_from, S(10));
  }
  EXPECT_EQ(*(*uses)[0].read_to, (*uses)[0].of == "x" ? S(10.25) : S(10.5));
}

// ---------------------------------------------------------------- history bookkeeping

TEST(TimeHistoryTest, WindowCapacityDuplicatesAndOutOfOrder) {
  TimeOptions o;
  o.window = Duration::Seconds(1);
  o.sample_capacity = 4;
  Graph g = *Graph::Create(o);
  const auto add = [&](double s, double x) {
    return g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w", "W"), Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(x, 0, 0), S(s));
  };
  const auto x_at = [&](double s) -> std::optional<double> {
    auto X = g.GetPose(kOinW, At{S(s)});
    if (!X) return std::nullopt;
    return X->value.value.translation.x();
  };
  ASSERT_TRUE(add(0.0, 0.0));
  ASSERT_TRUE(add(0.4, 4.0));
  ASSERT_TRUE(add(0.2, 2.0));  // out of order
  EXPECT_NEAR(*x_at(0.1), 1.0, 1e-12);
  EXPECT_NEAR(*x_at(0.3), 3.0, 1e-12);
  ASSERT_TRUE(add(0.6, 6.0));
  ASSERT_TRUE(add(0.8, 8.0));  // capacity 4: 0.0 dropped
  EXPECT_FALSE(x_at(0.1).has_value());
  EXPECT_NEAR(*x_at(0.3), 3.0, 1e-12);
  ASSERT_TRUE(add(1.2, 12.0));  // window: samples older than 0.2 dropped; capacity drops 0.2
  ASSERT_TRUE(add(1.4, 14.0));  // window drops 0.4 - exactly newest - W stays
  EXPECT_FALSE(x_at(0.5).has_value());
  EXPECT_NEAR(*x_at(0.7), 7.0, 1e-12);
  EXPECT_EQ(add(0.39, 0.0).error().code, ErrorCode::kStampTooOld);
  // Replace policy (default): another value at an existing stamp replaces it.
  ASSERT_TRUE(add(0.8, 80.0));
  EXPECT_NEAR(*x_at(0.8), 80.0, 1e-12);
  // A sample exactly at newest - window is kept.
  ASSERT_TRUE(add(2.4, 24.0));
  EXPECT_NEAR(*x_at(1.4), 14.0, 1e-12);
  EXPECT_TRUE(add(1.4, 14.0).has_value());
}

TEST(TimeHistoryTest, OptionsAreValidated) {
  TimeOptions o;
  o.window = Duration::Nanoseconds(0);
  EXPECT_EQ(Graph::Create(o).error().code, ErrorCode::kInvalidNumber);
  o.window = Duration::Seconds(-1);
  EXPECT_EQ(Graph::Create(o).error().code, ErrorCode::kInvalidNumber);
  o = TimeOptions{};
  o.sample_capacity = 1;
  EXPECT_EQ(Graph::Create(o).error().code, ErrorCode::kInvalidNumber);
  EXPECT_EQ(TimeOptions{}.sample_capacity, 1024u);
  EXPECT_EQ(TimeOptions{}.window, Duration::Seconds(10));
  EXPECT_LE(Graph::BytesPerPoseSample(), 72u);
}

TEST(TimeHistoryTest, StampsFromSecondsRoundExactly) {
  EXPECT_EQ(NanosecondsFromSeconds(1.5), 1500000000);
  EXPECT_EQ(NanosecondsFromSeconds(-2.25), -2250000000);
  EXPECT_EQ(NanosecondsFromSeconds(12.48),
            12480000000);  // 12.48 is 12.4799999999999997...: nearest
  EXPECT_EQ(NanosecondsFromSeconds(0.0009765625), 976563);  // 976562.5 ns exactly: away from zero
  EXPECT_EQ(NanosecondsFromSeconds(-0.0009765625), -976563);
  EXPECT_EQ(NanosecondsFromSeconds(std::ldexp(1.0, -31)), 0);  // 0.4657 ns
  EXPECT_EQ(NanosecondsFromSeconds(3 * std::ldexp(1.0, -31)), 1);
  EXPECT_EQ(NanosecondsFromSeconds(1e9), 1000000000000000000);
  EXPECT_EQ(NanosecondsFromSeconds(9.2e9), 9200000000000000000);
  EXPECT_FALSE(NanosecondsFromSeconds(9.2000001e9).has_value());
  EXPECT_FALSE(NanosecondsFromSeconds(-9.3e9).has_value());
  EXPECT_FALSE(NanosecondsFromSeconds(NAN).has_value());
  EXPECT_FALSE(NanosecondsFromSeconds(INFINITY).has_value());
  EXPECT_EQ(NanosecondsFromSeconds(1e-300), 0);
  // Huge stamps work end to end (saturating window arithmetic).
  Graph g;
  const Stamp lo = Stamp::Nanoseconds(INT64_MIN + 1), hi = Stamp::Nanoseconds(INT64_MAX);
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w", "W"), Rz(0), Eigen::Vector3d(0, 0, 0), lo)
          .has_value());
  EXPECT_EQ(
      g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w", "W"), Rz(0), Eigen::Vector3d(1, 0, 0), hi)
          .has_value(),
      true);
  auto X = g.GetPose(kOinW, At{hi});
  ASSERT_TRUE(X.has_value());
  EXPECT_EQ(X->value.value.translation.x(), 1.0);
  EXPECT_EQ(g.GetPose(kOinW, At{lo}).error().code,
            ErrorCode::kExtrapolation);  // dropped by the window
}

// ---------------------------------------------------------------- time travel

TEST(TimeTravelTest, ThePointSideAtOneTimeTheReferenceSideAtAnother) {
  // A gripper {g} on a moving base {b} (wrt world {w}), an object {o} seen at t1 by a camera
  // {c} fixed on the base. Where was the object at t1 relative to the gripper at t2, assuming
  // the object stayed fixed in the world?
  const ScrewMotion base;
  const Orbit object;
  Graph g;
  ASSERT_TRUE(g.AddBody("World").has_value());
  ASSERT_TRUE(g.AddFrame("w", "World").has_value());
  for (int i = 0; i <= 20; ++i) {
    const double s = i * 0.05;
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "Base").RelativeTo("w"), base.q(s), base.p(s), S(s))
                    .has_value());
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("o", "Obj").RelativeTo("w"), object.q(s), object.p(s), S(s))
                    .has_value());
  }
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("gr", "Base").RelativeTo("b"), Rx(0.3), Eigen::Vector3d(0.1, 0.2, 0.3))
          .has_value());
  const double t1 = 0.3, t2 = 0.8;
  auto X = g.GetPose(PoseSpec::Of("o").RelativeTo("gr"), TimeTravel{S(t1), S(t2), "w"});
  ASSERT_TRUE(X.has_value());
  EXPECT_EQ(*X->time.time, S(t1));
  EXPECT_EQ(*X->time.ref_time, S(t2));
  // By hand: X_GO = X_GB X_BW(t2) X_WO(t1).
  const Eigen::Quaterniond q_WG = base.q(t2) * Rx(0.3);
  const Eigen::Vector3d p_WG = base.q(t2) * Eigen::Vector3d(0.1, 0.2, 0.3) + base.p(t2);
  ExpectNear(X->value.value.rotation, Eigen::Quaterniond(q_WG.conjugate() * object.q(t1)), 1e-12);
  ExpectNear(X->value.value.translation, Eigen::Vector3d(q_WG.conjugate() * (object.p(t1) - p_WG)),
             1e-12);
  // Expressed in the world [w] (taken at t2) and as a position.
  auto P = g.GetPosition(PoseSpec::Of("o").RelativeTo("gr").ExpressedIn("w"),
                         TimeTravel{S(t1), S(t2), "w"});
  ASSERT_TRUE(P.has_value());
  ExpectNear(P->value.value, Eigen::Vector3d(object.p(t1) - p_WG), 1e-12);
  // Errors: the fixed frame unknown, not in the tree.
  auto e = g.GetPose(PoseSpec::Of("o").RelativeTo("gr"), TimeTravel{S(t1), S(t2), "nowhere"});
  EXPECT_EQ(e.error().code, ErrorCode::kUnknownFrame);
  EXPECT_TRUE(e.error().time.fixed_frame);
  ASSERT_TRUE(g.AddFrame("far", "World").has_value());
  EXPECT_EQ(
      g.GetPose(PoseSpec::Of("o").RelativeTo("gr"), TimeTravel{S(t1), S(t2), "far"}).error().code,
      ErrorCode::kNoPosePath);
  EXPECT_EQ(
      g.GetPose(PoseSpec::Of("o").RelativeTo("gr"), TimeTravel{S(t1), S(3), "w"}).error().code,
      ErrorCode::kExtrapolation);
}

}  // namespace
}  // namespace semgraph::core
