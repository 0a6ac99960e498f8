// Test helpers for the bag readers: the fixtures written at test time by
// tests/ros/fixtures/write_ros1_bags.py (python3-rosbag, Python's sqlite3) and their
// expected.json, read with yaml-cpp (JSON is YAML); a record reader; a comparison of decoded
// messages with the JSON values.
#pragma once

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/messages.h"

namespace semgraph::ros::testing {

// Where the fixture script wrote the bags (a ctest fixture runs it first).
inline std::string FixtureDir() { return SEMGRAPH_ROS_BAG_FIXTURES; }
inline std::string FixturePath(const std::string& name) { return FixtureDir() + "/" + name; }

inline const YAML::Node& Expected() {
  static const YAML::Node node = YAML::LoadFile(FixturePath("expected.json"));
  return node;
}

inline std::string Hex(std::span<const std::uint8_t> bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (const std::uint8_t b : bytes) {
    s += kHex[b >> 4];
    s += kHex[b & 15];
  }
  return s;
}

inline std::vector<std::uint8_t> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void WriteFile(const std::string& path, std::span<const std::uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

// A scratch folder for one test, emptied first. Named after the running test too: ctest runs the
// tests of one binary in parallel processes, which must not share a folder.
inline std::string ScratchDir(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::path(SEMGRAPH_ROS_TEST_SCRATCH) /
                   ((test != nullptr ? std::string(test->name()) + "_" : std::string()) + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// A record copied out of the reader (views die at the next Next()).
struct OwnedRecord {
  std::string topic, type_name;
  MessageEncoding encoding = MessageEncoding::kOther;
  MessageKind kind = MessageKind::kOther;
  std::int64_t log_time_ns = 0;
  std::vector<std::uint8_t> data;
};

// Reads every record; on a reader error, returns it in `error`.
inline std::vector<OwnedRecord> ReadAll(BagReader& reader, std::optional<BagError>* error) {
  std::vector<OwnedRecord> out;
  BagRecord r;
  for (;;) {
    auto got = reader.Next(r);
    if (!got) {
      if (error != nullptr) *error = got.error();
      return out;
    }
    if (!*got) return out;
    out.push_back({std::string(r.topic), std::string(r.type_name), r.encoding, r.kind,
                   r.log_time_ns, std::vector<std::uint8_t>(r.data.begin(), r.data.end())});
  }
}

inline void ExpectHeader(const Header& h, const YAML::Node& v, bool ros1) {
  EXPECT_EQ(h.stamp.sec, v["stamp"][0].as<std::int64_t>());
  EXPECT_EQ(h.stamp.nanosec, v["stamp"][1].as<std::uint32_t>());
  EXPECT_EQ(h.frame_id, v["frame_id"].as<std::string>());
  if (ros1) {
    EXPECT_EQ(h.seq, v["seq"].as<std::uint32_t>());
  }
}

inline std::vector<double> Doubles(const YAML::Node& v) { return v.as<std::vector<double>>(); }

// Decodes `data` (ROS 1 or CDR, by `ros1`) as the JSON's kind and compares every value exactly
// (the script writes doubles with Python's round-trip repr).
inline void ExpectDecodesTo(std::span<const std::uint8_t> data, const YAML::Node& want, bool ros1) {
  const std::string kind = want["kind"].as<std::string>();
  const YAML::Node& v = want["value"];
  if (kind == "tf") {
    TFMessage msg;
    auto ok = ros1 ? DecodeRos1(data, msg) : DecodeCdr(data, msg);
    ASSERT_TRUE(ok) << Describe(ok.error());
    ASSERT_EQ(msg.transforms.size(), v["transforms"].size());
    for (std::size_t i = 0; i < msg.transforms.size(); ++i) {
      const TransformStamped& t = msg.transforms[i];
      const YAML::Node& w = v["transforms"][i];
      ExpectHeader(t.header, w, ros1);
      EXPECT_EQ(t.child_frame_id, w["child_frame_id"].as<std::string>());
      const Vector3& p = t.transform.translation;
      const Quaternion& q = t.transform.rotation;
      EXPECT_EQ((std::vector<double>{p.x, p.y, p.z}), Doubles(w["translation"]));
      EXPECT_EQ((std::vector<double>{q.x, q.y, q.z, q.w}), Doubles(w["rotation"]));
    }
  } else if (kind == "joint_state") {
    JointState msg;
    auto ok = ros1 ? DecodeRos1(data, msg) : DecodeCdr(data, msg);
    ASSERT_TRUE(ok) << Describe(ok.error());
    ExpectHeader(msg.header, v, ros1);
    EXPECT_EQ(msg.name, v["name"].as<std::vector<std::string>>());
    EXPECT_EQ(msg.position, Doubles(v["position"]));
    EXPECT_EQ(msg.velocity, Doubles(v["velocity"]));
    EXPECT_EQ(msg.effort, Doubles(v["effort"]));
  } else {
    ASSERT_EQ(kind, "string");
    String msg;
    auto ok = ros1 ? DecodeRos1(data, msg) : DecodeCdr(data, msg);
    ASSERT_TRUE(ok) << Describe(ok.error());
    EXPECT_EQ(msg.data, v["data"].as<std::string>());
  }
}

// Compares a bag's records with expected.json's messages of `bag`: order, topic, type,
// encoding, kind, log time, bytes and decoded values.
inline void ExpectBagMatches(const std::vector<OwnedRecord>& got, const std::string& bag,
                             MessageEncoding encoding) {
  const YAML::Node want = Expected()["bags"][bag]["messages"];
  ASSERT_TRUE(want.IsSequence()) << bag;
  ASSERT_EQ(got.size(), want.size()) << bag;
  for (std::size_t i = 0; i < got.size(); ++i) {
    SCOPED_TRACE(bag + " record " + std::to_string(i));
    const YAML::Node& w = want[i];
    EXPECT_EQ(got[i].topic, w["topic"].as<std::string>());
    EXPECT_EQ(got[i].type_name, w["type"].as<std::string>());
    EXPECT_EQ(got[i].encoding, encoding);
    const std::string kind = w["kind"].as<std::string>();
    EXPECT_EQ(got[i].kind, kind == "tf"            ? MessageKind::kTfMessage
                           : kind == "joint_state" ? MessageKind::kJointState
                                                   : MessageKind::kString);
    EXPECT_EQ(got[i].log_time_ns, w["log_time"].as<std::int64_t>());
    EXPECT_EQ(Hex(got[i].data), w["data"].as<std::string>());
    ExpectDecodesTo(got[i].data, w, encoding == MessageEncoding::kRos1);
  }
}

}  // namespace semgraph::ros::testing
