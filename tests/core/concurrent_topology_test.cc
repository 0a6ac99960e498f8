// Topology changes while readers run (docs/realtime.md): a grasp loop. A writer thread moves an
// object between a table and a gripper at 100 Hz (RemovePose + AddPose, RemoveTwist +
// AddTwist), adds unrelated frames and twist edges after every change (so the value arrays grow
// by many blocks), and recompiles the object's query after each change, publishing it to the
// readers. Reader threads evaluate compiled queries at full speed: the published object query
// (its path changes), the gripper's pose and the arm's twist (untouched), plain and memoized.
// Every answer must be the pose of the graph the query was compiled on (computed here by hand
// with Eigen, independently of semgraph) or kQueryInvalidated; untouched queries must always
// answer, with their hand-computed values. Runs under ThreadSanitizer in CI (stage_tsan).
// It prints the readers' evaluation latency during the changes (a measurement, not a check).
//
// Scene: body W frame {w}; table T {t} wrt {w}; arm A {a} wrt {w}; gripper G {g} wrt {a};
// object O {o} wrt {t} (state 0, on the table) or wrt {g} (state 1, grasped).
// Twist edges: A wrt W at {a} in [a]; O wrt T (state 0) or wrt G (state 1) at {o} in [o].
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using Eigen::AngleAxisd;
using Eigen::Isometry3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using semgraph::testing::CountAllocations;

Isometry3d Make(const Quaterniond& q, const Vector3d& p) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}

bool Near(const Isometry3d& X, const Isometry3d& Y) {
  return (X.matrix() - Y.matrix()).cwiseAbs().maxCoeff() < 1e-12;
}

// The edges of the scene (edge form: pose of the head in the tail).
const Quaterniond q_WT(AngleAxisd(0.3, Vector3d::UnitZ()));
const Vector3d p_WT(1.0, 0.5, 0.0);
const Quaterniond q_WA(AngleAxisd(-0.7, Vector3d::UnitZ()));
const Vector3d p_WA(-0.2, 0.1, 0.8);
const Quaterniond q_AG(AngleAxisd(1.1, Vector3d(1, 1, 0).normalized()));
const Vector3d p_AG(0.0, 0.4, 0.3);
const Quaterniond q_TO(AngleAxisd(0.9, Vector3d::UnitX()));
const Vector3d p_TO(0.2, -0.1, 0.75);
const Quaterniond q_GO(AngleAxisd(-0.4, Vector3d::UnitY()));
const Vector3d p_GO(0.0, 0.0, 0.12);
const Vector3d v_WAa_a(0.1, -0.2, 0.05), w_WA_a(0.0, 0.0, 0.6);
const Vector3d v_O(0.01, 0.02, 0.03), w_O(0.3, 0.0, 0.0);

// A reader's latency histogram (10 ns buckets up to 20 us, then one overflow bucket, and the
// exact maximum): fixed size, so recording allocates nothing.
struct Latencies {
  static constexpr std::size_t kBuckets = 2000;
  std::vector<std::uint64_t> count = std::vector<std::uint64_t>(kBuckets + 1);
  std::uint64_t n = 0, max_ns = 0;
  void Add(std::chrono::steady_clock::duration d) noexcept {
    const auto ns =
        static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(d).count());
    ++count[std::min<std::uint64_t>(ns / 10, kBuckets)];
    ++n;
    max_ns = std::max(max_ns, ns);
  }
  void Merge(const Latencies& o) {
    for (std::size_t i = 0; i <= kBuckets; ++i) count[i] += o.count[i];
    n += o.n;
    max_ns = std::max(max_ns, o.max_ns);
  }
  // The upper edge of the bucket holding quantile f (ns; "> 20000" shows as 20010).
  [[nodiscard]] std::uint64_t Quantile(double f) const noexcept {
    const auto rank = static_cast<std::uint64_t>(f * static_cast<double>(n));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i <= kBuckets; ++i) {
      seen += count[i];
      if (seen > rank) return 10 * (i + 1);
    }
    return max_ns;
  }
};

struct ReaderCounts {
  std::size_t evaluations = 0, answered = 0, invalidated = 0;
  std::size_t wrong = 0;            // an answer other than the compiled graph's pose
  std::size_t bad_code = 0;         // a code other than kOk / kQueryInvalidated
  std::size_t untouched_wrong = 0;  // an untouched query failed or answered wrongly
  Latencies latency;                // evaluations of the changed query while no change runs
  Latencies during_change;          // ... that started while the writer was changing the topology
};

template <class B>
class ConcurrentTopologyTest : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(ConcurrentTopologyTest, Backends);

TYPED_TEST(ConcurrentTopologyTest, GraspLoopWhileReadersEvaluateCompiledQueries) {
  using B = TypeParam;
  constexpr int kChanges = 100;         // 100 grasps and releases, at 100 Hz: about a second
  constexpr int kFramesPerChange = 40;  // unrelated frames added after each change (4,000 in all)

  SceneGraph<B> graph;
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("t", "T").RelativeTo("w", "W"), q_WT, p_WT));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), q_WA, p_WA));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("g", "G").RelativeTo("a", "A"), q_AG, p_AG));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("o", "O").RelativeTo("t", "T"), q_TO, p_TO));
  ASSERT_TRUE(
      graph.AddTwist(TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"), v_WAa_a, w_WA_a));
  ASSERT_TRUE(graph.AddTwist(TwistSpec::Of("o", "O").RelativeTo("T").ExpressedIn("o"), v_O, w_O));

  // By hand: the object's pose in {w} on the table and in the gripper, and the gripper's.
  const Isometry3d X_WG = Make(q_WA, p_WA) * Make(q_AG, p_AG);
  const Isometry3d X_WO[2] = {Make(q_WT, p_WT) * Make(q_TO, p_TO), X_WG * Make(q_GO, p_GO)};
  ASSERT_FALSE(Near(X_WO[0], X_WO[1]));

  // The object query of each state, compiled by the writer after each change; published[i] is
  // compiled on state i % 2.
  std::vector<std::optional<CompiledPose<B>>> published(kChanges + 1);
  std::atomic<int> latest{0};
  {
    auto q = graph.CompilePose(PoseSpec::Of("o").RelativeTo("w"));
    ASSERT_TRUE(q);
    published[0].emplace(*q);
  }
  auto gripper = graph.CompilePose(PoseSpec::Of("g").RelativeTo("w"));
  auto arm_twist = graph.CompileTwist(TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"));
  ASSERT_TRUE(gripper && arm_twist);

  std::atomic<bool> stop{false}, changing{false};
  constexpr int kReaders = 2;
  std::vector<ReaderCounts> counts(kReaders);
  const auto reader = [&](ReaderCounts& c, bool memoized) {
    auto cache = gripper->MakeCache();  // this thread's memo (allocated before the loop)
    while (!stop.load(std::memory_order_relaxed)) {
      const int i = latest.load(std::memory_order_acquire);
      const CompiledPose<B>& object = *published[static_cast<std::size_t>(i)];
      const bool during = changing.load(std::memory_order_relaxed);
      const auto t0 = std::chrono::steady_clock::now();
      const auto X = object.Evaluate();
      (during ? c.during_change : c.latency).Add(std::chrono::steady_clock::now() - t0);
      ++c.evaluations;
      if (X) {
        ++c.answered;
        c.wrong += !Near(X->ToIsometry(), X_WO[i % 2]);
      } else if (X.error().code == ErrorCode::kQueryInvalidated) {
        ++c.invalidated;
      } else {
        ++c.bad_code;
      }
      const auto G = memoized ? gripper->Evaluate(cache) : gripper->Evaluate();
      c.untouched_wrong += !G || !Near(G->ToIsometry(), X_WG);
      const auto V = arm_twist->Evaluate();
      c.untouched_wrong +=
          !V || (V->linear - v_WAa_a).norm() > 1e-15 || (V->angular - w_WA_a).norm() > 1e-15;
    }
  };
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r) readers.emplace_back(reader, std::ref(counts[r]), r == 1);

  // The writer: grasp, release, grasp, ... at 100 Hz.
  int writer_failures = 0, unrelated = 0;
  std::chrono::steady_clock::duration longest_change{};
  auto next = std::chrono::steady_clock::now();
  for (int i = 1; i <= kChanges; ++i) {
    next += std::chrono::milliseconds(10);
    std::this_thread::sleep_until(next);
    changing.store(true, std::memory_order_relaxed);
    const auto t0 = std::chrono::steady_clock::now();
    const bool grasp = i % 2 == 1;
    writer_failures += !graph.RemovePose("o", grasp ? "t" : "g");
    writer_failures += !(grasp ? graph.AddPose(PoseSpec::Of("o").RelativeTo("g"), q_GO, p_GO)
                               : graph.AddPose(PoseSpec::Of("o").RelativeTo("t"), q_TO, p_TO));
    writer_failures += !graph.RemoveTwist("o", grasp ? "T" : "G");
    writer_failures += !graph.AddTwist(
        TwistSpec::Of("o").RelativeTo(grasp ? "G" : "T").ExpressedIn("o"), v_O, w_O);
    longest_change = std::max(longest_change, std::chrono::steady_clock::now() - t0);
    auto q = graph.CompilePose(PoseSpec::Of("o").RelativeTo("w"));
    writer_failures += !q;
    if (q) published[static_cast<std::size_t>(i)].emplace(*q);
    latest.store(i, std::memory_order_release);
    for (int k = 0; k < kFramesPerChange; ++k, ++unrelated) {  // growth: new value blocks
      const std::string f = "u" + std::to_string(unrelated), body = "U" + std::to_string(unrelated);
      writer_failures += !graph.AddPose(PoseSpec::Of(f, body).RelativeTo("w"), q_WT, p_WT);
      if (k % 4 == 0) {
        writer_failures +=
            !graph.AddTwist(TwistSpec::Of(f, body).RelativeTo("W").ExpressedIn(f), v_O, w_O);
      }
    }
    changing.store(false, std::memory_order_relaxed);
  }
  stop = true;
  for (std::thread& t : readers) t.join();
  EXPECT_EQ(writer_failures, 0);
  EXPECT_EQ(CheckInvariants(graph), "");

  ReaderCounts all;
  for (const ReaderCounts& c : counts) {
    all.evaluations += c.evaluations;
    all.answered += c.answered;
    all.invalidated += c.invalidated;
    all.wrong += c.wrong;
    all.bad_code += c.bad_code;
    all.untouched_wrong += c.untouched_wrong;
    all.latency.Merge(c.latency);
    all.during_change.Merge(c.during_change);
  }
  EXPECT_EQ(all.wrong, 0u) << "answers that are neither the pose before nor after a change";
  EXPECT_EQ(all.bad_code, 0u);
  EXPECT_EQ(all.untouched_wrong, 0u) << "a query whose path no change touches failed or changed";
  EXPECT_GT(all.answered, 0u);
  // The last published query (state kChanges % 2) answers, and nothing it reads allocates.
  {
    const CompiledPose<B>& last = *published[kChanges];
    auto cache = gripper->MakeCache();
    CountAllocations counting;
    const auto X = last.Evaluate();
    const auto G = gripper->Evaluate(cache);
    const auto V = arm_twist->Evaluate();
    EXPECT_EQ(counting.count(), 0u);
    ASSERT_TRUE(X && G && V);
    EXPECT_TRUE(Near(X->ToIsometry(), X_WO[kChanges % 2]));
  }
  // Every earlier query was invalidated by the change after it.
  for (int i = 0; i < kChanges; ++i) {
    const auto X = published[static_cast<std::size_t>(i)]->Evaluate();
    ASSERT_FALSE(X);
    EXPECT_EQ(X.error().code, ErrorCode::kQueryInvalidated);
  }

  std::printf(
      "[ grasp loop ] %d changes at 100 Hz, %d unrelated frames added; %zu evaluations of the "
      "changed "
      "query: %zu answered, %zu invalidated, %zu wrong; longest change (remove + add of the pose "
      "and "
      "twist edges) %lld us\n",
      kChanges, unrelated, all.evaluations, all.answered, all.invalidated, all.wrong,
      static_cast<long long>(
          std::chrono::duration_cast<std::chrono::microseconds>(longest_change).count()));
  for (const auto& [what, L] :
       {std::pair<const char*, const Latencies*>{"during changes", &all.during_change},
        std::pair<const char*, const Latencies*>{"between changes", &all.latency}}) {
    std::printf(
        "[ grasp loop ] reader latency %s (%llu evaluations, ns, 10 ns buckets): p50 %llu, p99 "
        "%llu, "
        "p99.9 %llu, max %llu\n",
        what, static_cast<unsigned long long>(L->n),
        static_cast<unsigned long long>(L->Quantile(0.5)),
        static_cast<unsigned long long>(L->Quantile(0.99)),
        static_cast<unsigned long long>(L->Quantile(0.999)),
        static_cast<unsigned long long>(L->max_ns));
  }
}

}  // namespace
}  // namespace semgraph::core
