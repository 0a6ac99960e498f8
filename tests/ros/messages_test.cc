// The message codecs against Foxglove's serializations (tests/ros/fixtures): decoding their
// bytes gives the values they were written from, and our encoding of those values gives their
// bytes exactly. Then hostile bytes: every truncation, lengths and counts past the end, missing
// NULs, and hand-computed samples (big-endian CDR, alignment).
#include "semgraph/ros/messages.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>

#include "fixture_data.h"

namespace semgraph::ros {
namespace {

using testing::Expected;
using testing::FixturesDir;
using testing::FromJson;
using testing::HaveFixtures;
using testing::ReadBytes;
using Bytes = std::vector<std::uint8_t>;

#define SKIP_WITHOUT_FIXTURES()                      \
  if (!HaveFixtures())                               \
  GTEST_SKIP() << "no fixtures in " << FixturesDir() \
               << " (ctest ros.fixtures writes them; needs node)"

// What one test does with one sample, for every message type: checks on (bytes, json value).
struct SampleChecks {
  std::function<void(const Bytes&, const YAML::Node&)> cdr;
  std::function<void(const Bytes&, const YAML::Node&)> ros1;
  std::function<void(const Bytes&)> cdr_truncations;
  std::function<void(const Bytes&)> ros1_truncations;
};

template <class M>
void CheckCdr(const Bytes& bytes, const YAML::Node& value) {
  const M expected = FromJson<M>(value, false);
  M decoded;
  auto r = DecodeCdr(std::span<const std::uint8_t>(bytes), decoded);
  ASSERT_TRUE(r.has_value()) << Describe(r.error());
  EXPECT_EQ(decoded, expected);
  Bytes encoded;
  auto w = EncodeCdr(expected, encoded);
  ASSERT_TRUE(w.has_value()) << Describe(w.error());
  EXPECT_EQ(encoded, bytes) << "our CDR differs from Foxglove's";
}

template <class M>
void CheckRos1(const Bytes& bytes, const YAML::Node& value) {
  const M expected = FromJson<M>(value, true);
  M decoded;
  auto r = DecodeRos1(std::span<const std::uint8_t>(bytes), decoded);
  ASSERT_TRUE(r.has_value()) << Describe(r.error());
  EXPECT_EQ(decoded, expected);
  Bytes encoded;
  auto w = EncodeRos1(expected, encoded);
  ASSERT_TRUE(w.has_value()) << Describe(w.error());
  EXPECT_EQ(encoded, bytes) << "our ROS 1 serialization differs from Foxglove's";
}

// Every proper prefix of a sample is refused, with an offset inside the prefix.
template <class M, bool kCdr>
void CheckTruncations(const Bytes& bytes) {
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const Bytes prefix(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    M m;
    auto r = kCdr ? DecodeCdr(std::span<const std::uint8_t>(prefix), m)
                  : DecodeRos1(std::span<const std::uint8_t>(prefix), m);
    ASSERT_FALSE(r.has_value()) << "a prefix of " << n << " of " << bytes.size() << " bytes";
    EXPECT_LE(r.error().offset, n);
    EXPECT_FALSE(r.error().message.empty());
  }
}

template <class M>
SampleChecks ChecksOf() {
  return SampleChecks{CheckCdr<M>, CheckRos1<M>, CheckTruncations<M, true>,
                      CheckTruncations<M, false>};
}

const std::map<std::string, SampleChecks>& ChecksByType() {
  static const std::map<std::string, SampleChecks> checks = {
      {"builtin_interfaces/Time", ChecksOf<Time>()},
      {"std_msgs/Header", ChecksOf<Header>()},
      {"geometry_msgs/Vector3", ChecksOf<Vector3>()},
      {"geometry_msgs/Quaternion", ChecksOf<Quaternion>()},
      {"geometry_msgs/Transform", ChecksOf<Transform>()},
      {"geometry_msgs/TransformStamped", ChecksOf<TransformStamped>()},
      {"tf2_msgs/TFMessage", ChecksOf<TFMessage>()},
      {"sensor_msgs/JointState", ChecksOf<JointState>()},
      {"std_msgs/String", ChecksOf<String>()},
      {"geometry_msgs/Point", ChecksOf<Point>()},
      {"geometry_msgs/Pose", ChecksOf<Pose>()},
      {"geometry_msgs/Twist", ChecksOf<Twist>()},
      {"geometry_msgs/PoseWithCovariance", ChecksOf<PoseWithCovariance>()},
      {"geometry_msgs/PoseWithCovarianceStamped", ChecksOf<PoseWithCovarianceStamped>()},
      {"geometry_msgs/TwistWithCovariance", ChecksOf<TwistWithCovariance>()},
      {"nav_msgs/Odometry", ChecksOf<Odometry>()},
  };
  return checks;
}

TEST(RosMessages, DecodesAndEncodesFoxgloveCdrOfEverySample) {
  SKIP_WITHOUT_FIXTURES();
  int n = 0;
  for (const auto& s : Expected()["samples"]) {
    const auto name = s["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto& checks = ChecksByType().at(s["type"].as<std::string>());
    checks.cdr(ReadBytes(FixturesDir() + "/cdr/" + name + ".bin"), s["value"]);
    ++n;
  }
  EXPECT_EQ(n, 15);
}

TEST(RosMessages, DecodesAndEncodesFoxgloveRos1OfEverySample) {
  SKIP_WITHOUT_FIXTURES();
  int n = 0;
  for (const auto& s : Expected()["samples"]) {
    if (!s["ros1"].as<bool>()) continue;
    const auto name = s["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto& checks = ChecksByType().at(s["type"].as<std::string>());
    checks.ros1(ReadBytes(FixturesDir() + "/ros1/" + name + ".bin"), s["value"]);
    ++n;
  }
  EXPECT_EQ(n, 14);
}

TEST(RosMessages, RefusesEveryTruncationOfEverySample) {
  SKIP_WITHOUT_FIXTURES();
  for (const auto& s : Expected()["samples"]) {
    const auto name = s["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto& checks = ChecksByType().at(s["type"].as<std::string>());
    checks.cdr_truncations(ReadBytes(FixturesDir() + "/cdr/" + name + ".bin"));
    if (s["ros1"].as<bool>()) {
      checks.ros1_truncations(ReadBytes(FixturesDir() + "/ros1/" + name + ".bin"));
    }
  }
}

// The messages with a covariance (expected.json's covariance_samples): both wires, every
// truncation. Their ROS 1 bytes are also genpy's (python3-geometry-msgs, python3-nav-msgs):
// the fixture ros_bag_fixtures (write_ros1_bags.py) fails unless genpy writes the same bytes.
TEST(RosMessages, CovarianceMessagesOfFoxgloveAndGenpy) {
  SKIP_WITHOUT_FIXTURES();
  int n = 0;
  for (const auto& s : Expected()["covariance_samples"]) {
    const auto name = s["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto& checks = ChecksByType().at(s["type"].as<std::string>());
    const Bytes cdr = ReadBytes(FixturesDir() + "/cdr/" + name + ".bin");
    const Bytes ros1 = ReadBytes(FixturesDir() + "/ros1/" + name + ".bin");
    checks.cdr(cdr, s["value"]);
    checks.ros1(ros1, s["value"]);
    checks.cdr_truncations(cdr);
    checks.ros1_truncations(ros1);
    ++n;
  }
  EXPECT_EQ(n, 7);
}

TEST(RosMessages, CovarianceIsThirtySixDoublesWithoutACount) {
  // PoseWithCovariance: 7 pose doubles then 36 covariance doubles, nothing else: 43 * 8 bytes
  // on both wires (plus CDR's header); entry i of the array is at 8 * (7 + i).
  PoseWithCovariance m;
  for (std::size_t i = 0; i < 36; ++i) m.covariance[i] = static_cast<double>(i) + 0.5;
  Bytes cdr, ros1;
  ASSERT_TRUE(EncodeCdr(m, cdr).has_value());
  ASSERT_TRUE(EncodeRos1(m, ros1).has_value());
  ASSERT_EQ(cdr.size(), 4U + 43U * 8U);
  ASSERT_EQ(ros1.size(), 43U * 8U);
  double x = 0;
  std::memcpy(&x, ros1.data() + 8 * (7 + 13), 8);
  EXPECT_EQ(x, 13.5);
  std::memcpy(&x, cdr.data() + 4 + 8 * (7 + 35), 8);
  EXPECT_EQ(x, 35.5);
  // Odometry: header "ab" (stamp 8, length 4, 3 bytes: 15), child "c" (4 + 2 at 16: 22), then
  // padding to 24 before the doubles: 24 + (7 + 36 + 6 + 36) * 8.
  Odometry o;
  o.header.frame_id = "ab";
  o.child_frame_id = "c";
  o.twist.covariance[0] = -1.0;
  ASSERT_TRUE(EncodeCdr(o, cdr).has_value());
  ASSERT_EQ(cdr.size(), 4U + 24U + 85U * 8U);
  std::memcpy(&x, cdr.data() + 4 + 24 + 8 * (7 + 36 + 6), 8);
  EXPECT_EQ(x, -1.0);
  Odometry back;
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(cdr), back).has_value());
  EXPECT_EQ(back, o);
}

// ---- Hand-computed bytes (no fixtures needed) ----

TEST(RosMessages, BigEndianCdrDecodes) {
  const Bytes be = {0x00, 0x00, 0x00, 0x00,   // CDR_BE
                    0xFF, 0xFF, 0xFF, 0xFB,   // sec = -5
                    0x00, 0x00, 0x00, 0x07};  // nanosec = 7
  Time t;
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(be), t).has_value());
  EXPECT_EQ(t, (Time{-5, 7}));
  const Bytes vec = {0,    0,    0, 0, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0,  // 1.0
                     0xC0, 0,    0, 0, 0,    0,    0, 0,              // -2.0
                     0x40, 0x08, 0, 0, 0,    0,    0, 0};             // 3.0
  Vector3 v;
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(vec), v).has_value());
  EXPECT_EQ(v, (Vector3{1.0, -2.0, 3.0}));
}

TEST(RosMessages, CdrAlignsDoublesFromAfterTheHeader) {
  // String "a": length 2 at 0, 'a' NUL at 4..5, then the 3 doubles start at 8 (relative to the
  // byte after the encapsulation header), not at 8 of the buffer.
  TransformStamped t;
  t.header.stamp = Time{1, 2};
  t.header.frame_id = "a";
  t.child_frame_id = "bc";
  t.transform.translation = Vector3{1, 2, 3};
  Bytes out;
  ASSERT_TRUE(EncodeCdr(t, out).has_value());
  // 8 stamp + 4+2 frame_id (14) + pad 2 (16) + 4+3 child (23) + pad 1 (24) + 56 doubles = 80.
  ASSERT_EQ(out.size(), 4U + 80U);
  EXPECT_EQ(out[4 + 16], 3);  // child_frame_id length, with its NUL
  EXPECT_EQ(out[4 + 23], 0);  // padding before the doubles
  double x = 0;
  std::memcpy(&x, out.data() + 4 + 24, 8);
  EXPECT_EQ(x, 1.0);
  TransformStamped back;
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(out), back).has_value());
  EXPECT_EQ(back, t);
}

CodecError DecodeError(const Bytes& bytes) {
  TFMessage m;
  auto r = DecodeCdr(std::span<const std::uint8_t>(bytes), m);
  EXPECT_FALSE(r.has_value());
  return r.has_value() ? CodecError{} : r.error();
}

TEST(RosMessages, RefusesLengthsAndCountsPastTheEnd) {
  // TFMessage with a count of 2^32 - 1 transforms and 4 bytes left: refused before allocating.
  auto e = DecodeError({0, 1, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4});
  EXPECT_EQ(e.offset, 4U);
  EXPECT_NE(e.message.find("sequence count 4294967295 past the end"), std::string::npos)
      << e.message;
  // One transform whose frame_id claims 1000 bytes.
  Bytes b = {0, 1, 0, 0, 1, 0, 0, 0, /*stamp*/ 0, 0, 0, 0, 0, 0, 0, 0, 0xE8, 0x03, 0, 0};
  b.resize(b.size() + 80, 0);
  e = DecodeError(b);
  EXPECT_EQ(e.offset, 16U);
  EXPECT_NE(e.message.find("string length 1000 past the end"), std::string::npos) << e.message;
}

TEST(RosMessages, RefusesStringsWithoutTheirNul) {
  const Bytes no_nul = {0, 1, 0, 0, 3, 0, 0, 0, 'a', 'b', 'c'};
  String s;
  auto r = DecodeCdr(std::span<const std::uint8_t>(no_nul), s);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().offset, 4U);
  EXPECT_NE(r.error().message.find("does not end with a NUL"), std::string::npos);
  const Bytes inner_nul = {0, 1, 0, 0, 4, 0, 0, 0, 'a', 0, 'c', 0};
  r = DecodeCdr(std::span<const std::uint8_t>(inner_nul), s);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().offset, 9U);
  // ROS 1 strings carry no NUL: the same bytes are "abc".
  const Bytes ros1 = {3, 0, 0, 0, 'a', 'b', 'c'};
  ASSERT_TRUE(DecodeRos1(std::span<const std::uint8_t>(ros1), s).has_value());
  EXPECT_EQ(s.data, "abc");
}

TEST(RosMessages, RefusesOtherEncapsulationsAndTrailingBytes) {
  String s;
  const Bytes xcdr2 = {0, 7, 0, 0, 1, 0, 0, 0, 0};
  auto r = DecodeCdr(std::span<const std::uint8_t>(xcdr2), s);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("not plain CDR"), std::string::npos);
  // 3 bytes of end padding are accepted (rmw_fastrtps pads to 4); 4 are not.
  const Bytes padded = {0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_TRUE(DecodeCdr(std::span<const std::uint8_t>(padded), s).has_value());
  const Bytes trailing = {0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0};
  r = DecodeCdr(std::span<const std::uint8_t>(trailing), s);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().offset, 9U);
  EXPECT_EQ(Describe(r.error()), "byte 9: 4 bytes after the end of the message");
  const Bytes ros1_trailing = {0, 0, 0, 0, 0};
  EXPECT_FALSE(DecodeRos1(std::span<const std::uint8_t>(ros1_trailing), s).has_value());
}

TEST(RosMessages, EncodingRefusesValuesTheWireCannotCarry) {
  Bytes out;
  Header h;
  h.stamp.sec = std::int64_t{1} << 31;  // over int32: fits ROS 1's uint32 only
  auto r = EncodeCdr(h, out);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("outside ROS 2's int32 range"), std::string::npos);
  EXPECT_TRUE(EncodeRos1(h, out).has_value());
  h.stamp.sec = -1;
  EXPECT_TRUE(EncodeCdr(h, out).has_value());
  EXPECT_FALSE(EncodeRos1(h, out).has_value());
  String s{std::string("a\0b", 3)};
  r = EncodeCdr(s, out);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("NUL"), std::string::npos);
  ASSERT_TRUE(EncodeRos1(s, out).has_value());  // ROS 1 strings are counted: NUL is a byte
  String back;
  ASSERT_TRUE(DecodeRos1(std::span<const std::uint8_t>(out), back).has_value());
  EXPECT_EQ(back, s);
}

TEST(RosMessages, DecodingReusesTheMessage) {
  // A long message then a short one into the same struct: no stale elements remain.
  JointState js;
  js.name = {"a", "b", "c"};
  js.position = {1, 2, 3};
  Bytes out;
  ASSERT_TRUE(EncodeCdr(js, out).has_value());
  JointState m;
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(out), m).has_value());
  JointState small;
  small.name = {"z"};
  ASSERT_TRUE(EncodeCdr(small, out).has_value());
  ASSERT_TRUE(DecodeCdr(std::span<const std::uint8_t>(out), m).has_value());
  EXPECT_EQ(m, small);
  EXPECT_EQ(ToNanoseconds(Time{-2, 500}), -1'999'999'500);
}

}  // namespace
}  // namespace semgraph::ros
