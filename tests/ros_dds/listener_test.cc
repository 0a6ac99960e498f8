// Listener (semgraph/ros_dds/listener.h) against another process on loopback
// (ros_dds_test_node): a broadcast scene read back (static and dynamic) answering every pose
// query as the original, a late joiner getting /tf_static, a burst of 1,000 transforms in one
// message, every finding of docs/ros.md "Transforms into the graph" from a live stream with the
// graph unchanged by each refused transform, and the latency from the broadcaster's write to
// the listener's graph, and PoseWithCovarianceStamped / Odometry topics read back with their
// covariances (hostile ones findings, the graph unchanged). Own DDS domain per test; loopback
// config from CYCLONEDDS_URI.
#include "semgraph/ros_dds/listener.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "child_process.h"
#include "dds_isolation.h"
#include "live_scene.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/ros_dds/broadcaster.h"

namespace semgraph::ros_dds {
namespace {

using namespace std::chrono_literals;
using core::PoseSpec;
using core::SceneGraph;
using dds_test::Child;
using ros_dds_test::kStep;
using ros_dds_test::kT0;

Child Node(std::uint32_t domain) {
  return Child({SEMGRAPH_ROS_DDS_TEST_NODE, std::to_string(domain)});
}

ListenerOptions On(std::uint32_t domain) {
  ListenerOptions o;
  o.domain = domain;
  return o;
}

// Every pose query between the frames, untimed and at each policy, answered alike by both.
void ExpectSameAnswers(const SceneGraph<>& original, const SceneGraph<>& read_back,
                       const std::vector<core::TimePolicy>& policies) {
  const auto& frames = ros_dds_test::SceneFrames();
  int compared = 0;
  for (const std::string& of : frames) {
    for (const std::string& wrt : frames) {
      const PoseSpec spec = PoseSpec::Of(of).RelativeTo(wrt);
      for (const core::TimePolicy& policy : policies) {
        const auto a = original.GetPose(spec, policy);
        const auto b = read_back.GetPose(spec, policy);
        ASSERT_EQ(a.has_value(), b.has_value()) << of << " wrt " << wrt;
        if (!a) {
          EXPECT_EQ(a.error().code, b.error().code) << of << " wrt " << wrt;
          continue;
        }
        const auto& X = a->value.value;
        const auto& Y = b->value.value;
        EXPECT_LE((X.translation - Y.translation).norm(), 1e-12) << of << " wrt " << wrt;
        EXPECT_LE(X.rotation.angularDistance(Y.rotation), 1e-12) << of << " wrt " << wrt;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, static_cast<int>(frames.size() * frames.size()));
}

// The stamps of the samples of the pose edge into `frame` (ns after kT0), for failure messages.
std::string History(const Listener& l, const std::string& frame) {
  std::string out = frame + " samples at";
  l.WithGraph([&](const SceneGraph<>& g) {
    const core::PoseHistory* h = g.pose_history(g.FindFrame(frame));
    if (h == nullptr) return;
    core::PoseHistory::Bracket b;
    for (std::int64_t t = kT0 - 1;;) {
      h->Find(t + 1, b);
      if (b.where == core::PoseHistory::Bracket::Where::kAfter) break;
      const bool first = b.where == core::PoseHistory::Bracket::Where::kBefore || b.exact;
      t = first ? b.s0 : b.s1;
      out += " " + std::to_string((t - kT0) / kStep);
    }
  });
  return out;
}

TEST(ListenerTest, BroadcastSceneReadBackAnswersEveryPoseQueryAsTheOriginal) {
  constexpr std::uint32_t kDomain = 141;
  constexpr int kSteps = 20;
  SceneGraph<> original;
  ASSERT_TRUE(ros_dds_test::BuildScene(original));
  for (int k = 1; k <= kSteps; ++k) ASSERT_TRUE(ros_dds_test::AddStep(original, k));

  // Mode same_body without a map (the table's inter-body timeless edge becomes constant), and
  // with the original's bodies (every edge keeps its kind).
  SceneGraph<> plain, mapped;
  auto l1 = Listener::Create(plain, On(kDomain));
  ListenerOptions with_map = On(kDomain);
  with_map.lift.bodies = BodiesOf(original);
  auto l2 = Listener::Create(mapped, with_map);
  ASSERT_TRUE(l1 && l2) << (l1 ? l2.error() : l1.error());

  Child node = Node(kDomain);
  ASSERT_TRUE(node.started());
  // The scene's first Broadcast() sends sample 0 before any reader can have it (rt/tf is
  // volatile). Once both listeners are matched and in sync with both rt/tf writers (the raw
  // one and the broadcaster), a rewind restates it, and it reaches them, the first time.
  ASSERT_TRUE(node.Command("scene"));
  ASSERT_TRUE(node.Command("wait_subscribers 2"));
  ASSERT_TRUE(node.Command("rewind"));
  const auto has = [](const Listener& l, const char* frame, std::int64_t stamp) {
    bool found = false;
    l.WithGraph([&](const SceneGraph<>& g) {
      const core::PoseHistory* h = g.pose_history(g.FindFrame(frame));
      double v[7];
      found = h != nullptr && h->ValueAt(stamp, v);
    });
    return found;
  };
  const auto both = [&](std::int64_t stamp) {
    for (Listener* l : {l1->get(), l2->get()}) {
      if (!has(*l, "base", stamp) || !has(*l, "arm", stamp)) return false;
    }
    return true;
  };
  ASSERT_TRUE((*l1)->WaitUntil([&] { return both(kT0); }, 20s))
      << History(**l1, "base") << "; " << History(**l2, "base");
  ASSERT_TRUE(node.Command("steps 1 " + std::to_string(kSteps)));
  const std::int64_t last = kT0 + kSteps * kStep;
  ASSERT_TRUE((*l1)->WaitUntil([&] { return both(last); }, 20s))
      << History(**l1, "base") << "; " << History(**l2, "base");
  for (Listener* l : {l1->get(), l2->get()}) {
    EXPECT_EQ(l->stats().counts.refused, 0u);
    EXPECT_EQ(l->stats().tf_static, 1u);
    EXPECT_TRUE(l->findings().empty());
  }
  std::vector<core::TimePolicy> policies = {
      core::Latest(), core::LatestCommon(),
      core::At(core::Stamp::Nanoseconds(kT0 - 1'000'000'000))};
  for (int h = 0; h <= 2 * kSteps + 1; ++h) {
    policies.push_back(core::At(core::Stamp::Nanoseconds(kT0 + h * kStep / 2)));
  }
  (*l1)->WithGraph([&](const SceneGraph<>& g) { ExpectSameAnswers(original, g, policies); });
  (*l2)->WithGraph([&](const SceneGraph<>& g) {
    ExpectSameAnswers(original, g, policies);
    // With the map, the bodies are the original's.
    for (const std::string& f : ros_dds_test::SceneFrames()) {
      EXPECT_EQ(g.body_name(g.body_of(g.FindFrame(f))),
                original.body_name(original.body_of(original.FindFrame(f))));
    }
  });
  // Without it, the static tree world-table-table_top is one body named after its root.
  (*l1)->WithGraph([&](const SceneGraph<>& g) {
    EXPECT_EQ(g.body_name(g.body_of(g.FindFrame("table_top"))), "world");
    EXPECT_EQ(g.body_name(g.body_of(g.FindFrame("camera"))), "base");
  });
}

TEST(ListenerTest, LateJoinerGetsTheStaticTransforms) {
  constexpr std::uint32_t kDomain = 142;
  SceneGraph<> original;
  ASSERT_TRUE(ros_dds_test::BuildScene(original));
  Child node = Node(kDomain);
  ASSERT_TRUE(node.Command("scene"));
  // The static message and sample 0, written (dds_write returned) before any reader exists.
  ASSERT_TRUE(node.Command("steps 0 0"));

  SceneGraph<> late;
  auto listener = Listener::Create(late, On(kDomain));
  ASSERT_TRUE(listener) << listener.error();
  Listener& l = **listener;
  ASSERT_TRUE(l.WaitUntil([&] { return l.stats().counts.applied == 4; }, 20s))
      << l.stats().counts.applied;
  EXPECT_EQ(l.stats().tf_static, 1u);  // keep-last 1: the one whole message
  EXPECT_EQ(l.stats().tf, 0u);         // /tf is volatile: sample 0 is gone
  l.WithGraph([&](const SceneGraph<>& g) {
    for (const auto& [of, wrt] : std::vector<std::pair<std::string, std::string>>{
             {"table", "world"}, {"table_top", "world"}, {"camera", "base"}, {"tool", "arm"}}) {
      const auto a = original.GetPose(PoseSpec::Of(of).RelativeTo(wrt));
      const auto b = g.GetPose(PoseSpec::Of(of).RelativeTo(wrt));
      ASSERT_TRUE(a && b) << of << " wrt " << wrt;
      EXPECT_LE((a->value.translation - b->value.translation).norm(), 1e-12);
      EXPECT_LE(a->value.rotation.angularDistance(b->value.rotation), 1e-12);
    }
    EXPECT_FALSE(g.GetPose(PoseSpec::Of("base").RelativeTo("world")).has_value());
  });
}

TEST(ListenerTest, BurstOfOneThousandTransformsInOneMessage) {
  constexpr std::uint32_t kDomain = 143;
  constexpr int kN = 1000;
  constexpr std::int64_t kSec = 1733300005;
  SceneGraph<> g;
  std::mutex mutex;
  std::vector<Arrival> arrivals;
  ListenerOptions options = On(kDomain);
  options.on_arrival = [&](const Arrival& a) {
    std::lock_guard<std::mutex> lock(mutex);
    arrivals.push_back(a);
  };
  auto listener = Listener::Create(g, options);
  ASSERT_TRUE(listener) << listener.error();
  Listener& l = **listener;
  Child node = Node(kDomain);
  ASSERT_TRUE(node.Command("wait_subscribers 1"));  // matched and in sync
  ASSERT_TRUE(node.Command("burst " + std::to_string(kN) + " " + std::to_string(kSec)));
  ASSERT_TRUE(l.WaitUntil([&] { return l.stats().counts.transforms == kN; }, 20s));
  EXPECT_EQ(l.stats().counts.applied, static_cast<std::uint64_t>(kN));
  EXPECT_EQ(l.stats().tf, 1u);
  ASSERT_TRUE(l.WaitUntil(
      [&] {  // on_arrival runs after the graph has the message
        std::lock_guard<std::mutex> lock(mutex);
        return !arrivals.empty();
      },
      5s));
  {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_EQ(arrivals.size(), 1u);
    EXPECT_EQ(arrivals[0].transforms, static_cast<std::size_t>(kN));
    EXPECT_GE(arrivals[0].applied_ns, arrivals[0].source_timestamp_ns);
  }
  l.WithGraph([&](const SceneGraph<>& graph) {
    EXPECT_EQ(graph.num_frames(), static_cast<std::size_t>(kN + 1));
    for (int i = 0; i < kN; ++i) {
      const std::string f = "f" + std::to_string(i);
      const auto at = core::At(core::Stamp::Nanoseconds(kSec * 1'000'000'000 + i));
      const auto X = graph.GetPose(PoseSpec::Of(f).RelativeTo("world"), at);
      ASSERT_TRUE(X) << f;
      EXPECT_EQ(X->value.value.translation, Eigen::Vector3d(0.001 * i, -0.002 * i, 0.5)) << f;
    }
    // Between two of them (both at their own stamps: LatestCommon has none in common).
    const auto X = graph.GetPose(PoseSpec::Of("f10").RelativeTo("f20"));
    ASSERT_TRUE(X);
    EXPECT_LE((X->value.translation - Eigen::Vector3d(-0.01, 0.02, 0)).norm(), 1e-15);
  });
}

// A compiled query evaluated on another thread while the receive thread adds 1,000 frames (a
// topology change each) and samples: the documented discipline (compile inside WithGraph,
// evaluate anywhere). Run under ThreadSanitizer in CI.
TEST(ListenerTest, CompiledQueriesRunWhileTheListenerAddsFrames) {
  constexpr std::uint32_t kDomain = 140;
  auto graph = SceneGraph<>::Create(core::TimeOptions{});
  ASSERT_TRUE(graph);
  auto listener = Listener::Create(*graph, On(kDomain));
  ASSERT_TRUE(listener) << listener.error();
  Listener& l = **listener;
  Child node = Node(kDomain);
  ASSERT_TRUE(node.Command("wait_subscribers 1"));  // matched and in sync
  ASSERT_TRUE(node.Command("tf world base 1733300000 0 1 2 3 0 0 0 1"));
  ASSERT_TRUE(l.WaitUntil([&] { return l.stats().counts.applied == 1; }, 20s));
  std::optional<core::CompiledPose<coord::QuaternionBackend>> query;
  l.WithGraph([&](const SceneGraph<>& g) {
    auto q = g.CompilePose(PoseSpec::Of("base").RelativeTo("world"));
    if (q) query.emplace(std::move(*q));
  });
  ASSERT_TRUE(query.has_value());
  std::atomic<bool> stop{false};
  std::atomic<int> answers{0};
  std::thread reader([&] {
    coord::QuaternionBackend::PoseCoords X;
    core::TimeReport report;
    while (!stop.load()) {
      if (query->Evaluate(X, core::Latest(), report) == core::ErrorCode::kOk) {
        // Every sample written has x = 1 and y = 2 (only z changes).
        if (X.translation.x() == 1.0 && X.translation.y() == 2.0) ++answers;
      }
    }
  });
  ASSERT_TRUE(node.Command("burst 1000 1733300001"));
  for (int i = 1; i <= 20; ++i) {
    ASSERT_TRUE(node.Command("tf world base 1733300000 " + std::to_string(i * 1000) + " 1 2 " +
                             std::to_string(3 + i) + " 0 0 0 1"));
  }
  const bool all = l.WaitUntil([&] { return l.stats().counts.applied == 1021; }, 20s);
  stop.store(true);
  reader.join();
  ASSERT_TRUE(all) << l.stats().counts.applied;
  EXPECT_GT(answers.load(), 0);
  coord::QuaternionBackend::PoseCoords X;
  core::TimeReport report;
  ASSERT_EQ(query->Evaluate(X, core::Latest(), report), core::ErrorCode::kOk);
  EXPECT_EQ(X.translation, Eigen::Vector3d(1, 2, 23));
}

// The graph's state as text: frames, bodies, parents, edge values, histories (size, newest).
std::string Snapshot(const SceneGraph<>& g) {
  std::string s;
  char buf[256];
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    const core::FrameIndex p = g.pose_parent(f);
    s += std::string(g.frame_name(f)) + "@" + std::string(g.body_name(g.body_of(f)));
    if (p.is_valid()) {
      const auto X = g.pose_value(f);
      std::snprintf(buf, sizeof buf, " <- %s [%.17g %.17g %.17g %.17g %.17g %.17g %.17g]",
                    std::string(g.frame_name(p)).c_str(), X.rotation.w(), X.rotation.x(),
                    X.rotation.y(), X.rotation.z(), X.translation.x(), X.translation.y(),
                    X.translation.z());
      s += buf;
      if (const core::PoseHistory* h = g.pose_history(f)) {
        s += " samples " + std::to_string(h->size()) + " newest " +
             std::to_string(h->newest_stamp());
      }
    }
    s += "\n";
  }
  return s;
}

constexpr const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="two_link">
  <link name="base_link"/>
  <link name="arm"/>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="arm"/>
    <origin xyz="0 0 0.5"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/>
  </joint>
</robot>
)";

struct Seen {
  std::mutex mutex;
  std::vector<std::pair<std::string, bool>> events;  // "code parent child", first
};

class FindingsTest : public ::testing::Test {
 protected:
  static constexpr std::uint32_t kDomain = 144;
  static constexpr const char* kT = "1733300010 0";

  void SetUp() override {
    ListenerOptions options = On(kDomain);
    // Two frames of one body not linked to each other (a duplicate path needs two).
    options.lift.bodies = {{"K7", {"k7a", "k7b"}}};
    options.on_finding = [this](const ros::FindingGroup& g, bool first) {
      std::lock_guard<std::mutex> lock(seen_.mutex);
      seen_.events.emplace_back(std::string(g.code.name()) + " " + g.parent + " " + g.child, first);
    };
    auto l = Listener::Create(same_body_graph_, options);
    ASSERT_TRUE(l) << l.error();
    same_body_ = std::move(*l);
    options.lift.static_mode = ros::StaticMode::kOwnBody;
    options.lift.bodies.clear();  // a map would put static children on their parents' bodies
    options.on_finding = nullptr;
    auto o = Listener::Create(own_body_graph_, options);
    ASSERT_TRUE(o) << o.error();
    own_body_ = std::move(*o);
    node_ = std::make_unique<Child>(
        std::vector<std::string>{SEMGRAPH_ROS_DDS_TEST_NODE, std::to_string(kDomain)});
    ASSERT_TRUE(node_->Command("wait_subscribers 2"));  // both listeners, in sync
  }

  // Sends a command that carries `transforms` transforms, waits until both listeners applied
  // or refused them all; returns whether they did.
  bool Send(const std::string& command, std::uint64_t transforms) {
    expected_ += transforms;
    if (!node_->Command(command)) return false;
    for (Listener* l : {same_body_.get(), own_body_.get()}) {
      if (!l->WaitUntil([&] { return l->stats().counts.transforms == expected_; }, 20s)) {
        return false;
      }
    }
    return true;
  }
  bool SendStatic(const std::string& parent, const std::string& child, const std::string& value) {
    statics_.insert(parent + " " + child);
    return Send("static " + parent + " " + child + " " + value, statics_.size());
  }
  std::string Graph() {
    std::string s;
    same_body_->WithGraph([&](const SceneGraph<>& g) { s = Snapshot(g); });
    return s;
  }
  static bool Has(const Listener& l, const std::string& code, const std::string& parent,
                  const std::string& child) {
    for (const ros::FindingGroup& g : l.findings()) {
      if (g.code.name() == code && g.parent == parent && g.child == child) return true;
    }
    return false;
  }
  // A refused transform: the finding with its code and frames, and the graph as before.
  void ExpectRefused(const std::string& command, std::uint64_t transforms, const std::string& code,
                     const std::string& parent, const std::string& child) {
    const std::string before = Graph();
    ASSERT_TRUE(Send(command, transforms)) << command;
    EXPECT_TRUE(Has(*same_body_, code, parent, child)) << command;
    EXPECT_EQ(Graph(), before) << command;
  }

  SceneGraph<> same_body_graph_, own_body_graph_;
  std::unique_ptr<Listener> same_body_, own_body_;
  std::unique_ptr<Child> node_;
  std::uint64_t expected_ = 0;
  std::set<std::string> statics_;
  Seen seen_;
};

TEST_F(FindingsTest, EveryFindingFromALiveStreamLeavesTheGraphUnchanged) {
  const std::string T = kT;
  const std::string id = " 0 0 0 0 0 0 1";
  ExpectRefused("tf a1 b1 " + T + " nan 0 0 0 0 0 1", 1, "invalid_number", "a1", "b1");
  ExpectRefused("tf a2 b2 " + T + " 0 0 0 0 0 0 2", 1, "invalid_rotation", "a2", "b2");
  ExpectRefused("tf a3 - " + T + id, 1, "invalid_name", "a3", "");
  ExpectRefused("tf a4 a4 " + T + id, 1, "self_edge", "a4", "a4");
  ASSERT_TRUE(Send("tf p5 c5 " + T + id, 1));
  ExpectRefused("tf q5 c5 " + T + id, 1, "multiple_pose_parents", "q5", "c5");
  ASSERT_TRUE(Send("tf x6 y6 " + T + id, 1));
  ExpectRefused("tf y6 x6 " + T + id, 1, "pose_cycle", "y6", "x6");
  ASSERT_TRUE(Send("tf m7 k7a " + T + id, 1));
  ExpectRefused("tf m7 k7b " + T + id, 1, "duplicate_pose_path", "m7", "k7b");
  // A changed static transform (the whole static message is re-sent, as tf2_ros does).
  ASSERT_TRUE(SendStatic("s8", "c8", "0 0 1 0 0 0 1"));
  statics_.insert("s8 c8");
  ExpectRefused("static s8 c8 0 0 2 0 0 0 1", statics_.size(), "constant_pose_change", "s8", "c8");
  // A frame both static and dynamic: constant_pose_change in mode same_body, stamp_mismatch
  // in mode own_body (its static transform is a timeless inter-body pose there).
  ASSERT_TRUE(SendStatic("s9", "c9", "0 1 0 0 0 0 1"));
  ExpectRefused("tf s9 c9 " + T + " 0 1.5 0 0 0 0 1", 1, "constant_pose_change", "s9", "c9");
  EXPECT_TRUE(Has(*own_body_, "stamp_mismatch", "s9", "c9"));
  ASSERT_TRUE(Send("tf w10 b10 " + T + id, 1));
  ExpectRefused("tf w10 b10 1733299990 0" + id, 1, "stamp_too_old", "w10", "b10");
  // Live, a frame's body is decided when it is first seen.
  ASSERT_TRUE(Send("tf m11 t11 " + T + id, 1));
  statics_.insert("base11 m11");
  ExpectRefused("static base11 m11" + id, statics_.size(), "frame_body_mismatch", "base11", "m11");

  // A robot model from /robot_description covers its joint's transform.
  const std::string urdf = ::testing::TempDir() + "/ros_dds_two_link.urdf";
  std::ofstream(urdf) << kUrdf;
  ASSERT_TRUE(node_->Command("urdf " + urdf));
  ASSERT_TRUE(same_body_->WaitUntil([&] { return same_body_->stats().robot_loaded; }, 20s));
  ASSERT_TRUE(node_->Command("joints 1733300010 0 shoulder 0.5"));
  ASSERT_TRUE(same_body_->WaitUntil([&] { return same_body_->stats().joint_states == 1; }, 20s));
  EXPECT_EQ(same_body_->stats().counts.joint_states, 1u);
  char q[96];  // R_z(0.5) at shoulder = 0.5, as (x, y, z, w), printed exactly
  std::snprintf(q, sizeof q, " 0 0 %.17g %.17g", std::sin(0.25), std::cos(0.25));
  ASSERT_TRUE(Send("tf base_link arm " + T + " 0 0 0.5" + q, 1));
  EXPECT_FALSE(Has(*same_body_, "model_mismatch", "base_link", "arm"));
  ExpectRefused("tf base_link arm " + T + " 0 0 0.5 0 0 0 1", 1, "model_mismatch", "base_link",
                "arm");
  // A joint state naming an unknown joint: a finding, nothing set.
  const std::string before = Graph();
  ASSERT_TRUE(node_->Command("joints 1733300011 0 elbow 0.1"));
  ASSERT_TRUE(same_body_->WaitUntil([&] { return same_body_->stats().joint_states == 2; }, 20s));
  ASSERT_TRUE(same_body_->WaitUntil(
      [&] { return same_body_->stats().counts.joint_states_refused == 1; }, 5s));
  EXPECT_EQ(Graph(), before);

  // Each group was reported once as new, as it happened.
  std::lock_guard<std::mutex> lock(seen_.mutex);
  std::set<std::string> firsts;
  for (const auto& [key, first] : seen_.events) {
    if (first) {
      EXPECT_TRUE(firsts.insert(key).second) << key;
    }
  }
  EXPECT_EQ(firsts.size(), same_body_->findings().size());
  for (const char* code :
       {"invalid_number", "invalid_rotation", "invalid_name", "self_edge", "multiple_pose_parents",
        "pose_cycle", "duplicate_pose_path", "constant_pose_change", "stamp_too_old",
        "frame_body_mismatch", "model_mismatch"}) {
    bool found = false;
    for (const std::string& k : firsts) found |= k.rfind(std::string(code) + " ", 0) == 0;
    EXPECT_TRUE(found) << code;
  }
}

// --- PoseWithCovarianceStamped and Odometry topics ----------------------------------------------

using Matrix6 = Eigen::Matrix<double, 6, 6>;

// A symmetric positive definite 6x6 with every entry distinct: A A^T + diag, A from `seed`.
Matrix6 Spd(double scale, int seed) {
  Matrix6 A;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) A(i, j) = std::sin(seed + 7 * i + 3 * j);
  }
  Matrix6 S = A * A.transpose();
  S.diagonal().array() += 1.0 + 0.25 * seed;
  return scale * S;
}

// Numbers printed exactly (%.17g), space-separated; a ROS covariance row-major.
std::string Numbers(std::initializer_list<double> xs) {
  std::string out;
  char buf[40];
  for (double x : xs) {
    std::snprintf(buf, sizeof buf, " %.17g", x);
    out += buf;
  }
  return out;
}
std::string Numbers(const Matrix6& S) {
  std::string out;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) out += Numbers({S(i, j)});
  }
  return out;
}

struct PublishedPose {
  std::int64_t sec = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Matrix6 S = Matrix6::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();  // odometry only
  Matrix6 S_twist = Matrix6::Identity();
  std::string odom_child = "base_link";  // "-": the empty name
  std::string PoseFields() const {
    return " " + std::to_string(sec) + " 0" +
           Numbers({p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()}) + Numbers(S);
  }
  std::string PoseCommand() const { return "pose /amcl_pose map" + PoseFields(); }
  std::string OdomCommand() const {
    return "odom /odom odom " + odom_child + PoseFields() +
           Numbers({v.x(), v.y(), v.z(), w.x(), w.y(), w.z()}) + Numbers(S_twist);
  }
};

class CovarianceTopicsTest : public ::testing::Test {
 protected:
  static constexpr std::uint32_t kDomain = 147;
  static constexpr std::int64_t kSec = 1733300020;

  void SetUp() override {
    ListenerOptions options = On(kDomain);
    options.lift.pose_topics = {{"/amcl_pose", "base_footprint"}};
    options.odometry_topics = {"/odom"};
    auto l = Listener::Create(graph_, options);
    ASSERT_TRUE(l) << l.error();
    listener_ = std::move(*l);
    node_ = std::make_unique<Child>(
        std::vector<std::string>{SEMGRAPH_ROS_DDS_TEST_NODE, std::to_string(kDomain)});
    // Best-effort readers: both sides matched before the first sample.
    ASSERT_TRUE(node_->Command("wait_match pose /amcl_pose 1"));
    ASSERT_TRUE(node_->Command("wait_match odom /odom 1"));
    ASSERT_TRUE(listener_->WaitUntil(
        [&] {
          return listener_->publishers("/amcl_pose") == 1 && listener_->publishers("/odom") == 1;
        },
        20s));
  }

  // The graph's complete state (Dump: frames, edges, values; Snapshot: histories).
  std::string State() {
    std::string s;
    listener_->WithGraph([&](const SceneGraph<>& g) { s = core::Dump(g) + Snapshot(g); });
    return s;
  }
  // Sends `command`, waits until `done()` (under the graph's lock).
  bool SendAndWait(const std::string& command, const std::function<bool()>& done) {
    return node_->Command(command) && listener_->WaitUntil(done, 20s);
  }

  SceneGraph<> graph_;
  std::unique_ptr<Listener> listener_;
  std::unique_ptr<Child> node_;
};

TEST_F(CovarianceTopicsTest, PosesAndOdometryReadBackWithTheirCovariances) {
  PublishedPose amcl;  // base_footprint wrt map
  amcl.sec = kSec;
  amcl.p = {1.25, -0.5, 0.0625};
  amcl.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  amcl.S = Spd(0.01, 1);
  PublishedPose odom;  // base_link wrt odom, and its twist
  odom.sec = kSec;
  odom.p = {0.2, 0.1, 0};
  odom.q = Eigen::Quaterniond(Eigen::AngleAxisd(-0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  odom.S = Spd(0.001, 2);
  odom.v = {0.4, -0.05, 0};
  odom.w = {0, 0.01, 0.2};
  odom.S_twist = Spd(1e-4, 3);

  const auto at = core::At(core::Stamp::Nanoseconds(kSec * 1'000'000'000));
  ASSERT_TRUE(node_->Command(amcl.PoseCommand()));
  ASSERT_TRUE(node_->Command(odom.OdomCommand()));
  ASSERT_TRUE(listener_->WaitUntil(
      [&] {
        const ListenerStats s = listener_->stats();
        return s.counts.poses_with_covariance == 1 && s.counts.odometry == 1;
      },
      20s))
      << listener_->stats().poses_with_covariance << " " << listener_->stats().odometry;
  EXPECT_TRUE(listener_->findings().empty());
  // ROS's 6x6 over (x, y, z, rotX, rotY, rotZ) of the pose in the header frame is semgraph's
  // edge form (coordinates convention, linear-angular): the published matrix, entry for entry.
  listener_->WithGraph([&](const SceneGraph<>& g) {
    for (const auto& [child, parent, m] :
         {std::tuple<const char*, const char*, const PublishedPose&>{"base_footprint", "map", amcl},
          {"base_link", "odom", odom}}) {
      const PoseSpec spec = PoseSpec::Of(child).RelativeTo(parent).ExpressedIn(parent);
      const auto X = g.GetPoseWithCovariance(spec, at);
      ASSERT_TRUE(X) << g.Describe(X.error(), spec);
      const Eigen::Isometry3d X_PC = X->value.value.ToIsometry();
      EXPECT_LE((X_PC.translation() - m.p).norm(), 1e-15) << child;
      EXPECT_LE((X_PC.linear() - m.q.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15) << child;
      EXPECT_LE((X->value.covariance - m.S).cwiseAbs().maxCoeff(), 1e-15) << child;
    }
    const auto body = [&](const char* f) {
      return std::string(g.body_name(g.body_of(g.FindFrame(f))));
    };
    const std::string child_body = body("base_link"), parent_body = body("odom");
    const auto spec = core::TwistSpec::Of("base_link", child_body)
                          .RelativeTo(parent_body)
                          .ExpressedIn("base_link");
    const auto V = g.GetTwistWithCovariance(spec, at);
    ASSERT_TRUE(V) << g.Describe(V.error(), spec);
    EXPECT_LE((V->value.value.linear - odom.v).norm(), 1e-15);
    EXPECT_LE((V->value.value.angular - odom.w).norm(), 1e-15);
    EXPECT_LE((V->value.covariance - odom.S_twist).cwiseAbs().maxCoeff(), 1e-15);
  });
  EXPECT_EQ(listener_->stats().poses_with_covariance, 1u);
  EXPECT_EQ(listener_->stats().odometry, 1u);
}

TEST_F(CovarianceTopicsTest, HostileMessagesAreFindingsAndLeaveTheGraphUnchanged) {
  PublishedPose good;
  good.sec = kSec;
  good.S = Spd(0.01, 4);
  good.S_twist = Spd(0.01, 5);
  ASSERT_TRUE(SendAndWait(good.PoseCommand(),
                          [&] { return listener_->stats().counts.poses_with_covariance == 1; }));
  ASSERT_TRUE(
      SendAndWait(good.OdomCommand(), [&] { return listener_->stats().counts.odometry == 1; }));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* what;
    bool odom;
    PublishedPose m;
    const char* code;
  };
  std::vector<Case> cases;
  const auto add = [&](const char* what, bool odom, const char* code, auto change) {
    PublishedPose m = good;
    m.sec = kSec + 1 + static_cast<std::int64_t>(cases.size());  // newer: it would be the newest
    change(m);
    cases.push_back({what, odom, m, code});
  };
  add("NaN position", false, "invalid_number", [&](PublishedPose& m) { m.p.x() = nan; });
  add("unnormalizable quaternion", false, "invalid_rotation",
      [](PublishedPose& m) { m.q = Eigen::Quaterniond(2, 0, 0, 0); });
  add("asymmetric pose covariance", false, "invalid_covariance",
      [](PublishedPose& m) { m.S(0, 1) += 0.5; });
  add("pose covariance not PSD", false, "invalid_covariance",  // eigenvalue -1 along e_3
      [](PublishedPose& m) {
        m.S = Matrix6::Identity();
        m.S(3, 3) = -1;
      });
  add("NaN in the pose covariance", false, "invalid_number",
      [&](PublishedPose& m) { m.S(2, 2) = nan; });
  add("odometry: NaN in the twist covariance", true, "invalid_number",
      [&](PublishedPose& m) { m.S_twist(2, 2) = nan; });
  add("odometry: twist covariance not PSD", true, "invalid_covariance", [](PublishedPose& m) {
    // symmetric, diagonal positive, indefinite: [[1, 2], [2, 1]] has eigenvalue -1
    m.S_twist = Matrix6::Identity();
    m.S_twist(0, 1) = m.S_twist(1, 0) = 2;
  });
  add("odometry: infinite twist", true, "invalid_number",
      [](PublishedPose& m) { m.w.z() = std::numeric_limits<double>::infinity(); });
  add("odometry: asymmetric pose covariance", true, "invalid_covariance",
      [](PublishedPose& m) { m.S(5, 0) -= 1e-3; });
  // Good numbers, refused by a graph rule (AddPose: nothing added).
  add("odometry: its child is its header frame", true, "self_edge",
      [](PublishedPose& m) { m.odom_child = "odom"; });
  add("odometry: an empty child frame", true, "invalid_name",
      [](PublishedPose& m) { m.odom_child = "-"; });
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::string before = State();
    ASSERT_TRUE(SendAndWait(c.odom ? c.m.OdomCommand() : c.m.PoseCommand(), [&] {
      return listener_->stats().counts.covariance_refused == i + 1;
    })) << c.what;
    bool found = false;
    for (const ros::FindingGroup& g : listener_->findings()) {
      if (g.last_stamp_ns != c.m.sec * 1'000'000'000) continue;
      found = true;
      EXPECT_EQ(g.code.name(), c.code) << c.what << ": " << g.message;
      EXPECT_EQ(g.topic, c.odom ? "/odom" : "/amcl_pose") << c.what;
      EXPECT_EQ(g.parent, c.odom ? "odom" : "map") << c.what;
      EXPECT_EQ(g.child, !c.odom                 ? "base_footprint"
                         : c.m.odom_child == "-" ? ""
                                                 : c.m.odom_child)
          << c.what;
    }
    EXPECT_TRUE(found) << c.what;
    EXPECT_EQ(State(), before) << c.what;
  }
  const ListenerStats s = listener_->stats();
  EXPECT_EQ(s.counts.poses_with_covariance, 1u);
  EXPECT_EQ(s.counts.odometry, 1u);
  EXPECT_EQ(s.poses_with_covariance + s.odometry, 2 + cases.size());
}

TEST(ListenerTest, LatencyFromTheBroadcastersWriteToTheListenersGraph) {
  constexpr std::uint32_t kDomain = 145;
  constexpr int kN = 500;
  SceneGraph<> g;
  std::mutex mutex;
  std::vector<std::int64_t> latencies;
  ListenerOptions options = On(kDomain);
  options.on_arrival = [&](const Arrival& a) {
    std::lock_guard<std::mutex> lock(mutex);
    if (a.topic == RosTopic::kTf) latencies.push_back(a.applied_ns - a.source_timestamp_ns);
  };
  auto listener = Listener::Create(g, options);
  ASSERT_TRUE(listener) << listener.error();
  Listener& l = **listener;
  Child node = Node(kDomain);
  ASSERT_TRUE(node.Command("latency_setup"));
  ASSERT_TRUE(node.Command("wait_subscribers 1"));  // raw writer and broadcaster, in sync
  ASSERT_TRUE(node.Command("latency " + std::to_string(kN) + " 200", 60s));
  ASSERT_TRUE(l.WaitUntil([&] { return l.stats().counts.applied == kN; }, 20s))
      << l.stats().counts.applied;
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(latencies.size(), static_cast<std::size_t>(kN));
  std::sort(latencies.begin(), latencies.end());
  const double median_us = latencies[kN / 2] / 1e3;
  const double p99_us = latencies[kN * 99 / 100] / 1e3;
  std::printf(
      "write -> graph latency over %d samples at 200 Hz: median %.1f us, p99 %.1f us, "
      "max %.1f us\n",
      kN, median_us, p99_us, latencies.back() / 1e3);
  RecordProperty("median_us", std::to_string(median_us));
  RecordProperty("p99_us", std::to_string(p99_us));
  EXPECT_GE(latencies.front(), 0);
  EXPECT_LT(median_us, 1e6);  // a loose bound: a shared CI machine; the numbers are the point
}

}  // namespace
}  // namespace semgraph::ros_dds
