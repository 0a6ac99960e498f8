// core/src/time_uncertainty.cc, timed_covariance.h and the covariances of stamped samples
// (edge_history.h, time_add.cc): covariances through every time policy and a time travel.
//
// Truth is Monte Carlo at a time (docs/uncertainty.md §3): each used edge's value at the
// query's time is perturbed by a draw from its covariance at that time (a sample's, or the
// interpolation (1 - l) S_i + l S_i+1 of two, computed here by hand from the stamps), applied
// exactly (p + dp, Exp(dth) R; v + dv, w + dw); the perturbed values are stored as samples at
// exactly that time in a fresh graph, the same query asked there, and the sample covariance of
// the answer's perturbation compared with the first-order answer within 5 standard errors of
// each entry (20000 draws; 4000 under ASan: support/sanitized.h). A time travel draws each stamped
// edge independently at both times. A planted sign error (rotation rows negated) must fail the same
// check. Then: errors with the graph unchanged, the duplicate rule with covariances, a sample
// without one counting as zero, and the timed covariance queries allocating nothing.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"
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
Stamp Ms(std::int64_t ms) { return Stamp::Nanoseconds(ms * 1000000); }

Covariance6 RandomCovariance(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return scale * (L * L.transpose() / 6.0);
}
Eigen::Vector3d RandomVector(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng));
}

// An edge of the scene: pose edges head -> tail (edge form), twist edges of head's body
// relative to tail_body at head in [head]; stamped (samples) or timeless (one value).
struct Sample {
  std::int64_t ms;
  Eigen::Matrix3d R;  // pose: rotation; twist: unused
  Eigen::Vector3d p;  // pose: position; twist: v
  Eigen::Vector3d w;  // twist: w
  Covariance6 S;
};
struct Edge {
  bool twist;
  std::string head, head_body, tail, tail_body;
  std::vector<Sample> samples;  // one with ms < 0: timeless
  bool stamped() const { return samples.front().ms >= 0; }
  PoseSpec pose_spec() const { return PoseSpec::Of(head, head_body).RelativeTo(tail, tail_body); }
  TwistSpec twist_spec() const {
    return TwistSpec::Of(head, head_body).RelativeTo(tail_body).ExpressedIn(head);
  }
};

// Bodies W {w}, A {a}, C {c, c2}, D {d}: w -> a stamped (1, 2, 3 s), a -> c stamped (0.5,
// 1.5, 2.5 s), w -> d timeless, c -> c2 constant; twist edges W -> {a}, A -> {c} stamped.
std::vector<Edge> RandomScene(std::mt19937& rng) {
  const auto samples = [&](std::vector<std::int64_t> ms) {
    std::vector<Sample> out;
    for (std::int64_t m : ms) {
      out.push_back({m, ExpR(0.5 * RandomVector(rng)), RandomVector(rng), RandomVector(rng),
                     RandomCovariance(rng, 1e-6)});
    }
    return out;
  };
  return {{false, "a", "A", "w", "W", samples({1000, 2000, 3000})},
          {false, "c", "C", "a", "A", samples({500, 1500, 2500})},
          {false, "d", "D", "w", "W", samples({-1})},
          {false, "c2", "C", "c", "C", samples({-1})},
          {true, "a", "A", "w", "W", samples({1000, 2000, 3000})},
          {true, "c", "C", "a", "A", samples({500, 1500, 2500})}};
}

void Add(Graph& g, const Edge& e, const Sample& s, bool with_covariance) {
  const CovarianceInput c{with_covariance ? &s.S : nullptr};
  const BuildResult r = [&] {
    if (e.twist) {
      return s.ms < 0 ? g.AddTwist(e.twist_spec(), s.p, s.w, c)
                      : g.AddTwist(e.twist_spec(), s.p, s.w, Ms(s.ms), c);
    }
    return s.ms < 0 ? g.AddPose(e.pose_spec(), s.R, s.p, c)
                    : g.AddPose(e.pose_spec(), s.R, s.p, Ms(s.ms), c);
  }();
  ASSERT_TRUE(r.has_value()) << r.error().message;
}
Graph Build(const std::vector<Edge>& scene) {
  TimeOptions o;
  o.window = Duration::Seconds(100);
  Graph g = *Graph::Create(o);
  for (const Edge& e : scene) {
    for (const Sample& s : e.samples) Add(g, e, s, true);
  }
  return g;
}

// An edge's value and covariance at ms (by hand: the bracketing samples' covariances
// interpolated; outside the samples the nearest one, a held twist's), its value read from the
// nominal graph.
Sample AtTime(const Graph& g, const Edge& e, std::int64_t ms) {
  Sample out = e.samples.front();
  if (!e.stamped()) return out;  // timeless: its one value
  out.ms = ms;
  const auto& v = e.samples;
  if (ms <= v.front().ms) {
    out.S = v.front().S;
  } else if (ms >= v.back().ms) {
    out.S = v.back().S;
  } else {
    for (std::size_t i = 0; i + 1 < v.size(); ++i) {
      if (v[i].ms <= ms && ms <= v[i + 1].ms) {
        const double l = double(ms - v[i].ms) / double(v[i + 1].ms - v[i].ms);
        out.S = (1.0 - l) * v[i].S + l * v[i + 1].S;
      }
    }
  }
  if (e.twist) {
    const auto V = g.GetTwist(e.twist_spec(), At{Ms(ms)});
    EXPECT_TRUE(V.has_value());
    out.p = V->value.linear;
    out.w = V->value.angular;
  } else {
    const auto X = g.GetPose(e.pose_spec(), At{Ms(ms)});
    EXPECT_TRUE(X.has_value());
    const Eigen::Isometry3d I = X->value.ToIsometry();
    out.R = I.linear();
    out.p = I.translation();
  }
  return out;
}

// A draw of the perturbed value.
Sample Perturbed(Sample s, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vector6 z;
  for (int i = 0; i < 6; ++i) z(i) = n(rng);
  const Vector6 d = s.S.llt().matrixL() * z;
  s.R = ExpR(d.tail<3>()) * s.R;
  s.p += d.head<3>();
  s.w += d.tail<3>();
  return s;
}

// The perturbed graph: every stamped edge with one sample per time in ms_of(edge) (each drawn
// independently at its time), every timeless edge drawn once.
template <class TimesOf>
Graph PerturbedGraphAt(const Graph& nominal, const std::vector<Edge>& scene, TimesOf&& ms_of,
                       std::mt19937& rng) {
  TimeOptions o;
  o.window = Duration::Seconds(100);
  Graph h = *Graph::Create(o);
  for (const Edge& e : scene) {
    if (!e.stamped()) {
      Add(h, e, Perturbed(AtTime(nominal, e, 0), rng), false);
      continue;
    }
    for (std::int64_t m : ms_of(e)) Add(h, e, Perturbed(AtTime(nominal, e, m), rng), false);
  }
  return h;
}
Graph PerturbedGraph(const Graph& nominal, const std::vector<Edge>& scene,
                     const std::vector<std::int64_t>& ms, std::mt19937& rng) {
  return PerturbedGraphAt(
      nominal, scene, [&](const Edge&) { return ms; }, rng);
}

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

Vector6 PoseDelta(const Graph::Pose& X0, const Graph::Pose& X1) {
  const Eigen::Isometry3d A = X0.ToIsometry(), B = X1.ToIsometry();
  Vector6 d;
  d << B.translation() - A.translation(), LogR(B.linear() * A.linear().transpose());
  return d;
}
Covariance6 Flipped(const Covariance6& S) {
  Vector6 f;
  f << 1, 1, 1, -1, -1, -1;
  return f.asDiagonal() * S * f.asDiagonal();
}

const PoseSpec kPose = PoseSpec::Of("c2", "C").RelativeTo("d", "D").ExpressedIn("a");
const TwistSpec kTwist = TwistSpec::Of("c2", "C").RelativeTo("W").ExpressedIn("d");

// One policy against Monte Carlo: the pose and the twist; `ms`: the time every edge is read at
// (the perturbed graph holds samples there only, and is asked under `perturbed_policy`).
void CheckPolicy(const TimePolicy& policy, std::int64_t ms, const TimePolicy& perturbed_policy) {
  std::mt19937 rng(static_cast<unsigned>(20261205 + ms));
  const std::vector<Edge> scene = RandomScene(rng);
  const Graph g = Build(scene);
  const auto pose = g.GetPoseWithCovariance(kPose, policy);
  const auto twist = g.GetTwistWithCovariance(kTwist, policy);
  const auto position = g.GetPositionWithCovariance(kPose, policy);
  const auto angular = g.GetAngularVelocityWithCovariance(
      TwistSpec::Of("d", "C").RelativeTo("W").ExpressedIn("d"), policy);
  ASSERT_TRUE(pose && twist && position && angular);
  std::vector<Vector6> d_pose, d_twist;
  std::vector<Eigen::Vector3d> d_position;
  for (int i = 0; i < kSamples; ++i) {
    const Graph h = PerturbedGraph(g, scene, {ms}, rng);
    const auto X = h.GetPose(kPose, perturbed_policy);
    const auto V = h.GetTwist(kTwist, perturbed_policy);
    ASSERT_TRUE(X) << h.Describe(X.error(), kPose);
    ASSERT_TRUE(V) << h.Describe(V.error(), kTwist);
    d_pose.push_back(PoseDelta(pose->value.value, X->value));
    d_position.push_back(d_pose.back().head<3>());
    Vector6 dV;
    dV << V->value.linear - twist->value.value.linear,
        V->value.angular - twist->value.value.angular;
    d_twist.push_back(dV);
  }
  EXPECT_GT(pose->value.covariance.trace(), 1e-7);
  EXPECT_GT(twist->value.covariance.trace(), 1e-7);
  std::printf("worst z at %lld ms: pose %.2f, twist %.2f; sign error: pose %.1f, twist %.1f\n",
              static_cast<long long>(ms), WorstZ<6>(pose->value.covariance, d_pose),
              WorstZ<6>(twist->value.covariance, d_twist),
              WorstZ<6>(Flipped(pose->value.covariance), d_pose),
              WorstZ<6>(Flipped(twist->value.covariance), d_twist));
  EXPECT_LT(WorstZ<6>(pose->value.covariance, d_pose), kMaxZ) << pose->value.covariance;
  EXPECT_LT(WorstZ<3>(position->value.covariance, d_position), kMaxZ);
  EXPECT_LT(WorstZ<6>(twist->value.covariance, d_twist), kMaxZ) << twist->value.covariance;
  EXPECT_GT(WorstZ<6>(Flipped(pose->value.covariance), d_pose), 3.0 * kMaxZ);
  EXPECT_GT(WorstZ<6>(Flipped(twist->value.covariance), d_twist), 3.0 * kMaxZ);
  // The untimed parts agree with the timed answer's.
  EXPECT_LE((position->value.covariance - pose->value.covariance.topLeftCorner<3, 3>()).norm(),
            1e-15);
}

TEST(TimeUncertainty, InterpolatedCovariancesMatchMonteCarlo) {
  CheckPolicy(At{Ms(1700)}, 1700, At{Ms(1700)});  // both stamped edges between samples
}
TEST(TimeUncertainty, ExactSampleCovariancesMatchMonteCarlo) {
  CheckPolicy(At{Ms(1500)}, 1500, At{Ms(1500)});  // a -> c at a sample, w -> a between two
}
TEST(TimeUncertainty, LatestCommonReadsEveryEdgeAtTheCommonTime) {
  CheckPolicy(LatestCommon{}, 2500, At{Ms(2500)});  // min of the newest stamps: 2.5 s
}

// Latest: each edge at its own newest sample (w -> a at 3 s, a -> c at 2.5 s).
TEST(TimeUncertainty, LatestReadsEachEdgesNewestSample) {
  std::mt19937 rng(99);
  const std::vector<Edge> scene = RandomScene(rng);
  const Graph g = Build(scene);
  const auto pose = g.GetPoseWithCovariance(kPose, Latest{});
  ASSERT_TRUE(pose);
  // The same as asking each edge's newest sample by hand: a graph with only those.
  TimeOptions o;
  o.window = Duration::Seconds(100);
  Graph h = *Graph::Create(o);
  for (const Edge& e : scene) Add(h, e, e.samples.back(), true);
  const auto same = h.GetPoseWithCovariance(kPose);
  ASSERT_TRUE(same);
  EXPECT_LE((pose->value.covariance - same->covariance).norm(), 1e-9 * same->covariance.norm());
  // And the untimed query reads the newest samples' covariances too.
  const auto untimed = g.GetPoseWithCovariance(kPose);
  ASSERT_TRUE(untimed);
  EXPECT_LE((untimed->covariance - same->covariance).norm(), 1e-9 * same->covariance.norm());
}

// Time travel: c2 at 1.2 s through {w} to a's frame at 2.2 s, in [d]; w -> a is used on both
// sides: two independent perturbations.
TEST(TimeUncertainty, TimeTravelSidesAreIndependent) {
  std::mt19937 rng(4242);
  const std::vector<Edge> scene = RandomScene(rng);
  const Graph g = Build(scene);
  const PoseSpec spec = PoseSpec::Of("c2", "C").RelativeTo("a", "A").ExpressedIn("d");
  const TimeTravel travel{Ms(1200), Ms(2200), "w"};
  const auto pose = g.GetPoseWithCovariance(spec, travel);
  const auto position = g.GetPositionWithCovariance(spec, travel);
  const auto orientation = g.GetOrientationWithCovariance(spec, travel);
  ASSERT_TRUE(pose && position && orientation);
  std::vector<Vector6> d;
  for (int i = 0; i < kSamples; ++i) {
    const Graph h = PerturbedGraph(g, scene, {1200, 2200}, rng);
    const auto X = h.GetPose(spec, travel);
    ASSERT_TRUE(X) << h.Describe(X.error(), spec);
    d.push_back(PoseDelta(pose->value.value, X->value));
  }
  std::printf("worst z, time travel: %.2f; sign error %.1f\n", WorstZ<6>(pose->value.covariance, d),
              WorstZ<6>(Flipped(pose->value.covariance), d));
  EXPECT_LT(WorstZ<6>(pose->value.covariance, d), kMaxZ) << pose->value.covariance;
  EXPECT_GT(WorstZ<6>(Flipped(pose->value.covariance), d), 3.0 * kMaxZ);
  EXPECT_LE((position->value.covariance - pose->value.covariance.topLeftCorner<3, 3>()).norm(),
            1e-15);
  EXPECT_LE(
      (orientation->value.covariance - pose->value.covariance.bottomRightCorner<3, 3>()).norm(),
      1e-15);
}

// Extrapolation at 3.4 s (horizon 1 s): w -> a from its sample at 3 s, a -> c from 2.5 s, each
// integrated with its twist edge's sample there; the truth perturbs those samples (pose and
// twist, independent) and integrates exactly (the perturbed graph holds just them).
TEST(TimeUncertainty, ExtrapolationPropagatesTheSampleAndTheIntegrationTwist) {
  std::mt19937 rng(777);
  const std::vector<Edge> scene = RandomScene(rng);
  const Graph g = Build(scene);
  const TimePolicy policy = At{Ms(3400), Duration::Seconds(1)};
  const auto pose = g.GetPoseWithCovariance(kPose, policy);
  ASSERT_TRUE(pose);
  EXPECT_TRUE(pose->time.extrapolated);
  std::vector<Vector6> d;
  for (int i = 0; i < kSamples; ++i) {
    const Graph h = PerturbedGraphAt(
        g, scene, [](const Edge& e) { return std::vector<std::int64_t>{e.samples.back().ms}; },
        rng);
    const auto X = h.GetPose(kPose, policy);
    ASSERT_TRUE(X) << h.Describe(X.error(), kPose);
    d.push_back(PoseDelta(pose->value.value, X->value));
  }
  std::printf("worst z, extrapolation: %.2f; sign error %.1f\n",
              WorstZ<6>(pose->value.covariance, d), WorstZ<6>(Flipped(pose->value.covariance), d));
  EXPECT_LT(WorstZ<6>(pose->value.covariance, d), kMaxZ) << pose->value.covariance;
  EXPECT_GT(WorstZ<6>(Flipped(pose->value.covariance), d), 3.0 * kMaxZ);
  // Without the integration twist's part (the sample's alone) the answer is too small.
  TimeOptions o;
  o.window = Duration::Seconds(100);
  Graph exact_twists = *Graph::Create(o);
  for (const Edge& e : scene) {
    for (const Sample& s : e.samples) Add(exact_twists, e, s, !e.twist);
  }
  const auto partial = exact_twists.GetPoseWithCovariance(kPose, policy);
  ASSERT_TRUE(partial);
  EXPECT_GT(WorstZ<6>(partial->value.covariance, d), 3.0 * kMaxZ);
}

// Checks: a bad covariance on a stamped sample is refused with the graph unchanged; the
// covariance is part of the sample's value for the duplicate rule; a sample without one
// counts as zero.
TEST(TimeUncertainty, StampedCovarianceChecksAndDuplicates) {
  TimeOptions o;
  o.duplicate_stamp = DuplicatePolicy::kReject;
  Graph g = *Graph::Create(o);
  const PoseSpec spec = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Covariance6 S = Covariance6::Identity() * 1e-4;
  ASSERT_TRUE(g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(1000), CovarianceInput{&S}));
  Covariance6 bad = S;
  bad(0, 1) = 1.0;  // not symmetric
  auto r = g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(2000), CovarianceInput{&bad});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidCovariance);
  bad = -S;  // negative eigenvalues
  r = g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(2000), CovarianceInput{&bad});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidCovariance);
  bad = S;
  bad(2, 2) = std::nan("");
  r = g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(2000), CovarianceInput{&bad});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidNumber);
  // Unchanged: still one sample (at 2 s: after the samples, no horizon).
  EXPECT_EQ(g.GetPose(spec, At{Ms(2000)}).error().code, ErrorCode::kExtrapolation);
  // The same value and covariance again: accepted, nothing changes; another covariance at
  // the same stamp is another value (duplicate_stamp under reject); none = zero differs too.
  EXPECT_TRUE(g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(1000), CovarianceInput{&S}));
  const Covariance6 S2 = 2.0 * S;
  r = g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(1000), CovarianceInput{&S2});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicateStamp);
  r = g.AddPose(spec, q, Eigen::Vector3d(1, 2, 3), Ms(1000));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kDuplicateStamp);
  const auto at1 = g.GetPoseWithCovariance(spec, At{Ms(1000)});
  ASSERT_TRUE(at1);
  EXPECT_LE((at1->value.covariance - S).norm(), 1e-18);
  // A sample without a covariance counts as zero: halfway, half the first one's.
  ASSERT_TRUE(g.AddPose(spec, q, Eigen::Vector3d(1, 2, 4), Ms(2000)));
  const auto mid = g.GetPoseWithCovariance(spec, At{Ms(1500)});
  ASSERT_TRUE(mid);
  EXPECT_LE((mid->value.covariance - 0.5 * S).norm(), 1e-18);
  const auto newest = g.GetPoseWithCovariance(spec, Latest{});
  ASSERT_TRUE(newest);
  EXPECT_TRUE(newest->value.covariance.isZero(0.0));
  // Twist samples carry theirs too (a twist given a convention is refused).
  const TwistSpec ts = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("a");
  ASSERT_TRUE(g.AddTwist(ts, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(), Ms(1000),
                         CovarianceInput{&S}));
  ASSERT_TRUE(g.AddTwist(ts, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(), Ms(2000),
                         CovarianceInput{&S2}));
  const auto tw = g.GetTwistWithCovariance(ts, At{Ms(1250)});
  ASSERT_TRUE(tw);
  EXPECT_LE((tw->value.covariance - 1.25 * S).norm(), 1e-18);
  r = g.AddTwist(
      ts, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(), Ms(3000),
      CovarianceInput{&S, CovarianceOrder::kLinearAngular, PoseCovarianceConvention::kBody});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.GetTwist(ts, At{Ms(3000)}).error().code, ErrorCode::kExtrapolation);
}

// Stamped updates through handles with a covariance (SetPose / SetTwist with a Stamp and a
// CovarianceInput): on edges whose first samples carried none (the handle's finder made room),
// allocation-free; the samples' covariances read back by hand (a sample's own, the
// interpolation (1 - l) S_i + l S_i+1, zero for the sample without one); the checks (a bad
// covariance, a twist with a convention, a stamp on a timeless edge, none on a stamped one)
// write nothing.
TEST(TimeUncertainty, StampedHandleUpdatesCarryCovariances) {
  Graph g = *Graph::Create(TimeOptions{});
  const PoseSpec spec = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  const TwistSpec ts = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("a");
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  ASSERT_TRUE(g.AddPose(spec, q, Eigen::Vector3d(0, 0, 0), Ms(1000)));  // no covariance
  ASSERT_TRUE(g.AddTwist(ts, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(), Ms(1000)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), q, Eigen::Vector3d(1, 0, 0)));
  const auto pose = g.FindPoseEdge("a", "w");
  const auto twist = g.FindTwistEdge("a", "W");
  const auto timeless = g.FindPoseEdge("b", "w");
  ASSERT_TRUE(pose && twist && timeless);
  Covariance6 S2 = Covariance6::Identity() * 1e-4, S3 = Covariance6::Identity() * 3e-4;
  S2(0, 5) = S2(5, 0) = 2e-5;
  const CovarianceInput in2{&S2}, in3{&S3};
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const Stamp s2 = Ms(2000);
  static_assert(noexcept(g.SetPose(*pose, q, zero, s2, in2))&& noexcept(
      g.SetTwist(*twist, zero, zero, s2, in2)));
  std::size_t allocations = 0;
  {
    semgraph::testing::CountAllocations counting;
    EXPECT_EQ(g.SetPose(*pose, q, Eigen::Vector3d(2, 0, 0), Ms(2000), in2), ErrorCode::kOk);
    EXPECT_EQ(g.SetPose(*pose, q, Eigen::Vector3d(3, 0, 0), Ms(3000), in3), ErrorCode::kOk);
    EXPECT_EQ(g.SetTwist(*twist, Eigen::Vector3d(2, 0, 0), Eigen::Vector3d::Zero(), Ms(2000), in2),
              ErrorCode::kOk);
    EXPECT_EQ(g.SetTwist(*twist, Eigen::Vector3d(3, 0, 0), Eigen::Vector3d::Zero(), Ms(3000), in3),
              ErrorCode::kOk);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  // By hand: at 1.5 s half of S2 (the first sample counts as zero), at 2.75 s 0.25 S2 + 0.75 S3,
  // at 2 s S2 itself; the values interpolated alongside (p_x = t, v_x = t).
  const auto p15 = g.GetPoseWithCovariance(spec, At{Ms(1500)});
  const auto p275 = g.GetPoseWithCovariance(spec, At{Ms(2750)});
  const auto v2 = g.GetTwistWithCovariance(ts, At{Ms(2000)});
  const auto v275 = g.GetTwistWithCovariance(ts, At{Ms(2750)});
  ASSERT_TRUE(p15 && p275 && v2 && v275);
  EXPECT_LE((p15->value.covariance - 0.5 * S2).norm(), 1e-18);
  EXPECT_LE((p275->value.covariance - (0.25 * S2 + 0.75 * S3)).norm(), 1e-18);
  EXPECT_NEAR(p275->value.value.ToIsometry().translation().x(), 2.75, 1e-12);
  EXPECT_LE((v2->value.covariance - S2).norm(), 1e-18);
  EXPECT_LE((v275->value.covariance - (0.25 * S2 + 0.75 * S3)).norm(), 1e-18);
  EXPECT_NEAR(v275->value.value.linear.x(), 2.75, 1e-12);
  // Refusals write nothing: a bad covariance, a twist with a convention, a stamp on a timeless
  // edge; then no stamp on a stamped edge.
  Covariance6 bad = S2;
  bad(0, 1) = 1.0;
  EXPECT_EQ(g.SetPose(*pose, q, Eigen::Vector3d(4, 0, 0), Ms(4000), CovarianceInput{&bad}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetTwist(*twist, Eigen::Vector3d(4, 0, 0), Eigen::Vector3d::Zero(), Ms(4000),
                       CovarianceInput{&bad}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetTwist(*twist, Eigen::Vector3d(4, 0, 0), Eigen::Vector3d::Zero(), Ms(4000),
                       CovarianceInput{&S2, CovarianceOrder::kLinearAngular,
                                       PoseCovarianceConvention::kBody}),
            ErrorCode::kInvalidCovariance);
  EXPECT_EQ(g.SetPose(*timeless, q, Eigen::Vector3d(4, 0, 0), Ms(4000), in2),
            ErrorCode::kStampMismatch);
  EXPECT_EQ(g.GetPose(spec, At{Ms(4000)}).error().code, ErrorCode::kExtrapolation);
  EXPECT_EQ(g.GetTwist(ts, At{Ms(4000)}).error().code, ErrorCode::kExtrapolation);
  EXPECT_TRUE(g.pose_covariance(g.FindFrame("b")).isZero(0.0));
  EXPECT_EQ(g.SetPose(*pose, q, Eigen::Vector3d(9, 0, 0), in2), ErrorCode::kStampMismatch);
  EXPECT_NEAR(g.GetPose(spec)->ToIsometry().translation().x(), 3.0, 0.0);
}

// One writer adding stamped samples with covariances while a reader asks for covariances at
// times inside the window: the sample at s is p = (s, 0, 0) with S = s 1e-6 I (s in seconds),
// so between two samples the linear interpolation gives p_x = t and S = t 1e-6 I exactly as
// the definition (1 - l) S_i + l S_i+1: a value paired with another sample's covariance, or a
// torn covariance, breaks S_00 = 1e-6 p_x (run under ThreadSanitizer in CI).
TEST(TimeUncertainty, ConcurrentReadersSeeEachValueWithItsCovariance) {
  TimeOptions o;
  o.interpolation = Interpolation::kLinear;
  o.window = Duration::Seconds(1);
  o.sample_capacity = 64;
  Graph g = *Graph::Create(o);
  const PoseSpec spec = PoseSpec::Of("a", "A").RelativeTo("w", "W");
  const auto add = [&](std::int64_t ms) {
    const Covariance6 S = Covariance6::Identity() * (1e-6 * double(ms) / 1000.0);
    return g.AddPose(spec, Eigen::Quaterniond::Identity(), Eigen::Vector3d(ms / 1000.0, 0, 0),
                     Ms(ms), CovarianceInput{&S});
  };
  for (std::int64_t ms = 0; ms <= 100; ms += 10) ASSERT_TRUE(add(ms));
  std::atomic<bool> done{false};
  std::atomic<std::int64_t> newest{100};
  std::atomic<int> bad{0}, answered{0};
  std::thread reader([&] {
    while (!done.load(std::memory_order_acquire)) {
      // Between two samples near the newest (the window keeps 1 s).
      const std::int64_t t = newest.load() - 35;
      const auto r = g.GetPoseWithCovariance(spec, At{Ms(t)});
      if (!r) {  // an add overlapped every attempt (build-time calls change the topology), or
                 // the reader slept while the capacity (64 samples) dropped its time
        const bool dropped = r.error().code == ErrorCode::kExtrapolation && newest.load() - t > 600;
        if (r.error().code != ErrorCode::kQueryInvalidated && !dropped) {
          std::fprintf(stderr, "error %s\n", std::string(base::ToString(r.error().code)).c_str());
          bad.fetch_add(1);
        }
        continue;
      }
      const double x = r->value.value.ToIsometry().translation().x();
      const Covariance6& S = r->value.covariance;
      if (std::abs(S(0, 0) - 1e-6 * x) > 1e-15 || std::abs(S(5, 5) - S(0, 0)) > 1e-18 ||
          S(0, 1) != 0.0) {
        bad.fetch_add(1);
      }
      answered.fetch_add(1);
    }
  });
  for (std::int64_t ms = 110; ms <= 200000 && answered.load() < 2000; ms += 10) {
    if (!add(ms)) bad.fetch_add(1000);
    newest.store(ms);
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GT(answered.load(), 0);
}

// ---------------------------------------------------------------- an edge shared by an
// extrapolation's integration twist and the query

// Bodies W {w} and H {h, s, s2}: h wrt w stamped (0 s, 1 s), the calibration s wrt h constant
// with a covariance, the twist of H relative to W given at s in [s] (1 s). The pose of s wrt w
// at 1.5 s extrapolates h wrt w from its 1 s sample with the integration twist
// TwistCoord(h|H, W, [h]), which reads the twist at s moved to h through the calibration: the
// calibration is used by the integration twist and by the query (one perturbation, spec §3).
// With `split`, the twist is given at s2 instead, a second constant frame with the same pose
// and covariance: two independent edges, what the double count computed.
struct SharedScene {
  Eigen::Matrix3d R_HS = ExpR(Eigen::Vector3d(0.1, -0.2, 0.3));
  Eigen::Vector3d p_HS{0.4, 0.1, -0.2};
  Covariance6 S_cal, S_pose0, S_pose1, S_twist;
  Eigen::Matrix3d R_WH0 = ExpR(Eigen::Vector3d(0.2, 0.1, 0.0)),
                  R_WH1 = ExpR(Eigen::Vector3d(0.25, 0.1, 0.1));
  Eigen::Vector3d p_WH0{1, 0, 0}, p_WH1{1.2, 0.3, 0};
  Eigen::Vector3d v_s{0.5, 0.2, 0.0}, w_s{0.1, -0.3, 1.0};
};
SharedScene MakeSharedScene() {
  std::mt19937 rng(2718);
  SharedScene sc;
  sc.S_cal = RandomCovariance(rng, 1e-6);
  sc.S_pose0 = RandomCovariance(rng, 1e-8);
  sc.S_pose1 = RandomCovariance(rng, 1e-8);
  sc.S_twist = RandomCovariance(rng, 1e-8);
  return sc;
}
// The graph; with rng: the calibration drawn once, the 1 s samples drawn (only they are used).
Graph SharedGraph(const SharedScene& sc, bool split, std::mt19937* rng) {
  TimeOptions o;
  o.window = Duration::Seconds(100);
  Graph g = *Graph::Create(o);
  const auto draw = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const Covariance6& S) {
    Sample x{0, R, p, Eigen::Vector3d::Zero(), S};
    return rng ? Perturbed(x, *rng) : x;
  };
  const Covariance6* none = nullptr;
  const auto cov = [&](const Covariance6& S) { return CovarianceInput{rng ? none : &S}; };
  const Sample cal = draw(sc.R_HS, sc.p_HS, sc.S_cal);
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("s", "H").RelativeTo("h", "H"), cal.R, cal.p, cov(sc.S_cal)));
  if (split) {
    const Sample cal2 = draw(sc.R_HS, sc.p_HS, sc.S_cal);
    EXPECT_TRUE(
        g.AddPose(PoseSpec::Of("s2", "H").RelativeTo("h", "H"), cal2.R, cal2.p, cov(sc.S_cal)));
  }
  const PoseSpec hw = PoseSpec::Of("h", "H").RelativeTo("w", "W");
  if (!rng) {
    EXPECT_TRUE(g.AddPose(hw, sc.R_WH0, sc.p_WH0, Ms(0), cov(sc.S_pose0)));
  }
  const Sample x1 = draw(sc.R_WH1, sc.p_WH1, sc.S_pose1);
  EXPECT_TRUE(g.AddPose(hw, x1.R, x1.p, Ms(1000), cov(sc.S_pose1)));
  Sample tw{0, Eigen::Matrix3d::Identity(), sc.v_s, sc.w_s, sc.S_twist};
  if (rng) tw = Perturbed(tw, *rng);
  const char* at = split ? "s2" : "s";
  EXPECT_TRUE(g.AddTwist(TwistSpec::Of(at, "H").RelativeTo("W").ExpressedIn(at), tw.p, tw.w,
                         Ms(1000), cov(sc.S_twist)));
  return g;
}

TEST(TimeUncertainty, EdgeSharedByIntegrationTwistAndQueryIsPerturbedOnce) {
  const SharedScene sc = MakeSharedScene();
  const Graph g = SharedGraph(sc, false, nullptr);
  const PoseSpec spec = PoseSpec::Of("s", "H").RelativeTo("w", "W");
  const TimePolicy policy = At{Ms(1500), Duration::Seconds(1)};
  const auto pose = g.GetPoseWithCovariance(spec, policy);
  const auto position = g.GetPositionWithCovariance(spec, policy);
  ASSERT_TRUE(pose && position);
  ASSERT_TRUE(pose->time.extrapolated);
  // The double count: the same scene with the calibration used by the twist split off into an
  // independent copy (the same value, the same covariance).
  const Graph split = SharedGraph(sc, true, nullptr);
  const auto twice = split.GetPoseWithCovariance(spec, policy);
  ASSERT_TRUE(twice);
  EXPECT_LE(PoseDelta(pose->value.value, twice->value.value).norm(), 1e-12);  // the same value
  std::mt19937 rng(1618);
  std::vector<Vector6> d;
  for (int i = 0; i < kSamples; ++i) {
    const Graph h = SharedGraph(sc, false, &rng);
    const auto X = h.GetPose(spec, policy);
    ASSERT_TRUE(X) << h.Describe(X.error(), spec);
    d.push_back(PoseDelta(pose->value.value, X->value));
  }
  const Covariance6& S = pose->value.covariance;
  std::printf(
      "shared edge: worst z %.2f (perturbed once), %.1f (counted twice); |S_twice - S| / |S| = "
      "%.3f\n",
      WorstZ<6>(S, d), WorstZ<6>(twice->value.covariance, d),
      (twice->value.covariance - S).norm() / S.norm());
  EXPECT_LT(WorstZ<6>(S, d), kMaxZ) << S;
  EXPECT_GT(WorstZ<6>(twice->value.covariance, d), 3.0 * kMaxZ);
  EXPECT_GT(WorstZ<6>(Flipped(S), d), 3.0 * kMaxZ);
  EXPECT_LE((position->value.covariance - S.topLeftCorner<3, 3>()).norm(), 1e-15);
  // A twist query at 1.5 s reads the held twist sample (at 1 s, as the integration twist) and
  // moves it with the extrapolated pose: the twist edge and the calibration are shared.
  const TwistSpec ts = TwistSpec::Of("s", "H").RelativeTo("W").ExpressedIn("w");
  const auto V = g.GetTwistWithCovariance(ts, policy);
  ASSERT_TRUE(V);
  std::vector<Vector6> dv;
  for (int i = 0; i < kSamples; ++i) {
    const Graph h = SharedGraph(sc, false, &rng);
    const auto W = h.GetTwist(ts, policy);
    ASSERT_TRUE(W);
    Vector6 x;
    x << W->value.linear - V->value.value.linear, W->value.angular - V->value.value.angular;
    dv.push_back(x);
  }
  std::printf("shared edges, twist: worst z %.2f\n", WorstZ<6>(V->value.covariance, dv));
  EXPECT_LT(WorstZ<6>(V->value.covariance, dv), kMaxZ) << V->value.covariance;
}

// ---------------------------------------------------------------- twists from poses

// Source poses: the twist of c2 (body C) relative to W in [d] at 1.7 s is the derivative of
// w -> a (samples 1 s, 2 s) plus that of a -> c (samples 1.5 s, 2.5 s), moved to c2 and
// rotated into [d] (Algorithm 3). Truth per draw: (1) the four bracketing samples perturbed
// by their own covariances (all samples of the stamped pose edges are drawn; each derivative
// uses its two), re-differentiated exactly by the graph (the twist of each edge's own body at
// its head in [h], source poses, one step: exactly the edge's derivative); (2) independently,
// every pose edge's value at 1.7 s drawn from its interpolated covariance (as the tests above),
// read as poses; (3) the answer combined here by hand from (1) and (2):
//   sum over edges h:  R_DH (v_h + w_h x p_HE_H, w_h),  e = c2.
// The specification makes each derivative independent of the edges' own values (§3).
const TwistSpec kPoseTwist = TwistSpec::Of("c2", "C").RelativeTo("W").ExpressedIn("d");
const TwistSpec kDerivA = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a");
const TwistSpec kDerivC = TwistSpec::Of("c", "C").RelativeTo("A").ExpressedIn("c");

Graph BuildWith(const std::vector<Edge>& scene, coord::Interpolation mode, bool perturb,
                std::mt19937* rng) {
  TimeOptions o;
  o.window = Duration::Seconds(100);
  o.interpolation = mode;
  Graph g = *Graph::Create(o);
  for (const Edge& e : scene) {
    if (e.twist) continue;
    for (const Sample& s : e.samples) {
      Add(g, e, perturb && e.stamped() ? Perturbed(s, *rng) : s, !perturb);
    }
  }
  return g;
}

// The hand combination (3): derivatives from `deriv`, poses from `poses`, at ms.
Vector6 CombineByHand(const Graph& deriv, const Graph& poses, std::int64_t ms) {
  Vector6 out = Vector6::Zero();
  const TimePolicy at = At{Ms(ms)};
  const std::pair<const TwistSpec*, const char*> steps[] = {{&kDerivA, "a"}, {&kDerivC, "c"}};
  for (const auto& [spec, h] : steps) {
    const auto V = deriv.GetTwist(*spec, at, TwistSource::kPoses);
    const auto p_HE = poses.GetPosition(PoseSpec::Of("c2").RelativeTo(h).ExpressedIn(h), at);
    const auto R_DH = poses.GetOrientation(PoseSpec::Of(h).RelativeTo("d"), at);
    EXPECT_TRUE(V && p_HE && R_DH);
    if (!V || !p_HE || !R_DH) return out;
    const Eigen::Matrix3d R = coord::QuaternionBackend::ToMatrix(R_DH->value.value);
    const Eigen::Vector3d w = V->value.angular;
    out.head<3>() += R * (V->value.linear + w.cross(p_HE->value.value));
    out.tail<3>() += R * w;
  }
  return out;
}

void CheckPoseSource(coord::Interpolation mode, unsigned seed) {
  constexpr std::int64_t kMs = 1700;
  std::mt19937 rng(seed);
  const std::vector<Edge> scene = RandomScene(rng);
  std::vector<Edge> pose_edges;
  for (const Edge& e : scene) {
    if (!e.twist) pose_edges.push_back(e);
  }
  const Graph g = BuildWith(scene, mode, false, nullptr);
  const TimePolicy at = At{Ms(kMs)};
  const auto twist = g.GetTwistWithCovariance(kPoseTwist, at, CovarianceOrder::kLinearAngular,
                                              TwistSource::kPoses);
  const auto linear = g.GetLinearVelocityWithCovariance(kPoseTwist, at, TwistSource::kPoses);
  const auto angular = g.GetAngularVelocityWithCovariance(kPoseTwist, at, TwistSource::kPoses);
  const auto plain = g.GetTwist(kPoseTwist, at, TwistSource::kPoses);
  ASSERT_TRUE(twist && linear && angular && plain);
  // The answer is the plain query's, and the hand combination reproduces it.
  EXPECT_EQ(twist->value.value.linear, plain->value.linear);
  EXPECT_EQ(twist->value.value.angular, plain->value.angular);
  Vector6 nominal;
  nominal << plain->value.linear, plain->value.angular;
  EXPECT_LE((CombineByHand(g, g, kMs) - nominal).norm(), 1e-9 * nominal.norm());
  EXPECT_EQ((linear->value.covariance - twist->value.covariance.topLeftCorner<3, 3>()).norm(), 0.0);
  EXPECT_LE((angular->value.covariance - twist->value.covariance.bottomRightCorner<3, 3>()).norm(),
            1e-12 * twist->value.covariance.norm());
  std::vector<Vector6> d;
  for (int i = 0; i < kSamples; ++i) {
    const Graph deriv = BuildWith(scene, mode, true, &rng);
    Graph poses = PerturbedGraph(g, pose_edges, {kMs}, rng);
    d.push_back(CombineByHand(deriv, poses, kMs) - nominal);
  }
  const Covariance6& S = twist->value.covariance;
  std::printf("source poses (%s): worst z %.2f; sign error %.1f; trace %.3g\n",
              mode == coord::Interpolation::kScrew ? "screw" : "linear", WorstZ<6>(S, d),
              WorstZ<6>(Flipped(S), d), S.trace());
  EXPECT_GT(S.trace(), 1e-7);
  EXPECT_LT(WorstZ<6>(S, d), kMaxZ) << S;
  EXPECT_GT(WorstZ<6>(Flipped(S), d), 3.0 * kMaxZ);
}

TEST(TimeUncertainty, TwistsFromPosesLinearMatchMonteCarlo) {
  CheckPoseSource(coord::Interpolation::kLinear, 31);
}
TEST(TimeUncertainty, TwistsFromPosesScrewMatchMonteCarlo) {
  CheckPoseSource(coord::Interpolation::kScrew, 32);
}

// Source poses with a covariance fails as the plain query (extrapolation outside the samples or
// on an edge with one sample, stale, invalid_number, a bad name) and changes nothing: the
// answers and covariances at 1.7 s are the same before and after.
TEST(TimeUncertainty, TwistsFromPosesErrorsAsThePlainQuery) {
  std::mt19937 rng(41);
  const std::vector<Edge> scene = RandomScene(rng);
  Graph g = BuildWith(scene, coord::Interpolation::kScrew, false, nullptr);
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("e", "E").RelativeTo("w", "W"), Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(1, 2, 3), Ms(1000)));
  const auto at = [](std::int64_t ms) { return TimePolicy{At{Ms(ms), Duration::Seconds(5)}}; };
  const auto before = g.GetTwistWithCovariance(
      kPoseTwist, at(1700), CovarianceOrder::kLinearAngular, TwistSource::kPoses);
  ASSERT_TRUE(before);
  const struct {
    TwistSpec spec;
    TimePolicy policy;
    ErrorCode code;
  } cases[] = {
      {kPoseTwist, at(3500), ErrorCode::kExtrapolation},  // beyond a -> c's samples
      {kPoseTwist, at(200), ErrorCode::kExtrapolation},   // before them
      {TwistSpec::Of("e", "E").RelativeTo("W").ExpressedIn("e"), at(1000),
       ErrorCode::kExtrapolation},  // one sample: no derivative
      {kPoseTwist, Latest{Ms(4000)}, ErrorCode::kStale},
      {kPoseTwist, At{Ms(1700), Duration::Nanoseconds(-1)}, ErrorCode::kInvalidNumber},
      {TwistSpec::Of("nope", "C").RelativeTo("W").ExpressedIn("d"), at(1700),
       ErrorCode::kUnknownFrame},
  };
  for (const auto& c : cases) {
    const auto plain = g.GetTwist(c.spec, c.policy, TwistSource::kPoses);
    const auto twist = g.GetTwistWithCovariance(c.spec, c.policy, CovarianceOrder::kLinearAngular,
                                                TwistSource::kPoses);
    const auto linear = g.GetLinearVelocityWithCovariance(c.spec, c.policy, TwistSource::kPoses);
    ASSERT_FALSE(plain);
    ASSERT_FALSE(twist);
    ASSERT_FALSE(linear);
    EXPECT_EQ(plain.error().code, c.code) << g.Describe(plain.error(), c.spec);
    EXPECT_EQ(twist.error().code, plain.error().code);
    EXPECT_EQ(g.Describe(twist.error(), c.spec), g.Describe(plain.error(), c.spec));
    EXPECT_EQ(linear.error().code, plain.error().code);
  }
  const auto after = g.GetTwistWithCovariance(kPoseTwist, at(1700), CovarianceOrder::kLinearAngular,
                                              TwistSource::kPoses);
  ASSERT_TRUE(after);
  EXPECT_EQ(after->value.value.linear, before->value.value.linear);
  EXPECT_EQ(after->value.covariance, before->value.covariance);
}

// The timed covariance queries allocate nothing (graph built, plans warmed up).
TEST(TimeUncertainty, TimedCovarianceQueriesDoNotAllocate) {
  std::mt19937 rng(5);
  const std::vector<Edge> scene = RandomScene(rng);
  const Graph g = Build(scene);
  const TimeTravel travel{Ms(1200), Ms(2200), "w"};
  const PoseSpec tt = PoseSpec::Of("c2", "C").RelativeTo("a", "A").ExpressedIn("d");
  double sum = 0.0;
  std::size_t allocations = 0;
  {
    semgraph::testing::CountAllocations counting;
    for (int i = 0; i < 100; ++i) {
      const TimePolicy policies[] = {At{Ms(1700 + i)}, Latest{}, LatestCommon{},
                                     At{Ms(3400 + i), Duration::Seconds(1)}};
      for (const TimePolicy& p : policies) {
        sum += g.GetPoseWithCovariance(kPose, p)->value.covariance.trace();
        sum += g.GetTwistWithCovariance(kTwist, p)->value.covariance.trace();
      }
      for (int k = 0; k < 3; ++k) {  // source poses: within the samples (never extrapolates)
        sum += g.GetTwistWithCovariance(kTwist, policies[k], CovarianceOrder::kLinearAngular,
                                        TwistSource::kPoses)
                   ->value.covariance.trace();
      }
      sum += g.GetPoseWithCovariance(tt, travel)->value.covariance.trace();
    }
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace semgraph::core
