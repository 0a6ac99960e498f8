// core/src/uncertainty.cc and core/include/semgraph/core/propagate.h: covariances on edges and
// the first-order covariance of every query's answer.
//
// Truth is Monte Carlo (docs/uncertainty.md §3): for random scenes, each sample draws every
// edge's perturbation from its covariance, applies it exactly (p + dp, Exp(dth) R; v + dv,
// w + dw) to the values, builds the perturbed scene from scratch and asks the same query; the
// sample covariance of the answer's perturbation (p' - p, Log(M' M^T); v' - v, w' - w) must
// agree with the first-order answer within the sampling error: every entry within 5 standard
// errors of a sample covariance of n normal draws, se_ij = sqrt((S_ii S_jj + S_ij^2) / n)
// (plus 1e-5 max S_ii for the second-order terms, at perturbations of 1e-3). A planted sign
// error (the rotation rows of the Jacobians negated) must fail that check.
// Then the checks of §2 with the graph unchanged, and conversions of covariances given in
// another form.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/sanitized.h"

namespace semgraph::core {
namespace {

using Graph = SceneGraph<coord::QuaternionBackend>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

Eigen::Matrix3d ExpR(const Eigen::Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(Eigen::AngleAxisd(th, w / th));
}
Eigen::Vector3d LogR(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// A scene: bodies B0..B4 with frames f_k, g_k (g_k fixed to B_k under f_k: a constant edge
// with a calibration covariance); f_k (k > 0) under a random frame of an earlier body; twist
// edges B_parent -> {f_k}. Every value carries a random covariance of order 1e-6.
struct PoseEdge {
  std::string head, head_body, tail, tail_body;
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  Covariance6 S;
};
struct TwistEdge {
  std::string point, body, ref_body;
  Eigen::Vector3d v, w;
  Covariance6 S;
};
struct Scene {
  std::vector<PoseEdge> poses;
  std::vector<TwistEdge> twists;
};

Covariance6 RandomCovariance(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return scale * (L * L.transpose() / 6.0);
}
Scene RandomScene(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Scene s;
  const auto frame = [](char c, int k) { return std::string(1, c) + std::to_string(k); };
  const auto body = [](int k) { return "B" + std::to_string(k); };
  for (int k = 0; k < 5; ++k) {
    if (k > 0) {
      const int parent = std::uniform_int_distribution<int>(0, k - 1)(rng);
      const char which = std::uniform_int_distribution<int>(0, 1)(rng) ? 'f' : 'g';
      s.poses.push_back({frame('f', k), body(k), frame(which, parent), body(parent),
                         ExpR(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                         Eigen::Vector3d(n(rng), n(rng), n(rng)), RandomCovariance(rng, 1e-6)});
      s.twists.push_back({frame('f', k), body(k), body(parent),
                          Eigen::Vector3d(n(rng), n(rng), n(rng)),
                          Eigen::Vector3d(n(rng), n(rng), n(rng)), RandomCovariance(rng, 1e-6)});
    }
    s.poses.push_back({frame('g', k), body(k), frame('f', k), body(k),
                       ExpR(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                       Eigen::Vector3d(n(rng), n(rng), n(rng)), RandomCovariance(rng, 1e-6)});
  }
  return s;
}

// Builds the scene; with `rng`, each value perturbed by a draw from its covariance.
void Build(const Scene& s, Graph& g, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const auto draw = [&](const Covariance6& S) {
    Vector6 z;
    for (int i = 0; i < 6; ++i) z(i) = n(*rng);
    return Vector6(S.llt().matrixL() * z);
  };
  for (const PoseEdge& e : s.poses) {
    const auto spec = PoseSpec::Of(e.head, e.head_body).RelativeTo(e.tail, e.tail_body);
    Eigen::Matrix3d R = e.R;
    Eigen::Vector3d p = e.p;
    if (rng) {
      const Vector6 d = draw(e.S);
      R = ExpR(d.tail<3>()) * R;
      p += d.head<3>();
      ASSERT_TRUE(g.AddPose(spec, R, p).has_value());
    } else {
      ASSERT_TRUE(g.AddPose(spec, R, p, CovarianceInput{&e.S}).has_value());
    }
  }
  for (const TwistEdge& e : s.twists) {
    const auto spec = TwistSpec::Of(e.point, e.body).RelativeTo(e.ref_body).ExpressedIn(e.point);
    if (rng) {
      const Vector6 d = draw(e.S);
      ASSERT_TRUE(g.AddTwist(spec, e.v + d.head<3>(), e.w + d.tail<3>()).has_value());
    } else {
      const auto ok = g.AddTwist(spec, e.v, e.w, CovarianceInput{&e.S});
      ASSERT_TRUE(ok.has_value()) << ok.error().message;
    }
  }
}

// The Monte Carlo check: the worst entry's distance in standard errors.
template <int N>
double WorstZ(const Eigen::Matrix<double, N, N>& S,
              const std::vector<Eigen::Matrix<double, N, 1>>& d) {
  const double n = static_cast<double>(d.size());
  Eigen::Matrix<double, N, 1> mean = Eigen::Matrix<double, N, 1>::Zero();
  for (const auto& x : d) mean += x;
  mean /= n;
  Eigen::Matrix<double, N, N> C = Eigen::Matrix<double, N, N>::Zero();
  for (const auto& x : d) C += (x - mean) * (x - mean).transpose();
  C /= n - 1.0;
  const double floor = 1e-5 * S.diagonal().maxCoeff();
  double worst = 0.0;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      const double se = std::sqrt((S(i, i) * S(j, j) + S(i, j) * S(i, j)) / n) + floor;
      worst = std::max(worst, std::abs(C(i, j) - S(i, j)) / se);
    }
  }
  return worst;
}

constexpr int kSamples = semgraph::testing::Draws(20000);  // fewer under ASan (sanitized.h)
constexpr double kMaxZ = 5.0;

struct Queries {
  PoseSpec pose;
  TwistSpec twist, angular;
};
Queries RandomQueries(std::mt19937& rng) {
  static const std::string names[] = {"f0", "g0", "f1", "g1", "f2", "g2", "f3", "g3", "f4", "g4"};
  static const std::string bodies[] = {"B0", "B1", "B2", "B3", "B4"};
  std::uniform_int_distribution<int> body(0, 4), side(0, 1), any(0, 9);
  const int ca = body(rng), cb = (ca + 1 + std::uniform_int_distribution<int>(0, 3)(rng)) % 5;
  const std::string& a = names[2 * ca + side(rng)];
  const std::string& e = names[2 * ca + side(rng)];
  const std::string& b = names[2 * cb + side(rng)];
  const std::string& f = names[2 * cb + side(rng)];
  const std::string& r = names[any(rng)];
  Queries q;
  q.pose = PoseSpec::Of(a, bodies[ca])
               .RelativeTo(b, bodies[cb])
               .ExpressedIn(r)
               .AtPoint(e)
               .RelativeToPoint(f);
  int cd = body(rng);
  if (cd == ca) cd = (ca + 1) % 5;
  q.twist = TwistSpec::Of(e, bodies[ca]).RelativeTo(bodies[cd]).ExpressedIn(r);
  q.angular = TwistSpec::Of(r, bodies[ca]).RelativeTo(bodies[cd]).ExpressedIn(r);
  return q;
}

Vector6 PoseDelta(const Graph::Pose& X0, const Graph::Pose& X1) {
  const Eigen::Isometry3d A = X0.ToIsometry(), B = X1.ToIsometry();
  Vector6 d;
  d << B.translation() - A.translation(), LogR(B.linear() * A.linear().transpose());
  return d;
}

// Every query kind on random scenes, against Monte Carlo; and the planted sign error fails.
TEST(Uncertainty, FirstOrderCovarianceMatchesMonteCarloForEveryQueryKind) {
  std::mt19937 rng(20261204);
  for (int scene_index = 0; scene_index < 3; ++scene_index) {
    const Scene scene = RandomScene(rng);
    Graph g;
    Build(scene, g, nullptr);
    const Queries q = RandomQueries(rng);
    const auto pose = g.GetPoseWithCovariance(q.pose);
    const auto position = g.GetPositionWithCovariance(q.pose);
    const auto orientation = g.GetOrientationWithCovariance(q.pose);
    const auto twist = g.GetTwistWithCovariance(q.twist);
    const auto linear = g.GetLinearVelocityWithCovariance(q.twist);
    const auto angular = g.GetAngularVelocityWithCovariance(q.angular);
    ASSERT_TRUE(pose && position && orientation && twist && linear && angular);
    std::vector<Vector6> d_pose, d_twist;
    std::vector<Eigen::Vector3d> d_position, d_orientation, d_linear, d_angular;
    for (int i = 0; i < kSamples; ++i) {
      Graph h;
      Build(scene, h, &rng);
      const auto X = h.GetPose(q.pose);
      const auto V = h.GetTwist(q.twist);
      const auto W = h.GetAngularVelocity(q.angular);
      ASSERT_TRUE(X && V && W);
      const Vector6 dX = PoseDelta(pose->value, *X);
      d_pose.push_back(dX);
      d_position.push_back(h.GetPosition(q.pose)->value - position->value.value);
      d_orientation.push_back(dX.tail<3>());
      Vector6 dV;
      dV << V->linear - twist->value.linear, V->angular - twist->value.angular;
      d_twist.push_back(dV);
      d_linear.push_back(dV.head<3>());
      d_angular.push_back(W->value - angular->value.value);
    }
    SCOPED_TRACE("scene " + std::to_string(scene_index));
    EXPECT_GT(pose->covariance.trace(), 1e-7);  // the answers are uncertain at all
    EXPECT_GT(twist->covariance.trace(), 1e-7);
    EXPECT_LT(WorstZ<6>(pose->covariance, d_pose), kMaxZ) << pose->covariance;
    EXPECT_LT(WorstZ<3>(position->covariance, d_position), kMaxZ);
    EXPECT_LT(WorstZ<3>(orientation->covariance, d_orientation), kMaxZ);
    EXPECT_LT(WorstZ<6>(twist->covariance, d_twist), kMaxZ) << twist->covariance;
    EXPECT_LT(WorstZ<3>(linear->covariance, d_linear), kMaxZ);
    EXPECT_LT(WorstZ<3>(angular->covariance, d_angular), kMaxZ);
    // The planted sign error: the rotation rows of every Jacobian negated (D J, D = diag(I, -I))
    // flip the position-rotation correlation; the same check rejects it.
    Vector6 flip;
    flip << 1, 1, 1, -1, -1, -1;
    const Covariance6 wrong = flip.asDiagonal() * pose->covariance * flip.asDiagonal();
    EXPECT_GT(WorstZ<6>(wrong, d_pose), 3.0 * kMaxZ);
    Vector6 flip_v;  // the angular rows of a twist Jacobian negated
    flip_v << 1, 1, 1, -1, -1, -1;
    const Covariance6 wrong_v = flip_v.asDiagonal() * twist->covariance * flip_v.asDiagonal();
    EXPECT_GT(WorstZ<6>(wrong_v, d_twist), 3.0 * kMaxZ);
  }
}

}  // namespace
}  // namespace semgraph::core

namespace semgraph::core {
namespace {

// Both backends give the same covariances (the propagation reads the backend's values only).
TEST(Uncertainty, BackendsAgree) {
  std::mt19937 rng(7);
  const Scene scene = RandomScene(rng);
  Graph g;
  SceneGraph<coord::HomogeneousBackend> h;
  Build(scene, g, nullptr);
  for (const PoseEdge& e : scene.poses) {
    ASSERT_TRUE(h.AddPose(PoseSpec::Of(e.head, e.head_body).RelativeTo(e.tail, e.tail_body), e.R,
                          e.p, CovarianceInput{&e.S}));
  }
  for (const TwistEdge& e : scene.twists) {
    ASSERT_TRUE(
        h.AddTwist(TwistSpec::Of(e.point, e.body).RelativeTo(e.ref_body).ExpressedIn(e.point), e.v,
                   e.w, CovarianceInput{&e.S}));
  }
  for (int i = 0; i < 10; ++i) {
    Queries q = RandomQueries(rng);
    // The homogeneous backend holds frame-form poses in [b] only (representation_constraint).
    q.pose.point = q.pose.orientation;
    q.pose.ref_point = q.pose.ref_orientation;
    q.pose.coordinate_frame = q.pose.ref_orientation;
    const auto a = g.GetPoseWithCovariance(q.pose);
    const auto b = h.GetPoseWithCovariance(q.pose);
    ASSERT_TRUE(a && b);
    EXPECT_LE((a->covariance - b->covariance).norm(), 1e-12 + 1e-9 * a->covariance.norm());
    const auto v = g.GetTwistWithCovariance(q.twist);
    const auto w = h.GetTwistWithCovariance(q.twist);
    ASSERT_TRUE(v && w);
    EXPECT_LE((v->covariance - w->covariance).norm(), 1e-12 + 1e-9 * v->covariance.norm());
  }
}

// Order and convention on input and output: the same covariance given in GTSAM's order and in
// the body convention is stored as the coordinates / linear_angular one; an edge asked back in
// its own form returns it; angular_linear output is the swap.
TEST(Uncertainty, OrdersAndConventionsRoundTrip) {
  std::mt19937 rng(8);
  const Covariance6 S = RandomCovariance(rng, 1e-4);
  const Eigen::Matrix3d R = ExpR(Eigen::Vector3d(0.3, -0.7, 1.1));
  const Eigen::Vector3d p(1, 2, 3);
  Covariance6 S_body = Covariance6::Zero();  // diag(R, R)^T S diag(R, R), by hand
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>() = R;
  D.bottomRightCorner<3, 3>() = R;
  S_body = D.transpose() * S * D;
  Covariance6 S_body_al;  // angular first
  S_body_al << S_body.bottomRightCorner<3, 3>(), S_body.bottomLeftCorner<3, 3>(),
      S_body.topRightCorner<3, 3>(), S_body.topLeftCorner<3, 3>();
  Graph g;
  const auto spec = PoseSpec::Of("c", "C").RelativeTo("w", "W");
  ASSERT_TRUE(g.AddPose(spec, R, p,
                        CovarianceInput{&S_body_al, CovarianceOrder::kAngularLinear,
                                        PoseCovarianceConvention::kBody}));
  EXPECT_LE((g.pose_covariance(g.FindFrame("c")) - S).norm(), 1e-15);
  const auto back = g.GetPoseWithCovariance(spec);
  ASSERT_TRUE(back);
  EXPECT_LE((back->covariance - S).norm(), 1e-15);
  const auto swapped = g.GetPoseWithCovariance(spec, CovarianceOrder::kAngularLinear);
  const Covariance6& Sb = back->covariance;
  EXPECT_TRUE((swapped->covariance.topLeftCorner<3, 3>() == Sb.bottomRightCorner<3, 3>()));
  EXPECT_TRUE((swapped->covariance.topRightCorner<3, 3>() == Sb.bottomLeftCorner<3, 3>()));
  // The inverse pose's covariance: J S J^T with the inverse's Jacobian written out by hand:
  // R^T -> dth' = -R^T dth, p' = -R^T p -> dp' = -R^T dp - R^T [p]x dth.
  Eigen::Matrix3d P;
  P << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
  J.topLeftCorner<3, 3>() = -R.transpose();
  J.topRightCorner<3, 3>() = -R.transpose() * P;
  J.bottomRightCorner<3, 3>() = -R.transpose();
  const auto inverse = g.GetPoseWithCovariance(PoseSpec::Of("w", "W").RelativeTo("c", "C"));
  ASSERT_TRUE(inverse);
  EXPECT_LE((inverse->covariance - J * S * J.transpose()).norm(), 1e-12 * S.norm());
}

// A value given in another form, relative to exact frames: asked back in that form it returns
// the covariance given (§1: the conversion's values taken as exact); a twist in another [r] too.
TEST(Uncertainty, ConvertedValuesAskedBackInTheirFormReturnTheirCovariance) {
  std::mt19937 rng(9);
  const Covariance6 S = RandomCovariance(rng, 1e-4);
  Graph g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.1, 0.2, 0.3))),
                        Eigen::Vector3d(1, 0, 0)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("e", "A").RelativeTo("a", "A"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(-0.4, 0.2, 0.1))),
                        Eigen::Vector3d(0, 2, 0)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("r", "W").RelativeTo("w", "W"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.5, -0.3, 0.9))),
                        Eigen::Vector3d(0, 0, 3)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(0, 1, 1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("f", "B").RelativeTo("b", "B"), Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(0, 0, 1)));
  // c|C wrt b|B given at point e... : a new edge b -> c given at c's point, ref point f, in [r].
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.2, 0.2, -0.2))),
                        Eigen::Vector3d(0.5, 0.5, 0.5)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "C").RelativeTo("c", "C"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.0, 0.7, 0.0))),
                        Eigen::Vector3d(0.3, 0, 0)));
  const auto form =
      PoseSpec::Of("c", "C").RelativeTo("b", "B").AtPoint("d").RelativeToPoint("f").ExpressedIn(
          "r");
  const Eigen::Quaterniond q(ExpR(Eigen::Vector3d(0.3, 0.1, 0.2)));
  ASSERT_TRUE(g.AddPose(form, q, Eigen::Vector3d(0.1, -0.2, 0.3), CovarianceInput{&S}));
  const auto back = g.GetPoseWithCovariance(form);
  ASSERT_TRUE(back);
  EXPECT_LE((back->covariance - S).norm(), 1e-12 * S.norm());
  EXPECT_GT((g.pose_covariance(g.FindFrame("c")) - S).norm(), 1e-3 * S.norm());  // converted
  // A twist in [r] of a frame whose path to r is exact.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("m", "M").RelativeTo("w", "W"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.6, 0.1, -0.3))),
                        Eigen::Vector3d(1, 1, 0)));
  const auto twist = TwistSpec::Of("m", "M").RelativeTo("W").ExpressedIn("r");
  ASSERT_TRUE(g.AddTwist(twist, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.1, 0.2, 0.3),
                         CovarianceInput{&S}));
  const auto tw = g.GetTwistWithCovariance(twist);
  ASSERT_TRUE(tw);
  EXPECT_LE((tw->covariance - S).norm(), 1e-12 * S.norm());
}

// §2: every error with the graph unchanged, in the rules' order.
TEST(Uncertainty, BadCovariancesAreRefusedWithTheGraphUnchanged) {
  Graph g;
  const Covariance6 good = 1e-4 * Covariance6::Identity();
  const auto spec = PoseSpec::Of("c", "C").RelativeTo("w", "W");
  ASSERT_TRUE(g.AddPose(spec, Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0),
                        CovarianceInput{&good}));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("k", "C").RelativeTo("c", "C"), Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(0, 1, 0), CovarianceInput{&good}));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c"),
                         Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(),
                         CovarianceInput{&good}));
  const std::string before = Dump(g);
  const Covariance6 pose_before = g.pose_covariance(g.FindFrame("c"));
  const auto unchanged = [&] {
    EXPECT_EQ(Dump(g), before);
    EXPECT_EQ(g.pose_covariance(g.FindFrame("c")), pose_before);
    EXPECT_EQ(g.pose_covariance(g.FindFrame("k")), good);
    EXPECT_EQ(g.twist_covariance(g.FindFrame("c")), good);
  };
  const auto expect = [&](BuildResult r, ErrorCode code, const char* phrase) {
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(phrase), std::string::npos) << r.error().message;
    unchanged();
  };
  Covariance6 nan = good, huge = good, asym = good, negative = good;
  nan(2, 3) = std::nan("");
  huge(4, 4) = 2e12;
  asym(0, 1) = 1e-3;
  negative(5, 5) = -1e-3;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d p(2, 0, 0);
  expect(g.AddPose(spec, I, p, CovarianceInput{&nan}), ErrorCode::kInvalidNumber, "(2, 3)");
  expect(g.AddPose(spec, I, p, CovarianceInput{&huge}), ErrorCode::kInvalidNumber, "(4, 4)");
  expect(g.AddPose(spec, I, p, CovarianceInput{&asym}), ErrorCode::kInvalidCovariance, "(0, 1)");
  expect(g.AddPose(spec, I, p, CovarianceInput{&negative}), ErrorCode::kInvalidCovariance,
         "eigenvalue");
  // invalid_rotation before invalid_covariance; invalid_covariance before node resolution
  // (frame c is on body C, not D: frame_body_mismatch comes later).
  expect(g.AddPose(spec, Eigen::Matrix3d(2.0 * I), p, CovarianceInput{&asym}),
         ErrorCode::kInvalidRotation, "");
  expect(g.AddPose(PoseSpec::Of("c", "D").RelativeTo("w", "W"), I, p, CovarianceInput{&asym}),
         ErrorCode::kInvalidCovariance, "(0, 1)");
  // The body convention: a pose in edge form only.
  expect(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("w", "W").ExpressedIn("c"), I, p,
                   CovarianceInput{&good, CovarianceOrder::kLinearAngular,
                                   PoseCovarianceConvention::kBody}),
         ErrorCode::kInvalidCovariance, "edge form");
  // A restated constant pose: the same value with another covariance, or none.
  const auto k = PoseSpec::Of("k", "C").RelativeTo("c", "C");
  const Covariance6 other = 2.0 * good;
  expect(g.AddPose(k, I, Eigen::Vector3d(0, 1, 0), CovarianceInput{&other}),
         ErrorCode::kConstantPoseChange, "covariance");
  expect(g.AddPose(k, I, Eigen::Vector3d(0, 1, 0)), ErrorCode::kConstantPoseChange, "covariance");
  EXPECT_TRUE(g.AddPose(k, I, Eigen::Vector3d(0, 1, 0), CovarianceInput{&good}));  // the same
  expect(g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c"),
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), CovarianceInput{&negative}),
         ErrorCode::kInvalidCovariance, "eigenvalue");
  // An update without a covariance makes the value exact.
  ASSERT_TRUE(g.AddPose(spec, I, p));
  EXPECT_EQ(g.pose_covariance(g.FindFrame("c")), Covariance6::Zero());
  EXPECT_EQ(g.GetPoseWithCovariance(spec)->covariance, Covariance6::Zero());
}

// A repair that re-roots a tree inverts its edges' values and covariances: every relation keeps
// its covariance.
TEST(Uncertainty, RerootingKeepsEveryRelationsCovariance) {
  std::mt19937 rng(10);
  const Covariance6 S1 = RandomCovariance(rng, 1e-4), S2 = RandomCovariance(rng, 1e-4);
  Graph g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("k", "K").RelativeTo("w", "W"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.2, -0.1, 0.4))),
                        Eigen::Vector3d(1, 2, 0), CovarianceInput{&S1}));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "B").RelativeTo("c", "C"),
                        Eigen::Matrix3d(ExpR(Eigen::Vector3d(0.5, 0.3, -0.2))),
                        Eigen::Vector3d(0, 1, 3), CovarianceInput{&S2}));
  const auto cb = PoseSpec::Of("c", "C").RelativeTo("b", "B");
  const auto before = g.GetPoseWithCovariance(cb);
  // k has a parent: repaired as the inverse b wrt k, after re-rooting b's tree at b.
  const auto r =
      g.AddPose(PoseSpec::Of("k", "K").RelativeTo("b", "B"), Eigen::Quaterniond::Identity(),
                Eigen::Vector3d(0, 0, 1), RepairPolicy{});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->applied, RepairKind::kRerooted) << r->change;
  EXPECT_EQ(g.pose_parent(g.FindFrame("c")), g.FindFrame("b"));  // the edge c -> b reversed
  const auto after = g.GetPoseWithCovariance(cb);
  ASSERT_TRUE(before && after);
  EXPECT_LE((after->covariance - before->covariance).norm(), 1e-12 * before->covariance.norm());
  EXPECT_LE((g.pose_covariance(g.FindFrame("c")) - before->covariance).norm(),
            1e-12 * before->covariance.norm());  // stored in the reversed edge's form
}

}  // namespace
}  // namespace semgraph::core
