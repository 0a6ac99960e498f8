// In-process tests of the mirror (semgraph/dds/mirror.h): hostile messages change nothing and
// are logged; a reader thread evaluates compiled queries while values stream in (run under
// ThreadSanitizer in CI). Own DDS domain per test; loopback config from CYCLONEDDS_URI.
#include <gtest/gtest.h>

#include <dds/dds.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

#include "scenes.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/dds/mirror.h"
#include "semgraph/dds/publisher.h"
#include "semgraph_wire.h"

namespace semgraph::dds_test {
namespace {

using namespace std::chrono_literals;

// A raw DDS writer on one of semgraph's topics, with the topic's QoS: what a hostile or buggy
// peer could send.
struct RawWriter {
  dds_entity_t participant = 0, writer = 0;
  RawWriter(std::uint32_t domain, const dds_topic_descriptor_t* desc, const char* name) {
    participant = dds_create_participant(domain, nullptr, nullptr);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_destination_order(qos, DDS_DESTINATIONORDER_BY_RECEPTION_TIMESTAMP);
    const dds_entity_t topic = dds_create_topic(participant, desc, name, qos, nullptr);
    writer = dds_create_writer(participant, topic, qos, nullptr);
    dds_delete_qos(qos);
  }
  ~RawWriter() { dds_delete(participant); }
};

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
  EXPECT_NE(all.find("structure from owner 'evil': element 0 (pose 'x'): a number is not finite"), std::string::npos) << all;
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
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("m", "M").RelativeTo("w", "W"), Eigen::Quaterniond::Identity(), {0, 0, 1}));
  ASSERT_TRUE(g.AddPose(core::PoseSpec::Of("a", "A").RelativeTo("m", "M"), Eigen::Quaterniond::Identity(), {0, 0, 0}));
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  auto edge = g.FindPoseEdge("a", "m");
  ASSERT_TRUE(edge);
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  std::optional<core::CompiledPose<coord::QuaternionBackend>> query;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    auto c = m.CompilePose(core::PoseSpec::Of("a").RelativeTo("w"));
    if (c) query.emplace(std::move(*c));
  });
  ASSERT_TRUE(query);
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
      if (std::abs(angle - X.translation.x() / 2.0) > 1e-9 || std::abs(X.translation.z() - 1.0) > 1e-12) {
        inconsistent.fetch_add(1);
      }
      evaluations.fetch_add(1);
    }
  });
  const int kUpdates = 20000;
  for (int k = 1; k <= kUpdates; ++k) {
    const double t = 1e-4 * k;
    ASSERT_EQ((*pub)->SetPose(*edge, Rz(t), {2.0 * t, 0, 0}), base::ErrorCode::kOk);
  }
  const bool seen = (*mirror)->WaitUntil(
      [&] {
        coord::QuaternionBackend::PoseCoords X;
        return query->Evaluate(X) == base::ErrorCode::kOk && std::abs(X.translation.x() - 2e-4 * kUpdates) < 1e-12;
      },
      5s);
  stop.store(true);
  reader.join();
  EXPECT_TRUE(seen);
  EXPECT_EQ(inconsistent.load(), 0);
  EXPECT_GT(evaluations.load(), 0);
  EXPECT_EQ((*pub)->write_failures(), 0u);
}

}  // namespace
}  // namespace semgraph::dds_test
