// The other process of the live ROS 2 tests: reads commands from stdin, one a line, and
// answers "ok N" (the command's number) or "error N message" on stdout.
//   scene                 the live scene (live_scene.h) into a graph, Broadcaster::Broadcast
//   steps A B             samples A..B of the scene (AddStep; 0: BuildScene's), one Broadcast
//                         each, 2 ms apart
//   rewind                Broadcaster::Rewind, then Broadcast (every stored sample again)
//   wait_subscribers N    until N readers matched each rt/tf writer here (the raw one, and the
//                         broadcasters made so far) and are in sync with it, so that every
//                         sample written afterwards reaches them (SyncWithReaders,
//                         Broadcaster::WaitForSubscribers: event-driven, no sleep)
//   wait_acks             until every matched reader acknowledged everything written so far
//   latency_setup         a Broadcaster of a graph of its own (for `latency`)
//   latency N HZ          N stamped samples world -> base at HZ, each broadcast at once (stamp:
//                         now)
//   tf P C SEC NSEC X Y Z QX QY QZ QW [P C ...]   one TFMessage on rt/tf, raw
//   static P C X Y Z QX QY QZ QW   sets the static transform P -> C and writes every static
//                         transform set so far in one TFMessage on rt/tf_static, raw
//   joints SEC NSEC NAME POS [NAME POS ...]   one JointState on rt/joint_states, raw
//   urdf FILE             the file's text as a String on rt/robot_description, raw
//   burst N SEC           one TFMessage of N transforms world -> f<i> on rt/tf, raw
//   wait_match KIND TOPIC N   until the writer of KIND (pose | odom) on TOPIC (made on first
//                         use, ROS 2's default QoS: reliable, volatile, keep last 10) matched N
//                         readers
//   pose TOPIC FRAME SEC NSEC X Y Z QX QY QZ QW C0 .. C35   one PoseWithCovarianceStamped, raw
//                         (frame names: "-" is the empty name)
//   odom TOPIC FRAME CHILD SEC NSEC X Y Z QX QY QZ QW C0 .. C35 VX VY VZ WX WY WZ C0 .. C35
//                         one Odometry, raw
//   sleep MS              waits MS milliseconds
// "Raw" messages are built here from the idlc-generated structs with this file's own QoS (the
// values of docs/ros.md), not through semgraph::ros_dds: an independent writer of the wire.
// Usage: ros_dds_test_node DOMAIN
#include <dds/dds.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "live_scene.h"
#include "ros2_messages.h"
#include "semgraph/ros_dds/broadcaster.h"
#include "semgraph_dds_shared/entity.h"

namespace {

using semgraph::core::SceneGraph;
using semgraph::ros_dds::Broadcaster;

struct Raw {
  dds_entity_t participant = 0, tf = 0, tf_static = 0, joints = 0, description = 0;
};

dds_entity_t Writer(dds_entity_t p, const dds_topic_descriptor_t* desc, const char* name,
                    bool durable, int depth) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(qos, durable ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  const dds_entity_t t = dds_create_topic(p, desc, name, qos, nullptr);
  const dds_entity_t w = dds_create_writer(p, t, qos, nullptr);
  dds_delete_qos(qos);
  return w;
}

struct TfRow {
  std::string parent, child;
  std::int32_t sec = 0;
  std::uint32_t nsec = 0;
  double v[7] = {0, 0, 0, 0, 0, 0, 1};
};

dds_return_t WriteTf(dds_entity_t writer, const std::vector<TfRow>& rows) {
  std::vector<geometry_msgs_msg_dds__TransformStamped_> w(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    w[i].header_.stamp_.sec_ = rows[i].sec;
    w[i].header_.stamp_.nanosec_ = rows[i].nsec;
    w[i].header_.frame_id_ = const_cast<char*>(rows[i].parent.c_str());
    w[i].child_frame_id_ = const_cast<char*>(rows[i].child.c_str());
    const double* v = rows[i].v;
    w[i].transform_.translation_ = {v[0], v[1], v[2]};
    w[i].transform_.rotation_ = {v[3], v[4], v[5], v[6]};
  }
  tf2_msgs_msg_dds__TFMessage_ m{};
  m.transforms_._length = m.transforms_._maximum = static_cast<std::uint32_t>(w.size());
  m.transforms_._buffer = w.data();
  return dds_write(writer, &m);
}

// Numbers of a command ("nan", "inf" too); false when fewer than out.size().
bool ReadNumbers(std::istringstream& in, double* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    std::string t;
    if (!(in >> t)) return false;
    out[i] = std::strtod(t.c_str(), nullptr);
  }
  return true;
}

// A frame name token: "-" is the empty name.
std::string Name(const std::string& token) { return token == "-" ? std::string() : token; }

bool ReadRow(std::istringstream& in, TfRow& row, bool stamped) {
  std::string p, c;
  if (!(in >> p >> c)) return false;
  row.parent = Name(p);
  row.child = Name(c);
  if (stamped) {
    long long sec = 0;
    if (!(in >> sec >> row.nsec)) return false;
    row.sec = static_cast<std::int32_t>(sec);
  }
  for (double& x : row.v) {
    std::string t;
    if (!(in >> t)) return false;
    x = std::strtod(t.c_str(), nullptr);  // "nan", "inf" too
  }
  return true;
}

class Node {
 public:
  explicit Node(std::uint32_t domain) : domain_(domain) {
    raw_.participant = dds_create_participant(domain, nullptr, nullptr);
    raw_.tf = Writer(raw_.participant, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", false, 100);
    raw_.tf_static =
        Writer(raw_.participant, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf_static", true, 1);
    raw_.joints = Writer(raw_.participant, &sensor_msgs_msg_dds__JointState__desc,
                         "rt/joint_states", false, 10);
    raw_.description =
        Writer(raw_.participant, &std_msgs_msg_dds__String__desc, "rt/robot_description", true, 1);
  }
  ~Node() { dds_delete(raw_.participant); }

  // The error text, empty when done.
  std::string Run(const std::string& line) {
    std::istringstream in(line);
    std::string cmd;
    in >> cmd;
    if (cmd == "scene") return Scene();
    if (cmd == "steps") {
      int a = 0, b = 0;
      in >> a >> b;
      for (int k = a; k <= b; ++k) {
        // Sample 0 is BuildScene's: step 0 only broadcasts.
        if (k > 0 && !semgraph::ros_dds_test::AddStep(scene_, k)) {
          return "step " + std::to_string(k);
        }
        if (auto sent = scene_broadcaster_->Broadcast(); !sent) return sent.error();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      return {};
    }
    if (cmd == "rewind") {  // every stored sample of the scene again
      if (!scene_broadcaster_) return "scene first";
      scene_broadcaster_->Rewind();
      auto sent = scene_broadcaster_->Broadcast();
      return sent ? std::string() : sent.error();
    }
    if (cmd == "wait_subscribers") {
      std::uint32_t n = 0;
      in >> n;
      const tf2_msgs_msg_dds__TFMessage_ key{};  // keyless: any sample names the one instance
      if (semgraph::dds_shared::SyncWithReaders(raw_.tf, n, DDS_SECS(20), &key) != 0) {
        return "raw rt/tf: no " + std::to_string(n) + " subscribers in sync";
      }
      for (Broadcaster* b : {scene_broadcaster_.get(), latency_broadcaster_.get()}) {
        if (b == nullptr) continue;
        if (auto synced = b->WaitForSubscribers(n, std::chrono::seconds(20)); !synced) {
          return synced.error();
        }
      }
      return {};
    }
    if (cmd == "wait_acks") {
      for (dds_entity_t w : {raw_.tf, raw_.tf_static, raw_.joints, raw_.description}) {
        if (dds_wait_for_acks(w, DDS_SECS(20)) != DDS_RETCODE_OK) return "no acknowledgement";
      }
      return {};
    }
    if (cmd == "sleep") {
      int ms = 0;
      in >> ms;
      std::this_thread::sleep_for(std::chrono::milliseconds(ms));
      return {};
    }
    if (cmd == "latency_setup") {
      auto b = Broadcaster::Create(latency_, {domain_, {}});
      if (!b) return b.error();
      latency_broadcaster_ = std::move(*b);
      return {};
    }
    if (cmd == "latency") return Latency(in);
    if (cmd == "tf") {
      std::vector<TfRow> rows;
      for (TfRow row; ReadRow(in, row, true);) rows.push_back(row);
      return dds_write_ok(WriteTf(raw_.tf, rows));
    }
    if (cmd == "static") {
      TfRow row;
      if (!ReadRow(in, row, false)) return "bad static";
      statics_[{row.parent, row.child}] = row;
      std::vector<TfRow> rows;
      for (const auto& [key, r] : statics_) rows.push_back(r);
      return dds_write_ok(WriteTf(raw_.tf_static, rows));
    }
    if (cmd == "joints") return Joints(in);
    if (cmd == "wait_match") {
      std::string kind, topic;
      std::uint32_t n = 0;
      in >> kind >> topic >> n;
      const dds_entity_t w = UserWriter(kind, topic);
      if (w < 0) return "no writer for " + kind + " " + topic;
      std::uint32_t matched = 0;
      if (semgraph::dds_shared::WaitForMatches(w, n, dds_time() + DDS_SECS(20), &matched) != 0) {
        return topic + ": " + std::to_string(matched) + " readers matched, not " +
               std::to_string(n);
      }
      return {};
    }
    if (cmd == "pose" || cmd == "odom") return PoseOrOdometry(cmd, in);
    if (cmd == "urdf") {
      std::string path;
      in >> path;
      std::ifstream f(path);
      std::stringstream text;
      text << f.rdbuf();
      const std::string xml = text.str();
      std_msgs_msg_dds__String_ s{const_cast<char*>(xml.c_str())};
      return dds_write_ok(dds_write(raw_.description, &s));
    }
    if (cmd == "burst") {
      int n = 0;
      long long sec = 0;
      in >> n >> sec;
      std::vector<TfRow> rows(n);
      for (int i = 0; i < n; ++i) {
        rows[i].parent = "world";
        rows[i].child = "f" + std::to_string(i);
        rows[i].sec = static_cast<std::int32_t>(sec);
        rows[i].nsec = static_cast<std::uint32_t>(i);
        rows[i].v[0] = 0.001 * i;
        rows[i].v[1] = -0.002 * i;
        rows[i].v[2] = 0.5;
      }
      return dds_write_ok(WriteTf(raw_.tf, rows));
    }
    return "unknown command " + cmd;
  }

 private:
  static std::string dds_write_ok(dds_return_t rc) {
    return rc == DDS_RETCODE_OK ? std::string() : std::string("dds_write: ") + dds_strretcode(rc);
  }

  std::string Scene() {
    if (!semgraph::ros_dds_test::BuildScene(scene_)) return "scene";
    auto b = Broadcaster::Create(scene_, {domain_, {}});
    if (!b) return b.error();
    scene_broadcaster_ = std::move(*b);
    auto sent = scene_broadcaster_->Broadcast();
    return sent ? std::string() : sent.error();
  }

  std::string Joints(std::istringstream& in) {
    long long sec = 0;
    std::uint32_t nsec = 0;
    in >> sec >> nsec;
    std::vector<std::string> names;
    std::vector<double> positions;
    for (std::string n, v; in >> n >> v;) {
      names.push_back(n);
      positions.push_back(std::strtod(v.c_str(), nullptr));
    }
    std::vector<char*> name_ptrs;
    for (std::string& n : names) name_ptrs.push_back(n.data());
    sensor_msgs_msg_dds__JointState_ m{};
    m.header_.stamp_.sec_ = static_cast<std::int32_t>(sec);
    m.header_.stamp_.nanosec_ = nsec;
    m.header_.frame_id_ = const_cast<char*>("");
    m.name_._length = m.name_._maximum = static_cast<std::uint32_t>(names.size());
    m.name_._buffer = name_ptrs.data();
    m.position_._length = m.position_._maximum = static_cast<std::uint32_t>(positions.size());
    m.position_._buffer = positions.data();
    return dds_write_ok(dds_write(raw_.joints, &m));
  }

  // The raw writer of a pose (PoseWithCovarianceStamped) or odom (Odometry) topic.
  dds_entity_t UserWriter(const std::string& kind, const std::string& topic) {
    const auto key = std::make_pair(kind, topic);
    if (auto it = user_writers_.find(key); it != user_writers_.end()) return it->second;
    const dds_topic_descriptor_t* desc =
        kind == "pose"   ? &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc
        : kind == "odom" ? &nav_msgs_msg_dds__Odometry__desc
                         : nullptr;
    if (desc == nullptr || topic.empty() || topic[0] != '/') return -1;
    const dds_entity_t w = Writer(raw_.participant, desc, ("rt" + topic).c_str(), false, 10);
    if (w >= 0) user_writers_[key] = w;
    return w;
  }

  std::string PoseOrOdometry(const std::string& kind, std::istringstream& in) {
    std::string topic, frame, child;
    long long sec = 0;
    std::uint32_t nsec = 0;
    in >> topic >> frame;
    if (kind == "odom") in >> child;
    in >> sec >> nsec;
    frame = Name(frame);
    child = Name(child);
    double pose[7 + 36], twist[6 + 36];
    if (!ReadNumbers(in, pose, 7 + 36)) return "bad " + kind;
    if (kind == "odom" && !ReadNumbers(in, twist, 6 + 36)) return "bad odom twist";
    const dds_entity_t w = UserWriter(kind, topic);
    if (w < 0) return "no writer for " + kind + " " + topic;
    std_msgs_msg_dds__Header_ header{};
    header.stamp_.sec_ = static_cast<std::int32_t>(sec);
    header.stamp_.nanosec_ = nsec;
    header.frame_id_ = frame.data();
    geometry_msgs_msg_dds__PoseWithCovariance_ p{};
    p.pose_.position_ = {pose[0], pose[1], pose[2]};
    p.pose_.orientation_ = {pose[3], pose[4], pose[5], pose[6]};
    std::copy(pose + 7, pose + 7 + 36, p.covariance_);
    if (kind == "pose") {
      geometry_msgs_msg_dds__PoseWithCovarianceStamped_ m{header, p};
      return dds_write_ok(dds_write(w, &m));
    }
    nav_msgs_msg_dds__Odometry_ m{};
    m.header_ = header;
    m.child_frame_id_ = child.data();
    m.pose_ = p;
    m.twist_.twist_.linear_ = {twist[0], twist[1], twist[2]};
    m.twist_.twist_.angular_ = {twist[3], twist[4], twist[5]};
    std::copy(twist + 6, twist + 6 + 36, m.twist_.covariance_);
    return dds_write_ok(dds_write(w, &m));
  }

  std::string Latency(std::istringstream& in) {
    int n = 0;
    double hz = 100;
    in >> n >> hz;
    if (!latency_broadcaster_) return "latency_setup first";
    Broadcaster& b = *latency_broadcaster_;
    using semgraph::core::PoseSpec;
    for (int i = 0; i < n; ++i) {
      const auto at = semgraph::core::Stamp::Nanoseconds(dds_time());
      const auto q = semgraph::ros_dds_test::AxisAngle(0.001 * i, 0, 0, 1);
      if (!latency_.AddPose(PoseSpec::Of("base", "base").RelativeTo("world", "world"), q,
                            Eigen::Vector3d(0.001 * i, 0, 0), at)) {
        return "latency sample";
      }
      if (auto sent = b.Broadcast(); !sent) return sent.error();
      std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(1e6 / hz)));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the last ones arrive
    return {};
  }

  std::uint32_t domain_;
  Raw raw_;
  std::map<std::pair<std::string, std::string>, TfRow> statics_;
  std::map<std::pair<std::string, std::string>, dds_entity_t> user_writers_;  // (kind, topic)
  SceneGraph<> scene_, latency_;
  std::unique_ptr<Broadcaster> scene_broadcaster_, latency_broadcaster_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: ros_dds_test_node DOMAIN\n");
    return 2;
  }
  Node node(static_cast<std::uint32_t>(std::strtoul(argv[1], nullptr, 10)));
  std::string line;
  for (int n = 1; std::getline(std::cin, line); ++n) {
    const std::string error = node.Run(line);
    if (error.empty()) {
      std::printf("ok %d\n", n);
    } else {
      std::printf("error %d %s\n", n, error.c_str());
    }
    std::fflush(stdout);
  }
  return 0;
}
