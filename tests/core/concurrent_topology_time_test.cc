// Topology changes while readers evaluate *timed* compiled queries (docs/realtime.md, "Topology
// changes while readers run"): the grasp loop of concurrent_topology_test.cc on stamped edges.
// A writer thread inserts samples continuously (1 kHz of stamps: the arm's pose, the object's
// pose and twist) and, at 100 Hz, moves the object between a table and a gripper: RemovePose +
// AddPose of the object's stamped pose edge, RemoveTwist + AddTwist of its stamped twist edge
// (so each removal retires a history that readers may be reading, and the re-add reuses it for
// the new edge), then compiles the object's queries and publishes them. Reader threads evaluate
// at full speed, at a time inside the histories (At) and at the newest samples (Latest): the
// object's pose (its path changes), its twist from the twist edge, its twist differentiated
// from the pose histories (TwistSource::kPoses), and the gripper's pose (untouched: the arm's
// edge is stamped but never removed). Every answer must be the hand-computed value (Eigen,
// independently of semgraph) of the graph the query was compiled on, at the time asked or at
// the stamps the report names, or kQueryInvalidated; the untouched query must always answer.
// Runs under ThreadSanitizer in CI (stage_tsan). It prints the readers' latency of the timed
// object pose evaluation, during and between changes (a measurement, not a check: noisy).
//
// Each change also removes and re-adds the stamped poses of eight clutter objects on the table
// (all removed, then all added: the free list hands the history of one clutter object to
// another, so a reader of an old clutter query may read another edge's samples; it must be
// invalidated), which also makes the change last long enough for readers to run during it.
//
// Scene: body W frame {w}; table T {t} wrt {w} (timeless); arm A {a} wrt {w} (stamped);
// gripper G {g} wrt {a} (timeless); object O {o} wrt {t} (state 0) or wrt {g} (state 1),
// stamped; the object's twist edge O wrt T (state 0) or wrt G (state 1) at {o} in [o], stamped;
// clutter Ck {ck} wrt {t} (stamped), k < 8.
// Every stamped pose keeps its rotation and moves its origin at a constant velocity, so linear
// interpolation is exact (up to rounding) and the pose-derivative twist is that velocity.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "semgraph/core/scene_graph.h"
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
template <class B>
Isometry3d ToIso(const typename B::PoseCoords& X) {
  return Make(B::ToQuaternion(B::RotationOf(X)), B::TranslationOf(X));
}
bool Near(const Isometry3d& X, const Isometry3d& Y) {
  return (X.matrix() - Y.matrix()).cwiseAbs().maxCoeff() < 1e-9;
}
bool Near(const Vector3d& a, const Vector3d& b) { return (a - b).cwiseAbs().maxCoeff() < 1e-9; }

Stamp Ms(std::int64_t ms) { return Stamp::Nanoseconds(ms * 1000000); }
double Sec(std::int64_t ms) { return static_cast<double>(ms) * 1e-3; }

// The edges (edge form: pose of the head in the tail), s in ms.
const Quaterniond q_WT(AngleAxisd(0.3, Vector3d::UnitZ()));
const Vector3d p_WT(1.0, 0.5, 0.0);
const Quaterniond q_WA(AngleAxisd(-0.7, Vector3d::UnitZ()));
const Vector3d p_WA(-0.2, 0.1, 0.8), u_WA(0.1, -0.2, 0.05);  // the arm's origin velocity, in [w]
const Quaterniond q_AG(AngleAxisd(1.1, Vector3d(1, 1, 0).normalized()));
const Vector3d p_AG(0.0, 0.4, 0.3);
const Quaterniond q_TO(AngleAxisd(0.9, Vector3d::UnitX()));
const Vector3d p_TO(0.2, -0.1, 0.75), u_TO(0.01, 0.02, 0.03);  // in [t]
const Quaterniond q_GO(AngleAxisd(-0.4, Vector3d::UnitY()));
const Vector3d p_GO(0.0, 0.0, 0.12), u_GO(-0.02, 0.01, 0.04);  // in [g]

Vector3d P_WA(std::int64_t s) { return p_WA + Sec(s) * u_WA; }
// The object's edge in state i: in {t} (0) or {g} (1).
Quaterniond QObj(int i) { return i == 0 ? q_TO : q_GO; }
Vector3d PObj(int i, std::int64_t s) {
  return i == 0 ? p_TO + Sec(s) * u_TO : p_GO + Sec(s) * u_GO;
}
// The object's twist edge value in state i (linear in s, so interpolation is exact).
Vector3d VObj(int i, std::int64_t s) {
  return i == 0 ? Vector3d(0.01, 0.02, 0.03) + Sec(s) * Vector3d(0.1, 0, 0)
                : Vector3d(-0.05, 0.04, 0.0) + Sec(s) * Vector3d(0, 0.2, 0);
}
Vector3d WObj(int i) { return i == 0 ? Vector3d(0.3, 0.0, 0.0) : Vector3d(0.0, -0.2, 0.1); }

// By hand: X_WO with the arm's sample at s_arm and the object's at s_obj.
Isometry3d X_WO(int i, std::int64_t s_arm, std::int64_t s_obj) {
  const Isometry3d X_obj = Make(QObj(i), PObj(i, s_obj));
  return i == 0 ? Make(q_WT, p_WT) * X_obj : Make(q_WA, P_WA(s_arm)) * Make(q_AG, p_AG) * X_obj;
}
// Clutter k: the object's table rotation, its own origin and velocity (in [t]).
constexpr int kClutter = 8;
Vector3d PClutter(int k, std::int64_t s) {
  return Vector3d(0.1 * k, -0.05 * k, 0.7) + Sec(s) * Vector3d(0.01 * (k + 1), -0.02, 0.003 * k);
}
Isometry3d X_WC(int k, std::int64_t s) { return Make(q_WT, p_WT) * Make(q_TO, PClutter(k, s)); }
const std::string kClutterName[kClutter] = {"c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7"};
const std::string kClutterBody[kClutter] = {"C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7"};
Isometry3d X_WG(std::int64_t s) { return Make(q_WA, P_WA(s)) * Make(q_AG, p_AG); }
// The velocity of o's origin wrt W in [w] from the pose derivatives (every rotation constant:
// no angular velocity, so moving the point changes nothing).
Vector3d V_WO(int i) { return i == 0 ? q_WT * u_TO : u_WA + (q_WA * q_AG) * u_GO; }

// A reader's latency histogram (10 ns buckets up to 50 us, then one overflow bucket, and the
// exact maximum): fixed size, so recording allocates nothing.
struct Latencies {
  static constexpr std::size_t kBuckets = 5000;
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
  std::size_t wrong = 0;            // an answer other than the compiled graph's value
  std::size_t bad_code = 0;         // a code other than kOk / kQueryInvalidated (or an allowed one)
  std::size_t untouched_wrong = 0;  // the untouched query failed or answered wrongly
  std::size_t untouched = 0;
  Latencies latency, during_change;  // the object's timed pose (At), between / during changes
  void Add(const ReaderCounts& c) {
    evaluations += c.evaluations;
    answered += c.answered;
    invalidated += c.invalidated;
    wrong += c.wrong;
    bad_code += c.bad_code;
    untouched_wrong += c.untouched_wrong;
    untouched += c.untouched;
    latency.Merge(c.latency);
    during_change.Merge(c.during_change);
  }
};

// The object's queries of one state, compiled by the writer after the change; first = the
// stamp of the state's first sample (its edges' histories start there).
template <class B>
struct Published {
  std::optional<CompiledPose<B>> pose;
  std::optional<CompiledTwist<B>> twist;       // from the twist edge: O wrt T / G at {o} in [o]
  std::optional<CompiledTwist<B>> derivative;  // from the poses: O wrt W at {o} in [w]
  std::optional<CompiledPose<B>> clutter[kClutter];  // Ck wrt {w}
  std::int64_t first = 0;
};

template <class B>
class ConcurrentTopologyTimeTest : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(ConcurrentTopologyTimeTest, Backends);

TYPED_TEST(ConcurrentTopologyTimeTest, GraspLoopOnStampedEdgesWhileReadersEvaluateTimedQueries) {
  using B = TypeParam;
  using PoseCoords = typename B::PoseCoords;
  constexpr int kChanges = 100;          // 100 grasps and releases at 100 Hz: about a second
  constexpr int kSamplesPerChange = 10;  // stamps 1 ms apart, one per real millisecond
  constexpr int kBatch = 256;            // evaluations per reader before it looks for a newer query

  TimeOptions options;
  options.interpolation = Interpolation::kLinear;
  options.window = Duration::Seconds(600);  // nothing leaves the window during the test
  options.sample_capacity = 4096;           // more than the samples written (about 1,000)
  auto made = SceneGraph<B>::Create(options);
  ASSERT_TRUE(made);
  SceneGraph<B> graph = std::move(*made);
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("t", "T").RelativeTo("w", "W"), q_WT, p_WT));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("a", "A").RelativeTo("w"), q_WA, P_WA(0), Ms(0)));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("g", "G").RelativeTo("a"), q_AG, p_AG));
  ASSERT_TRUE(graph.AddPose(PoseSpec::Of("o", "O").RelativeTo("t"), QObj(0), PObj(0, 0), Ms(0)));
  ASSERT_TRUE(graph.AddTwist(TwistSpec::Of("o").RelativeTo("T").ExpressedIn("o"), VObj(0, 0),
                             WObj(0), Ms(0)));
  for (int k = 0; k < kClutter; ++k) {
    ASSERT_TRUE(graph.AddPose(PoseSpec::Of(kClutterName[k], kClutterBody[k]).RelativeTo("t"), q_TO,
                              PClutter(k, 0), Ms(0)));
  }
  ASSERT_FALSE(Near(X_WO(0, 5, 5), X_WO(1, 5, 5)));
  ASSERT_FALSE(Near(V_WO(0), V_WO(1)));

  std::vector<Published<B>> published(kChanges + 1);
  const auto compile = [&](int i, std::int64_t first) {
    Published<B>& p = published[static_cast<std::size_t>(i)];
    auto pose = graph.CompilePose(PoseSpec::Of("o").RelativeTo("w"));
    auto twist =
        graph.CompileTwist(TwistSpec::Of("o").RelativeTo(i % 2 == 0 ? "T" : "G").ExpressedIn("o"));
    auto derivative = graph.CompileTwist(TwistSpec::Of("o").RelativeTo("W").ExpressedIn("w"),
                                         TwistSource::kPoses);
    if (!pose || !twist || !derivative) return false;
    for (int k = 0; k < kClutter; ++k) {
      auto c = graph.CompilePose(PoseSpec::Of(kClutterName[k]).RelativeTo("w"));
      if (!c) return false;
      p.clutter[k].emplace(std::move(*c));
    }
    p.pose.emplace(std::move(*pose));
    p.twist.emplace(std::move(*twist));
    p.derivative.emplace(std::move(*derivative));
    p.first = first;
    return true;
  };
  ASSERT_TRUE(compile(0, 0));
  auto gripper = graph.CompilePose(PoseSpec::Of("g").RelativeTo("w"));
  ASSERT_TRUE(gripper);

  std::atomic<int> latest{0};
  std::atomic<std::int64_t> written{0};  // every edge has a sample at this stamp
  std::atomic<bool> stop{false}, changing{false};
  constexpr int kReaders = 2;
  std::vector<ReaderCounts> counts(kReaders);

  const auto reader = [&](ReaderCounts& c, std::uint64_t seed) {
    std::uint64_t x = seed;
    const auto next = [&] {
      x = x * 6364136223846793005ull + 1442695040888963407ull;
      return x >> 33;
    };
    const auto outcome = [&](ErrorCode code, bool right, bool allowed_failure = false) {
      ++c.evaluations;
      if (code == ErrorCode::kOk) {
        ++c.answered;
        c.wrong += !right;
      } else if (code == ErrorCode::kQueryInvalidated) {
        ++c.invalidated;
      } else if (!allowed_failure) {
        ++c.bad_code;
      }
    };
    while (!stop.load(std::memory_order_relaxed)) {
      const int i = latest.load(std::memory_order_acquire);
      const Published<B>& q = published[static_cast<std::size_t>(i)];
      const int state = i % 2;
      for (int k = 0; k < kBatch && !stop.load(std::memory_order_relaxed); ++k) {
        // A time in the state's histories (if the state is still current; else the queries
        // are invalidated whatever the time).
        const std::int64_t newest = written.load(std::memory_order_acquire);
        const std::int64_t span = std::max<std::int64_t>(newest - q.first, 0);
        const std::int64_t t =
            q.first + static_cast<std::int64_t>(next() % static_cast<std::uint64_t>(span + 1));
        PoseCoords X;
        TimeReport r;
        const bool during = changing.load(std::memory_order_relaxed);
        const auto t0 = std::chrono::steady_clock::now();
        const ErrorCode at = q.pose->Evaluate(X, At{Ms(t)}, r);
        (during ? c.during_change : c.latency).Add(std::chrono::steady_clock::now() - t0);
        outcome(at, at == ErrorCode::kOk && Near(ToIso<B>(X), X_WO(state, t, t)));

        // Latest: each edge's newest sample; the report names the stamps read (state 1 reads
        // the arm's and the object's: either may be the older).
        const ErrorCode lat = q.pose->Evaluate(X, Latest{}, r);
        bool right = false;
        if (lat == ErrorCode::kOk && r.oldest && r.newest) {
          const std::int64_t lo = r.oldest->nanoseconds() / 1000000,
                             hi = r.newest->nanoseconds() / 1000000;
          const Isometry3d Y = ToIso<B>(X);
          right = lo >= q.first && (Near(Y, X_WO(state, lo, hi)) || Near(Y, X_WO(state, hi, lo)));
        }
        outcome(lat, right);

        // The twist edge at t (interpolated) and its newest sample.
        Vector3d v, w;
        const ErrorCode tw = q.twist->Evaluate(v, w, At{Ms(t)}, r);
        outcome(tw, tw == ErrorCode::kOk && Near(v, VObj(state, t)) && Near(w, WObj(state)));
        const ErrorCode tl = q.twist->Evaluate(v, w, Latest{}, r);
        outcome(tl, tl == ErrorCode::kOk && r.newest &&
                        Near(v, VObj(state, r.newest->nanoseconds() / 1000000)) &&
                        Near(w, WObj(state)));

        // The pose derivative at t: the segment's velocity. At the state's first stamp the
        // object's history may hold that one sample only (no segment: kExtrapolation).
        const ErrorCode d = q.derivative->Evaluate(v, w, At{Ms(t)}, r);
        outcome(d, d == ErrorCode::kOk && Near(v, V_WO(state)) && Near(w, Vector3d::Zero()),
                d == ErrorCode::kExtrapolation && t == q.first);

        // A clutter object at t (its history may be another clutter object's old one).
        const int ck = static_cast<int>(next() % kClutter);
        const ErrorCode cc = q.clutter[ck]->Evaluate(X, At{Ms(t)}, r);
        outcome(cc, cc == ErrorCode::kOk && Near(ToIso<B>(X), X_WC(ck, t)));

        // Untouched: the gripper (the arm's stamped edge is never removed) at t.
        const ErrorCode gr = gripper->Evaluate(X, At{Ms(t)}, r);
        ++c.untouched;
        c.untouched_wrong += gr != ErrorCode::kOk || !Near(ToIso<B>(X), X_WG(t));
      }
    }
  };
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r) readers.emplace_back(reader, std::ref(counts[r]), 12345u + r);

  // The writer: samples every millisecond, a grasp or release every 10.
  int writer_failures = 0;
  std::size_t bytes_after_warmup = 0;
  std::chrono::steady_clock::duration longest_change{};
  auto arm = graph.FindPoseEdge("a", "w");
  auto obj = graph.FindPoseEdge("o", "t");
  auto obj_twist = graph.FindTwistEdge("o", "T");
  ASSERT_TRUE(arm && obj && obj_twist);
  std::vector<PoseHandle> clutter;
  for (int k = 0; k < kClutter; ++k) {
    auto h = graph.FindPoseEdge(kClutterName[k], "t");
    ASSERT_TRUE(h);
    clutter.push_back(*h);
  }
  std::int64_t s = 0;
  auto tick = std::chrono::steady_clock::now();
  for (int i = 1; i <= kChanges; ++i) {
    const int before = (i - 1) % 2, after = i % 2;
    for (int k = 1; k < kSamplesPerChange; ++k) {  // samples of state i - 1
      tick += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(tick);
      ++s;
      writer_failures += graph.SetPose(*arm, q_WA, P_WA(s), Ms(s)) != ErrorCode::kOk;
      writer_failures +=
          graph.SetPose(*obj, QObj(before), PObj(before, s), Ms(s)) != ErrorCode::kOk;
      writer_failures +=
          graph.SetTwist(*obj_twist, VObj(before, s), WObj(before), Ms(s)) != ErrorCode::kOk;
      for (int c = 0; c < kClutter; ++c) {
        writer_failures += graph.SetPose(clutter[c], q_TO, PClutter(c, s), Ms(s)) != ErrorCode::kOk;
      }
      written.store(s, std::memory_order_release);
    }
    tick += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(tick);
    ++s;
    changing.store(true, std::memory_order_relaxed);
    const auto t0 = std::chrono::steady_clock::now();
    const char* from = before == 0 ? "t" : "g";
    const char* to = after == 0 ? "t" : "g";
    writer_failures += !graph.RemovePose("o", from);
    writer_failures +=
        !graph.AddPose(PoseSpec::Of("o").RelativeTo(to), QObj(after), PObj(after, s), Ms(s));
    writer_failures += !graph.RemoveTwist("o", before == 0 ? "T" : "G");
    writer_failures +=
        !graph.AddTwist(TwistSpec::Of("o").RelativeTo(after == 0 ? "T" : "G").ExpressedIn("o"),
                        VObj(after, s), WObj(after), Ms(s));
    writer_failures += graph.SetPose(*arm, q_WA, P_WA(s), Ms(s)) != ErrorCode::kOk;
    for (int c = 0; c < kClutter; ++c) writer_failures += !graph.RemovePose(kClutterName[c], "t");
    for (int c = 0; c < kClutter; ++c) {
      writer_failures += !graph.AddPose(PoseSpec::Of(kClutterName[c]).RelativeTo("t"), q_TO,
                                        PClutter(c, s), Ms(s));
      auto h = graph.FindPoseEdge(kClutterName[c], "t");
      writer_failures += !h;
      if (h) clutter[static_cast<std::size_t>(c)] = *h;
    }
    longest_change = std::max(longest_change, std::chrono::steady_clock::now() - t0);
    obj = graph.FindPoseEdge("o", to);
    obj_twist = graph.FindTwistEdge("o", after == 0 ? "T" : "G");
    writer_failures += !obj || !obj_twist || !compile(i, s);
    if (!obj || !obj_twist) break;
    written.store(s, std::memory_order_release);
    latest.store(i, std::memory_order_release);
    changing.store(false, std::memory_order_relaxed);
    if (i == 2) bytes_after_warmup = graph.ApproximateBytesExcludingNames();
  }
  stop = true;
  for (std::thread& t : readers) t.join();
  ASSERT_EQ(writer_failures, 0);
  // Bounded memory: after one grasp and one release every history is reused (no growth).
  EXPECT_EQ(graph.ApproximateBytesExcludingNames(), bytes_after_warmup);

  ReaderCounts all;
  for (const ReaderCounts& c : counts) all.Add(c);
  EXPECT_EQ(all.wrong, 0u) << "answers that are neither the value before nor after a change";
  EXPECT_EQ(all.bad_code, 0u);
  EXPECT_EQ(all.untouched_wrong, 0u) << "the untouched query failed or changed";
  EXPECT_GT(all.answered, 0u);
  EXPECT_GT(all.untouched, 0u);

  // The last published queries answer, allocating nothing; every earlier one is invalidated.
  {
    const Published<B>& last = published[kChanges];
    PoseCoords X;
    Vector3d v, w;
    TimeReport r;
    ErrorCode codes[4];
    {
      CountAllocations counting;
      codes[0] = last.pose->Evaluate(X, At{Ms(s)}, r);
      codes[1] = last.twist->Evaluate(v, w, Latest{}, r);
      codes[2] = last.derivative->Evaluate(v, w, Latest{}, r);
      codes[3] = gripper->Evaluate(X, Latest{}, r);
      EXPECT_EQ(counting.count(), 0u);
    }
    EXPECT_EQ(codes[0], ErrorCode::kOk);
    EXPECT_EQ(codes[1], ErrorCode::kOk);
    EXPECT_EQ(codes[2],
              ErrorCode::kExtrapolation);  // the object's new edge has one sample: no segment
    EXPECT_EQ(codes[3], ErrorCode::kOk);
    ASSERT_EQ(last.pose->Evaluate(X, At{Ms(s)}, r), ErrorCode::kOk);
    EXPECT_TRUE(Near(ToIso<B>(X), X_WO(kChanges % 2, s, s)));
  }
  std::size_t stale_invalidated = 0;
  for (int i = 0; i < kChanges; ++i) {
    const Published<B>& p = published[static_cast<std::size_t>(i)];
    PoseCoords X;
    Vector3d v, w;
    TimeReport r;
    stale_invalidated += p.pose->Evaluate(X, At{Ms(p.first)}, r) == ErrorCode::kQueryInvalidated;
    stale_invalidated += p.twist->Evaluate(v, w, Latest{}, r) == ErrorCode::kQueryInvalidated;
    stale_invalidated += p.derivative->Evaluate(v, w, Latest{}, r) == ErrorCode::kQueryInvalidated;
    for (const auto& c : p.clutter)
      stale_invalidated += c->Evaluate(X, Latest{}, r) == ErrorCode::kQueryInvalidated;
  }
  EXPECT_EQ(stale_invalidated, (3u + kClutter) * kChanges);
  EXPECT_GT(all.invalidated, 0u) << "no reader evaluated a query while its edges changed";

  std::printf(
      "[ timed grasp loop ] %d changes at 100 Hz, %lld samples per stamped edge; %zu evaluations "
      "of the "
      "changed queries: %zu answered, %zu invalidated, %zu wrong; longest change %lld us\n",
      kChanges, static_cast<long long>(s), all.evaluations, all.answered, all.invalidated,
      all.wrong,
      static_cast<long long>(
          std::chrono::duration_cast<std::chrono::microseconds>(longest_change).count()));
  for (const auto& [what, L] :
       {std::pair<const char*, const Latencies*>{"during changes", &all.during_change},
        std::pair<const char*, const Latencies*>{"between changes", &all.latency}}) {
    std::printf(
        "[ timed grasp loop ] reader latency of the object's pose At(t) %s (%llu evaluations, wall "
        "ns, "
        "10 ns buckets): p50 %llu, p99 %llu, p99.9 %llu, max %llu\n",
        what, static_cast<unsigned long long>(L->n),
        static_cast<unsigned long long>(L->Quantile(0.5)),
        static_cast<unsigned long long>(L->Quantile(0.99)),
        static_cast<unsigned long long>(L->Quantile(0.999)),
        static_cast<unsigned long long>(L->max_ns));
  }
}

}  // namespace
}  // namespace semgraph::core
