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

namespace semgraph::core {
namespace {

using semgraph::testing::AllocationCounter;

Eigen::Matrix3d ExpR(const Eigen::Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(Eigen::AngleAxisd(th, w / th));
}
Covariance6 RandomCovariance(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return 1e-6 * L * L.transpose();
}

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
