// The real-time path with time (docs/time.md, docs/realtime.md): stamped SetPose / SetTwist by
// handle and compiled queries under every policy allocate nothing; one writer appending samples
// while readers evaluate at any time in the window never sees a torn sample or a half-shifted
// history (run under ThreadSanitizer in CI, .ci/run stage tsan).
//
// The concurrency check is by value: every sample the writer stores at stamp s is the exact
// function X(s) = (Rz(0), (s, 2 s, 3 s)) (seconds), so any interpolation between two samples of
// it is exactly X(t) in linear mode; a torn or mixed read would break that identity.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using Graph = SceneGraph<coord::QuaternionBackend>;
using semgraph::testing::CountAllocations;

Stamp Ms(std::int64_t ms) { return Stamp::Nanoseconds(ms * 1000000); }
Eigen::Vector3d Line(Stamp s) { return Eigen::Vector3d(1, 2, 3) * s.seconds(); }

Graph MakeGraph() {
  TimeOptions o;
  o.interpolation = Interpolation::kLinear;
  o.window = Duration::Seconds(1);
  Graph g = *Graph::Create(o);
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), Eigen::Quaterniond::Identity(),
                        Line(Ms(0)), Ms(0))
                  .has_value());
  EXPECT_TRUE(g.AddPose(PoseSpec::Of("b", "A").RelativeTo("a"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(0, 0, 1))
                  .has_value());
  EXPECT_TRUE(g.AddTwist(TwistSpec::Of("a").RelativeTo("W").ExpressedIn("a"),
                         Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::Zero(), Ms(0))
                  .has_value());
  return g;
}

TEST(TimeRealtimeTest, StampedUpdatesAndTimedCompiledQueriesDoNotAllocate) {
  Graph g = MakeGraph();
  auto pose = g.FindPoseEdge("a", "w");
  auto twist = g.FindTwistEdge("a", "W");
  auto q = g.CompilePose(PoseSpec::Of("b").RelativeTo("w"));
  auto v = g.CompileTwist(TwistSpec::Of("b").RelativeTo("W").ExpressedIn("w"));
  auto vp =
      g.CompileTwist(TwistSpec::Of("b").RelativeTo("W").ExpressedIn("w"), TwistSource::kPoses);
  ASSERT_TRUE(pose && twist && q && v && vp);
  std::size_t allocations = 0;
  int failures = 0;
  {
    CountAllocations counting;
    for (std::int64_t i = 1; i <= 3000; ++i) {  // in order, past the window and the capacity
      failures +=
          g.SetPose(*pose, Eigen::Quaterniond::Identity(), Line(Ms(i)), Ms(i)) != ErrorCode::kOk;
      failures += g.SetTwist(*twist, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::Zero(), Ms(i)) !=
                  ErrorCode::kOk;
    }
    failures += g.SetPose(*pose, Eigen::Quaterniond::Identity(), Line(Ms(2500)), Ms(2500)) !=
                ErrorCode::kOk;  // replace
    failures += g.SetPose(*pose, Eigen::Quaterniond::Identity(), Line(Ms(0)), Ms(0)) !=
                ErrorCode::kStampTooOld;
    Graph::Backend::PoseCoords X;
    Eigen::Vector3d lin, ang;
    TimeReport r;
    const TimePolicy policies[] = {Latest{}, At{Ms(2700)},
                                   At{Ms(3100), Duration::Milliseconds(200)}, LatestCommon{},
                                   Latest{Ms(2999)}};
    for (const TimePolicy& p : policies) {
      failures += q->Evaluate(X, p, r) != ErrorCode::kOk;
      failures += v->Evaluate(lin, ang, p, r) != ErrorCode::kOk;
    }
    failures += vp->Evaluate(lin, ang, At{Ms(2700)}, r) != ErrorCode::kOk;
    failures += vp->Evaluate(lin, ang) != ErrorCode::kOk;  // untimed: under Latest
    failures += q->Evaluate(X, At{Ms(5000)}, r) != ErrorCode::kExtrapolation;
    failures += q->Evaluate(X, Latest{Ms(4000)}, r) != ErrorCode::kStale;
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(failures, 0);
  // And the values are right: at 2.7 s on the line, 1 m above a.
  Graph::Backend::PoseCoords X;
  TimeReport r;
  ASSERT_EQ(q->Evaluate(X, At{Ms(2700)}, r), ErrorCode::kOk);
  EXPECT_NEAR((X.translation - (Line(Ms(2700)) + Eigen::Vector3d(0, 0, 1))).norm(), 0.0, 1e-12);
  // The extrapolated pose integrates the measured twist (1, 2, 3) m/s: the line again.
  ASSERT_EQ(q->Evaluate(X, At{Ms(3100), Duration::Milliseconds(200)}, r), ErrorCode::kOk);
  EXPECT_TRUE(r.extrapolated);
  EXPECT_NEAR((X.translation - (Line(Ms(3100)) + Eigen::Vector3d(0, 0, 1))).norm(), 0.0, 1e-12);
  // From the pose history: the line's speed.
  Eigen::Vector3d lin, ang;
  ASSERT_EQ(vp->Evaluate(lin, ang, At{Ms(2700)}, r), ErrorCode::kOk);
  EXPECT_NEAR((lin - Eigen::Vector3d(1, 2, 3)).norm(), 0.0, 1e-6);
}

TEST(TimeRealtimeTest, OneWriterAppendsWhileReadersEvaluateAtAnyTime) {
  Graph g = MakeGraph();
  auto pose = g.FindPoseEdge("a", "w");
  auto q = g.CompilePose(PoseSpec::Of("b").RelativeTo("w"));
  ASSERT_TRUE(pose && q);
  constexpr std::int64_t kSamples = 20000;
  std::atomic<std::int64_t> written{0};
  std::atomic<int> bad{0};
  std::atomic<long> reads{0};
  std::atomic<int> started{0};
  std::thread writer([&] {
    while (started.load(std::memory_order_acquire) < 2)
      std::this_thread::yield();  // overlap readers
    for (std::int64_t i = 1; i <= kSamples; ++i) {
      // Mostly in order; every 7th sample arrives late (out of order, shifting the history).
      const std::int64_t s = i % 7 == 0 ? i - 3 : i;
      if (g.SetPose(*pose, Eigen::Quaterniond::Identity(), Line(Ms(s)), Ms(s)) != ErrorCode::kOk)
        ++bad;
      written.store(i, std::memory_order_release);
    }
  });
  std::vector<std::thread> readers;
  for (int k = 0; k < 2; ++k) {
    readers.emplace_back([&, k] {
      std::uint64_t x = 12345 + k;
      long mine = 0;
      started.fetch_add(1, std::memory_order_release);
      // While the writer runs, then 100 more reads each against the final history (a loaded
      // machine may run the writer to its end before a reader gets a core).
      for (;;) {
        const bool writing = written.load(std::memory_order_acquire) < kSamples;
        if (!writing && mine++ >= 100) break;
        const std::int64_t newest = written.load(std::memory_order_acquire);
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        const std::int64_t t =
            newest - static_cast<std::int64_t>(x >> 40) % 900;  // within the window
        Graph::Backend::PoseCoords X;
        TimeReport r;
        const ErrorCode code = q->Evaluate(X, At{Ms(t)}, r);
        if (code == ErrorCode::kOk) {
          if ((X.translation - (Line(Ms(t)) + Eigen::Vector3d(0, 0, 1))).norm() > 1e-9) ++bad;
          reads.fetch_add(1, std::memory_order_relaxed);
        } else if (code != ErrorCode::kExtrapolation) {
          ++bad;  // the only possible failure: t just outside what was written
        }
      }
    });
  }
  writer.join();
  for (auto& r : readers) r.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GT(reads.load(), 0);
}

}  // namespace
}  // namespace semgraph::core
