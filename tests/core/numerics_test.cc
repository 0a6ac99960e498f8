// Numerical robustness: long chains stay within a stated error bound of an independent
// long-double computation; repeated value updates do not drift; a large scene builds, answers
// and tears down (LeakSanitizer checks the teardown in the ASan CI stage).
//
// Legend: f0 <- f1 <- ... <- fn a chain of frames on bodies L0..Ln; X_0k the pose of fk in f0.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using QuaternionLD = Eigen::Quaternion<long double>;
using VectorLD = Eigen::Matrix<long double, 3, 1>;

struct Link {
  Quaterniond q;
  Vector3d p;
};

std::vector<Link> RandomLinks(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&] { return (rng() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };
  std::vector<Link> links(n);
  for (Link& l : links) {
    l.q = Quaterniond(uniform(), uniform(), uniform(), uniform()).normalized();
    l.p = Vector3d(uniform(), uniform(), uniform());
  }
  return links;
}

// Chain of n links; returns the graph with frames f0..fn.
void BuildChain(SceneGraph<>& graph, const std::vector<Link>& links) {
  for (std::size_t i = 0; i < links.size(); ++i) {
    const std::string child = "f" + std::to_string(i + 1), parent = "f" + std::to_string(i);
    ASSERT_TRUE(graph.AddPose(PoseSpec::Of(child, "L" + std::to_string(i + 1))
                                  .RelativeTo(parent, "L" + std::to_string(i)),
                              links[i].q, links[i].p));
  }
}

// Error bound for a chain of n compositions: each composition adds O(eps) relative error to the
// rotation and O(eps * |p|) to the position; we state 4 n eps (rotation angle) and
// 4 n eps max(1, |p|) (position), with eps = 2^-52.
TEST(Numerics, TenThousandDeepChainStaysWithinTheStatedBound) {
  constexpr int kDepth = 10000;
  const auto links = RandomLinks(kDepth, 7);
  SceneGraph<> graph;
  BuildChain(graph, links);
  // Independent reference in long double: X_0n = X_01 X_12 ... X_(n-1)n.
  QuaternionLD q_ref = QuaternionLD::Identity();
  VectorLD p_ref = VectorLD::Zero();
  for (const Link& l : links) {
    const QuaternionLD q = l.q.cast<long double>();
    p_ref += q_ref * l.p.cast<long double>();
    q_ref = q_ref * q;
    q_ref.normalize();
  }
  const double eps = std::ldexp(1.0, -52);
  const double position_bound =
      4.0 * kDepth * eps * std::max(1.0, static_cast<double>(p_ref.norm()));
  const double angle_bound = 4.0 * kDepth * eps;
  auto X = graph.GetPose(PoseSpec::Of("f" + std::to_string(kDepth)).RelativeTo("f0"));
  ASSERT_TRUE(X);
  const Quaterniond q_expected = q_ref.cast<double>();
  const Vector3d p_expected = p_ref.cast<double>();
  EXPECT_LT((X->value.translation - p_expected).norm(), position_bound);
  EXPECT_LT(X->value.rotation.angularDistance(q_expected), angle_bound);
  auto compiled = graph.CompilePose(PoseSpec::Of("f" + std::to_string(kDepth)).RelativeTo("f0"));
  ASSERT_TRUE(compiled);
  coord::QuaternionBackend::PoseCoords Y;
  ASSERT_EQ(compiled->Evaluate(Y), ErrorCode::kOk);
  EXPECT_LT((Y.translation - p_expected).norm(), position_bound);
  EXPECT_LT(Y.rotation.angularDistance(q_expected), angle_bound);
  // The reverse query (root in the tip frame) too.
  auto X_n0 = graph.GetPose(PoseSpec::Of("f0").RelativeTo("f" + std::to_string(kDepth)));
  ASSERT_TRUE(X_n0);
  EXPECT_LT((X_n0->value.translation + (q_expected.conjugate() * p_expected)).norm(),
            position_bound);
}

#ifdef NDEBUG
constexpr long kUpdates = 10'000'000;
#else
constexpr long kUpdates = 1'000'000;  // Debug and sanitizer builds: same check, fewer rounds
#endif

// A loop that integrates a small rotation into an edge, reading back what it wrote each time,
// 10^7 times: the stored quaternion must stay unit (SetPose renormalizes every input within
// 1e-6 of unit), and the angle must follow the sum of the increments.
TEST(Numerics, RepeatedReadComposeWriteDoesNotDrift) {
  SceneGraph<> graph;
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("l", "L").RelativeTo("b", "B"), Quaterniond::Identity(),
                            Vector3d(1, 0, 0)));
  auto edge = graph.FindPoseEdge("l", "b");
  ASSERT_TRUE(edge);
  const double step = 1e-3;
  const Quaterniond dq(Eigen::AngleAxisd(step, Vector3d::UnitZ()));
  const FrameIndex l = graph.FindFrame("l");
  for (long i = 0; i < kUpdates; ++i) {
    const auto X = graph.pose_value(l);
    ASSERT_EQ(graph.SetPose(*edge, X.rotation * dq, X.translation), ErrorCode::kOk) << i;
  }
  const auto X = graph.pose_value(l);
  EXPECT_NEAR(X.rotation.norm(), 1.0, 1e-15);
  // Expected angle: kUpdates * step, modulo 2 pi.
  const double expected = std::remainder(kUpdates * step, 2 * M_PI);
  const Quaterniond q_expected(Eigen::AngleAxisd(expected, Vector3d::UnitZ()));
  EXPECT_LT(X.rotation.angularDistance(q_expected), 1e-6);
  EXPECT_EQ(X.translation, Vector3d(1, 0, 0));
}

TEST(Numerics, RepeatedUpdatesLeaveExactlyTheLastValue) {
  SceneGraph<> graph;
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("l", "L").RelativeTo("b", "B"), Quaterniond::Identity(),
                            Vector3d::Zero()));
  ASSERT_TRUE(graph.AddTwist(TwistSpec::Of("l", "L").RelativeTo("B").ExpressedIn("l"),
                             Vector3d::Zero(), Vector3d::Zero()));
  auto pose = graph.FindPoseEdge("l", "b");
  auto twist = graph.FindTwistEdge("l", "B");
  auto query = graph.CompilePose(PoseSpec::Of("l").RelativeTo("b"));
  ASSERT_TRUE(pose && twist && query);
  const auto links = RandomLinks(64, 11);
  for (long i = 0; i < kUpdates / 10; ++i) {
    const Link& k = links[i % links.size()];
    ASSERT_EQ(graph.SetPose(*pose, k.q, k.p), ErrorCode::kOk);
    ASSERT_EQ(graph.SetTwist(*twist, k.p, k.p.reverse()), ErrorCode::kOk);
  }
  const Link& last = links[(kUpdates / 10 - 1) % links.size()];
  coord::QuaternionBackend::PoseCoords X;
  ASSERT_EQ(query->Evaluate(X), ErrorCode::kOk);
  EXPECT_LT(X.rotation.angularDistance(last.q), 1e-15);
  EXPECT_EQ(X.translation, last.p);
  EXPECT_EQ(graph.twist_value(graph.FindFrame("l"))->linear, last.p);
}

// A large random tree: builds, answers, tears down (LeakSanitizer in CI). The 10^6-frame run is
// in the benchmarks (build_random_tree/1000000).
TEST(Numerics, LargeRandomTreeBuildsAnswersAndTearsDown) {
#ifdef NDEBUG
  constexpr int kFrames = 200000;
#else
  constexpr int kFrames = 50000;
#endif
  std::mt19937_64 rng(3);
  const auto links = RandomLinks(kFrames, 5);
  auto graph = std::make_unique<SceneGraph<>>();
  std::vector<int> parent(kFrames + 1, -1);
  for (int i = 1; i <= kFrames; ++i) {
    parent[i] = static_cast<int>(rng() % i);
    ASSERT_TRUE(graph->AddPose(
        PoseSpec::Of("t" + std::to_string(i), "T" + std::to_string(i))
            .RelativeTo("t" + std::to_string(parent[i]), "T" + std::to_string(parent[i])),
        links[i - 1].q, links[i - 1].p));
  }
  EXPECT_EQ(graph->num_frames(), static_cast<std::size_t>(kFrames + 1));
  // Spot-check a few leaf-to-root poses against a direct composition along the parents.
  for (int leaf : {kFrames, kFrames / 2, kFrames / 3}) {
    Quaterniond q = Quaterniond::Identity();
    Vector3d p = Vector3d::Zero();
    for (int f = leaf; f != 0;
         f = parent[f]) {  // X_0leaf = X_0.. ... X_parent,f, built from the top
      const Link& l = links[f - 1];
      p = l.q * p + l.p;
      q = l.q * q;
    }
    auto X = graph->GetPose(PoseSpec::Of("t" + std::to_string(leaf)).RelativeTo("t0"));
    ASSERT_TRUE(X);
    EXPECT_LT((X->value.translation - p).norm(), 1e-9);
    EXPECT_LT(X->value.rotation.angularDistance(q), 1e-9);
  }
  graph.reset();  // teardown: every allocation released (LeakSanitizer checks at exit)
}

}  // namespace
}  // namespace semgraph::core
