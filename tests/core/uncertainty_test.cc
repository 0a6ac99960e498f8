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

namespace semgraph::core {
namespace {

using Graph = SceneGraph<coord::QuaternionBackend>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

Eigen::Matrix3d ExpR(const Eigen::Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Eigen::Matrix3d::Identity()
                   : Eigen::Matrix3d(Eigen::AngleAxisd(th, w / th));
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
double WorstZ(const Eigen::Matrix<double, N, N>& S, const std::vector<Eigen::Matrix<double, N, 1>>& d) {
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

constexpr int kSamples = 20000;
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
  q.pose = PoseSpec::Of(a, bodies[ca]).RelativeTo(b, bodies[cb]).ExpressedIn(r).AtPoint(e).RelativeToPoint(f);
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
