// core/compiled_covariance.h at a time (Evaluate with a TimePolicy): the compiled pose,
// position and orientation queries with covariance give the one-shot timed query's answer,
// covariance and report (GetPoseWithCovariance(spec, policy), whose truth is Monte Carlo:
// time_uncertainty_test.cc) under Latest, At a sample's stamp, At between samples and
// LatestCommon, on random stamped scenes, on both backends; one covariance by hand (the linear
// interpolation of two samples' covariances); the errors (kStale, kExtrapolation, also with a
// horizon, kInvalidNumber, kQueryInvalidated after a removal) leave the outputs unchanged; and
// an evaluation allocates nothing. Extrapolation (within max_extrapolation, after and before the
// samples, latest common, beyond the horizon): the one-shot's answer, covariance (1e-12
// relative) and report or error on random scenes whose twists are given at calibration frames,
// and on the shared-edge scene of time_uncertainty_test.cc (an edge used by the integration
// twist and the query); one extrapolated edge by hand; no allocation when extrapolating.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "semgraph/core/compiled_covariance.h"
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

// Frames f0..f6 on bodies B0..B6, f_k under a random earlier frame; each edge stamped (samples
// near 1, 2 and 3 s, the first at or before 1 s and the last at or after 3 s, so [1 s, 3 s] is
// inside every edge's samples) or timeless; every value with a covariance. Also the stamps.
template <class Graph>
void BuildScene(Graph& g, std::mt19937& rng, std::vector<std::int64_t>& stamps) {
  std::uniform_int_distribution<int> jitter(0, 300), coin(0, 3);
  for (int k = 1; k < 7; ++k) {
    const auto [f, F, t, T, s] = RandomTreeEdge(rng, k);
    const PoseSpec spec = PoseSpec::Of(f, F).RelativeTo(t, T);
    if (coin(rng) == 0) {
      const Covariance6 S = RandomCovariance(rng);
      const auto added =
          g.AddPose(spec, ExpR(0.5 * RandomVector(rng)), RandomVector(rng), CovarianceInput{&S});
      ASSERT_TRUE(added) << added.error().message;
      continue;
    }
    for (const std::int64_t ms : {1000 - jitter(rng), 2000 + jitter(rng), 3000 + jitter(rng)}) {
      const Covariance6 S = RandomCovariance(rng);
      const auto added = g.AddPose(spec, ExpR(0.5 * RandomVector(rng)), RandomVector(rng), Ms(ms),
                                   CovarianceInput{&S});
      ASSERT_TRUE(added) << added.error().message;
      stamps.push_back(ms);
    }
  }
}

void ExpectSameReport(const TimeReport& a, const TimeReport& b) {
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.oldest, b.oldest);
  EXPECT_EQ(a.newest, b.newest);
  EXPECT_EQ(a.extrapolated, b.extrapolated);
}

// Returns whether the query answered (false: both gave the same error).
template <class Graph>
bool ExpectSameAsOneShot(const Graph& g, const PoseSpec& spec, const TimePolicy& policy) {
  using B = typename Graph::Backend;
  auto pose = g.CompilePoseWithCovariance(spec);
  auto position = g.CompilePositionWithCovariance(spec);
  auto orientation = g.CompileOrientationWithCovariance(spec);
  const auto code_of = [](const auto& r) { return r ? ErrorCode::kOk : r.error().code; };
  EXPECT_TRUE(pose && position && orientation)
      << base::ToString(code_of(pose)) << " " << base::ToString(code_of(position)) << " "
      << base::ToString(code_of(orientation));
  if (!pose || !position || !orientation) return false;
  const auto one_shot = g.GetPoseWithCovariance(spec, policy);
  typename B::PoseCoords X = B::Identity();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  const ErrorCode code = pose->Evaluate(X, S, policy, report);
  if (!one_shot) {  // the same error (every edge is read inside its samples here, or fails)
    EXPECT_EQ(code, one_shot.error().code);
    return false;
  }
  EXPECT_EQ(code, ErrorCode::kOk);
  if (code != ErrorCode::kOk) return false;
  const Eigen::Isometry3d O = one_shot->value.value.ToIsometry();
  EXPECT_LE((B::ToMatrix(B::RotationOf(X)) - O.linear()).norm(), 1e-12);
  EXPECT_LE((B::TranslationOf(X) - O.translation()).norm(), 1e-12);
  const Covariance6& S1 = one_shot->value.covariance;
  EXPECT_LE((S - S1).norm(), 1e-12 * S1.norm() + 1e-20);
  ExpectSameReport(report, one_shot->time);
  // Reordered, and the position's and orientation's parts.
  Covariance6 S_swapped;
  EXPECT_EQ(pose->Evaluate(X, S_swapped, policy, report, CovarianceOrder::kAngularLinear),
            ErrorCode::kOk);
  EXPECT_TRUE((S_swapped == coord::SwapHalves(S)));
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S3 = Eigen::Matrix3d::Zero();
  const auto p1 = g.GetPositionWithCovariance(spec, policy);
  EXPECT_TRUE(p1);
  if (!p1) return false;
  EXPECT_EQ(position->Evaluate(p, S3, policy, report), ErrorCode::kOk);
  EXPECT_LE((p - p1->value.value.value).norm(), 1e-12);
  EXPECT_LE((S3 - p1->value.covariance).norm(), 1e-12 * p1->value.covariance.norm() + 1e-20);
  ExpectSameReport(report, p1->time);
  typename B::Rotation R = B::RotationOf(B::Identity());
  const auto R1 = g.GetOrientationWithCovariance(spec, policy);
  EXPECT_TRUE(R1);
  if (!R1) return false;
  EXPECT_EQ(orientation->Evaluate(R, S3, policy, report), ErrorCode::kOk);
  EXPECT_LE((B::ToMatrix(R) - B::ToMatrix(R1->value.value.value)).norm(), 1e-12);
  EXPECT_LE((S3 - R1->value.covariance).norm(), 1e-12 * R1->value.covariance.norm() + 1e-20);
  ExpectSameReport(report, R1->time);
  return true;
}

// a|A wrt b|B in [r] (r = b on the homogeneous backend, whose pose is expressed in its
// reference orientation), a, b, r random frames (also calibrations s_k with `calibrations`).
template <class Graph>
PoseSpec RandomSpec(std::mt19937& rng, bool calibrations, semgraph::testing::SpecNames& names) {
  auto& [a, b, r, C, D] = names;
  a = RandomFrameName(rng, 6, calibrations);
  b = RandomFrameName(rng, 6, calibrations);
  const bool homogeneous = std::is_same_v<typename Graph::Backend, coord::HomogeneousBackend>;
  r = homogeneous ? b : RandomFrameName(rng, 6, calibrations);
  C = "B" + a.substr(1);
  D = "B" + b.substr(1);
  return PoseSpec::Of(a, C).RelativeTo(b, D).ExpressedIn(r);
}

template <class Graph>
void RandomScenes(Interpolation mode, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::int64_t> stamps;
  const auto build = [&](Graph& g, std::mt19937& r) {
    stamps.clear();
    BuildScene(g, r, stamps);
  };
  const auto policies = [&](std::mt19937& r) {
    std::int64_t stamp = 2000;  // a sample's stamp inside [1 s, 3 s] when there is one
    for (const std::int64_t s : stamps) {
      if (s >= 1000 && s <= 3000) stamp = s;
    }
    const TimePolicy p[] = {Latest{}, At{Ms(stamp)},
                            At{Ms(std::uniform_int_distribution<int>(1001, 2999)(r))},
                            LatestCommon{}};
    return std::to_array(p);
  };
  const auto draw = [](std::mt19937& r, semgraph::testing::SpecNames& names) {
    return RandomSpec<Graph>(r, false, names);
  };
  const int answered = semgraph::testing::CountAnswered<Graph>(rng, build, draw, policies,
                                                               ExpectSameAsOneShot<Graph>, mode);
  EXPECT_EQ(answered, 6 * 10 * 4);  // every edge is read inside its samples: no error
}

TEST(CompiledCovarianceTime, SameAsOneShotOnRandomStampedScenesScrew) {
  RandomScenes<SceneGraph<coord::QuaternionBackend>>(Interpolation::kScrew, 3);
  RandomScenes<SceneGraph<coord::HomogeneousBackend>>(Interpolation::kScrew, 4);
}

TEST(CompiledCovarianceTime, SameAsOneShotOnRandomStampedScenesLinear) {
  RandomScenes<SceneGraph<coord::QuaternionBackend>>(Interpolation::kLinear, 5);
  RandomScenes<SceneGraph<coord::HomogeneousBackend>>(Interpolation::kLinear, 6);
}

// Frames f0..f6 on bodies B0..B6, f_k under a random earlier frame, and s_k on B_k: a constant
// calibration under f_k with a covariance, where the twist of B_k relative to the parent's
// body is given (in [s_k]). Each pose edge f_k stamped (samples near 1, 2 and 3 s) or timeless,
// its twist edge stamped at the same stamps (the integration twist is read at the stamp of the
// extrapolated sample) or timeless; every value with a covariance. A query on s_k with f_k's
// edge extrapolated uses the calibration both directly and through the integration twist.
template <class Graph>
void BuildExtrapolationScene(Graph& g, std::mt19937& rng) {
  std::uniform_int_distribution<int> jitter(0, 300), coin(0, 3);
  for (int k = 1; k < 7; ++k) {
    const auto [f, F, t, T, s] = RandomTreeEdge(rng, k);
    const PoseSpec pose = PoseSpec::Of(f, F).RelativeTo(t, T);
    const TwistSpec twist = TwistSpec::Of(s, F).RelativeTo(T).ExpressedIn(s);
    Covariance6 S = RandomCovariance(rng);
    ASSERT_TRUE(g.AddPose(PoseSpec::Of(s, F).RelativeTo(f, F), ExpR(0.5 * RandomVector(rng)),
                          RandomVector(rng), CovarianceInput{&S}));
    const bool stamped = coin(rng) != 0, twist_stamped = coin(rng) != 0;
    const std::int64_t stamps[] = {1000 - jitter(rng), 2000 + jitter(rng), 3000 + jitter(rng)};
    for (const std::int64_t ms : stamps) {
      S = RandomCovariance(rng);
      const Eigen::Vector3d x = RandomVector(rng), y = RandomVector(rng);
      const BuildResult r = stamped ? g.AddPose(pose, ExpR(0.5 * x), y, Ms(ms), CovarianceInput{&S})
                                    : g.AddPose(pose, ExpR(0.5 * x), y, CovarianceInput{&S});
      ASSERT_TRUE(r) << r.error().message;
      if (!stamped) break;
    }
    for (const std::int64_t ms : stamps) {
      S = RandomCovariance(rng);
      const Eigen::Vector3d v = RandomVector(rng), w = 0.3 * RandomVector(rng);
      const BuildResult q = twist_stamped ? g.AddTwist(twist, v, w, Ms(ms), CovarianceInput{&S})
                                          : g.AddTwist(twist, v, w, CovarianceInput{&S});
      ASSERT_TRUE(q) << q.error().message;
      if (!twist_stamped) break;
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
      [](std::mt19937& r, semgraph::testing::SpecNames& names) {
        return RandomSpec<Graph>(r, true, names);
      },
      ExpectSameAsOneShot<Graph>,
      [](const Graph& g, const PoseSpec& spec, const TimePolicy& policy) {
        return g.GetPose(spec, policy)->time.extrapolated;
      });
}

TEST(CompiledCovarianceTime, ExtrapolationSameAsOneShotOnRandomScenes) {
  RandomExtrapolations<SceneGraph<coord::QuaternionBackend>>(31);
  RandomExtrapolations<SceneGraph<coord::HomogeneousBackend>>(32);
}

using Graph = SceneGraph<coord::QuaternionBackend>;
using B = coord::QuaternionBackend;

// One edge a -> w with samples at 1 s (S0, p0) and 3 s (S1, p1), identity rotations: at 1.5 s
// the answer (a wrt w, in [w]: the edge's own form) is p0 + (p1 - p0) / 4 with covariance
// 3/4 S0 + 1/4 S1 (docs/uncertainty.md, "Time"), by hand.
struct OneEdge {
  Graph g = MakeTimedGraph<Graph>(Interpolation::kLinear);
  Covariance6 S0, S1;
  Eigen::Vector3d p0{1.0, 2.0, 3.0}, p1{5.0, -2.0, 7.0};
  PoseSpec spec = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  OneEdge() {
    std::mt19937 rng(9);
    S0 = RandomCovariance(rng);
    S1 = RandomCovariance(rng);
    EXPECT_TRUE(g.AddPose(spec, Eigen::Matrix3d::Identity(), p0, Ms(1000), CovarianceInput{&S0}));
    EXPECT_TRUE(g.AddPose(spec, Eigen::Matrix3d::Identity(), p1, Ms(3000), CovarianceInput{&S1}));
  }
};

TEST(CompiledCovarianceTime, InterpolatedCovarianceOfOneEdgeByHand) {
  OneEdge s;
  auto compiled = s.g.CompilePoseWithCovariance(s.spec);
  ASSERT_TRUE(compiled);
  B::PoseCoords X = B::Identity();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  ASSERT_EQ(compiled->Evaluate(X, S, At{Ms(1500)}, report), ErrorCode::kOk);
  EXPECT_LE((B::TranslationOf(X) - Eigen::Vector3d(2.0, 1.0, 4.0)).norm(), 1e-12);
  EXPECT_LE((B::ToMatrix(B::RotationOf(X)) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LE((S - (0.75 * s.S0 + 0.25 * s.S1)).norm(), 1e-15 * s.S0.norm());
  EXPECT_EQ(report.time, Ms(1500));
  EXPECT_EQ(report.oldest, Ms(1000));
  EXPECT_EQ(report.newest, Ms(3000));
  EXPECT_FALSE(report.extrapolated);
  // At a stamp: that sample's covariance; latest: the newest's.
  ASSERT_EQ(compiled->Evaluate(X, S, At{Ms(1000)}, report), ErrorCode::kOk);
  EXPECT_LE((S - s.S0).norm(), 1e-15 * s.S0.norm());  // stored symmetric
  ASSERT_EQ(compiled->Evaluate(X, S, Latest{}, report), ErrorCode::kOk);
  EXPECT_LE((S - s.S1).norm(), 1e-15 * s.S1.norm());
  EXPECT_LE((B::TranslationOf(X) - s.p1).norm(), 1e-12);
}

// Each error leaves X and S as they were.
void ExpectUnchangedOn(CompiledPoseWithCovariance<B>& q, const TimePolicy& policy,
                       ErrorCode expected) {
  B::PoseCoords X = B::MakePose(B::FromMatrix(ExpR(Eigen::Vector3d(0.1, 0.2, 0.3))),
                                Eigen::Vector3d(9.0, 8.0, 7.0));
  const B::PoseCoords X_before = X;
  Covariance6 S = Covariance6::Constant(42.0);
  TimeReport report;
  EXPECT_EQ(q.Evaluate(X, S, policy, report), expected);
  EXPECT_TRUE((B::ToMatrix(B::RotationOf(X)) == B::ToMatrix(B::RotationOf(X_before))));
  EXPECT_TRUE((B::TranslationOf(X) == B::TranslationOf(X_before)));
  EXPECT_TRUE((S == Covariance6::Constant(42.0)));
}

TEST(CompiledCovarianceTime, ErrorsLeaveTheOutputsUnchanged) {
  OneEdge s;
  auto compiled = s.g.CompilePoseWithCovariance(s.spec);
  ASSERT_TRUE(compiled);
  ExpectUnchangedOn(*compiled, Latest{Ms(5000)}, ErrorCode::kStale);
  EXPECT_EQ(s.g.GetPoseWithCovariance(s.spec, Latest{Ms(5000)}).error().code, ErrorCode::kStale);
  ExpectUnchangedOn(*compiled, At{Ms(100)}, ErrorCode::kExtrapolation);
  EXPECT_EQ(s.g.GetPoseWithCovariance(s.spec, At{Ms(100)}).error().code, ErrorCode::kExtrapolation);
  ExpectUnchangedOn(*compiled, At{Ms(3500)}, ErrorCode::kExtrapolation);
  ExpectUnchangedOn(*compiled, At{Ms(1500), Duration::Seconds(-1)}, ErrorCode::kInvalidNumber);
  // Within the horizon but no integration twist (no twist path from A to W): as the one-shot.
  ExpectUnchangedOn(*compiled, At{Ms(3500), Duration::Seconds(1)}, ErrorCode::kExtrapolation);
  EXPECT_EQ(s.g.GetPoseWithCovariance(s.spec, At{Ms(3500), Duration::Seconds(1)}).error().code,
            ErrorCode::kExtrapolation);
  ExpectUnchangedOn(*compiled, LatestCommon{Duration::Seconds(1), Ms(5000)}, ErrorCode::kStale);
  // A removed edge.
  ASSERT_TRUE(s.g.RemovePose("a", "w"));
  ExpectUnchangedOn(*compiled, At{Ms(1500)}, ErrorCode::kQueryInvalidated);
  ExpectUnchangedOn(*compiled, Latest{}, ErrorCode::kQueryInvalidated);
  ExpectUnchangedOn(*compiled, LatestCommon{}, ErrorCode::kQueryInvalidated);
}

TEST(CompiledCovarianceTime, PositionAndOrientationErrorsLeaveTheOutputsUnchanged) {
  OneEdge s;
  auto position = s.g.CompilePositionWithCovariance(s.spec);
  auto orientation = s.g.CompileOrientationWithCovariance(s.spec);
  ASSERT_TRUE(position && orientation);
  Eigen::Vector3d p(1.0, 2.0, 3.0);
  B::Rotation R = B::RotationOf(
      B::MakePose(B::FromMatrix(ExpR(Eigen::Vector3d(0.1, 0.2, 0.3))), Eigen::Vector3d::Zero()));
  const B::Rotation R_before = R;
  Eigen::Matrix3d S = Eigen::Matrix3d::Constant(42.0);
  TimeReport report;
  EXPECT_EQ(position->Evaluate(p, S, At{Ms(100)}, report), ErrorCode::kExtrapolation);
  EXPECT_EQ(orientation->Evaluate(R, S, Latest{Ms(5000)}, report), ErrorCode::kStale);
  EXPECT_TRUE((p == Eigen::Vector3d(1.0, 2.0, 3.0)));
  EXPECT_TRUE((B::ToMatrix(R) == B::ToMatrix(R_before)));
  EXPECT_TRUE((S == Eigen::Matrix3d::Constant(42.0)));
}

// The compiled pose, position and orientation queries of one spec with their outputs; Evaluate
// runs the three under a policy and adds the traces of the covariances answered to sum.
struct CompiledParts {
  CompiledParts(const Graph& g, const PoseSpec& spec)
      : pose(g.CompilePoseWithCovariance(spec)),
        position(g.CompilePositionWithCovariance(spec)),
        orientation(g.CompileOrientationWithCovariance(spec)) {}
  bool compiled() const { return pose && position && orientation; }
  void Evaluate(const TimePolicy& policy) noexcept {
    if (pose->Evaluate(X, S, policy, report) == ErrorCode::kOk) sum += S.trace();
    if (position->Evaluate(p, S3, policy, report) == ErrorCode::kOk) sum += S3.trace();
    if (orientation->Evaluate(R, S3, policy, report) == ErrorCode::kOk) sum += S3.trace();
  }
  Expected<CompiledPoseWithCovariance<B>, QueryError> pose;
  Expected<CompiledPositionWithCovariance<B>, QueryError> position;
  Expected<CompiledOrientationWithCovariance<B>, QueryError> orientation;
  B::PoseCoords X = B::Identity();
  Covariance6 S = Covariance6::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  B::Rotation R = B::RotationOf(B::Identity());
  Eigen::Matrix3d S3 = Eigen::Matrix3d::Zero();
  TimeReport report;
  double sum = 0.0;
};

TEST(CompiledCovarianceTime, EvaluationAtATimeDoesNotAllocate) {
  std::mt19937 rng(21);
  Graph g = MakeTimedGraph<Graph>(Interpolation::kScrew);
  std::vector<std::int64_t> stamps;
  BuildScene(g, rng, stamps);
  CompiledParts q(g, PoseSpec::Of("f6", "B6").RelativeTo("f5", "B5").ExpressedIn("f4"));
  ASSERT_TRUE(q.compiled());
  const std::size_t allocations = AllocationsOf(100, [&q](int i) {
    const TimePolicy policies[] = {At{Ms(1200 + 10 * i)}, Latest{}, LatestCommon{}, At{Ms(100)}};
    for (const TimePolicy& policy : policies) q.Evaluate(policy);
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(q.sum, 0.0);
  static_assert(noexcept(q.pose->Evaluate(q.X, q.S, Latest{}, q.report)));
  static_assert(noexcept(q.position->Evaluate(q.p, q.S3, Latest{}, q.report)));
  static_assert(noexcept(q.orientation->Evaluate(q.R, q.S3, Latest{}, q.report)));
}

// One edge a -> w with a sample at 1 s (identity rotation, p0, covariance S_p on dp only) and
// the twist of A relative to W at a in [a], timeless: v = (1, 2, 0), w = 0, covariance S_v on dv
// only. At 1.5 s (horizon 1 s) the answer is p0 + 0.5 v, its covariance in dp S_p + 0.25 S_v
// (X_k Exp(dt xi) with R = I, w = 0: dp = dp_k + dt dv), by hand; the report: read at 1 s,
// extrapolated. Beyond the horizon: kExtrapolation, outputs unchanged.
TEST(CompiledCovarianceTime, ExtrapolatedCovarianceOfOneEdgeByHand) {
  Graph g = MakeTimedGraph<Graph>(Interpolation::kScrew);
  const PoseSpec spec = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  Covariance6 S_p = Covariance6::Zero(), S_v = Covariance6::Zero();
  S_p.topLeftCorner<3, 3>() = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  S_v.topLeftCorner<3, 3>() = Eigen::Vector3d(4e-4, 8e-4, 1e-3).asDiagonal();
  const Eigen::Vector3d p0(1.0, 2.0, 3.0), v(1.0, 2.0, 0.0);
  ASSERT_TRUE(g.AddPose(spec, Eigen::Matrix3d::Identity(), p0, Ms(1000), CovarianceInput{&S_p}));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"), v,
                         Eigen::Vector3d::Zero(), CovarianceInput{&S_v}));
  auto compiled = g.CompilePoseWithCovariance(spec);
  ASSERT_TRUE(compiled);
  B::PoseCoords X = B::Identity();
  Covariance6 S = Covariance6::Zero();
  TimeReport report;
  ASSERT_EQ(compiled->Evaluate(X, S, At{Ms(1500), Duration::Seconds(1)}, report), ErrorCode::kOk);
  EXPECT_LE((B::TranslationOf(X) - (p0 + 0.5 * v)).norm(), 1e-12);
  EXPECT_LE((B::ToMatrix(B::RotationOf(X)) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  Covariance6 expected = Covariance6::Zero();
  expected.topLeftCorner<3, 3>() = S_p.topLeftCorner<3, 3>() + 0.25 * S_v.topLeftCorner<3, 3>();
  EXPECT_LE((S - expected).norm(), 1e-12 * expected.norm()) << S;
  EXPECT_EQ(report.time, Ms(1500));
  EXPECT_EQ(report.oldest, Ms(1000));
  EXPECT_EQ(report.newest, Ms(1000));
  EXPECT_TRUE(report.extrapolated);
  // Before the sample too (dt = -0.5 s).
  ASSERT_EQ(compiled->Evaluate(X, S, At{Ms(500), Duration::Seconds(1)}, report), ErrorCode::kOk);
  EXPECT_LE((B::TranslationOf(X) - (p0 - 0.5 * v)).norm(), 1e-12);
  EXPECT_LE((S - expected).norm(), 1e-12 * expected.norm()) << S;
  ExpectUnchangedOn(*compiled, At{Ms(2500), Duration::Seconds(1)}, ErrorCode::kExtrapolation);
  EXPECT_EQ(g.GetPoseWithCovariance(spec, At{Ms(2500), Duration::Seconds(1)}).error().code,
            ErrorCode::kExtrapolation);
}

// The scene of time_uncertainty_test.cc's shared-edge test: h wrt w stamped (0 s, 1 s), the
// calibration s wrt h constant with a covariance, the twist of H relative to W given at s. The
// pose of s wrt w at 1.5 s extrapolates h wrt w with an integration twist that reads the
// calibration, which the query reads too (perturbed once: the one-shot's Monte Carlo test).
// The compiled queries give the one-shot's numbers; with `split` the twist is given at s2, an
// independent copy of the calibration: the same value, another covariance (the double count
// the keyed sink avoids), which the compiled query gives too.
Graph SharedGraph(bool split) {
  std::mt19937 rng(2718);
  Graph g = MakeTimedGraph<Graph>(Interpolation::kScrew);
  const Covariance6 S_cal = RandomCovariance(rng), S0 = 1e-2 * RandomCovariance(rng),
                    S1 = 1e-2 * RandomCovariance(rng), S_tw = 1e-2 * RandomCovariance(rng);
  for (const char* s : {"s", "s2"}) {
    if (s[1] != '\0' && !split) break;
    EXPECT_TRUE(g.AddPose(PoseSpec::Of(s, "H").RelativeTo("h", "H"),
                          ExpR(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.4, 0.1, -0.2),
                          CovarianceInput{&S_cal}));
  }
  const PoseSpec hw = PoseSpec::Of("h", "H").RelativeTo("w", "W");
  EXPECT_TRUE(g.AddPose(hw, ExpR(Eigen::Vector3d(0.2, 0.1, 0.0)), Eigen::Vector3d(1, 0, 0), Ms(0),
                        CovarianceInput{&S0}));
  EXPECT_TRUE(g.AddPose(hw, ExpR(Eigen::Vector3d(0.25, 0.1, 0.1)), Eigen::Vector3d(1.2, 0.3, 0),
                        Ms(1000), CovarianceInput{&S1}));
  const char* at = split ? "s2" : "s";
  EXPECT_TRUE(g.AddTwist(TwistSpec::Of(at, "H").RelativeTo("W").ExpressedIn(at),
                         Eigen::Vector3d(0.5, 0.2, 0.0), Eigen::Vector3d(0.1, -0.3, 1.0), Ms(1000),
                         CovarianceInput{&S_tw}));
  return g;
}

TEST(CompiledCovarianceTime, EdgeSharedByIntegrationTwistAndQuerySameAsOneShot) {
  const Graph g = SharedGraph(false), split = SharedGraph(true);
  const TimePolicy policy = At{Ms(1500), Duration::Seconds(1)};
  const PoseSpec spec = PoseSpec::Of("s", "H").RelativeTo("w", "W");
  for (const PoseSpec& q : {spec, PoseSpec::Of("w", "W").RelativeTo("s", "H").ExpressedIn("h")}) {
    ASSERT_TRUE(ExpectSameAsOneShot(g, q, policy));
    ASSERT_TRUE(ExpectSameAsOneShot(split, q, policy));
    ASSERT_TRUE(g.GetPose(q, policy)->time.extrapolated);
  }
  auto once = g.CompilePoseWithCovariance(spec);
  auto twice = split.CompilePoseWithCovariance(spec);
  ASSERT_TRUE(once && twice);
  B::PoseCoords X1 = B::Identity(), X2 = B::Identity();
  Covariance6 S1, S2;
  TimeReport report;
  ASSERT_EQ(once->Evaluate(X1, S1, policy, report), ErrorCode::kOk);
  ASSERT_EQ(twice->Evaluate(X2, S2, policy, report), ErrorCode::kOk);
  EXPECT_LE((B::TranslationOf(X1) - B::TranslationOf(X2)).norm(), 1e-12);
  EXPECT_GT((S1 - S2).norm(), 0.05 * S1.norm());
}

TEST(CompiledCovarianceTime, ExtrapolatedEvaluationDoesNotAllocate) {
  std::mt19937 rng(23);
  Graph g = MakeTimedGraph<Graph>(Interpolation::kScrew);
  BuildExtrapolationScene(g, rng);
  CompiledParts q(g, PoseSpec::Of("s6", "B6").RelativeTo("s5", "B5").ExpressedIn("f4"));
  ASSERT_TRUE(q.compiled());
  ASSERT_EQ(q.pose->Evaluate(q.X, q.S, At{Ms(3400), Duration::Seconds(1)}, q.report),
            ErrorCode::kOk);
  ASSERT_TRUE(q.report.extrapolated);
  const std::size_t allocations = AllocationsOf(100, [&q](int i) {
    const TimePolicy policies[] = {
        At{Ms(3350 + i), Duration::Seconds(1)}, At{Ms(600 - i), Duration::Seconds(1)},
        LatestCommon{Duration::Seconds(1)}, At{Ms(3400), Duration::Milliseconds(1)}};
    for (const TimePolicy& policy : policies) q.Evaluate(policy);
  });
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(q.sum, 0.0);
}

}  // namespace
}  // namespace semgraph::core
