// In-process tests of the mirror (semgraph/dds/mirror.h): hostile messages change nothing and
// are logged; a reader thread evaluates compiled queries (a pose, a wrench) while values stream in
// (run under ThreadSanitizer in CI). Own DDS domain per test; loopback config from CYCLONEDDS_URI.
#include "semgraph/dds/mirror.h"

#include <dds/dds.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

#include "dds_isolation.h"
#include "mirror_test_support.h"
#include "scenes.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/dds/publisher.h"
#include "semgraph_wire.h"

namespace semgraph::dds_test {
namespace {

using namespace std::chrono_literals;

TEST(MirrorTest, MalformedMessagesAreRejectedAndChangeNothing) {
  constexpr std::uint32_t kDomain = 21;
  std::mutex log_mutex;
  std::vector<std::string> logs;
  dds::MirrorOptions options;
  options.name = "m";
  options.domain = kDomain;
  options.log = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(log_mutex);
    logs.push_back(line);
  };
  auto mirror = dds::Mirror::Create(options);
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  ASSERT_TRUE(BuildRobot(g));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub) << pub.error();
  ASSERT_TRUE((*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = Dump(m); });

  // Structures: NaN, a non-unit quaternion, an invalid name, an unknown kind.
  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", head[] = "x", body[] = "X", tail[] = "w", tail_body[] = "W", empty[] = "";
  auto element = [&](std::uint8_t kind, char* h, double q0, double p0) {
    semgraph_wire_Element e{};
    e.kind = kind;
    e.edge = 7;
    e.head = h;
    e.head_body = body;
    e.tail = tail;
    e.tail_body = tail_body;
    e.numbers[0] = q0;
    e.numbers[4] = p0;
    return e;
  };
  const semgraph_wire_Element bad[] = {element(semgraph_wire_ELEMENT_POSE, head, 1.0, std::nan("")),
                                       element(semgraph_wire_ELEMENT_POSE, head, 0.5, 0.0),
                                       element(semgraph_wire_ELEMENT_POSE, empty, 1.0, 0.0),
                                       element(9, head, 1.0, 0.0)};
  std::uint64_t revision = 0;
  for (const semgraph_wire_Element& e : bad) {
    semgraph_wire_Element copy = e;
    semgraph_wire_Structure s{};
    s.owner = owner;
    s.source = 99;
    s.revision = ++revision;
    s.elements._length = s.elements._maximum = 1;
    s.elements._buffer = &copy;
    ASSERT_EQ(dds_write(structures.writer, &s), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);  // keep-last 1: let each one arrive
  }
  // Values for a real edge: NaN, a non-unit quaternion, an unknown kind.
  RawWriter values(kDomain, &semgraph_wire_Value_desc, "semgraph_values");
  const auto edge = g.FindFrame("l1").value();
  const double nan = std::nan("");
  const double rows[][7] = {{1, 0, 0, 0, nan, 0, 0}, {2, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0, 0}};
  for (int i = 0; i < 3; ++i) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = edge;
    v.kind = i == 2 ? 5 : semgraph_wire_VALUE_POSE;
    v.seq = 1000 + i;
    std::copy(rows[i], rows[i] + 7, v.numbers);
    ASSERT_EQ(dds_write(values.writer, &v), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 7; }, 5s))
      << (*mirror)->messages_rejected();
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->Owners().size(), 1u);  // "evil" was never accepted
  std::lock_guard<std::mutex> lock(log_mutex);
  std::string all;
  for (const std::string& l : logs) all += l + "\n";
  EXPECT_NE(all.find("structure from owner 'evil': element 0 (pose 'x'): a number is not finite"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("not a unit quaternion (invalid_rotation)"), std::string::npos) << all;
  EXPECT_NE(all.find("element 0 (pose ''): invalid name"), std::string::npos) << all;
  EXPECT_NE(all.find("unknown kind 9"), std::string::npos) << all;
  EXPECT_NE(all.find("value of edge " + std::to_string(edge)), std::string::npos) << all;
  EXPECT_NE(all.find(": unknown kind"), std::string::npos) << all;
}

// One writer (the receive thread) and a reader thread evaluating a compiled query while the
// publisher streams: every answer is one consistent value (angle about z equals x / 2).
TEST(MirrorTest, ReaderThreadEvaluatesWhileValuesStream) {
  constexpr std::uint32_t kDomain = 22;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("m", "M").RelativeTo("w", "W"),
                        Eigen::Quaterniond::Identity(), {0, 0, 1}));
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("m", "M"),
                        Eigen::Quaterniond::Identity(), {0, 0, 0}));
  // A wrench on A by M streams as well: a compiled wrench query reads it on the reader thread.
  ASSERT_TRUE(g.AddWrench(core::WrenchSpec::On("A").By("M").At("a"), {0, 0, 0}, {0, 0, 0}));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  auto edge = g.FindPoseEdge("a", "m");
  ASSERT_TRUE(edge);
  auto wrench = g.FindWrench("A", "M");
  ASSERT_TRUE(wrench);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  std::optional<core::CompiledPose<coord::QuaternionBackend>> query;
  std::optional<core::CompiledWrench<coord::QuaternionBackend>> wrench_query;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    auto c = m.CompilePose(core::PoseSpec::Of("a").RelativeTo("w"));
    if (c) query.emplace(std::move(*c));
    auto cw = m.CompileWrench(core::WrenchSpec::On("A").By("M").At("a"));
    if (cw) wrench_query.emplace(std::move(*cw));
  });
  ASSERT_TRUE(query);
  ASSERT_TRUE(wrench_query);
  std::atomic<bool> stop{false};
  std::atomic<long> evaluations{0}, inconsistent{0};
  std::thread reader([&] {
    coord::QuaternionBackend::PoseCoords X;
    while (!stop.load()) {
      if (query->Evaluate(X) != base::ErrorCode::kOk) {
        inconsistent.fetch_add(1);
        continue;
      }
      const double angle = 2.0 * std::atan2(X.rotation.z(), X.rotation.w());
      if (std::abs(angle - X.translation.x() / 2.0) > 1e-9 ||
          std::abs(X.translation.z() - 1.0) > 1e-12) {
        inconsistent.fetch_add(1);
      }
      // The wrench (t, 2t, 0), (0, 0, 3t) is read whole or not at all (its sequence lock).
      Eigen::Vector3d f, mo;
      if (wrench_query->Evaluate(f, mo) != base::ErrorCode::kOk ||
          std::abs(f.y() - 2.0 * f.x()) > 1e-12 || std::abs(mo.z() - 3.0 * f.x()) > 1e-12) {
        inconsistent.fetch_add(1);
      }
      evaluations.fetch_add(1);
    }
  });
  const int kUpdates = 20000;
  for (int k = 1; k <= kUpdates; ++k) {
    const double t = 1e-4 * k;
    ASSERT_EQ((*pub)->SetPose(*edge, Rz(t), {2.0 * t, 0, 0}), base::ErrorCode::kOk);
    if (k % 4 == 0) {
      ASSERT_EQ((*pub)->SetWrench(*wrench, {t, 2.0 * t, 0}, {0, 0, 3.0 * t}), base::ErrorCode::kOk);
    }
  }
  const bool seen = (*mirror)->WaitUntil(
      [&] {
        coord::QuaternionBackend::PoseCoords X;
        Eigen::Vector3d f, mo;
        return query->Evaluate(X) == base::ErrorCode::kOk &&
               std::abs(X.translation.x() - 2e-4 * kUpdates) < 1e-12 &&
               wrench_query->Evaluate(f, mo) == base::ErrorCode::kOk &&
               std::abs(f.x() - 1e-4 * kUpdates) < 1e-15;
      },
      5s);
  stop.store(true);
  reader.join();
  EXPECT_TRUE(seen);
  EXPECT_EQ(inconsistent.load(), 0);
  EXPECT_GT(evaluations.load(), 0);
  EXPECT_EQ((*pub)->write_failures(), 0u);
}

// A raw DDS writer on the sample topic (keep-last per edge as the publishers' own).
struct RawSampleWriter : RawWriter {
  explicit RawSampleWriter(std::uint32_t domain)
      : RawWriter(domain, &semgraph_wire_Value_desc, "semgraph_samples") {}
};

std::vector<double> PoseAt(const core::SceneGraph<>& g, const char* of, const char* wrt,
                           std::int64_t t) {
  auto X = g.GetPose(core::PoseSpec::Of(of).RelativeTo(wrt), core::At(core::Stamp::Nanoseconds(t)));
  if (!X) return {};
  const auto& c = X->value.value;
  Eigen::Quaterniond q(c.rotation);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z(), c.translation.x(), c.translation.y(), c.translation.z()};
}
std::vector<double> TwistAt(const core::SceneGraph<>& g, std::int64_t t) {
  auto V = g.GetTwist(core::TwistSpec::Of("a").RelativeTo("W").ExpressedIn("w"),
                      core::At(core::Stamp::Nanoseconds(t)));
  if (!V) return {};
  return {V->value.linear.x(),  V->value.linear.y(),  V->value.linear.z(),
          V->value.angular.x(), V->value.angular.y(), V->value.angular.z()};
}
void ExpectAllNear(const std::vector<double>& a, const std::vector<double>& b, double tol,
                   const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  ASSERT_FALSE(a.empty()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i], b[i], tol) << what << " [" << i << "]";
}

// Stamped edges replicate as stamped edges: the structure carries their kind and the graph's
// time options, the samples go into the mirror's histories (sent out of order: the history
// sorts them), so answers at a time on the mirror equal the publisher's; a different value at
// an existing stamp (policy reject) is dropped by the history's rule and changes nothing.
TEST(MirrorTest, StampedSamplesReplicateHistories) {
  constexpr std::uint32_t kDomain = 23;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  core::TimeOptions time;
  time.window = core::Duration::Seconds(5);
  time.duplicate_stamp = core::DuplicatePolicy::kReject;
  time.sample_capacity = 128;
  auto made = core::SceneGraph<>::Create(time);
  ASSERT_TRUE(made);
  core::SceneGraph<>& g = *made;
  const std::int64_t t0 = 1'000'000'000;
  const std::int64_t dt = 10'000'000;  // 10 ms
  auto angle = [](int k) { return 0.01 * k; };
  auto position = [](int k) { return Eigen::Vector3d(0.02 * k, 1.0, -0.5 * 0.001 * k); };
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("w", "W"), Rz(angle(0)),
                        position(0), core::Stamp::Nanoseconds(t0)));
  ASSERT_TRUE(g.AddTwist(core::TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"),
                         {0.1, 0, 0}, {0, 0, 0.2}, core::Stamp::Nanoseconds(t0)));
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("c", "C").RelativeTo("w", "W"), Rx(0.1), {0, 0, 2}));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  auto pose = g.FindPoseEdge("a", "w");
  auto twist = g.FindTwistEdge("a", "W");
  ASSERT_TRUE(pose && twist);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  // The replica took the publisher's time options (it was empty).
  const core::TimeOptions& mt = (*mirror)->graph().time_options();
  EXPECT_EQ(mt.window, time.window);
  EXPECT_EQ(mt.duplicate_stamp, time.duplicate_stamp);
  EXPECT_EQ(mt.sample_capacity, time.sample_capacity);

  // Samples 1..60: the even ones first, then the odd ones (out of order), then sample 30 again.
  constexpr int kSamples = 60;
  std::vector<int> order;
  for (int k = 2; k <= kSamples; k += 2) order.push_back(k);
  for (int k = 1; k <= kSamples; k += 2) order.push_back(k);
  order.push_back(30);
  for (int k : order) {
    const core::Stamp s = core::Stamp::Nanoseconds(t0 + k * dt);
    ASSERT_EQ((*pub)->SetPose(*pose, Rz(angle(k)), position(k), s), base::ErrorCode::kOk) << k;
    ASSERT_EQ((*pub)->SetTwist(*twist, {0.1 + 0.01 * k, 0, 0}, {0, 0, 0.2}, s),
              base::ErrorCode::kOk)
        << k;
  }
  auto edge_state = [&](bool want_twist) {
    for (const dds::EdgeState& e : (*mirror)->Edges()) {
      if (e.head == "a" && e.twist == want_twist) return e;
    }
    return dds::EdgeState{};
  };
  ASSERT_TRUE((*mirror)->WaitUntil(
      [&] {
        return edge_state(false).received >= order.size() &&
               edge_state(true).received >= order.size();
      },
      5s))
      << edge_state(false).received << " " << edge_state(true).received;
  EXPECT_TRUE(edge_state(false).stamped);
  EXPECT_EQ(edge_state(false).newest_time_ns, t0 + kSamples * dt);
  EXPECT_EQ((*pub)->write_failures(), 0u);

  // A hostile sample: another value at an existing stamp (policy reject) is refused by the
  // history's rule: counted, nothing changes.
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = Dump(m); });
  {
    RawSampleWriter raw(kDomain);
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = g.FindFrame("a").value();
    v.kind = semgraph_wire_VALUE_POSE;
    v.seq = 5000;
    v.time_ns = t0 + 20 * dt;
    const double n[7] = {1, 0, 0, 0, 9, 9, 9};
    std::copy(n, n + 7, v.numbers);
    ASSERT_EQ(dds_write(raw.writer, &v), DDS_RETCODE_OK);
    ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->samples_dropped() >= 1; }, 5s));
  }
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->messages_rejected(), 0u);

  // Answers at given stamps (on samples, between samples, before the first one) equal the
  // publisher's; on a sample they equal the value set there, composed by hand.
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    for (int k = 0; k <= kSamples; ++k) {
      for (std::int64_t off : {std::int64_t{0}, dt / 3}) {
        const std::int64_t t = t0 + k * dt + off;
        if (k == kSamples && off != 0) continue;
        ExpectAllNear(PoseAt(m, "a", "w", t), PoseAt(g, "a", "w", t), 1e-12,
                      "pose at " + std::to_string(t));
        ExpectAllNear(PoseAt(m, "a", "c", t), PoseAt(g, "a", "c", t), 1e-12,
                      "pose a wrt c at " + std::to_string(t));
        ExpectAllNear(TwistAt(m, t), TwistAt(g, t), 1e-12, "twist at " + std::to_string(t));
      }
      const Eigen::Quaterniond q = Rz(angle(k));
      const Eigen::Vector3d p = position(k);
      ExpectAllNear(PoseAt(m, "a", "w", t0 + k * dt),
                    {q.w(), q.x(), q.y(), q.z(), p.x(), p.y(), p.z()}, 1e-12,
                    "hand-made pose at sample " + std::to_string(k));
    }
    // Staleness shows in stamps: the newest sample is older than not_before.
    auto stale = m.GetPose(core::PoseSpec::Of("a").RelativeTo("w"),
                           core::Latest(core::Stamp::Nanoseconds(t0 + kSamples * dt + 1)));
    ASSERT_FALSE(stale);
    EXPECT_EQ(stale.error().code, base::ErrorCode::kStale);
  });
}

// Stamped samples with covariances (docs/uncertainty.md, "Time"): the structure carries a
// stamped edge's newest sample with its covariance (here the first one, sent only that way),
// each stamped SetPose / SetTwist with a covariance sends the sample with the covariance its
// history stored (out of order: the history sorts them), a sample without one is exact. The
// mirror's graph then answers at a time between two samples i, i+1 with the interpolation
// (1 - l) S_i + l S_i+1, l = (t - t_i) / (t_i+1 - t_i), computed here by hand.
TEST(MirrorTest, StampedSamplesCarryTheirCovariances) {
  constexpr std::uint32_t kDomain = 29;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  core::TimeOptions time;
  time.window = core::Duration::Seconds(5);
  time.sample_capacity = 64;
  auto made = core::SceneGraph<>::Create(time);
  ASSERT_TRUE(made);
  core::SceneGraph<>& g = *made;
  const std::int64_t t0 = 1'000'000'000, dt = 100'000'000;  // 100 ms
  const auto at = [&](int k) { return core::Stamp::Nanoseconds(t0 + k * dt); };
  // Pose covariances S0..S2, twist covariances T0..T2 (sample 3 carries none: zero).
  core::Covariance6 S1 = TestCovariance(2.0), T2 = TestCovariance(4.0);
  S1(0, 4) = S1(4, 0) = 3e-5;  // not a multiple of another: a wrong pairing shows
  T2(1, 5) = T2(5, 1) = -2e-5;
  const core::Covariance6 S[3] = {TestCovariance(1.0), S1, TestCovariance(0.5)};
  const core::Covariance6 T[3] = {TestCovariance(3.0), TestCovariance(0.25), T2};
  const core::PoseSpec pose_spec = core::PoseSpec::Of("a", "A").RelativeTo("w", "W");
  const core::TwistSpec twist_spec = core::TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a");
  // Sample k: p = (k, 0, 0), v = (0, 2k, 0), identity rotation and w = 0 (the covariance of the
  // single edge is then the edge's own, in the query's form).
  const auto p = [](int k) { return Eigen::Vector3d(k, 0, 0); };
  const auto v = [](int k) { return Eigen::Vector3d(0, 2.0 * k, 0); };
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  ASSERT_TRUE(g.AddPose(pose_spec, q, p(0), at(0), core::CovarianceInput{&S[0]}));
  ASSERT_TRUE(g.AddTwist(twist_spec, v(0), zero, at(0), core::CovarianceInput{&T[0]}));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  auto pose = g.FindPoseEdge("a", "w");
  auto twist = g.FindTwistEdge("a", "W");
  ASSERT_TRUE(pose && twist);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  for (int k : {2, 1}) {
    ASSERT_EQ((*pub)->SetPose(*pose, q, p(k), at(k), core::CovarianceInput{&S[k]}),
              base::ErrorCode::kOk);
    ASSERT_EQ((*pub)->SetTwist(*twist, v(k), zero, at(k), core::CovarianceInput{&T[k]}),
              base::ErrorCode::kOk);
  }
  ASSERT_EQ((*pub)->SetPose(*pose, q, p(3), at(3)), base::ErrorCode::kOk);
  ASSERT_EQ((*pub)->SetTwist(*twist, v(3), zero, at(3)), base::ErrorCode::kOk);
  auto received = [&](bool want_twist) {
    for (const dds::EdgeState& e : (*mirror)->Edges()) {
      if (e.head == "a" && e.twist == want_twist) return e.received;
    }
    return std::uint64_t{0};
  };
  ASSERT_TRUE(
      (*mirror)->WaitUntil([&] { return received(false) >= 3 && received(true) >= 3; }, 5s));
  EXPECT_EQ((*mirror)->messages_rejected(), 0u);
  EXPECT_EQ((*pub)->write_failures(), 0u);

  // By hand: on sample k its own; between k and k+1 the weights from the stamps.
  struct Probe {
    std::int64_t t;
    core::Covariance6 S, T;
  };
  const auto mix = [](const core::Covariance6& A, const core::Covariance6& B, double l) {
    return core::Covariance6((1.0 - l) * A + l * B);
  };
  const core::Covariance6 Z = core::Covariance6::Zero();
  const std::vector<Probe> probes = {
      {t0, S[0], T[0]},  // the structure's sample
      {t0 + dt / 4, mix(S[0], S[1], 0.25), mix(T[0], T[1], 0.25)},
      {t0 + dt, S[1], T[1]},
      {t0 + dt + 3 * dt / 5, mix(S[1], S[2], 0.6), mix(T[1], T[2], 0.6)},
      {t0 + 2 * dt + dt / 2, mix(S[2], Z, 0.5), mix(T[2], Z, 0.5)},  // sample 3: exact
      {t0 + 3 * dt, Z, Z},
  };
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    for (const Probe& pr : probes) {
      const core::Stamp s = core::Stamp::Nanoseconds(pr.t);
      const double x = double(pr.t - t0) / double(dt);  // p_x = k at sample k, linear between
      const auto X = m.GetPoseWithCovariance(pose_spec, core::At{s});
      const auto V = m.GetTwistWithCovariance(twist_spec, core::At{s});
      ASSERT_TRUE(X && V) << pr.t;
      EXPECT_LE((X->value.covariance - pr.S).cwiseAbs().maxCoeff(), 1e-18)
          << "pose at " << pr.t << "\n"
          << X->value.covariance << "\nexpected\n"
          << pr.S;
      EXPECT_LE((V->value.covariance - pr.T).cwiseAbs().maxCoeff(), 1e-18)
          << "twist at " << pr.t << "\n"
          << V->value.covariance << "\nexpected\n"
          << pr.T;
      EXPECT_NEAR(X->value.value.ToIsometry().translation().x(), x, 1e-12) << pr.t;
      EXPECT_NEAR(V->value.value.linear.y(), 2.0 * x, 1e-12) << pr.t;
    }
    // The edge's record follows the newest sample (exact).
    EXPECT_TRUE(m.pose_covariance(m.FindFrame("a")).isZero(0.0));
  });
}

// The wire's packed covariance (semgraph_wire.idl): the upper triangle of S, row by row.
void PackUpper(const core::Covariance6& S, double* out) {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) out[k++] = S(i, j);
  }
}

// Hostile covariances of stamped samples: on the sample topic (a pose covariance that is not
// positive semidefinite, a negative variance, a NaN in a twist covariance; the wire's packed
// upper triangle cannot carry an asymmetric matrix) and in a structure (a stamped edge with a
// covariance that is not PSD, one with a NaN). Each is refused with a report naming the edge,
// and the mirror's graph is unchanged.
TEST(MirrorTest, HostileStampedCovariancesAreRefused) {
  constexpr std::uint32_t kDomain = 30;
  std::mutex log_mutex;
  std::string logs;
  auto mirror = dds::Mirror::Create(LoggingOptions(kDomain, log_mutex, logs));
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  const core::Covariance6 S = TestCovariance(1.0);
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("w", "W"), Rz(0.1), {1, 0, 0},
                        core::Stamp::Nanoseconds(100), core::CovarianceInput{&S}));
  ASSERT_TRUE(g.AddTwist(core::TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"),
                         {0.1, 0, 0}, {0, 0, 0.2}, core::Stamp::Nanoseconds(100)));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = Dump(m); });

  RawSampleWriter samples(kDomain);
  auto sample = [&](std::uint8_t kind, std::uint64_t seq, std::int64_t time_ns) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = g.FindFrame("a").value();
    v.kind = kind;
    v.seq = seq;
    v.time_ns = time_ns;
    if (kind == semgraph_wire_VALUE_POSE) v.numbers[0] = 1;  // identity, at the origin
    PackUpper(S, v.covariance);
    return v;
  };
  semgraph_wire_Value not_psd = sample(semgraph_wire_VALUE_POSE, 10, 200);
  not_psd.covariance[1] = 1.0;  // S(0, 1) = 1 with variances of 4e-4 and 5e-4
  semgraph_wire_Value negative = sample(semgraph_wire_VALUE_POSE, 11, 300);
  negative.covariance[0] = -1e-3;  // S(0, 0) < 0
  semgraph_wire_Value nan = sample(semgraph_wire_VALUE_TWIST, 12, 200);
  nan.covariance[20] = std::nan("");  // S(5, 5)
  for (const semgraph_wire_Value* v : {&not_psd, &negative, &nan})
    ASSERT_EQ(dds_write(samples.writer, v), DDS_RETCODE_OK);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 3; }, 5s))
      << (*mirror)->messages_rejected();

  // Structures of another owner: stamped edges into {x} (not PSD) and {y} (a NaN).
  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", x[] = "x", y[] = "y", body[] = "X", tail[] = "w", tail_body[] = "W";
  semgraph_wire_Element e{};
  e.kind = semgraph_wire_ELEMENT_POSE;
  e.head = x;
  e.head_body = body;
  e.tail = tail;
  e.tail_body = tail_body;
  e.stamped = true;
  e.time_ns = 5;
  e.numbers[0] = 1;
  PackUpper(S, e.covariance);
  e.covariance[1] = 1.0;
  std::uint64_t revision = 0;
  auto structure = [&](semgraph_wire_Element* el) {
    semgraph_wire_Structure s{};
    s.owner = owner;
    s.source = 77;
    s.revision = ++revision;
    s.elements._length = s.elements._maximum = 1;
    s.elements._buffer = el;
    ASSERT_EQ(dds_write(structures.writer, &s), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);  // keep-last 1: let each one arrive
  };
  structure(&e);
  auto refused_x = [&] {
    for (const dds::Report& r : (*mirror)->Refusals()) {
      if (r.owner == "evil" && r.code == "invalid_covariance") return true;
    }
    return false;
  };
  ASSERT_TRUE((*mirror)->WaitUntil(refused_x, 5s));
  std::string refusal;
  for (const dds::Report& r : (*mirror)->Refusals()) refusal += r.message + "\n";
  EXPECT_NE(refusal.find("{x}"), std::string::npos) << refusal;
  semgraph_wire_Element f = e;
  f.head = y;
  f.covariance[1] = S(0, 1);
  f.covariance[7] = std::nan("");
  const std::uint64_t rejected = (*mirror)->messages_rejected();
  structure(&f);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() > rejected; }, 5s));

  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    after = Dump(m);
    EXPECT_FALSE(m.FindFrame("x").is_valid());
    EXPECT_FALSE(m.FindFrame("y").is_valid());
  });
  EXPECT_EQ(before, after);
  std::lock_guard<std::mutex> lock(log_mutex);
  EXPECT_NE(logs.find("sample into 'a': invalid_covariance"), std::string::npos) << logs;
  EXPECT_NE(logs.find("sample into 'a': invalid_number"), std::string::npos) << logs;
  EXPECT_NE(logs.find("element 0 (pose 'y'): a covariance entry is not finite"), std::string::npos)
      << logs;
  EXPECT_EQ(logs.find("carries no covariance"), std::string::npos) << logs;
}

// Hostile messages for the time fields: a stamped sample for an unstamped edge, a stamp out of
// range, an unstamped value for a stamped edge, a stamped body, absurd time options. Each is
// rejected with a log line and changes nothing.
TEST(MirrorTest, HostileTimeFieldsAreRejected) {
  constexpr std::uint32_t kDomain = 24;
  std::mutex log_mutex;
  std::string logs;
  auto mirror = dds::Mirror::Create(LoggingOptions(kDomain, log_mutex, logs));
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("w", "W"), Rz(0.1), {1, 0, 0},
                        core::Stamp::Nanoseconds(100)));
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("u", "U").RelativeTo("w", "W"), Rz(0.2), {0, 1, 0}));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = Dump(m); });

  RawSampleWriter samples(kDomain);
  RawWriter values(kDomain, &semgraph_wire_Value_desc, "semgraph_values");
  auto value = [&](const char* frame, std::int64_t time_ns, std::uint64_t seq) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = g.FindFrame(frame).value();
    v.kind = semgraph_wire_VALUE_POSE;
    v.seq = seq;
    v.time_ns = time_ns;
    v.numbers[0] = 1;
    return v;
  };
  semgraph_wire_Value v1 = value("u", 200, 10);        // stamped sample, unstamped edge
  semgraph_wire_Value v2 = value("a", INT64_MIN, 11);  // stamp out of range
  semgraph_wire_Value v3 = value("a", 0, 12);          // unstamped value, stamped edge
  ASSERT_EQ(dds_write(samples.writer, &v1), DDS_RETCODE_OK);
  ASSERT_EQ(dds_write(samples.writer, &v2), DDS_RETCODE_OK);
  ASSERT_EQ(dds_write(values.writer, &v3), DDS_RETCODE_OK);

  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", head[] = "x", body[] = "X", tail[] = "w", tail_body[] = "W";
  semgraph_wire_Element body_element{};
  body_element.kind = semgraph_wire_ELEMENT_BODY;
  body_element.head = body;
  body_element.head_body = body;
  body_element.tail = tail;
  body_element.tail_body = tail_body;
  body_element.stamped = true;
  semgraph_wire_Element pose_element = body_element;
  pose_element.kind = semgraph_wire_ELEMENT_POSE;
  pose_element.head = head;
  pose_element.stamped = true;
  pose_element.time_ns = 5;
  pose_element.numbers[0] = 1;
  std::uint64_t revision = 0;
  auto structure = [&](semgraph_wire_Element* e, std::uint32_t capacity) {
    semgraph_wire_Structure s{};
    s.owner = owner;
    s.source = 77;
    s.revision = ++revision;
    s.elements._length = s.elements._maximum = 1;
    s.elements._buffer = e;
    s.window_ns = 1'000'000'000;
    s.sample_capacity = capacity;
    ASSERT_EQ(dds_write(structures.writer, &s), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);  // keep-last 1: let each one arrive
  };
  structure(&body_element, 16);
  structure(&pose_element, 0xFFFFFFFFu);  // would preallocate 4e9 samples per edge
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 5; }, 5s))
      << (*mirror)->messages_rejected();
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->Owners().size(), 1u);
  std::lock_guard<std::mutex> lock(log_mutex);
  EXPECT_NE(logs.find("sample: a stamped sample for the unstamped edge into 'u'"),
            std::string::npos)
      << logs;
  EXPECT_NE(logs.find("the stamp is out of range (invalid_number)"), std::string::npos) << logs;
  EXPECT_NE(logs.find("value: an unstamped value for the stamped edge into 'a'"), std::string::npos)
      << logs;
  EXPECT_NE(logs.find("element 0 (body 'X'): only edges can be stamped"), std::string::npos)
      << logs;
  EXPECT_NE(logs.find("sample capacity 4294967295 is outside [2, 1048576]"), std::string::npos)
      << logs;
}

// Joints: a publisher's joints (a revolute, a mimic of it, a fixed one) replicate through
// AddJoint and their states through SetJoints / SetJointState; the mimic follows on the mirror.
// Hostile joint messages (an unknown joint type, a NaN, a state for a fixed joint, a stamped
// state for a timeless joint, a joint that takes an edge the owner also publishes) are rejected
// with a log line and change nothing.
TEST(MirrorTest, JointsReplicateAndHostileJointMessagesAreRejected) {
  constexpr std::uint32_t kDomain = 25;
  std::mutex log_mutex;
  std::string logs;
  auto mirror = dds::Mirror::Create(LoggingOptions(kDomain, log_mutex, logs));
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  core::JointSpec j1;
  j1.name = "j1";
  j1.type = core::JointType::kRevolute;
  j1.parent = "w";
  j1.parent_body = "W";
  j1.child = "l1";
  j1.child_body = "L1";
  j1.p_origin = {0, 0, 1};
  j1.axis = {0, 0, 2};  // normalized by the graph
  j1.lower = -2;
  j1.upper = 2;
  core::JointSpec j2 = j1;
  j2.name = "j2";
  j2.parent = "l1";
  j2.parent_body = "L1";
  j2.child = "l2";
  j2.child_body = "L2";
  j2.p_origin = {0.5, 0, 0};
  j2.mimic = "j1";
  j2.multiplier = 2;
  j2.offset = 0.25;
  core::JointSpec fixed = j1;
  fixed.name = "f";
  fixed.type = core::JointType::kFixed;
  fixed.parent = "l2";
  fixed.parent_body = "L2";
  fixed.child = "t";
  fixed.child_body = "T";
  fixed.q_origin = Rx(0.3);
  fixed.p_origin = {0.1, 0.2, 0};
  ASSERT_TRUE(g.AddJoint(j1));
  ASSERT_TRUE(g.AddJoint(j2));
  ASSERT_TRUE(g.AddJoint(fixed));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  const std::string_view names[] = {"j1"};
  auto group = g.MakeJointGroup(names);
  ASSERT_TRUE(group);
  const double q[] = {0.4}, qdot[] = {-0.1};
  ASSERT_EQ((*pub)->SetJointState(*group, q, qdot), base::ErrorCode::kOk);
  ASSERT_TRUE((*mirror)->WaitUntil(
      [&] {
        bool set = false;
        (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
          auto h = m.FindJoint("j1");
          set = h && m.joint_position(*h) == 0.4;
        });
        return set && (*mirror)->CaughtUp();
      },
      5s));
  // The mirror's t in w: X_w,l1(q) X_l1,l2(2q + 0.25) X_l2,t, composed by hand.
  const Eigen::Isometry3d X_wt =
      Iso(Rz(0.4), {0, 0, 1}) * Iso(Rz(2 * 0.4 + 0.25), {0.5, 0, 0}) * Iso(Rx(0.3), {0.1, 0.2, 0});
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    EXPECT_EQ(m.num_joints(), 3u);
    auto X = m.GetPose(core::PoseSpec::Of("t").RelativeTo("w"));
    ASSERT_TRUE(X);
    EXPECT_LT((X->ToIsometry().matrix() - X_wt.matrix()).norm(), 1e-12);
    auto V = m.GetTwist(core::TwistSpec::Of("l1").RelativeTo("W").ExpressedIn("l1"));
    ASSERT_TRUE(V);
    EXPECT_NEAR(V->angular.z(), -0.1, 1e-15);
    before = Dump(m);
  });

  // Hostile structures of another owner.
  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", name[] = "k", parent[] = "w", parent_body[] = "W", child[] = "x",
       child_body[] = "X", empty[] = "";
  semgraph_wire_Joint joint{};
  joint.id = 1;
  joint.type = semgraph_wire_JOINT_REVOLUTE;
  joint.name = name;
  joint.parent = parent;
  joint.parent_body = parent_body;
  joint.child = child;
  joint.child_body = child_body;
  joint.mimic = empty;
  joint.origin[0] = 1;
  joint.axis[0] = 1;
  joint.upper = 1;
  semgraph_wire_Element edge{};
  edge.kind = semgraph_wire_ELEMENT_POSE;
  edge.head = child;
  edge.head_body = child_body;
  edge.tail = parent;
  edge.tail_body = parent_body;
  edge.numbers[0] = 1;
  std::uint64_t revision = 0;
  auto structure = [&](semgraph_wire_Joint j, bool with_edge) {
    semgraph_wire_Structure s{};
    s.owner = owner;
    s.source = 78;
    s.revision = ++revision;
    if (with_edge) {
      s.elements._length = s.elements._maximum = 1;
      s.elements._buffer = &edge;
    }
    s.joints._length = s.joints._maximum = 1;
    s.joints._buffer = &j;
    ASSERT_EQ(dds_write(structures.writer, &s), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);
  };
  semgraph_wire_Joint unknown = joint;
  unknown.type = 7;
  structure(unknown, false);
  semgraph_wire_Joint nan_joint = joint;
  nan_joint.axis[1] = std::nan("");
  structure(nan_joint, false);
  structure(joint, true);  // the joint's pose edge published as an edge too
  // Hostile joint states for the publisher's joints.
  RawWriter values(kDomain, &semgraph_wire_Value_desc, "semgraph_values");
  RawSampleWriter samples(kDomain);
  auto state = [&](const char* joint_name, double qv, std::uint64_t seq) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = g.FindJoint(joint_name)->index.value();
    v.kind = semgraph_wire_VALUE_JOINT;
    v.seq = seq;
    v.numbers[0] = qv;
    v.time_ns = 1000;
    return v;
  };
  const semgraph_wire_Value fixed_state = state("f", 0.1, 50);
  const semgraph_wire_Value stamped_state = state("j1", 0.2, 51);  // j1 is timeless
  const semgraph_wire_Value nan_state = state("j1", std::nan(""), 52);
  ASSERT_EQ(dds_write(values.writer, &fixed_state), DDS_RETCODE_OK);
  ASSERT_EQ(dds_write(samples.writer, &stamped_state), DDS_RETCODE_OK);
  ASSERT_EQ(dds_write(values.writer, &nan_state), DDS_RETCODE_OK);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 6; }, 5s))
      << (*mirror)->messages_rejected();
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->Owners().size(), 1u);
  std::lock_guard<std::mutex> lock(log_mutex);
  EXPECT_NE(logs.find("joint 0 ('k'): unknown joint type 7"), std::string::npos) << logs;
  EXPECT_NE(logs.find("joint 0 ('k'): a number is not finite (invalid_number)"), std::string::npos)
      << logs;
  EXPECT_NE(logs.find("joint 0 ('k'): a second edge into the same frame"), std::string::npos)
      << logs;
  EXPECT_NE(logs.find("a state for the fixed or mimic joint 'f'"), std::string::npos) << logs;
  EXPECT_NE(logs.find("a stamped sample for the unstamped joint 'j1'"), std::string::npos) << logs;
  EXPECT_NE(logs.find("value of edge " + std::to_string(g.FindJoint("j1")->index.value()) +
                      " from source"),
            std::string::npos)
      << logs;
}

// Batches (Publisher::BeginBatch / Flush): one cycle's values of several edges, an unstamped
// pose, stamped samples and a joint state, in one DDS write; the mirror applies them in order
// as single values (stamped samples with their covariances). A mirror that joins later gets
// every edge's latest value: the next Flush republishes the structure for it (a stamped edge's
// newest sample with its covariance). A batch of too many updates is rejected whole.
TEST(MirrorTest, BatchesApplyAsSingleValuesAndLateMirrorsGetTheLatest) {
  const auto SampleCovariance = [](int k) {
    return core::Covariance6(k % 2 == 0 ? TestCovariance(0.01 * k) : core::Covariance6::Zero());
  };
  constexpr std::uint32_t kDomain = 26;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("w", "W"), Rz(0), {0, 0, 0}));
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("b", "B").RelativeTo("w", "W"), Rz(0), {0, 0, 0},
                        core::Stamp::Nanoseconds(0)));
  core::JointSpec j;
  j.name = "j";
  j.type = core::JointType::kPrismatic;
  j.parent = "a";
  j.parent_body = "A";
  j.child = "l";
  j.child_body = "L";
  j.axis = {0, 1, 0};
  j.upper = 10;
  ASSERT_TRUE(g.AddJoint(j));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  auto a = g.FindPoseEdge("a", "w");
  auto b = g.FindPoseEdge("b", "w");
  const std::string_view names[] = {"j"};
  auto group = g.MakeJointGroup(names);
  ASSERT_TRUE(a && b && group);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  constexpr int kCycles = 200;
  for (int k = 1; k <= kCycles; ++k) {
    (*pub)->BeginBatch();
    ASSERT_EQ((*pub)->SetPose(*a, Rz(0.01 * k), {0.1 * k, 0, 0}), base::ErrorCode::kOk);
    // b's samples: with a covariance on even cycles (SampleCovariance), exact on odd ones.
    const core::Stamp s = core::Stamp::Nanoseconds(1000 * k);
    const core::Covariance6 S = SampleCovariance(k);
    ASSERT_EQ(k % 2 == 0 ? (*pub)->SetPose(*b, Rz(-0.01 * k), {0, 0.1 * k, 0}, s,
                                           core::CovarianceInput{&S})
                         : (*pub)->SetPose(*b, Rz(-0.01 * k), {0, 0.1 * k, 0}, s),
              base::ErrorCode::kOk);
    const double q[] = {0.01 * k};
    ASSERT_EQ((*pub)->SetJointPositions(*group, q), base::ErrorCode::kOk);
    (*pub)->Flush();
  }
  // Every edge's last value arrived (a structure republished for this mirror, when it matched
  // after the first PublishStructure, may have carried some values before their batch did).
  auto last_seen = [&] {
    std::uint64_t seen = 0;
    for (const dds::EdgeState& e : (*mirror)->Edges()) {
      if (e.seq == static_cast<std::uint64_t>(kCycles)) ++seen;
    }
    return seen;
  };
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return last_seen() == 3; }, 5s)) << last_seen();
  EXPECT_LE((*mirror)->values_applied(), 3u * kCycles);
  EXPECT_EQ((*pub)->write_failures(), 0u);
  auto check = [&](const core::SceneGraph<>& m, const std::string& who) {
    // l in w: X_wa X_al, a translation of 2 along y (q = 2) after a's last value.
    auto X = m.GetPose(core::PoseSpec::Of("l").RelativeTo("w"));
    ASSERT_TRUE(X) << who;
    const Eigen::Isometry3d X_wl =
        Iso(Rz(0.01 * kCycles), {0.1 * kCycles, 0, 0}) * Iso(Rz(0), {0, 0.01 * kCycles, 0});
    EXPECT_LT((X->ToIsometry().matrix() - X_wl.matrix()).norm(), 1e-12) << who;
    // The stamped edge's history holds every cycle's sample.
    for (int k = 1; k <= kCycles; ++k) {
      auto Y = m.GetPose(core::PoseSpec::Of("b").RelativeTo("w"),
                         core::At(core::Stamp::Nanoseconds(1000 * k)));
      ASSERT_TRUE(Y) << who << " " << k;
      EXPECT_LT(
          (Y->value.ToIsometry().matrix() - Iso(Rz(-0.01 * k), {0, 0.1 * k, 0}).matrix()).norm(),
          1e-12)
          << who << " " << k;
      // With its covariance (the single edge's, in the query's form: the same numbers).
      auto C = m.GetPoseWithCovariance(core::PoseSpec::Of("b").RelativeTo("w"),
                                       core::At(core::Stamp::Nanoseconds(1000 * k)));
      ASSERT_TRUE(C) << who << " " << k;
      EXPECT_LE((C->value.covariance - SampleCovariance(k)).cwiseAbs().maxCoeff(), 1e-18)
          << who << " " << k;
    }
  };
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { check(m, "mirror"); });

  // A late mirror: it matches, the next Flush republishes the structure with the latest values.
  auto late = dds::Mirror::Create({"late", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(late);
  ASSERT_TRUE((*late)->WaitUntil([&] { return (*late)->CaughtUp(); }, 5s));
  const std::uint64_t revision = (*pub)->revision();
  ASSERT_TRUE((*late)->WaitUntil(
      [&] {
        (*pub)->BeginBatch();
        (*pub)->Flush();  // an empty cycle: only the republish, once the late mirror matched
        return (*pub)->revision() > revision && (*late)->Owners().size() == 1 &&
               (*late)->Owners()[0].revision == (*pub)->revision() && (*late)->CaughtUp();
      },
      5s));
  (*late)->WithGraph([&](const core::SceneGraph<>& m) {
    auto X = m.GetPose(core::PoseSpec::Of("l").RelativeTo("w"));
    ASSERT_TRUE(X);
    const Eigen::Isometry3d X_wl =
        Iso(Rz(0.01 * kCycles), {0.1 * kCycles, 0, 0}) * Iso(Rz(0), {0, 0.01 * kCycles, 0});
    EXPECT_LT((X->ToIsometry().matrix() - X_wl.matrix()).norm(), 1e-12);
    // b's newest sample, with its covariance (the structure carries both).
    auto C = m.GetPoseWithCovariance(core::PoseSpec::Of("b").RelativeTo("w"),
                                     core::At(core::Stamp::Nanoseconds(1000 * kCycles)));
    ASSERT_TRUE(C);
    EXPECT_LE((C->value.covariance - SampleCovariance(kCycles)).cwiseAbs().maxCoeff(), 1e-18);
  });

  // A hostile batch: more updates than a batch may hold.
  RawWriter batches(kDomain, &semgraph_wire_Batch_desc, "semgraph_batches");
  std::vector<semgraph_wire_Update> many(2000);
  for (semgraph_wire_Update& u : many) {
    u.edge = g.FindFrame("a").value();
    u.seq = 100000;
    u.numbers[0] = 1;
  }
  semgraph_wire_Batch big{};
  big.source = (*pub)->source();
  big.serial = 1;
  big.updates._length = big.updates._maximum = static_cast<std::uint32_t>(many.size());
  big.updates._buffer = many.data();
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = Dump(m); });
  const std::uint64_t rejected = (*mirror)->messages_rejected();
  ASSERT_EQ(dds_write(batches.writer, &big), DDS_RETCODE_OK);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() > rejected; }, 5s));
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = Dump(m); });
  EXPECT_EQ(before, after);
}

}  // namespace
}  // namespace semgraph::dds_test
