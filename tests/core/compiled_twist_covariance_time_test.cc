// core/compiled_twist_covariance.h at a time (Evaluate with a TimePolicy): the compiled twist
// query with covariance gives the one-shot timed query's answer, covariance and report
// (GetTwistWithCovariance(spec, policy), whose truth is Monte Carlo: time_uncertainty_test.cc)
// under Latest, At a sample's stamp, At between samples and LatestCommon, on random scenes of
// stamped and timeless pose and twist edges, on both backends (also the linear and angular
// velocities); one twist edge's interpolated
// covariance by hand; the errors (kStale, kExtrapolation, also beyond the horizon,
// kInvalidNumber, kQueryInvalidated after a removal) leave the outputs unchanged; and an
// evaluation allocates nothing. Extrapolation (held twists, extrapolated pose edges, within
// max_extrapolation, after and before the samples, latest common, beyond the horizon): the
// one-shot's answer, covariance (1e-12 relative) and report or error on random scenes and on
// the shared-edge scene; a held twist by hand; no allocation when extrapolating.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/compiled_twist_covariance.h"
#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"
#include "support/random_covariance.h"

namespace semgraph::core {
namespace {

using semgraph::testing::AllocationsOf;
using semgraph::testing::ExpR;
using semgraph::testing::MakeTimedGraph;
using semgraph::testing::Ms;
using semgraph::testing::RandomCovariance;
using semgraph::testing::RandomFrameName;
using semgraph::testing::RandomTreeEdge;
using semgraph::testing::RandomVector;
using semgraph::testing::SpecNames;

// Frames f0..f5 on bodies B0..B5, f_k under a random earlier frame, and the twist edge of B_k
// relative to that frame's body at f_k in [f_k]; each edge stamped (samples near 1, 2 and 3 s,
// [1 s, 3 s] inside them all) or timeless; every value with a covariance.
template <class Graph>
void BuildScene(Graph& g, std::mt19937& rng) {
  std::uniform_int_distribution<int> jitter(0, 300), coin(0, 2);
  for (int k = 1; k < 6; ++k) {
    const auto [f, F, t, T, s] = RandomTreeEdge(rng, k);
    const PoseSpec pose = PoseSpec::Of(f, F).RelativeTo(t, T);
    const TwistSpec twist = TwistSpec::Of(f, F).RelativeTo(T).ExpressedIn(f);
    for (int kind = 0; kind < 2; ++kind) {
      const bool stamped = coin(rng) != 0;
      for (const std::int64_t ms : {1000 - jitter(rng), 2000 + jitter(rng), 3000 + jitter(rng)}) {
        const Covariance6 S = RandomCovariance(rng);
        const CovarianceInput c{&S};
        const Eigen::Vector3d x = RandomVector(rng), y = RandomVector(rng);
        const BuildResult r =
            kind == 0 ? (stamped ? g.AddPose(pose, ExpR(0.5 * x), y, Ms(ms), c)
                                 : g.AddPose(pose, ExpR(0.5 * x), y, c))
                      : (stamped ? g.AddTwist(twist, x, y, Ms(ms), c) : g.AddTwist(twist, x, y, c));
        ASSERT_TRUE(r) << r.error().message;
        if (!stamped) break;
      }
    }
  }
}

// Returns whether the query answered (false: both gave the same error).
template <class Graph>
bool ExpectSameAsOneShot(const Graph& g, const TwistSpec& spec, const TimePolicy& policy,
                         TwistSource source = TwistSource::kTwists) {
  auto compiled = g.CompileTwistWithCovariance(spec, source);
  EXPECT_TRUE(compiled);
  if (!compiled) return false;
  const auto one_shot =
      g.GetTwistWithCovariance(spec, policy, CovarianceOrder::kLinearAngular, source);
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  const ErrorCode code = compiled->Evaluate(v, w, S, policy, report);
  if (!one_shot) {
    EXPECT_EQ(code, one_shot.error().code);
    return false;
  }
  EXPECT_EQ(code, ErrorCode::kOk);
  if (code != ErrorCode::kOk) return false;
  EXPECT_LE((v - one_shot->value.value.linear).norm(), 1e-12);
  EXPECT_LE((w - one_shot->value.value.angular).norm(), 1e-12);
  const Covariance6& S1 = one_shot->value.covariance;
  EXPECT_LE((S - S1).norm(), 1e-12 * S1.norm() + 1e-20);
  EXPECT_EQ(report.time, one_shot->time.time);
  EXPECT_EQ(report.oldest, one_shot->time.oldest);
  EXPECT_EQ(report.newest, one_shot->time.newest);
  EXPECT_EQ(report.extrapolated, one_shot->time.extrapolated);
  // The linear and angular velocities.
  auto linear = g.CompileLinearVelocityWithCovariance(spec, source);
  auto angular = g.CompileAngularVelocityWithCovariance(spec, source);
  const auto v1 = g.GetLinearVelocityWithCovariance(spec, policy, source);
  const auto w1 = g.GetAngularVelocityWithCovariance(spec, policy, source);
  EXPECT_TRUE(linear && angular && v1 && w1);
  if (!linear || !angular || !v1 || !w1) return false;
  Eigen::Matrix3d S3 = Eigen::Matrix3d::Zero();
  EXPECT_EQ(linear->Evaluate(v, S3, policy, report), ErrorCode::kOk);
  EXPECT_LE((v - v1->value.value.value).norm(), 1e-12);
  EXPECT_LE((S3 - v1->value.covariance).norm(), 1e-12 * v1->value.covariance.norm() + 1e-20);
  EXPECT_EQ(report.oldest, v1->time.oldest);
  EXPECT_EQ(angular->Evaluate(w, S3, policy, report), ErrorCode::kOk);
  EXPECT_LE((w - w1->value.value.value).norm(), 1e-12);
  EXPECT_LE((S3 - w1->value.covariance).norm(), 1e-12 * w1->value.covariance.norm() + 1e-20);
  EXPECT_EQ(report.oldest, w1->time.oldest);
  return true;
}

// e|C wrt D in [r], e and r random frames (also calibrations s_k with `calibrations`), C e's
// body, D a random body.
TwistSpec RandomSpec(std::mt19937& rng, bool calibrations, SpecNames& names) {
  std::string &e = names[0], &r = names[1], &C = names[2], &D = names[3];
  e = RandomFrameName(rng, 5, calibrations);
  r = RandomFrameName(rng, 5, calibrations);
  C = "B" + e.substr(1);
  D = "B" + std::to_string(std::uniform_int_distribution<int>(0, 5)(rng));
  return TwistSpec::Of(e, C).RelativeTo(D).ExpressedIn(r);
}

// The number of the random comparisons answered on BuildScene's scenes, twists from `source`,
// under Latest, At near 2 s (a sample's stamp when some edge is stamped), At between samples
// (from `first_between` ms), LatestCommon, and from poses also beyond the samples with a 1 s
// horizon (never extrapolated).
template <class Graph>
int RandomScenes(unsigned seed, TwistSource source, int first_between) {
  std::mt19937 rng(seed);
  const bool from_poses = source == TwistSource::kPoses;
  const auto policies = [&](std::mt19937& r) {
    const std::int64_t sample = std::uniform_int_distribution<int>(0, 300)(r);
    const std::int64_t between = std::uniform_int_distribution<int>(first_between, 2999)(r);
    std::vector<TimePolicy> p = {Latest{}, At{Ms(2000 + sample)}, At{Ms(between)}, LatestCommon{}};
    if (from_poses) p.push_back(At{Ms(3400), Duration::Seconds(1)});
    return p;
  };
  const auto check = [source](const Graph& g, const TwistSpec& spec, const TimePolicy& policy) {
    return ExpectSameAsOneShot(g, spec, policy, source);
  };
  return semgraph::testing::CountAnswered<Graph>(
      rng, BuildScene<Graph>,
      [](std::mt19937& r, SpecNames& names) { return RandomSpec(r, false, names); }, policies,
      check);
}

TEST(CompiledTwistCovarianceTime, SameAsOneShotOnRandomStampedScenes) {
  // Every edge is read inside its samples: no error.
  const TwistSource twists = TwistSource::kTwists;
  EXPECT_EQ(RandomScenes<SceneGraph<coord::QuaternionBackend>>(7, twists, 1001), 6 * 10 * 4);
  EXPECT_EQ(RandomScenes<SceneGraph<coord::HomogeneousBackend>>(8, twists, 1001), 6 * 10 * 4);
}

using Graph = SceneGraph<coord::QuaternionBackend>;

// One twist edge A wrt W at a in [a], samples at 1 s (S0) and 3 s (S1): at 2.5 s the answer is
// the linear interpolation of the two twists, with covariance 1/4 S0 + 3/4 S1, by hand.
struct OneTwist {
  Graph g = MakeTimedGraph<Graph>();
  Covariance6 S0, S1;
  Eigen::Vector3d v0{1.0, 2.0, 3.0}, w0{0.1, 0.2, 0.3}, v1{5.0, -2.0, 7.0}, w1{-0.3, 0.0, 0.5};
  TwistSpec spec = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a");
  OneTwist() {
    std::mt19937 rng(9);
    S0 = RandomCovariance(rng);
    S1 = RandomCovariance(rng);
    EXPECT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), Eigen::Matrix3d::Identity(),
                          Eigen::Vector3d::Zero()));
    EXPECT_TRUE(g.AddTwist(spec, v0, w0, Ms(1000), CovarianceInput{&S0}));
    EXPECT_TRUE(g.AddTwist(spec, v1, w1, Ms(3000), CovarianceInput{&S1}));
  }
};

TEST(CompiledTwistCovarianceTime, InterpolatedCovarianceOfOneTwistEdgeByHand) {
  OneTwist s;
  auto compiled = s.g.CompileTwistWithCovariance(s.spec);
  ASSERT_TRUE(compiled);
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  ASSERT_EQ(compiled->Evaluate(v, w, S, At{Ms(2500)}, report), ErrorCode::kOk);
  EXPECT_LE((v - (0.25 * s.v0 + 0.75 * s.v1)).norm(), 1e-12);
  EXPECT_LE((w - (0.25 * s.w0 + 0.75 * s.w1)).norm(), 1e-12);
  EXPECT_LE((S - (0.25 * s.S0 + 0.75 * s.S1)).norm(), 1e-15 * s.S0.norm());
  EXPECT_EQ(report.time, Ms(2500));
  EXPECT_EQ(report.oldest, Ms(1000));
  EXPECT_EQ(report.newest, Ms(3000));
}

void ExpectUnchangedOn(CompiledTwistWithCovariance<coord::QuaternionBackend>& q,
                       const TimePolicy& policy, ErrorCode expected) {
  Eigen::Vector3d v(1.0, 2.0, 3.0), w(4.0, 5.0, 6.0);
  Covariance6 S = Covariance6::Constant(42.0);
  TimeReport report;
  EXPECT_EQ(q.Evaluate(v, w, S, policy, report), expected);
  EXPECT_TRUE((v == Eigen::Vector3d(1.0, 2.0, 3.0)));
  EXPECT_TRUE((w == Eigen::Vector3d(4.0, 5.0, 6.0)));
  EXPECT_TRUE((S == Covariance6::Constant(42.0)));
}

TEST(CompiledTwistCovarianceTime, ErrorsLeaveTheOutputsUnchanged) {
  OneTwist s;
  auto compiled = s.g.CompileTwistWithCovariance(s.spec);
  ASSERT_TRUE(compiled);
  ExpectUnchangedOn(*compiled, Latest{Ms(5000)}, ErrorCode::kStale);
  ExpectUnchangedOn(*compiled, At{Ms(100)}, ErrorCode::kExtrapolation);
  ExpectUnchangedOn(*compiled, At{Ms(1500), Duration::Seconds(-1)}, ErrorCode::kInvalidNumber);
  // Beyond the horizon: as the one-shot query.
  ExpectUnchangedOn(*compiled, At{Ms(3500), Duration::Milliseconds(400)},
                    ErrorCode::kExtrapolation);
  EXPECT_EQ(
      s.g.GetTwistWithCovariance(s.spec, At{Ms(3500), Duration::Milliseconds(400)}).error().code,
      ErrorCode::kExtrapolation);
  ASSERT_TRUE(s.g.RemoveTwist("a", "W"));
  ExpectUnchangedOn(*compiled, At{Ms(1500)}, ErrorCode::kQueryInvalidated);
  ExpectUnchangedOn(*compiled, LatestCommon{}, ErrorCode::kQueryInvalidated);
}

// The outputs of the compiled twist queries; each Add evaluates one query under a policy and
// adds the trace of the covariance answered to sum.
struct Outputs {
  template <class Query>
  void AddTwist(Query& q, const TimePolicy& policy) noexcept {
    if (q.Evaluate(v, w, S, policy, report) == ErrorCode::kOk) sum += S.trace();
  }
  template <class Query>
  void AddLinear(Query& q, const TimePolicy& policy) noexcept {
    if (q.Evaluate(v, S3, policy, report) == ErrorCode::kOk) sum += S3.trace();
  }
  template <class Query>
  void AddAngular(Query& q, const TimePolicy& policy) noexcept {
    if (q.Evaluate(w, S3, policy, report) == ErrorCode::kOk) sum += S3.trace();
  }
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Covariance6 S = Covariance6::Zero();
  Eigen::Matrix3d S3 = Eigen::Matrix3d::Zero();
  TimeReport report;
  double sum = 0.0;
};

TEST(CompiledTwistCovarianceTime, EvaluationAtATimeDoesNotAllocate) {
  std::mt19937 rng(21);
  Graph g = MakeTimedGraph<Graph>();
  BuildScene(g, rng);
  const TwistSpec spec = TwistSpec::Of("f5", "B5").RelativeTo("B0").ExpressedIn("f3");
  auto compiled = g.CompileTwistWithCovariance(spec);
  ASSERT_TRUE(compiled);
  Outputs o;
  std::size_t allocations = AllocationsOf(100, [&](int i) {
    const TimePolicy policies[] = {At{Ms(1200 + 10 * i)}, Latest{}, LatestCommon{}, At{Ms(100)}};
    for (const TimePolicy& policy : policies) o.AddTwist(*compiled, policy);
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(o.sum, 0.0);
  static_assert(noexcept(compiled->Evaluate(o.v, o.w, o.S, Latest{}, o.report)));
  auto linear = g.CompileLinearVelocityWithCovariance(spec);
  auto angular = g.CompileAngularVelocityWithCovariance(spec);
  ASSERT_TRUE(linear && angular);
  allocations = AllocationsOf(100, [&](int i) {
    o.AddLinear(*linear, At{Ms(1200 + 10 * i)});
    o.AddAngular(*angular, LatestCommon{});
  });
  EXPECT_EQ(allocations, 0u);
  static_assert(noexcept(linear->Evaluate(o.v, o.S3, Latest{}, o.report)));
  static_assert(noexcept(angular->Evaluate(o.w, o.S3, Latest{}, o.report)));
}

// Within the horizon the newest twist sample is held (by hand: its value and covariance S1);
// before the first, the oldest (S0); the report says so.
TEST(CompiledTwistCovarianceTime, HeldTwistOfOneTwistEdgeByHand) {
  OneTwist s;
  auto compiled = s.g.CompileTwistWithCovariance(s.spec);
  ASSERT_TRUE(compiled);
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  ASSERT_EQ(compiled->Evaluate(v, w, S, At{Ms(3500), Duration::Seconds(1)}, report),
            ErrorCode::kOk);
  EXPECT_LE((v - s.v1).norm(), 1e-12);
  EXPECT_LE((w - s.w1).norm(), 1e-12);
  EXPECT_LE((S - s.S1).norm(), 1e-15 * s.S1.norm());
  EXPECT_EQ(report.time, Ms(3500));
  EXPECT_EQ(report.oldest, Ms(3000));
  EXPECT_EQ(report.newest, Ms(3000));
  EXPECT_TRUE(report.extrapolated);
  ASSERT_EQ(compiled->Evaluate(v, w, S, At{Ms(500), Duration::Seconds(1)}, report), ErrorCode::kOk);
  EXPECT_LE((v - s.v0).norm(), 1e-12);
  EXPECT_LE((S - s.S0).norm(), 1e-15 * s.S0.norm());
  EXPECT_TRUE(ExpectSameAsOneShot(s.g, s.spec, At{Ms(3500), Duration::Seconds(1)}));
}

// BuildScene with each twist edge stamped at its pose edge's stamps when both are stamped (the
// integration twist of an extrapolated pose edge is read at its sample's stamp, without
// extrapolation), and a constant calibration s_k under f_k (covariance) where the twist is given
// when `calibrated`: queries at s_k then share it with the integration twist.
template <class Graph>
void BuildExtrapolationScene(Graph& g, std::mt19937& rng) {
  std::uniform_int_distribution<int> jitter(0, 300), coin(0, 2);
  for (int k = 1; k < 6; ++k) {
    const auto [f, F, t, T, s] = RandomTreeEdge(rng, k);
    Covariance6 S = RandomCovariance(rng);
    ASSERT_TRUE(g.AddPose(PoseSpec::Of(s, F).RelativeTo(f, F), ExpR(0.5 * RandomVector(rng)),
                          RandomVector(rng), CovarianceInput{&S}));
    const PoseSpec pose = PoseSpec::Of(f, F).RelativeTo(t, T);
    const TwistSpec twist = TwistSpec::Of(s, F).RelativeTo(T).ExpressedIn(s);
    const std::int64_t stamps[] = {1000 - jitter(rng), 2000 + jitter(rng), 3000 + jitter(rng)};
    for (int kind = 0; kind < 2; ++kind) {
      const bool stamped = coin(rng) != 0;
      for (const std::int64_t ms : stamps) {
        S = RandomCovariance(rng);
        const CovarianceInput c{&S};
        const Eigen::Vector3d x = RandomVector(rng), y = RandomVector(rng);
        const BuildResult r = kind == 0 ? (stamped ? g.AddPose(pose, ExpR(0.5 * x), y, Ms(ms), c)
                                                   : g.AddPose(pose, ExpR(0.5 * x), y, c))
                                        : (stamped ? g.AddTwist(twist, x, 0.3 * y, Ms(ms), c)
                                                   : g.AddTwist(twist, x, 0.3 * y, c));
        ASSERT_TRUE(r) << r.error().message;
        if (!stamped) break;
      }
    }
  }
}

// Extrapolation (within max_extrapolation, after and before every edge's samples, latest
// common, beyond the horizon): the compiled queries give the one-shot's answer, covariance and
// report, or its error.
template <class Graph>
void RandomExtrapolations(unsigned seed) {
  std::mt19937 rng(seed);
  semgraph::testing::CompareExtrapolations<Graph>(
      rng, BuildExtrapolationScene<Graph>,
      [](std::mt19937& r, SpecNames& names) { return RandomSpec(r, true, names); },
      [](const Graph& g, const TwistSpec& spec, const TimePolicy& policy) {
        return ExpectSameAsOneShot(g, spec, policy);
      },
      [](const Graph& g, const TwistSpec& spec, const TimePolicy& policy) {
        return g.GetTwist(spec, policy)->time.extrapolated;
      });
}

TEST(CompiledTwistCovarianceTime, ExtrapolationSameAsOneShotOnRandomScenes) {
  RandomExtrapolations<SceneGraph<coord::QuaternionBackend>>(41);
  RandomExtrapolations<SceneGraph<coord::HomogeneousBackend>>(42);
}

// time_uncertainty_test.cc's shared-edge scene: h wrt w stamped (0 s, 1 s), the calibration s
// wrt h constant with a covariance, the twist of H relative to W given at s (1 s). The twist of
// H at s relative to W in [w] at 1.5 s reads the held twist and moves it with h wrt w,
// extrapolated with the same twist through the same calibration: shared edges, perturbed once
// (the one-shot's Monte Carlo test); the compiled query gives the one-shot's numbers.
TEST(CompiledTwistCovarianceTime, EdgesSharedByIntegrationTwistAndQuerySameAsOneShot) {
  std::mt19937 rng(2718);
  Graph g = MakeTimedGraph<Graph>();
  const Covariance6 S_cal = RandomCovariance(rng), S0 = 1e-2 * RandomCovariance(rng),
                    S1 = 1e-2 * RandomCovariance(rng), S_tw = 1e-2 * RandomCovariance(rng);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("s", "H").RelativeTo("h", "H"),
                        ExpR(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.4, 0.1, -0.2),
                        CovarianceInput{&S_cal}));
  const PoseSpec hw = PoseSpec::Of("h", "H").RelativeTo("w", "W");
  ASSERT_TRUE(g.AddPose(hw, ExpR(Eigen::Vector3d(0.2, 0.1, 0.0)), Eigen::Vector3d(1, 0, 0), Ms(0),
                        CovarianceInput{&S0}));
  ASSERT_TRUE(g.AddPose(hw, ExpR(Eigen::Vector3d(0.25, 0.1, 0.1)), Eigen::Vector3d(1.2, 0.3, 0),
                        Ms(1000), CovarianceInput{&S1}));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("s", "H").RelativeTo("W").ExpressedIn("s"),
                         Eigen::Vector3d(0.5, 0.2, 0.0), Eigen::Vector3d(0.1, -0.3, 1.0), Ms(1000),
                         CovarianceInput{&S_tw}));
  const TimePolicy policy = At{Ms(1500), Duration::Seconds(1)};
  for (const TwistSpec& spec : {TwistSpec::Of("s", "H").RelativeTo("W").ExpressedIn("w"),
                                TwistSpec::Of("w", "W").RelativeTo("H").ExpressedIn("h")}) {
    EXPECT_TRUE(ExpectSameAsOneShot(g, spec, policy));
    EXPECT_TRUE(g.GetTwist(spec, policy)->time.extrapolated);
  }
}

TEST(CompiledTwistCovarianceTime, ExtrapolatedEvaluationDoesNotAllocate) {
  std::mt19937 rng(27);
  Graph g = MakeTimedGraph<Graph>();
  BuildExtrapolationScene(g, rng);
  const TwistSpec spec = TwistSpec::Of("s5", "B5").RelativeTo("B0").ExpressedIn("s3");
  auto compiled = g.CompileTwistWithCovariance(spec);
  auto linear = g.CompileLinearVelocityWithCovariance(spec);
  ASSERT_TRUE(compiled && linear);
  Outputs o;
  ASSERT_EQ(compiled->Evaluate(o.v, o.w, o.S, At{Ms(3400), Duration::Seconds(1)}, o.report),
            ErrorCode::kOk);
  ASSERT_TRUE(o.report.extrapolated);
  const std::size_t allocations = AllocationsOf(100, [&](int i) {
    const TimePolicy policies[] = {
        At{Ms(3350 + i), Duration::Seconds(1)}, At{Ms(600 - i), Duration::Seconds(1)},
        LatestCommon{Duration::Seconds(1)}, At{Ms(3400), Duration::Milliseconds(1)}};
    for (const TimePolicy& policy : policies) {
      o.AddTwist(*compiled, policy);
      o.AddLinear(*linear, policy);
    }
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(o.sum, 0.0);
}

// Twist source `poses` (CompileTwistWithCovariance(spec, kPoses)): the one-shot's answer,
// covariance and report or error (GetTwistWithCovariance(spec, policy, order, kPoses), Monte
// Carlo tested in time_uncertainty_test.cc) on random scenes, under Latest, At a stamp, At
// between samples, LatestCommon, and beyond the samples with a horizon (never extrapolated).
TEST(CompiledTwistCovarianceTime, FromPosesSameAsOneShotOnRandomScenes) {
  const TwistSource poses = TwistSource::kPoses;
  for (const int answered :
       {RandomScenes<SceneGraph<coord::QuaternionBackend>>(51, poses, 1301),
        RandomScenes<SceneGraph<coord::HomogeneousBackend>>(52, poses, 1301)}) {
    std::printf("from poses: %d of %d answered\n", answered, 6 * 10 * 5);
    EXPECT_GT(answered, 6 * 10 * 3);
  }
}

// One pose edge a -> w, identity rotations, samples p0 at 1 s and p1 at 1.5 s with covariances
// on dp only: the twist of A relative to W at a in [a] from poses, between them, is
// (p1 - p0) / 0.5 s with covariance (S0 + S1) / 0.25 s^2 on dv (the difference of two
// independent samples over dt), by hand; the untimed Evaluate reads the newest segment (the
// same here). A removed edge: kQueryInvalidated.
TEST(CompiledTwistCovarianceTime, FromPosesOneEdgeByHand) {
  Graph g = MakeTimedGraph<Graph>();
  const PoseSpec pose = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  Covariance6 S0 = Covariance6::Zero(), S1 = Covariance6::Zero();
  S0.topLeftCorner<3, 3>() = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  S1.topLeftCorner<3, 3>() = Eigen::Vector3d(3e-4, 1e-4, 5e-4).asDiagonal();
  const Eigen::Vector3d p0(1.0, 2.0, 3.0), p1(2.0, 1.0, 3.5);
  ASSERT_TRUE(g.AddPose(pose, Eigen::Matrix3d::Identity(), p0, Ms(1000), CovarianceInput{&S0}));
  ASSERT_TRUE(g.AddPose(pose, Eigen::Matrix3d::Identity(), p1, Ms(1500), CovarianceInput{&S1}));
  const TwistSpec spec = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a");
  auto compiled = g.CompileTwistWithCovariance(spec, TwistSource::kPoses);
  ASSERT_TRUE(compiled);
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  Covariance6 expected = Covariance6::Zero();
  expected.topLeftCorner<3, 3>() = (S0 + S1).topLeftCorner<3, 3>() / 0.25;
  ASSERT_EQ(compiled->Evaluate(v, w, S, At{Ms(1200)}, report), ErrorCode::kOk);
  EXPECT_LE((v - (p1 - p0) / 0.5).norm(), 1e-12);
  EXPECT_LE(w.norm(), 1e-12);
  EXPECT_LE((S - expected).norm(), 1e-12 * expected.norm()) << S;
  EXPECT_EQ(report.oldest, Ms(1000));
  EXPECT_EQ(report.newest, Ms(1500));
  EXPECT_FALSE(report.extrapolated);
  ASSERT_EQ(compiled->Evaluate(v, w, S), ErrorCode::kOk);
  EXPECT_LE((v - (p1 - p0) / 0.5).norm(), 1e-12);
  EXPECT_LE((S - expected).norm(), 1e-12 * expected.norm()) << S;
  // Never extrapolated, whatever the horizon (as the one-shot query).
  ExpectUnchangedOn(*compiled, At{Ms(1600), Duration::Seconds(1)}, ErrorCode::kExtrapolation);
  EXPECT_EQ(g.GetTwistWithCovariance(spec, At{Ms(1600), Duration::Seconds(1)},
                                     CovarianceOrder::kLinearAngular, TwistSource::kPoses)
                .error()
                .code,
            ErrorCode::kExtrapolation);
  ASSERT_TRUE(g.RemovePose("a", "w"));
  ExpectUnchangedOn(*compiled, At{Ms(1200)}, ErrorCode::kQueryInvalidated);
}

TEST(CompiledTwistCovarianceTime, FromPosesEvaluationDoesNotAllocate) {
  std::mt19937 rng(29);
  Graph g = MakeTimedGraph<Graph>();
  BuildScene(g, rng);
  const TwistSpec spec = TwistSpec::Of("f5", "B5").RelativeTo("B0").ExpressedIn("f3");
  auto compiled = g.CompileTwistWithCovariance(spec, TwistSource::kPoses);
  auto angular = g.CompileAngularVelocityWithCovariance(spec, TwistSource::kPoses);
  ASSERT_TRUE(compiled && angular);
  Outputs o;
  const std::size_t allocations = AllocationsOf(100, [&](int i) {
    const TimePolicy policies[] = {At{Ms(1400 + 10 * i)}, Latest{}, LatestCommon{},
                                   At{Ms(100), Duration::Seconds(1)}};
    for (const TimePolicy& policy : policies) {
      o.AddTwist(*compiled, policy);
      o.AddAngular(*angular, policy);
    }
    if (compiled->Evaluate(o.v, o.w, o.S) == ErrorCode::kOk) o.sum += o.S.trace();
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(o.sum, 0.0);
}

}  // namespace
}  // namespace semgraph::core
