// Queries under a time policy (core/src/time_query.cc), the settled rules of docs/time.md:
//   §4  time travel: the fixed frame is resolved with the query's other frames (error order)
//   §5  twist source `poses`: nothing is extrapolated, the horizon is ignored; every edge the
//       query uses (also one that only moves the answer to its point or frame) needs samples
//       at the query time
//   §4  latest common with a horizon: t* before a used edge's first sample is integrated back
//       with the measured twist, within the horizon (LatestCommon{horizon}, new with this rule)
//
// Ground truth is analytic:
//   ScrewMotion  X(s) = (Rz(w s), c - Rz(w s) c + h s z): a one-parameter subgroup (X(0) = I),
//                so X(s0) Exp((s - s0) xi) = X(s) exactly; its screw twist xi = (c x w z + h z, w
//                z)
//   Orbit        X(s) = (Rz(a s) Rx(b s), rho (cos a s, sin a s, 0)); body twist
//                w = a Rx(b s)^T z + b x, v = R(s)^T dp/ds
// Read at sample stamps, or integrated exactly, so the expected values hold to rounding.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "support/tolerance.h"
#include "time_motions.h"

namespace semgraph::core {
namespace {

using semgraph::testing::ExpectNear;
using Graph = SceneGraph<coord::QuaternionBackend>;

using namespace time_motions;  // S, Rz, Rx, ScrewMotion, Orbit

// The error of a query result; code kOk when it answered (error() of an answer is not one).
template <class R>
QueryError ErrorOf(const R& r) {
  if (!r.has_value()) return r.error();
  QueryError ok;
  ok.code = ErrorCode::kOk;
  return ok;
}

// Samples at from, from + step, ..., to (k * step, no accumulated rounding).
template <class F>
void Sample(double from, double to, double step, F&& f) {
  const int n = static_cast<int>(std::lround((to - from) / step));
  for (int i = 0; i <= n; ++i) f(from + i * step);
}

// ---------------------------------------------------------------- §4 time travel, error order

// W <- {a}|A (Orbit, stamped 0..1), W <- {g}|G (timeless), {far}|W alone in its tree.
template <class G>
G TravelGraph() {
  G g;
  const Orbit orbit;
  EXPECT_TRUE(g.AddBody("W").has_value());
  EXPECT_TRUE(g.AddFrame("w", "W").has_value());
  EXPECT_TRUE(g.AddFrame("far", "W").has_value());
  Sample(0, 1, 0.1, [&](double s) {
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w"), orbit.q(s), orbit.p(s), S(s))
                    .has_value());
  });
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("g", "G").RelativeTo("w"), Rz(0.5), Eigen::Vector3d(1, 2, 3))
                  .has_value());
  return g;
}

void ExpectFixedFrameError(const QueryResult<Timed<Graph::Pose>>& r, ErrorCode code) {
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(ErrorOf(r).code, code);
  EXPECT_TRUE(ErrorOf(r).time.fixed_frame) << "the error is not the fixed frame's";
}

TEST(TimeQueryTravelTest, TheFixedFrameIsResolvedWithTheQuerysOtherFrames) {
  const Graph g = TravelGraph<Graph>();
  const auto travel = [](std::string_view fixed, Duration horizon = {}) {
    return TimeTravel{S(0.3), S(0.6), fixed, horizon};
  };
  const PoseSpec good = PoseSpec::Of("a").RelativeTo("g");
  // unknown_frame (the fixed frame) before unknown_body (the query's reference body).
  const PoseSpec unknown_body = PoseSpec::Of("a").RelativeTo("g", "Nobody");
  ExpectFixedFrameError(g.GetPose(unknown_body, travel("nowhere")), ErrorCode::kUnknownFrame);
  // ... and before frame_body_mismatch and the query's own no_pose_path.
  ExpectFixedFrameError(g.GetPose(PoseSpec::Of("a", "G").RelativeTo("g"), travel("nowhere")),
                        ErrorCode::kUnknownFrame);
  ExpectFixedFrameError(g.GetPose(PoseSpec::Of("a").RelativeTo("far"), travel("nowhere")),
                        ErrorCode::kUnknownFrame);
  // Near misses: a known fixed frame leaves the query's own errors.
  EXPECT_EQ(ErrorOf(g.GetPose(unknown_body, travel("w"))).code, ErrorCode::kUnknownBody);
  EXPECT_FALSE(ErrorOf(g.GetPose(unknown_body, travel("w"))).time.fixed_frame);
  EXPECT_EQ(ErrorOf(g.GetPose(PoseSpec::Of("a", "G").RelativeTo("g"), travel("w"))).code,
            ErrorCode::kFrameBodyMismatch);
  // The query's unknown frame comes before the fixed frame's (one step, query fields first).
  auto e = g.GetPose(PoseSpec::Of("nope").RelativeTo("g"), travel("nowhere"));
  EXPECT_EQ(ErrorOf(e).code, ErrorCode::kUnknownFrame);
  EXPECT_FALSE(ErrorOf(e).time.fixed_frame);
  // invalid_name of the fixed frame before the query's unknown_frame and before invalid_number.
  ExpectFixedFrameError(g.GetPose(PoseSpec::Of("nope").RelativeTo("g"), travel("")),
                        ErrorCode::kInvalidName);
  ExpectFixedFrameError(g.GetPose(good, travel("", Duration::Nanoseconds(-1))),
                        ErrorCode::kInvalidName);
  EXPECT_EQ(ErrorOf(g.GetPose(PoseSpec::Of("").RelativeTo("g"), travel(""))).code,
            ErrorCode::kInvalidName);
  EXPECT_FALSE(ErrorOf(g.GetPose(PoseSpec::Of("").RelativeTo("g"), travel(""))).time.fixed_frame);
  // invalid_number (a negative horizon) before the fixed frame's unknown_frame.
  EXPECT_EQ(ErrorOf(g.GetPose(good, travel("nowhere", Duration::Nanoseconds(-1)))).code,
            ErrorCode::kInvalidNumber);
  // Position and orientation resolve it the same way.
  const PoseSpec p_unknown_body = PoseSpec::Of("a").RelativeTo("g", "Nobody");
  auto P = g.GetPosition(p_unknown_body, travel("nowhere"));
  EXPECT_EQ(ErrorOf(P).code, ErrorCode::kUnknownFrame);
  EXPECT_TRUE(ErrorOf(P).time.fixed_frame);
  auto R = g.GetOrientation(p_unknown_body, travel("nowhere"));
  EXPECT_EQ(ErrorOf(R).code, ErrorCode::kUnknownFrame);
  EXPECT_TRUE(ErrorOf(R).time.fixed_frame);
  EXPECT_EQ(ErrorOf(g.GetPosition(p_unknown_body, travel("w"))).code, ErrorCode::kUnknownBody);
  // The message speaks of the fixed frame, not of a field of the query.
  EXPECT_EQ(g.Describe(ErrorOf(g.GetPose(unknown_body, travel("nowhere"))), unknown_body),
            "query failed (unknown_frame): the fixed frame of the time travel does not exist");
}

TEST(TimeQueryTravelTest, AFixedFrameOutsideTheTreeComesBeforeARepresentationConstraint) {
  using HGraph = SceneGraph<coord::HomogeneousBackend>;
  const HGraph g = TravelGraph<HGraph>();
  // A homogeneous transform cannot be expressed in [w] != [g]: representation_constraint.
  const PoseSpec in_w = PoseSpec::Of("a").RelativeTo("g").ExpressedIn("w");
  EXPECT_EQ(ErrorOf(g.GetPose(in_w, TimeTravel{S(0.3), S(0.6), "w"})).code,
            ErrorCode::kRepresentationConstraint);
  // no_pose_path (the fixed frame not in the query's tree) comes first.
  auto e = g.GetPose(in_w, TimeTravel{S(0.3), S(0.6), "far"});
  EXPECT_EQ(ErrorOf(e).code, ErrorCode::kNoPosePath);
  EXPECT_TRUE(ErrorOf(e).time.fixed_frame);
  // Near miss: the same travel without the constraint answers, with the analytic value
  // X_GA = X_WG^-1 X_WA(0.3) (the point side at 0.3; the reference side is timeless).
  const Orbit orbit;
  auto X = g.GetPose(PoseSpec::Of("a").RelativeTo("g"), TimeTravel{S(0.3), S(0.6), "w"});
  ASSERT_TRUE(X.has_value());
  const Eigen::Matrix4d T = X->value.value.matrix();
  const Eigen::Matrix3d R_GA = (Rz(0.5).conjugate() * orbit.q(0.3)).toRotationMatrix();
  const Eigen::Vector3d p_GA = Rz(0.5).conjugate() * (orbit.p(0.3) - Eigen::Vector3d(1, 2, 3));
  EXPECT_LE((T.topLeftCorner<3, 3>() - R_GA).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((T.topRightCorner<3, 1>() - p_GA).cwiseAbs().maxCoeff(), 1e-12);
}

// ---------------------------------------------------------------- §5 source poses, no
// extrapolation

// W <- {a}|A (ScrewMotion, stamped 0..1) <- {o}|O (Orbit, stamped 0..0.5 only), with the
// measured twist of O wrt A (so a horizon could integrate the edge o <- a past 0.5).
Graph PosesGraph() {
  Graph g;
  const ScrewMotion screw;
  const Orbit orbit;
  EXPECT_TRUE(g.AddBody("W").has_value());
  EXPECT_TRUE(g.AddFrame("w", "W").has_value());
  Sample(0, 1, 0.1, [&](double s) {
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w"), screw.q(s), screw.p(s), S(s))
                    .has_value());
  });
  Sample(0, 0.5, 0.05, [&](double s) {
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("a"), orbit.q(s), orbit.p(s), S(s))
                    .has_value());
    EXPECT_TRUE(g.AddTwist(TwistSpec::Of("o").RelativeTo("A").ExpressedIn("o"), orbit.v(s),
                           orbit.omega(s), S(s))
                    .has_value());
  });
  return g;
}

struct TwistValue {
  Eigen::Vector3d linear, angular;
};
// The twist of A wrt W at the point of A at {o}, in [w], at a sample stamp s of both edges.
TwistValue ExpectedTwistOfAAtO(double s) {
  const ScrewMotion screw;
  const Orbit orbit;
  const Eigen::Vector3d w_WA_W = screw.q(s) * screw.omega();
  const Eigen::Vector3d p_AoOo_W = screw.q(s) * orbit.p(s);
  return {screw.q(s) * screw.v() + w_WA_W.cross(p_AoOo_W), w_WA_W};
}

TEST(TimeQueryPosesTest, AnEdgeThatOnlyMovesThePointIsNotExtrapolated) {
  const Graph g = PosesGraph();
  const TwistSpec at_o = TwistSpec::Of("o", "A").RelativeTo("W").ExpressedIn("w");
  const Duration horizon = Duration::Milliseconds(500);
  // Near miss: at 0.3 s (a stamp of both edges) the derivative of a <- w moved to o, analytic;
  // the horizon is ignored (nothing extrapolated).
  auto V = g.GetTwist(at_o, At{S(0.3), horizon}, TwistSource::kPoses);
  ASSERT_TRUE(V.has_value());
  const auto expected = ExpectedTwistOfAAtO(0.3);
  ExpectNear(V->value.linear, expected.linear, 1e-12);
  ExpectNear(V->value.angular, expected.angular, 1e-12);
  EXPECT_FALSE(V->time.extrapolated);
  // At 0.7 s the edge o <- a (read only to move the answer to o) has samples in [0, 0.5]: even
  // with a 0.5 s horizon and the twist of O wrt A at hand, extrapolation.
  auto e = g.GetTwist(at_o, At{S(0.7), horizon}, TwistSource::kPoses);
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(ErrorOf(e).code, ErrorCode::kExtrapolation);
  EXPECT_EQ(g.Describe(ErrorOf(e), at_o),
            "query failed (extrapolation): pose of {o}|O wrt {a}|A has samples in [0.000, 0.500] "
            "s; asked 0.700 s");
  // The same through the linear and angular velocity queries.
  EXPECT_EQ(ErrorOf(g.GetLinearVelocity(at_o, At{S(0.7), horizon}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
  // The source twists honours the horizon: the twist edge holds its sample at 0.5 s.
  auto held = g.GetTwist(TwistSpec::Of("o").RelativeTo("A").ExpressedIn("o"), At{S(0.7), horizon});
  ASSERT_TRUE(held.has_value());
  EXPECT_TRUE(held->time.extrapolated);
  ExpectNear(held->value.angular, Orbit().omega(0.5), 1e-12);
}

TEST(TimeQueryPosesTest, AnEdgeThatOnlyMovesTheFrameIsNotExtrapolated) {
  const Graph g = PosesGraph();
  // The twist of A wrt W at a, expressed in [o]: the edge o <- a only changes the frame.
  const TwistSpec in_o = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("o");
  const Duration horizon = Duration::Milliseconds(500);
  auto V = g.GetTwist(in_o, At{S(0.4), horizon}, TwistSource::kPoses);
  ASSERT_TRUE(V.has_value());
  const ScrewMotion screw;
  const Orbit orbit;
  // In [a] the body twist (v, w) of the screw; [o] has R_AO = orbit.q(0.4).
  ExpectNear(V->value.angular, Eigen::Vector3d(orbit.q(0.4).conjugate() * screw.omega()), 1e-12);
  ExpectNear(V->value.linear, Eigen::Vector3d(orbit.q(0.4).conjugate() * screw.v()), 1e-12);
  EXPECT_EQ(ErrorOf(g.GetTwist(in_o, At{S(0.7), horizon}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
  const TwistSpec w_in_o = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("o");
  EXPECT_EQ(ErrorOf(g.GetAngularVelocity(w_in_o, At{S(0.7), horizon}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
  // The differentiated edge itself is never extrapolated either.
  EXPECT_EQ(ErrorOf(g.GetTwist(in_o, At{S(1.2), horizon}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
}

TEST(TimeQueryPosesTest, ACompiledTwistFromPosesIgnoresTheHorizonToo) {
  const Graph g = PosesGraph();
  const TwistSpec at_o = TwistSpec::Of("o", "A").RelativeTo("W").ExpressedIn("w");
  auto c = g.CompileTwist(at_o, TwistSource::kPoses);
  ASSERT_TRUE(c.has_value());
  Eigen::Vector3d v, w;
  TimeReport report;
  ASSERT_EQ(c->Evaluate(v, w, At{S(0.3), Duration::Milliseconds(500)}, report), ErrorCode::kOk);
  const auto expected = ExpectedTwistOfAAtO(0.3);
  ExpectNear(v, expected.linear, 1e-12);
  ExpectNear(w, expected.angular, 1e-12);
  EXPECT_EQ(c->Evaluate(v, w, At{S(0.7), Duration::Milliseconds(500)}, report),
            ErrorCode::kExtrapolation);
  // A negative horizon is still invalid_number (ignored, not unchecked).
  EXPECT_EQ(c->Evaluate(v, w, At{S(0.3), Duration::Nanoseconds(-1)}, report),
            ErrorCode::kInvalidNumber);
  EXPECT_EQ(
      ErrorOf(g.GetTwist(at_o, At{S(0.3), Duration::Nanoseconds(-1)}, TwistSource::kPoses)).code,
      ErrorCode::kInvalidNumber);
}

// The untimed Evaluate of a compiled twist from poses reads the newest samples, as the one-shot
// query under Latest and the compiled query with covariance do: the same answer or the same
// error. W <- {a}|A (ScrewMotion) with `samples` stamps 0, 0.1, ... (none: a timeless edge at
// X(0.5)).
Graph ScrewGraph(int samples) {
  Graph g;
  const ScrewMotion screw;
  EXPECT_TRUE(g.AddBody("W").has_value());
  EXPECT_TRUE(g.AddFrame("w", "W").has_value());
  const PoseSpec a = PoseSpec::Of("a", "A").RelativeTo("w");
  if (samples == 0) {
    EXPECT_TRUE(g.AddPose(a, screw.q(0.5), screw.p(0.5)).has_value());
  }
  for (int i = 0; i < samples; ++i) {
    const double s = 0.1 * i;
    EXPECT_TRUE(g.AddPose(a, screw.q(s), screw.p(s), S(s)).has_value());
  }
  return g;
}

TEST(TimeQueryPosesTest, AnUntimedCompiledTwistFromPosesOfOneSampleIsExtrapolation) {
  Graph g = ScrewGraph(1);
  const TwistSpec spec = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("w");
  // The one-shot query: one sample has no derivative.
  EXPECT_EQ(ErrorOf(g.GetTwist(spec, Latest{}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
  EXPECT_EQ(ErrorOf(g.GetTwist(spec, At{S(0)}, TwistSource::kPoses)).code,
            ErrorCode::kExtrapolation);
  // The compiled query, untimed and under Latest: the same code, the outputs untouched.
  auto c = g.CompileTwist(spec, TwistSource::kPoses);
  ASSERT_TRUE(c.has_value());
  const Eigen::Vector3d sentinel(7, 8, 9);
  Eigen::Vector3d v = sentinel, w = sentinel;
  EXPECT_EQ(c->Evaluate(v, w), ErrorCode::kExtrapolation);
  ExpectNear(v, sentinel, 0.0);
  ExpectNear(w, sentinel, 0.0);
  EXPECT_EQ(ErrorOf(c->Evaluate()).code, ErrorCode::kExtrapolation);
  TimeReport report;
  EXPECT_EQ(c->Evaluate(v, w, Latest{}, report), ErrorCode::kExtrapolation);
  // The compiled query with covariance, untimed.
  auto cc = g.CompileTwistWithCovariance(spec, TwistSource::kPoses);
  ASSERT_TRUE(cc.has_value());
  Covariance6 S_V = Covariance6::Zero();
  EXPECT_EQ(cc->Evaluate(v, w, S_V), ErrorCode::kExtrapolation);
  // A second sample gives the derivative (a one-parameter subgroup: exactly its screw twist).
  auto edge = g.FindPoseEdge("a", "w");
  ASSERT_TRUE(edge.has_value());
  const ScrewMotion screw;
  ASSERT_EQ(g.SetPose(*edge, screw.q(0.1), screw.p(0.1), S(0.1)), ErrorCode::kOk);
  ASSERT_EQ(c->Evaluate(v, w), ErrorCode::kOk);
  ExpectNear(v, Eigen::Vector3d(screw.q(0.1) * screw.v()), 1e-12);
  ExpectNear(w, Eigen::Vector3d(screw.q(0.1) * screw.omega()), 1e-12);
}

TEST(TimeQueryPosesTest, AnUntimedCompiledTwistFromPosesOfATimelessEdgeIsZero) {
  const Graph g = ScrewGraph(0);
  const TwistSpec spec = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("w");
  auto c = g.CompileTwist(spec, TwistSource::kPoses);
  ASSERT_TRUE(c.has_value());
  Eigen::Vector3d v(7, 8, 9), w(7, 8, 9);
  ASSERT_EQ(c->Evaluate(v, w), ErrorCode::kOk);  // a constant pose does not move
  ExpectNear(v, Eigen::Vector3d::Zero(), 0.0);
  ExpectNear(w, Eigen::Vector3d::Zero(), 0.0);
  auto one_shot = g.GetTwist(spec, Latest{}, TwistSource::kPoses);
  ASSERT_TRUE(one_shot.has_value());
  ExpectNear(one_shot->value.linear, Eigen::Vector3d::Zero(), 0.0);
  ExpectNear(one_shot->value.angular, Eigen::Vector3d::Zero(), 0.0);
}

TEST(TimeQueryPosesTest, AnUntimedCompiledTwistFromPosesEqualsTheOneShotUnderLatest) {
  // Newest sample at 1 s: the segment before it, the screw twist moved to [w] at X(1).
  const Graph g = ScrewGraph(11);
  const ScrewMotion screw;
  const TwistSpec spec = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("w");
  auto c = g.CompileTwist(spec, TwistSource::kPoses);
  ASSERT_TRUE(c.has_value());
  Eigen::Vector3d v, w;
  ASSERT_EQ(c->Evaluate(v, w), ErrorCode::kOk);
  ExpectNear(v, Eigen::Vector3d(screw.q(1) * screw.v()), 1e-12);
  ExpectNear(w, Eigen::Vector3d(screw.q(1) * screw.omega()), 1e-12);
  auto one_shot = g.GetTwist(spec, Latest{}, TwistSource::kPoses);
  ASSERT_TRUE(one_shot.has_value());
  ExpectNear(v, one_shot->value.linear, 1e-12);
  ExpectNear(w, one_shot->value.angular, 1e-12);
  // Two differentiated-or-moving edges with different newest stamps (a at 1 s, o at 0.5 s).
  const Graph p = PosesGraph();
  const TwistSpec at_o = TwistSpec::Of("o", "A").RelativeTo("W").ExpressedIn("w");
  auto co = p.CompileTwist(at_o, TwistSource::kPoses);
  ASSERT_TRUE(co.has_value());
  ASSERT_EQ(co->Evaluate(v, w), ErrorCode::kOk);
  auto expected = p.GetTwist(at_o, Latest{}, TwistSource::kPoses);
  ASSERT_TRUE(expected.has_value());
  ExpectNear(v, expected->value.linear, 1e-12);
  ExpectNear(w, expected->value.angular, 1e-12);
}

// ---------------------------------------------------------------- §4 latest common with a horizon

// W <- {a}|A (Orbit, stamped 0..1 s) and W <- {o}|O (ScrewMotion, stamped 2..3 s, with its
// measured screw twist at the same stamps): latest common of o wrt a is t* = 1 s, a second
// before o's first sample.
Graph LatestCommonGraph(bool with_twist) {
  Graph g;
  const ScrewMotion screw;
  const Orbit orbit;
  EXPECT_TRUE(g.AddBody("W").has_value());
  EXPECT_TRUE(g.AddFrame("w", "W").has_value());
  Sample(0, 1, 0.1, [&](double s) {
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w"), orbit.q(s), orbit.p(s), S(s))
                    .has_value());
  });
  Sample(2, 3, 0.1, [&](double s) {
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("o", "O").RelativeTo("w"), screw.q(s), screw.p(s), S(s))
                    .has_value());
    if (with_twist) {
      EXPECT_TRUE(g.AddTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("o"), screw.v(),
                             screw.omega(), S(s))
                      .has_value());
    }
  });
  return g;
}

TEST(TimeQueryLatestCommonTest, AnEdgeStartingAfterTStarIsIntegratedBackWithinTheHorizon) {
  const Graph g = LatestCommonGraph(/*with_twist=*/true);
  const PoseSpec o_in_a = PoseSpec::Of("o").RelativeTo("a");
  // X_AO(1) = X_WA(1)^-1 X_WO(1): the screw motion integrated back from its sample at 2 s by
  // its constant twist is the motion at 1 s exactly.
  const ScrewMotion screw;
  const Orbit orbit;
  const Eigen::Quaterniond q_AO = orbit.q(1).conjugate() * screw.q(1);
  const Eigen::Vector3d p_AO = orbit.q(1).conjugate() * (screw.p(1) - orbit.p(1));
  auto X = g.GetPose(o_in_a, LatestCommon{Duration::Milliseconds(1500)});
  ASSERT_TRUE(X.has_value()) << g.Describe(X.error(), o_in_a);
  ExpectNear(X->value.value.rotation, q_AO, 1e-12);
  ExpectNear(X->value.value.translation, p_AO, 1e-12);
  ASSERT_TRUE(X->time.time.has_value());
  EXPECT_EQ(*X->time.time, S(1));
  EXPECT_TRUE(X->time.extrapolated);
  EXPECT_EQ(*X->time.oldest, S(1));  // a's sample at 1 s
  EXPECT_EQ(*X->time.newest, S(2));  // o's first sample and the twist read there
  // The same as At{t*} with that horizon, and through a compiled query.
  auto Y = g.GetPose(o_in_a, At{S(1), Duration::Milliseconds(1500)});
  ASSERT_TRUE(Y.has_value());
  ExpectNear(Y->value.value.translation, X->value.value.translation, 0.0);
  auto c = g.CompilePose(o_in_a);
  ASSERT_TRUE(c.has_value());
  coord::QuaternionBackend::PoseCoords Z;
  TimeReport report;
  ASSERT_EQ(c->Evaluate(Z, LatestCommon{Duration::Milliseconds(1500)}, report), ErrorCode::kOk);
  ExpectNear(Z.translation, p_AO, 1e-12);
  EXPECT_EQ(*report.time, S(1));
  EXPECT_TRUE(report.extrapolated);
  // Near misses: no horizon, or one shorter than the gap (1 s): extrapolation, naming o.
  for (const LatestCommon policy : {LatestCommon{}, LatestCommon{Duration::Milliseconds(999)}}) {
    auto e = g.GetPose(o_in_a, policy);
    ASSERT_FALSE(e.has_value());
    EXPECT_EQ(g.Describe(e.error(), o_in_a),
              "query failed (extrapolation): pose of {o}|O wrt {w}|W has samples in [2.000, 3.000] "
              "s; asked 1.000 s");
  }
  // A negative horizon is invalid_number.
  EXPECT_EQ(ErrorOf(g.GetPose(o_in_a, LatestCommon{Duration::Nanoseconds(-1)})).code,
            ErrorCode::kInvalidNumber);
}

TEST(TimeQueryLatestCommonTest, WithoutATwistPathTheHorizonDoesNotHelp) {
  const Graph g = LatestCommonGraph(/*with_twist=*/false);
  EXPECT_EQ(
      ErrorOf(g.GetPose(PoseSpec::Of("o").RelativeTo("a"), LatestCommon{Duration::Seconds(5)}))
          .code,
      ErrorCode::kExtrapolation);
  // Near miss: a query that uses only o has t* = 3 s, inside its samples.
  const ScrewMotion screw;
  auto X = g.GetPose(PoseSpec::Of("o").RelativeTo("w"), LatestCommon{Duration::Seconds(5)});
  ASSERT_TRUE(X.has_value());
  EXPECT_FALSE(X->time.extrapolated);
  ExpectNear(X->value.value.translation, screw.p(3), 1e-12);
}

}  // namespace
}  // namespace semgraph::core
