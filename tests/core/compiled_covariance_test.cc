// core/compiled_covariance.h and the real-time setters with a covariance: a compiled pose query
// with covariance gives the one-shot query's answer and covariance (whose truth is Monte Carlo,
// uncertainty_test.cc) for every form of pose, on both backends; it allocates nothing, is
// noexcept, follows SetPose with and without a covariance, and is invalidated by a removal.
#include "semgraph/core/compiled_covariance.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"
#include "support/random_covariance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::AllocationCounter;
using semgraph::testing::ExpR;
using semgraph::testing::RandomCovariance;

// Frames f0..f7 on bodies B0..B7 (f_k under a random earlier frame), g_k fixed to B_k under f_k.
template <class Graph>
void BuildTree(Graph& g, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 8; ++k) {
    const std::string f = "f" + std::to_string(k), body = "B" + std::to_string(k);
    const Covariance6 S1 = RandomCovariance(rng), S2 = RandomCovariance(rng);
    if (k > 0) {
      const int parent = std::uniform_int_distribution<int>(0, k - 1)(rng);
      ASSERT_TRUE(g.AddPose(PoseSpec::Of(f, body).RelativeTo("f" + std::to_string(parent),
                                                             "B" + std::to_string(parent)),
                            ExpR(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                            Eigen::Vector3d(n(rng), n(rng), n(rng)), CovarianceInput{&S1}));
    }
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("g" + std::to_string(k), body).RelativeTo(f, body),
                          ExpR(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                          Eigen::Vector3d(n(rng), n(rng), n(rng)), CovarianceInput{&S2}));
  }
}

template <class Graph>
void ExpectSameAsOneShot(Graph& g, const PoseSpec& spec) {
  auto compiled = g.CompilePoseWithCovariance(spec);
  ASSERT_TRUE(compiled) << static_cast<int>(compiled.error().code);
  const auto one_shot = g.GetPoseWithCovariance(spec);
  ASSERT_TRUE(one_shot);
  const auto answer = compiled->Evaluate();
  ASSERT_TRUE(answer);
  const Eigen::Isometry3d A = answer->value.ToIsometry(), O = one_shot->value.ToIsometry();
  EXPECT_LE((A.matrix() - O.matrix()).norm(), 1e-9);
  EXPECT_LE((answer->covariance - one_shot->covariance).norm(), 1e-9 * one_shot->covariance.norm());
  const auto swapped = compiled->Evaluate(CovarianceOrder::kAngularLinear);
  EXPECT_TRUE((swapped->covariance == coord::SwapHalves(answer->covariance)));
}

TEST(CompiledCovariance, SameAsOneShotForEveryFormOnBothBackends) {
  std::mt19937 rng(11);
  SceneGraph<coord::QuaternionBackend> g;
  SceneGraph<coord::HomogeneousBackend> h;
  BuildTree(g, rng);
  std::mt19937 rng2(11);
  BuildTree(h, rng2);
  std::uniform_int_distribution<int> body(0, 7), side(0, 1);
  for (int i = 0; i < 40; ++i) {
    const int c = body(rng), d = body(rng);
    const auto name = [&](int k) { return (side(rng) ? "f" : "g") + std::to_string(k); };
    const std::string a = name(c), e = name(c), b = name(d), f = name(d), r = name(body(rng));
    const std::string C = "B" + std::to_string(c), D = "B" + std::to_string(d);
    ExpectSameAsOneShot(
        g, PoseSpec::Of(a, C).RelativeTo(b, D).ExpressedIn(r).AtPoint(e).RelativeToPoint(f));
    ExpectSameAsOneShot(h, PoseSpec::Of(a, C).RelativeTo(b, D));
  }
}

template <class Graph>
void ExpectPartsSameAsOneShot(Graph& g, const PoseSpec& spec) {
  auto position = g.CompilePositionWithCovariance(spec);
  auto orientation = g.CompileOrientationWithCovariance(spec);
  ASSERT_TRUE(position && orientation);
  const auto p = position->Evaluate();
  const auto p_one_shot = g.GetPositionWithCovariance(spec);
  ASSERT_TRUE(p && p_one_shot);
  EXPECT_EQ(p->value.semantics, p_one_shot->value.semantics);
  EXPECT_LE((p->value.value - p_one_shot->value.value).norm(), 1e-9);
  EXPECT_LE((p->covariance - p_one_shot->covariance).norm(), 1e-9 * p_one_shot->covariance.norm());
  const auto R = orientation->Evaluate();
  const auto R_one_shot = g.GetOrientationWithCovariance(spec);
  ASSERT_TRUE(R && R_one_shot);
  EXPECT_EQ(R->value.semantics, R_one_shot->value.semantics);
  using B = typename Graph::Backend;
  EXPECT_LE((B::ToMatrix(R->value.value) - B::ToMatrix(R_one_shot->value.value)).norm(), 1e-9);
  EXPECT_LE((R->covariance - R_one_shot->covariance).norm(), 1e-9 * R_one_shot->covariance.norm());
}

// The compiled query puts each uncertain edge in the next SIMD lane (covariance_lanes.h) and
// skips exact ones: a chain of 13 edges, every third exact (no covariance given), so the lanes
// span three blocks with a partial last one; queries up, down and across the chain, expressed in
// a third frame (d != 0: the orientation operator enters), on both backends; then one uncertain
// edge updated to a new covariance and one given none (its lane holds zeros).
TEST(CompiledCovariance, ExactAndUncertainEdgesAcrossLaneBlocksOnBothBackends) {
  const auto build = [](auto& g) {
    std::mt19937 rng(13);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int k = 1; k <= 13; ++k) {
      const Covariance6 S = RandomCovariance(rng);
      const CovarianceInput input = k % 3 == 0 ? CovarianceInput{} : CovarianceInput{&S};
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of("c" + std::to_string(k), "K" + std::to_string(k))
                        .RelativeTo("c" + std::to_string(k - 1), "K" + std::to_string(k - 1)),
                    ExpR(Eigen::Vector3d(n(rng), n(rng), n(rng))),
                    Eigen::Vector3d(n(rng), n(rng), n(rng)), input));
    }
  };
  SceneGraph<coord::QuaternionBackend> g;
  SceneGraph<coord::HomogeneousBackend> h;
  build(g);
  build(h);
  const PoseSpec tip = PoseSpec::Of("c13", "K13").RelativeTo("c0", "K0");
  ExpectSameAsOneShot(g, tip);
  ExpectSameAsOneShot(h, tip);
  ExpectSameAsOneShot(g, PoseSpec::Of("c13", "K13").RelativeTo("c2", "K2").ExpressedIn("c7"));
  ExpectSameAsOneShot(g, PoseSpec::Of("c4", "K4").RelativeTo("c11", "K11").ExpressedIn("c9"));
  ExpectSameAsOneShot(h, PoseSpec::Of("c4", "K4").RelativeTo("c11", "K11"));
  ExpectSameAsOneShot(g, PoseSpec::Of("c12", "K12").RelativeTo("c1", "K1").ExpressedIn("c6"));
  // Updates: c5 gets another covariance, c8 none.
  auto compiled = g.CompilePoseWithCovariance(tip);
  ASSERT_TRUE(compiled);
  const Covariance6 S_new = 9e-4 * Covariance6::Identity();
  const auto c5 = g.FindPoseEdge("c5", "c4"), c8 = g.FindPoseEdge("c8", "c7");
  ASSERT_TRUE(c5 && c8);
  const Eigen::Quaterniond q(ExpR(Eigen::Vector3d(0.3, -0.2, 0.1)));
  ASSERT_EQ(g.SetPose(*c5, q, Eigen::Vector3d(1, 2, 3), CovarianceInput{&S_new}), ErrorCode::kOk);
  ASSERT_EQ(g.SetPose(*c8, q, Eigen::Vector3d(-1, 0, 2)), ErrorCode::kOk);
  coord::QuaternionBackend::PoseCoords X;
  Covariance6 S;
  ASSERT_EQ(compiled->Evaluate(X, S), ErrorCode::kOk);
  const auto one_shot = g.GetPoseWithCovariance(tip);
  ASSERT_TRUE(one_shot);
  EXPECT_LE((S - one_shot->covariance).norm(), 1e-9 * one_shot->covariance.norm());
  EXPECT_LE((coord::Pose<coord::QuaternionBackend>{compiled->semantics(), X}.ToIsometry().matrix() -
             one_shot->value.ToIsometry().matrix())
                .norm(),
            1e-9);
}

TEST(CompiledCovariance, PositionAndOrientationAreTheOneShotAnswersOnBothBackends) {
  std::mt19937 rng(13);
  SceneGraph<coord::QuaternionBackend> g;
  SceneGraph<coord::HomogeneousBackend> h;
  BuildTree(g, rng);
  std::mt19937 rng2(13);
  BuildTree(h, rng2);
  std::uniform_int_distribution<int> body(0, 7), side(0, 1);
  for (int i = 0; i < 40; ++i) {
    const int c = body(rng), d = body(rng);
    const auto name = [&](int k) { return (side(rng) ? "f" : "g") + std::to_string(k); };
    const std::string a = name(c), b = name(d), r = name(body(rng));
    const std::string C = "B" + std::to_string(c), D = "B" + std::to_string(d);
    ExpectPartsSameAsOneShot(g, PoseSpec::Of(a, C).RelativeTo(b, D).ExpressedIn(r));
    ExpectPartsSameAsOneShot(h, PoseSpec::Of(a, C).RelativeTo(b, D));
  }
}

// By hand: one uncertain edge X_01 (covariance S in the edge form: at f1's origin, in [f0]):
// f1's position wrt f0 in [f0] carries its linear block, the reverse position in [f1] its
// first-order image below; the orientation in [f1] is checked by finite differences.
TEST(CompiledCovariance, PositionAndOrientationOfOneEdgeByHand) {
  SceneGraph<> g;
  std::mt19937 rng(14);
  const Covariance6 S = RandomCovariance(rng);
  const Eigen::Matrix3d R_01 = ExpR(Eigen::Vector3d(0.3, -0.2, 0.9));
  const Eigen::Vector3d p_0o1o_0(0.5, -1.0, 2.0);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("f1", "B1").RelativeTo("f0", "B0"), R_01, p_0o1o_0,
                        CovarianceInput{&S}));
  auto p = g.CompilePositionWithCovariance(PoseSpec::Of("f1", "B1").RelativeTo("f0", "B0"));
  auto R = g.CompileOrientationWithCovariance(
      PoseSpec::Of("f1", "B1").RelativeTo("f0", "B0").ExpressedIn("f1"));
  ASSERT_TRUE(p && R);
  Eigen::Vector3d p_value;
  Eigen::Matrix3d S_p, S_R;
  coord::QuaternionBackend::Rotation q_value;
  ASSERT_EQ(p->Evaluate(p_value, S_p), ErrorCode::kOk);
  ASSERT_EQ(R->Evaluate(q_value, S_R), ErrorCode::kOk);
  EXPECT_LE((p_value - p_0o1o_0).norm(), 1e-12);
  EXPECT_LE((S_p - S.topLeftCorner<3, 3>()).norm(), 1e-15);
  // The orientation's Jacobian by central differences of the plain query on perturbed copies
  // of the edge (p + dp, Exp(dth) R_01), the answer's change read as M' = Exp(d) M.
  Eigen::Matrix<double, 3, 6> J_R;
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix3d M[2];
    for (int sign = 0; sign < 2; ++sign) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d(i) = sign == 0 ? h : -h;
      SceneGraph<> perturbed;
      ASSERT_TRUE(perturbed.AddPose(PoseSpec::Of("f1", "B1").RelativeTo("f0", "B0"),
                                    ExpR(d.tail<3>()) * R_01, p_0o1o_0 + d.head<3>()));
      M[sign] =
          perturbed
              .GetOrientation(PoseSpec::Of("f1", "B1").RelativeTo("f0", "B0").ExpressedIn("f1"))
              ->value.toRotationMatrix();
    }
    const Eigen::AngleAxisd d_M(M[0] * M[1].transpose());
    J_R.col(i) = d_M.angle() * d_M.axis() / (2 * h);
  }
  EXPECT_LE((S_R - J_R * S * J_R.transpose()).norm(), 1e-9 * S.norm());
  // f0's origin wrt f1's in [f1]: -R_01^T p; perturbed, -(Exp(dth) R_01)^T (p + dp), to first
  // order -R_01^T dp - R_01^T [p]x dth.
  auto back = g.CompilePositionWithCovariance(
      PoseSpec::Of("f0", "B0").RelativeTo("f1", "B1").ExpressedIn("f1"));
  ASSERT_TRUE(back);
  ASSERT_EQ(back->Evaluate(p_value, S_p), ErrorCode::kOk);
  Eigen::Matrix3d p_x;
  p_x << 0, -p_0o1o_0.z(), p_0o1o_0.y(), p_0o1o_0.z(), 0, -p_0o1o_0.x(), -p_0o1o_0.y(),
      p_0o1o_0.x(), 0;
  Eigen::Matrix<double, 3, 6> J;
  J << -R_01.transpose(), -R_01.transpose() * p_x;
  EXPECT_LE((p_value + R_01.transpose() * p_0o1o_0).norm(), 1e-12);
  EXPECT_LE((S_p - J * S * J.transpose()).norm(), 1e-15);
}

TEST(CompiledCovariance, PositionAndOrientationErrorsAndInvalidation) {
  std::mt19937 rng(15);
  SceneGraph<> g;
  BuildTree(g, rng);
  const auto unknown = PoseSpec::Of("nowhere", "B1").RelativeTo("f0", "B0");
  ASSERT_FALSE(g.CompilePositionWithCovariance(unknown));
  EXPECT_EQ(g.CompilePositionWithCovariance(unknown).error().code,
            g.CompilePosition(unknown).error().code);
  EXPECT_EQ(g.CompileOrientationWithCovariance(unknown).error().code,
            g.CompileOrientation(unknown).error().code);
  const auto wrong_body = PoseSpec::Of("f1", "B2").RelativeTo("f0", "B0");
  EXPECT_EQ(g.CompilePositionWithCovariance(wrong_body).error().code,
            g.CompilePosition(wrong_body).error().code);
  auto p = g.CompilePositionWithCovariance(PoseSpec::Of("g7", "B7").RelativeTo("g0", "B0"));
  auto R = g.CompileOrientationWithCovariance(PoseSpec::Of("g7", "B7").RelativeTo("g0", "B0"));
  ASSERT_TRUE(p && R);
  Eigen::Vector3d p_value;
  Eigen::Matrix3d S_p, S_R;
  Eigen::Quaterniond q_value;
  static_assert(noexcept(p->Evaluate(p_value, S_p))&& noexcept(R->Evaluate(q_value, S_R)));
  const std::size_t before = AllocationCounter::total();
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(p->Evaluate(p_value, S_p), ErrorCode::kOk);
    ASSERT_EQ(R->Evaluate(q_value, S_R), ErrorCode::kOk);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  ASSERT_TRUE(g.RemovePose("g7", "f7"));
  EXPECT_EQ(p->Evaluate(p_value, S_p), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(R->Evaluate(q_value, S_R), ErrorCode::kQueryInvalidated);
}

TEST(CompiledCovariance, RealTimeNoAllocationFollowsUpdatesAndRemovals) {
  std::mt19937 rng(12);
  SceneGraph<> g;
  BuildTree(g, rng);
  auto compiled = g.CompilePoseWithCovariance(PoseSpec::Of("g7", "B7").RelativeTo("g0", "B0"));
  ASSERT_TRUE(compiled);
  const auto handle = g.FindPoseEdge("f7", g.frame_name(g.pose_parent(g.FindFrame("f7"))));
  ASSERT_TRUE(handle);
  Eigen::Quaterniond q(ExpR(Eigen::Vector3d(0.1, 0.2, 0.3)));
  coord::QuaternionBackend::PoseCoords X;
  Covariance6 S, S_new = 4e-6 * Covariance6::Identity();
  static_assert(noexcept(compiled->Evaluate(X, S)));
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const CovarianceInput input{&S_new};
  static_assert(noexcept(g.SetPose(*handle, q, zero, input)));
  const std::size_t before = AllocationCounter::total();
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(g.SetPose(*handle, q, Eigen::Vector3d(i, 0, 0), CovarianceInput{&S_new}),
              ErrorCode::kOk);
    ASSERT_EQ(compiled->Evaluate(X, S), ErrorCode::kOk);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_EQ(g.pose_covariance(g.FindFrame("f7")), S_new);
  const auto one_shot = g.GetPoseWithCovariance(PoseSpec::Of("g7", "B7").RelativeTo("g0", "B0"));
  EXPECT_LE((S - one_shot->covariance).norm(), 1e-12);
  // An update without a covariance: the edge is exact again; a bad covariance changes nothing.
  Covariance6 bad = S_new;
  bad(0, 1) = 1.0;
  EXPECT_EQ(g.SetPose(*handle, q, Eigen::Vector3d::Zero(), CovarianceInput{&bad}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.pose_covariance(g.FindFrame("f7")), S_new);
  ASSERT_EQ(g.SetPose(*handle, q, Eigen::Vector3d::Zero()), ErrorCode::kOk);
  EXPECT_EQ(g.pose_covariance(g.FindFrame("f7")), Covariance6::Zero());
  Covariance6 S_exact;
  ASSERT_EQ(compiled->Evaluate(X, S_exact), ErrorCode::kOk);
  EXPECT_LT((S_exact - S).norm(), (S - Covariance6::Zero()).norm());  // f7's share is gone
  EXPECT_LE((S_exact -
             g.GetPoseWithCovariance(PoseSpec::Of("g7", "B7").RelativeTo("g0", "B0"))->covariance)
                .norm(),
            1e-12);
  // A removal invalidates.
  ASSERT_TRUE(g.RemovePose("f7", g.frame_name(g.pose_parent(g.FindFrame("f7")))));
  EXPECT_EQ(compiled->Evaluate(X, S), ErrorCode::kQueryInvalidated);
}

}  // namespace
}  // namespace semgraph::core
