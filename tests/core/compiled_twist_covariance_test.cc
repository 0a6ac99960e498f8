// core/compiled_twist_covariance.h: a compiled twist (linear, angular velocity) query with
// covariance. Truth: central differences of the plain twist query over perturbed copies of every
// edge (pose and twist), summed as sum J_i S_i J_i^T, on a scene where points, frames and heads
// lie on different chains and edges are traversed both ways; and the one-shot query (whose truth
// is Monte Carlo, uncertainty_test.cc) on random trees, both backends, every part. It allocates
// nothing, is noexcept, follows SetTwist / SetPose with a covariance, and is invalidated by a
// removal; its compile errors are CompileTwist's.
#include "semgraph/core/compiled_twist_covariance.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"
#include "support/random_covariance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::AllocationCounter;
using semgraph::testing::ExpR;
using semgraph::testing::RandomCovariance;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// A scene description, so that the same scene can be rebuilt with one edge perturbed.
// Frames f<k> on bodies B<k>, f<k> under f<parent[k]>; g<k> fixed to B<k> under f<k>; a twist
// edge B<parent[k]> -> {f<k>}|B<k> for each k > 0. Every edge uncertain but twist edge 2.
struct Scene {
  struct PoseEdge {
    std::string of, body, to, to_body;
    Eigen::Matrix3d R;
    Vec p;
    Covariance6 S;
  };
  struct TwistEdge {
    std::string head, body, ref_body;
    Vec v, w;
    Covariance6 S;
  };
  std::vector<PoseEdge> poses;
  std::vector<TwistEdge> twists;

  explicit Scene(std::mt19937& rng, int n = 6) {
    for (int k = 0; k < n; ++k) {
      const std::string f = "f" + std::to_string(k), B = "B" + std::to_string(k);
      if (k > 0) {
        const int parent = std::uniform_int_distribution<int>(0, k - 1)(rng);
        const std::string fp = "f" + std::to_string(parent), Bp = "B" + std::to_string(parent);
        poses.push_back(
            {f, B, fp, Bp, ExpR(RandomVector(rng)), RandomVector(rng), RandomCovariance(rng)});
        twists.push_back({f, B, Bp, RandomVector(rng), RandomVector(rng),
                          k == 2 ? Covariance6::Zero() : RandomCovariance(rng)});
      }
      poses.push_back({"g" + std::to_string(k), B, f, B, ExpR(RandomVector(rng)), RandomVector(rng),
                       RandomCovariance(rng)});
    }
  }
  // The graph, with edge `perturbed` (poses first, then twists) moved by d: a pose edge to
  // (Exp(d_th) R, p + d_p), a twist edge to (v + d_v, w + d_w) (the edge form's coordinates).
  template <class B>
  void Build(SceneGraph<B>& g, int perturbed = -1, const Vec6& d = Vec6::Zero()) const {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const PoseEdge& e = poses[i];
      const bool moved = static_cast<int>(i) == perturbed;
      const Vec6 di = moved ? d : Vec6::Zero();
      ASSERT_TRUE(g.AddPose(PoseSpec::Of(e.of, e.body).RelativeTo(e.to, e.to_body),
                            Eigen::Matrix3d(ExpR(di.tail<3>()) * e.R), Vec(e.p + di.head<3>()),
                            CovarianceInput{&e.S}));
    }
    for (std::size_t i = 0; i < twists.size(); ++i) {
      const TwistEdge& e = twists[i];
      const bool moved = static_cast<int>(i + poses.size()) == perturbed;
      const Vec6 di = moved ? d : Vec6::Zero();
      ASSERT_TRUE(
          g.AddTwist(TwistSpec::Of(e.head, e.body).RelativeTo(e.ref_body).ExpressedIn(e.head),
                     Vec(e.v + di.head<3>()), Vec(e.w + di.tail<3>()), CovarianceInput{&e.S}));
    }
  }
  int num_edges() const { return static_cast<int>(poses.size() + twists.size()); }
  const Covariance6& S(int i) const {
    return i < static_cast<int>(poses.size()) ? poses[static_cast<std::size_t>(i)].S
                                              : twists[i - poses.size()].S;
  }
};

// sum_i J_i S_i J_i^T with J_i by central differences of GetTwist on perturbed scenes.
Covariance6 FiniteDifferenceCovariance(const Scene& scene, const TwistSpec& spec) {
  Covariance6 S = Covariance6::Zero();
  const double h = 1e-6;
  for (int i = 0; i < scene.num_edges(); ++i) {
    Eigen::Matrix<double, 6, 6> J;
    for (int c = 0; c < 6; ++c) {
      Vec6 answer[2];
      for (int sign = 0; sign < 2; ++sign) {
        Vec6 d = Vec6::Zero();
        d(c) = sign == 0 ? h : -h;
        SceneGraph<> g;
        scene.Build(g, i, d);
        const auto V = g.GetTwist(spec);
        EXPECT_TRUE(V);
        if (!V) return S;
        answer[sign] << V->linear, V->angular;
      }
      J.col(c) = (answer[0] - answer[1]) / (2 * h);
    }
    S += J * scene.S(i) * J.transpose();
  }
  return S;
}

TEST(CompiledTwistCovariance, MatchesFiniteDifferencesOfThePlainQuery) {
  std::mt19937 rng(21);
  const Scene scene(rng);
  SceneGraph<> g;
  scene.Build(g);
  std::uniform_int_distribution<int> node(0, 5), side(0, 1);
  int cases = 0;
  for (int i = 0; i < 12; ++i) {
    const int c = node(rng), d = node(rng);
    if (c == d) continue;
    const auto name = [&](int k) { return (side(rng) ? "f" : "g") + std::to_string(k); };
    const std::string e = name(node(rng)), r = name(node(rng));
    const std::string C = "B" + std::to_string(c), D = "B" + std::to_string(d);
    const TwistSpec spec = TwistSpec::Of(e, C).RelativeTo(D).ExpressedIn(r);
    SCOPED_TRACE(e + "|" + C + " wrt " + D + " in [" + r + "]");
    auto compiled = g.CompileTwistWithCovariance(spec);
    ASSERT_TRUE(compiled);
    const auto answer = compiled->Evaluate();
    ASSERT_TRUE(answer);
    const auto plain = g.GetTwist(spec);
    ASSERT_TRUE(plain);
    EXPECT_LE((answer->value.linear - plain->linear).norm(), 1e-9);
    EXPECT_LE((answer->value.angular - plain->angular).norm(), 1e-9);
    const Covariance6 S_fd = FiniteDifferenceCovariance(scene, spec);
    EXPECT_LE((answer->covariance - S_fd).norm(), 1e-5 * S_fd.norm())
        << answer->covariance << "\n\n"
        << S_fd;
    ++cases;
  }
  EXPECT_GE(cases, 8);
}

template <class Graph>
void ExpectSameAsOneShot(Graph& g, const TwistSpec& spec) {
  auto twist = g.CompileTwistWithCovariance(spec);
  auto linear = g.CompileLinearVelocityWithCovariance(spec);
  ASSERT_TRUE(twist && linear);
  const auto answer = twist->Evaluate();
  const auto one_shot = g.GetTwistWithCovariance(spec);
  ASSERT_TRUE(answer && one_shot);
  EXPECT_EQ(answer->value.semantics, one_shot->value.semantics);
  EXPECT_LE((answer->value.linear - one_shot->value.linear).norm(), 1e-9);
  EXPECT_LE((answer->value.angular - one_shot->value.angular).norm(), 1e-9);
  EXPECT_LE((answer->covariance - one_shot->covariance).norm(),
            1e-9 * (1.0 + one_shot->covariance.norm()));
  const auto swapped = twist->Evaluate(CovarianceOrder::kAngularLinear);
  ASSERT_TRUE(swapped);
  EXPECT_TRUE((swapped->covariance == coord::SwapHalves(answer->covariance)));
  const auto v = linear->Evaluate();
  const auto v_one_shot = g.GetLinearVelocityWithCovariance(spec);
  ASSERT_TRUE(v && v_one_shot);
  EXPECT_EQ(v->value.semantics, v_one_shot->value.semantics);
  EXPECT_LE((v->covariance - v_one_shot->covariance).norm(),
            1e-9 * (1.0 + v_one_shot->covariance.norm()));
  // The angular velocity takes body, ref_body and [r] only.
  TwistSpec angular_spec = spec;
  angular_spec.point = "";
  auto angular = g.CompileAngularVelocityWithCovariance(angular_spec);
  ASSERT_TRUE(angular);
  const auto w = angular->Evaluate();
  const auto w_one_shot = g.GetAngularVelocityWithCovariance(angular_spec);
  ASSERT_TRUE(w && w_one_shot);
  EXPECT_EQ(w->value.semantics, w_one_shot->value.semantics);
  EXPECT_LE((w->value.value - w_one_shot->value.value).norm(), 1e-9);
  EXPECT_LE((w->covariance - w_one_shot->covariance).norm(),
            1e-9 * (1.0 + w_one_shot->covariance.norm()));
}

TEST(CompiledTwistCovariance, SameAsOneShotOnRandomTreesOnBothBackends) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    const Scene scene(rng, 8);
    SceneGraph<coord::QuaternionBackend> g;
    SceneGraph<coord::HomogeneousBackend> h;
    scene.Build(g);
    scene.Build(h);
    std::uniform_int_distribution<int> node(0, 7), side(0, 1);
    for (int i = 0; i < 15; ++i) {
      const auto name = [&](int k) { return (side(rng) ? "f" : "g") + std::to_string(k); };
      const std::string e = name(node(rng)), r = name(node(rng));
      const std::string C = "B" + std::to_string(node(rng)), D = "B" + std::to_string(node(rng));
      const TwistSpec spec = TwistSpec::Of(e, C).RelativeTo(D).ExpressedIn(r);
      SCOPED_TRACE(e + "|" + C + " wrt " + D + " in [" + r + "]");
      ExpectSameAsOneShot(g, spec);
      ExpectSameAsOneShot(h, spec);
    }
  }
}

TEST(CompiledTwistCovariance, CompileErrorsAreCompileTwists) {
  std::mt19937 rng(22);
  const Scene scene(rng);
  SceneGraph<> g;
  scene.Build(g);
  const TwistSpec bad[] = {TwistSpec::Of("nowhere", "B1").RelativeTo("B0").ExpressedIn("f0"),
                           TwistSpec::Of("f1", "B1").RelativeTo("Nobody").ExpressedIn("f0"),
                           TwistSpec::Of("f1", "B1").RelativeTo("B0").ExpressedIn("nowhere"),
                           TwistSpec::Of("f1", "B1").RelativeTo("").ExpressedIn("f0")};
  for (const TwistSpec& spec : bad) {
    const auto compiled = g.CompileTwistWithCovariance(spec);
    ASSERT_FALSE(compiled);
    EXPECT_EQ(compiled.error().code, g.CompileTwist(spec).error().code);
    EXPECT_EQ(g.CompileLinearVelocityWithCovariance(spec).error().code, compiled.error().code);
  }
  // The angular velocity needs a body (there is no point to take it from).
  const auto no_body = g.CompileAngularVelocityWithCovariance(
      TwistSpec::Of("", "").RelativeTo("B0").ExpressedIn("f0"));
  ASSERT_FALSE(no_body);
  EXPECT_EQ(no_body.error().code, g.GetAngularVelocityWithCovariance(
                                       TwistSpec::Of("", "").RelativeTo("B0").ExpressedIn("f0"))
                                      .error()
                                      .code);
}

TEST(CompiledTwistCovariance, RealTimeNoAllocationFollowsUpdatesAndRemovals) {
  std::mt19937 rng(23);
  const Scene scene(rng, 8);
  SceneGraph<> g;
  scene.Build(g);
  const TwistSpec spec = TwistSpec::Of("g7", "B7").RelativeTo("B0").ExpressedIn("g3");
  auto compiled = g.CompileTwistWithCovariance(spec);
  ASSERT_TRUE(compiled);
  auto twist_handle = g.FindTwistEdge("f7", scene.twists.back().ref_body);
  auto pose_handle = g.FindPoseEdge("f7", scene.poses[scene.poses.size() - 2].to);
  ASSERT_TRUE(twist_handle && pose_handle);
  Vec v, w;
  Covariance6 S, S_new = 4e-6 * Covariance6::Identity();
  static_assert(noexcept(compiled->Evaluate(v, w, S)));
  const CovarianceInput input{&S_new};
  const Eigen::Quaterniond q(ExpR(Vec(0.1, 0.2, 0.3)));
  const std::size_t before = AllocationCounter::total();
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(g.SetTwist(*twist_handle, Vec(i, 0, 0), Vec(0, 0, 1), input), ErrorCode::kOk);
    ASSERT_EQ(g.SetPose(*pose_handle, q, Vec(0, i, 0), input), ErrorCode::kOk);
    ASSERT_EQ(compiled->Evaluate(v, w, S), ErrorCode::kOk);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  const auto one_shot = g.GetTwistWithCovariance(spec);
  ASSERT_TRUE(one_shot);
  EXPECT_LE((v - one_shot->value.linear).norm(), 1e-9);
  EXPECT_LE((S - one_shot->covariance).norm(), 1e-12 * (1.0 + S.norm()));
  // The same value without a covariance: the twist edge is exact again, and only its share
  // (J S J^T with S = 4e-6 I: a positive trace) is gone.
  ASSERT_EQ(g.SetTwist(*twist_handle, Vec(99, 0, 0), Vec(0, 0, 1)), ErrorCode::kOk);
  Covariance6 S_exact;
  ASSERT_EQ(compiled->Evaluate(v, w, S_exact), ErrorCode::kOk);
  EXPECT_LE((S_exact - g.GetTwistWithCovariance(spec)->covariance).norm(), 1e-12);
  EXPECT_LT(S_exact.trace(), S.trace());
  // A removal invalidates (nothing written).
  ASSERT_TRUE(g.RemoveTwist("f7", scene.twists.back().ref_body));
  const Vec v_before = v;
  EXPECT_EQ(compiled->Evaluate(v, w, S), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(v, v_before);
}

}  // namespace
}  // namespace semgraph::core
