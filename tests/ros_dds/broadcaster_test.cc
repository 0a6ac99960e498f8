// Broadcaster (semgraph/ros_dds/broadcaster.h): the bytes Cyclone DDS puts on the wire for its
// rt/tf and rt/tf_static samples, taken raw (dds_takecdr), equal Foxglove's serialization of
// the same messages (tests/ros/fixtures/write_fixtures.mjs: broadcast_tf, broadcast_tf_static);
// what each Broadcast() sends (only what changed); WaitForSubscribers (a timeout without
// readers; with one, a sample without data, then the broadcast reaches it); BodiesOf.
#include "semgraph/ros_dds/broadcaster.h"

#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <thread>
#include <vector>

#include "dds_isolation.h"
#include "ros2_messages.h"

namespace semgraph::ros_dds {
namespace {

using core::PoseSpec;
using core::SceneGraph;
using core::Stamp;
using Bytes = std::vector<std::uint8_t>;

constexpr std::int64_t kStaticClock = 1'700'000'000'000'000'042;

// The graph whose messages write_fixtures.mjs writes as broadcast_tf / broadcast_tf_static.
void BuildFixtureGraph(SceneGraph<>& g) {
  for (const char* b : {"world", "base", "arm", "table"}) ASSERT_TRUE(g.AddBody(b));
  ASSERT_TRUE(g.AddFrame("world", "world"));
  ASSERT_TRUE(g.AddFrame("base_link", "base"));
  ASSERT_TRUE(g.AddFrame("arm_link", "arm"));
  ASSERT_TRUE(g.AddFrame("camera_link", "base"));
  ASSERT_TRUE(g.AddFrame("table", "table"));
  const Eigen::Quaterniond id = Eigen::Quaterniond::Identity();
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("base_link").RelativeTo("world"), id,
                        Eigen::Vector3d(0.1, 0.2, 0.3), Stamp::Nanoseconds(1733300001000000500)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("base_link").RelativeTo("world"),
                        Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5), Eigen::Vector3d(0.25, -0.5, 1.5),
                        Stamp::Nanoseconds(1733300002000000000)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("arm_link").RelativeTo("base_link"), id,
                        Eigen::Vector3d(0, 0, 0.5), Stamp::Nanoseconds(1733300001999999999)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("camera_link").RelativeTo("base_link"),
                        Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5), Eigen::Vector3d(0.05, 0, 0.125)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("table").RelativeTo("world"), id, Eigen::Vector3d(2, 0, 0)));
}

Bytes ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A reader that takes samples as serialized data (Cyclone's serdata), with the QoS of a
// tf2_ros listener written out here.
struct RawReader {
  RawReader(dds_entity_t participant, const char* topic, bool durable) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_durability(qos, durable ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 100);
    const dds_entity_t t =
        dds_create_topic(participant, &tf2_msgs_msg_dds__TFMessage__desc, topic, qos, nullptr);
    reader = dds_create_reader(participant, t, qos, nullptr);
    dds_delete_qos(qos);
  }
  // The next sample's bytes as serialized (encapsulation header included); empty on timeout.
  Bytes Take(std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      ddsi_serdata* sd[1] = {nullptr};
      dds_sample_info_t info[1];
      if (dds_takecdr(reader, sd, 1, info, DDS_ANY_STATE) == 1) {
        Bytes bytes(ddsi_serdata_size(sd[0]));
        ddsi_serdata_to_ser(sd[0], 0, bytes.size(), bytes.data());
        ddsi_serdata_unref(sd[0]);
        if (info[0].valid_data) return bytes;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return {};
  }
  dds_entity_t reader = 0;
};

TEST(BroadcasterTest, SamplesOnTheWireAreFoxglovesSerializationByteForByte) {
  const std::string dir = SEMGRAPH_ROS_FIXTURES;
  const Bytes expected_tf = ReadFile(dir + "/ros_dds/broadcast_tf.bin");
  const Bytes expected_static = ReadFile(dir + "/ros_dds/broadcast_tf_static.bin");
  if (expected_tf.empty() || expected_static.empty()) {
    GTEST_SKIP() << "no Foxglove fixtures in " << dir << " (ctest's ros.fixtures writes them)";
  }
  constexpr std::uint32_t kDomain = 146;
  SceneGraph<> g;
  BuildFixtureGraph(g);
  auto b = Broadcaster::Create(g, {kDomain, [] { return kStaticClock; }});
  ASSERT_TRUE(b) << b.error();
  const dds_entity_t participant = dds_create_participant(kDomain, nullptr, nullptr);
  ASSERT_GT(participant, 0);
  RawReader tf(participant, "rt/tf", false), tf_static(participant, "rt/tf_static", true);
  ASSERT_GT(tf.reader, 0);
  ASSERT_GT(tf_static.reader, 0);
  ASSERT_TRUE((*b)->WaitForSubscribers(1, std::chrono::seconds(10)));  // Take skips its unregister
  ASSERT_EQ((*b)->subscribers(), 1u);
  const auto sent = (*b)->Broadcast();
  ASSERT_TRUE(sent) << sent.error();
  EXPECT_EQ(sent->tf_transforms, 3u);
  EXPECT_EQ(sent->static_transforms, 2u);
  const Bytes got_tf = tf.Take(std::chrono::seconds(10));
  const Bytes got_static = tf_static.Take(std::chrono::seconds(10));
  ASSERT_FALSE(got_tf.empty());
  ASSERT_FALSE(got_static.empty());
  EXPECT_EQ(got_tf, expected_tf);
  EXPECT_EQ(got_static, expected_static);
  EXPECT_EQ(Bytes(got_tf.begin(), got_tf.begin() + 4), (Bytes{0, 1, 0, 0}));  // XCDR1, LE
  dds_delete(participant);
}

TEST(BroadcasterTest, WaitForSubscribersWaitsForReadersInSyncAndSendsNoData) {
  constexpr std::uint32_t kDomain = 151;
  SceneGraph<> g;
  BuildFixtureGraph(g);
  auto b = Broadcaster::Create(g, {kDomain, {}});
  ASSERT_TRUE(b) << b.error();
  // No reader: a timeout, with the counts.
  const auto t0 = std::chrono::steady_clock::now();
  const auto none = (*b)->WaitForSubscribers(1, std::chrono::milliseconds(150));
  ASSERT_FALSE(none);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(150));
  EXPECT_EQ(none.error(),
            "0 subscriber(s) matched on rt/tf of 1 expected, or not all in sync, within 150 ms");
  const dds_entity_t participant = dds_create_participant(kDomain, nullptr, nullptr);
  ASSERT_GT(participant, 0);
  RawReader tf(participant, "rt/tf", false);
  ASSERT_GT(tf.reader, 0);
  ASSERT_TRUE((*b)->WaitForSubscribers(1, std::chrono::seconds(10)));
  EXPECT_EQ((*b)->subscribers(), 1u);
  // What it sent: one unregister, no data (a tf reader skips it).
  ddsi_serdata* sd[1] = {nullptr};
  dds_sample_info_t info[1];
  ASSERT_EQ(dds_takecdr(tf.reader, sd, 1, info, DDS_ANY_STATE), 1);
  ddsi_serdata_unref(sd[0]);
  EXPECT_FALSE(info[0].valid_data);
  EXPECT_NE(info[0].instance_state, DDS_IST_ALIVE);
  EXPECT_EQ(dds_takecdr(tf.reader, sd, 1, info, DDS_ANY_STATE), 0);
  // The next broadcast's samples reach the reader, and the instance is alive again.
  ASSERT_TRUE((*b)->Broadcast());
  EXPECT_FALSE(tf.Take(std::chrono::seconds(10)).empty());
  dds_delete(participant);
}

TEST(BroadcasterTest, EachBroadcastSendsWhatChanged) {
  SceneGraph<> g;
  BuildFixtureGraph(g);
  std::int64_t clock = kStaticClock;
  auto b = Broadcaster::Create(g, {147, [&] { return clock; }});
  ASSERT_TRUE(b) << b.error();
  Broadcaster& br = **b;

  ros::TFMessage tf, tf_static;
  br.Pending(tf, tf_static);
  ASSERT_EQ(tf.transforms.size(), 3u);
  EXPECT_EQ(tf.transforms[1].header.frame_id, "world");  // parent: the edge's tail
  EXPECT_EQ(tf.transforms[1].child_frame_id, "base_link");
  EXPECT_EQ(tf.transforms[1].header.stamp, (ros::Time{1733300002, 0}));
  EXPECT_EQ(tf.transforms[1].transform.rotation, (ros::Quaternion{0.5, -0.5, 0.5, 0.5}));
  EXPECT_EQ(tf.transforms[2].header.stamp, (ros::Time{1733300001, 999999999}));
  ASSERT_EQ(tf_static.transforms.size(), 2u);
  EXPECT_EQ(tf_static.transforms[0].header.stamp, (ros::Time{1700000000, 42}));

  auto sent = br.Broadcast();
  ASSERT_TRUE(sent);
  EXPECT_EQ(sent->tf_transforms, 3u);
  EXPECT_EQ(sent->static_transforms, 2u);
  sent = br.Broadcast();  // nothing new
  ASSERT_TRUE(sent);
  EXPECT_EQ(sent->tf_transforms, 0u);
  EXPECT_EQ(sent->static_transforms, 0u);

  // One new sample: only it; a changed timeless edge: the whole static message again.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("arm_link").RelativeTo("base_link"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0.75),
                        Stamp::Nanoseconds(1733300003000000000)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("table").RelativeTo("world"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(3, 0, 0)));
  clock += 1'000'000'000;
  br.Pending(tf, tf_static);
  ASSERT_EQ(tf.transforms.size(), 1u);
  EXPECT_EQ(tf.transforms[0].child_frame_id, "arm_link");
  EXPECT_EQ(tf.transforms[0].transform.translation, (ros::Vector3{0, 0, 0.75}));
  sent = br.Broadcast();
  ASSERT_TRUE(sent);
  EXPECT_EQ(sent->tf_transforms, 1u);
  EXPECT_EQ(sent->static_transforms, 2u);
  ASSERT_EQ(br.last_static().transforms.size(), 2u);
  EXPECT_EQ(br.last_static().transforms[1].transform.translation, (ros::Vector3{3, 0, 0}));
  EXPECT_EQ(br.last_static().transforms[1].header.stamp, (ros::Time{1700000001, 42}));

  // A stamp outside ROS 2's int32 seconds is an error naming the edge; nothing is marked sent.
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("arm_link").RelativeTo("base_link"),
                        Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1),
                        Stamp::Nanoseconds(std::int64_t{1} << 62)));
  sent = br.Broadcast();
  ASSERT_FALSE(sent);
  EXPECT_NE(sent.error().find("{arm_link} wrt {base_link}"), std::string::npos) << sent.error();
  br.Pending(tf, tf_static);
  EXPECT_EQ(tf.transforms.size(), 1u);
}

TEST(BroadcasterTest, BodiesOfListsEveryFrameOnItsBody) {
  SceneGraph<> g;
  BuildFixtureGraph(g);
  const ros::BodiesMap map = BodiesOf(g);
  EXPECT_EQ(map.size(), 4u);
  EXPECT_EQ(map.at("base"), (std::vector<std::string>{"base_link", "camera_link"}));
  EXPECT_EQ(map.at("world"), (std::vector<std::string>{"world"}));
}

}  // namespace
}  // namespace semgraph::ros_dds
