#include "fixture_data.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace semgraph::ros::testing {

std::string FixturesDir() {
  if (const char* env = std::getenv("SEMGRAPH_ROS_FIXTURES")) return env;
  return SEMGRAPH_ROS_FIXTURES;
}

bool HaveFixtures() { return std::filesystem::exists(FixturesDir() + "/expected.json"); }

const YAML::Node& Expected() {
  static const YAML::Node node = YAML::LoadFile(FixturesDir() + "/expected.json");
  return node;
}

std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << path;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string TempPath(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("semgraph_ros_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

namespace {
Time TimeOf(const YAML::Node& v) {
  return Time{v["sec"].as<std::int64_t>(), v["nanosec"].as<std::uint32_t>()};
}
Header HeaderOf(const YAML::Node& v, bool ros1) {
  Header h;
  h.seq = ros1 ? v["seq"].as<std::uint32_t>() : 0;
  h.stamp = TimeOf(v["stamp"]);
  h.frame_id = v["frame_id"].as<std::string>();
  return h;
}
Vector3 Vector3Of(const YAML::Node& v) {
  return Vector3{v["x"].as<double>(), v["y"].as<double>(), v["z"].as<double>()};
}
Quaternion QuaternionOf(const YAML::Node& v) {
  return Quaternion{v["x"].as<double>(), v["y"].as<double>(), v["z"].as<double>(),
                    v["w"].as<double>()};
}
Transform TransformOf(const YAML::Node& v) {
  return Transform{Vector3Of(v["translation"]), QuaternionOf(v["rotation"])};
}
TransformStamped TransformStampedOf(const YAML::Node& v, bool ros1) {
  return TransformStamped{HeaderOf(v["header"], ros1), v["child_frame_id"].as<std::string>(),
                          TransformOf(v["transform"])};
}
std::vector<double> Doubles(const YAML::Node& v) {
  std::vector<double> out;
  for (const auto& x : v) out.push_back(x.as<double>());
  return out;
}
Point PointOf(const YAML::Node& v) {
  return Point{v["x"].as<double>(), v["y"].as<double>(), v["z"].as<double>()};
}
Pose PoseOf(const YAML::Node& v) {
  return Pose{PointOf(v["position"]), QuaternionOf(v["orientation"])};
}
Twist TwistOf(const YAML::Node& v) {
  return Twist{Vector3Of(v["linear"]), Vector3Of(v["angular"])};
}
Covariance36 CovarianceOf(const YAML::Node& v) {
  Covariance36 out{};
  EXPECT_EQ(v.size(), out.size());
  for (std::size_t i = 0; i < out.size() && i < v.size(); ++i) out[i] = v[i].as<double>();
  return out;
}
PoseWithCovariance PoseWithCovarianceOf(const YAML::Node& v) {
  return PoseWithCovariance{PoseOf(v["pose"]), CovarianceOf(v["covariance"])};
}
TwistWithCovariance TwistWithCovarianceOf(const YAML::Node& v) {
  return TwistWithCovariance{TwistOf(v["twist"]), CovarianceOf(v["covariance"])};
}
}  // namespace

template <>
Time FromJson<Time>(const YAML::Node& v, bool) {
  return TimeOf(v);
}
template <>
Header FromJson<Header>(const YAML::Node& v, bool ros1) {
  return HeaderOf(v, ros1);
}
template <>
Vector3 FromJson<Vector3>(const YAML::Node& v, bool) {
  return Vector3Of(v);
}
template <>
Quaternion FromJson<Quaternion>(const YAML::Node& v, bool) {
  return QuaternionOf(v);
}
template <>
Transform FromJson<Transform>(const YAML::Node& v, bool) {
  return TransformOf(v);
}
template <>
TransformStamped FromJson<TransformStamped>(const YAML::Node& v, bool ros1) {
  return TransformStampedOf(v, ros1);
}
template <>
TFMessage FromJson<TFMessage>(const YAML::Node& v, bool ros1) {
  TFMessage m;
  for (const auto& t : v["transforms"]) m.transforms.push_back(TransformStampedOf(t, ros1));
  return m;
}
template <>
JointState FromJson<JointState>(const YAML::Node& v, bool ros1) {
  JointState m;
  m.header = HeaderOf(v["header"], ros1);
  for (const auto& n : v["name"]) m.name.push_back(n.as<std::string>());
  m.position = Doubles(v["position"]);
  m.velocity = Doubles(v["velocity"]);
  m.effort = Doubles(v["effort"]);
  return m;
}
template <>
String FromJson<String>(const YAML::Node& v, bool) {
  return String{v["data"].as<std::string>()};
}
template <>
Point FromJson<Point>(const YAML::Node& v, bool) {
  return PointOf(v);
}
template <>
Pose FromJson<Pose>(const YAML::Node& v, bool) {
  return PoseOf(v);
}
template <>
Twist FromJson<Twist>(const YAML::Node& v, bool) {
  return TwistOf(v);
}
template <>
PoseWithCovariance FromJson<PoseWithCovariance>(const YAML::Node& v, bool) {
  return PoseWithCovarianceOf(v);
}
template <>
PoseWithCovarianceStamped FromJson<PoseWithCovarianceStamped>(const YAML::Node& v, bool ros1) {
  return PoseWithCovarianceStamped{HeaderOf(v["header"], ros1), PoseWithCovarianceOf(v["pose"])};
}
template <>
TwistWithCovariance FromJson<TwistWithCovariance>(const YAML::Node& v, bool) {
  return TwistWithCovarianceOf(v);
}
template <>
Odometry FromJson<Odometry>(const YAML::Node& v, bool ros1) {
  return Odometry{HeaderOf(v["header"], ros1), v["child_frame_id"].as<std::string>(),
                  PoseWithCovarianceOf(v["pose"]), TwistWithCovarianceOf(v["twist"])};
}

std::uint64_t LoadU64(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | b.at(at + static_cast<std::size_t>(i));
  return v;
}
std::uint32_t LoadU32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return std::uint32_t{b.at(at)} | std::uint32_t{b.at(at + 1)} << 8 |
         std::uint32_t{b.at(at + 2)} << 16 | std::uint32_t{b.at(at + 3)} << 24;
}
void StoreU64(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b.at(at + static_cast<std::size_t>(i)) = (v >> (8 * i)) & 0xFFU;
}
void StoreU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.at(at + static_cast<std::size_t>(i)) = (v >> (8 * i)) & 0xFFU;
}

std::vector<RecordAt> McapRecords(const std::vector<std::uint8_t>& file) {
  std::vector<RecordAt> out;
  std::size_t pos = 8;
  while (pos + 9 <= file.size() - 8) {
    const std::uint64_t len = LoadU64(file, pos + 1);
    out.push_back(RecordAt{pos, file[pos], len});
    pos += 9 + len;
  }
  return out;
}

RecordAt FirstRecord(const std::vector<std::uint8_t>& file, std::uint8_t opcode) {
  for (const auto& r : McapRecords(file)) {
    if (r.opcode == opcode) return r;
  }
  ADD_FAILURE() << "no record with opcode " << int{opcode};
  return RecordAt{0, 0, 0};
}

void ResealDataCrc(std::vector<std::uint8_t>& file, const RecordAt& end) {
  const uLong crc = crc32(0L, file.data(), static_cast<uInt>(end.offset));
  StoreU32(file, end.offset + 9, static_cast<std::uint32_t>(crc));
}

}  // namespace semgraph::ros::testing
