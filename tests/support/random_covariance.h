// File: tests/support/random_covariance.h
//
// Random draws for the covariance tests: stamps in milliseconds, rotations from a rotation
// vector, covariances 1e-6 L L^T (L with standard normal entries: positive semidefinite, almost
// surely definite) and standard normal vectors. Deterministic given rng.
//
// Also the scaffolding of the compiled-vs-one-shot tests at a time: a graph keeping 100 s
// (MakeTimedGraph); random frame names and tree edges; the loop over random scenes (CountAnswered:
// kRandomScenes graphs, kQueriesPerScene specs each, every policy of a list, what differs passed as
// callables); the extrapolation policies and comparison (CompareExtrapolations: its counts printed
// and checked); and the allocations of rounds of evaluations (AllocationsOf, alloc_counter.h).
// The answers are checked by the callables; the helpers check only counts (CompareExtrapolations).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

#include "semgraph/coord/covariance.h"
#include "semgraph/core/time.h"
#include "support/alloc_counter.h"

namespace semgraph::testing {

inline core::Stamp Ms(std::int64_t ms) { return core::Stamp::Nanoseconds(ms * 1000000); }

inline Eigen::Matrix3d ExpR(const Eigen::Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(Eigen::AngleAxisd(th, w / th));
}
inline coord::Covariance6 RandomCovariance(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return 1e-6 * L * L.transpose();
}
inline Eigen::Vector3d RandomVector(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng));
}

// A graph keeping a window of 100 s, interpolating in `mode`.
template <class Graph>
Graph MakeTimedGraph(core::Interpolation mode = core::TimeOptions{}.interpolation) {
  core::TimeOptions o;
  o.window = core::Duration::Seconds(100);
  o.interpolation = mode;
  return *Graph::Create(o);
}

// f<k>, k uniform in [0, last]; with `calibrations`, s<k> instead on a coin flip when k > 0
// (the coin drawn only then).
inline std::string RandomFrameName(std::mt19937& rng, int last, bool calibrations = false) {
  const int k = std::uniform_int_distribution<int>(0, last)(rng);
  const bool s = calibrations && k > 0 && std::uniform_int_distribution<int>(0, 1)(rng) != 0;
  return std::string(s ? "s" : "f") + std::to_string(k);
}

// The names of edge k of a random tree: frame f<k> on body B<k> (F) under frame t = f<parent> on
// body T = B<parent>, parent uniform in [0, k); s<k>, a calibration frame on B<k>.
struct TreeEdge {
  std::string f, F, t, T, s;
};
inline TreeEdge RandomTreeEdge(std::mt19937& rng, int k) {
  const std::string c = std::to_string(k);
  const std::string p = std::to_string(std::uniform_int_distribution<int>(0, k - 1)(rng));
  return {"f" + c, "B" + c, "f" + p, "B" + p, "s" + c};
}

inline constexpr int kRandomScenes = 6, kQueriesPerScene = 10;
// The names a random spec views (a spec owns none): they live as long as its checks.
using SpecNames = std::array<std::string, 5>;

// The random comparisons' loop: kRandomScenes graphs (MakeTimedGraph(mode)) filled by
// build(g, rng), on each kQueriesPerScene specs draw(rng, names), each under every policy of
// policies(rng) (drawn after the spec) checked by check(g, spec, policy): true when answered.
// Returns the number answered.
template <class Graph, class Build, class Draw, class Policies, class Check>
int CountAnswered(std::mt19937& rng, Build build, Draw draw, Policies policies, Check check,
                  core::Interpolation mode = core::TimeOptions{}.interpolation) {
  int answered = 0;
  for (int scene = 0; scene < kRandomScenes; ++scene) {
    Graph g = MakeTimedGraph<Graph>(mode);
    build(g, rng);
    for (int i = 0; i < kQueriesPerScene; ++i) {
      SpecNames names;
      const auto spec = draw(rng, names);
      for (const core::TimePolicy& policy : policies(rng)) answered += check(g, spec, policy);
    }
  }
  return answered;
}

// Extrapolation: within a 1 s horizon after and before samples near 1 s and 3 s, latest common
// within 1 s, and beyond a 50 ms horizon.
inline std::array<core::TimePolicy, 4> ExtrapolationPolicies() {
  using core::At, core::Duration;
  return {At{Ms(3400), Duration::Seconds(1)}, At{Ms(600), Duration::Seconds(1)},
          core::LatestCommon{Duration::Seconds(1)}, At{Ms(3400), Duration::Milliseconds(50)}};
}

// CountAnswered under ExtrapolationPolicies (screw interpolation), also counting the answers
// extrapolated(g, spec, policy) says were extrapolated; prints both counts and expects more
// than 30 extrapolated.
template <class Graph, class Build, class Draw, class Check, class Extrapolated>
void CompareExtrapolations(std::mt19937& rng, Build build, Draw draw, Check check,
                           Extrapolated extrapolated) {
  int n_extrapolated = 0;
  const auto count = [&](const Graph& g, const auto& spec, const core::TimePolicy& policy) {
    if (!check(g, spec, policy)) return false;
    n_extrapolated += extrapolated(g, spec, policy);
    return true;
  };
  const auto policies = [](std::mt19937&) { return ExtrapolationPolicies(); };
  const int answered =
      CountAnswered<Graph>(rng, build, draw, policies, count, core::Interpolation::kScrew);
  std::printf("extrapolation: %d of %d answered, %d extrapolated\n", answered,
              kRandomScenes * kQueriesPerScene * 4, n_extrapolated);
  EXPECT_GT(n_extrapolated, 30);
}

// The allocations made by round(0), ..., round(rounds - 1).
template <class Round>
std::size_t AllocationsOf(int rounds, Round round) {
  CountAllocations counting;
  for (int i = 0; i < rounds; ++i) round(i);
  return counting.count();
}

}  // namespace semgraph::testing
