// ros_messages_fuzzer: the ROS message decoders of ros/include/semgraph/ros/messages.h on
// arbitrary bytes. Must never crash, hang or read out of bounds.
//
// Input: byte 0 picks the message type and the wire; the rest is the serialized message.
//   byte 0 < 18: type byte 0 % 9 (Time, Header, Vector3, Quaternion, Transform,
//                TransformStamped, TFMessage, JointState, String), wire (byte 0 / 9) % 2
//                (ROS 2 CDR, ROS 1);
//   byte 0 >= 18, k = byte 0 - 18: type k % 7 (Point, Pose, Twist, PoseWithCovariance,
//                PoseWithCovarianceStamped, TwistWithCovariance, Odometry), wire (k / 7) % 2.
// (The messages with a covariance came later: the first 18 values keep their meaning, and so
// do the seeds written for them.)
// Checks:
//   - an error has a message and an offset within the input;
//   - ROS 1 is canonical: a decoded message encodes back to exactly the input bytes;
//   - CDR: a decoded message encodes (little-endian, no end padding), and that encoding decodes
//     and encodes again to the same bytes (idempotent; byte equality, so NaNs compare).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include "semgraph/ros/messages.h"

namespace {

using semgraph::ros::CodecError;
using Bytes = std::vector<std::uint8_t>;

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "ros_messages_fuzzer: %s\n", what);
  std::abort();
}

template <class M>
void Run(std::span<const std::uint8_t> in, bool ros1) {
  namespace r = semgraph::ros;
  M m;
  auto d = ros1 ? r::DecodeRos1(in, m) : r::DecodeCdr(in, m);
  if (!d.has_value()) {
    if (d.error().message.empty()) Fail("an error without a message");
    if (d.error().offset > in.size()) Fail("an error offset past the input");
    return;
  }
  Bytes once;
  auto e = ros1 ? r::EncodeRos1(m, once) : r::EncodeCdr(m, once);
  if (!e.has_value()) Fail("a decoded message does not encode");
  if (ros1) {
    if (once.size() != in.size() || !std::equal(once.begin(), once.end(), in.begin())) {
      Fail("ROS 1: encode(decode(x)) != x");
    }
    return;
  }
  M again;
  if (!r::DecodeCdr(std::span<const std::uint8_t>(once), again).has_value()) {
    Fail("CDR: our encoding does not decode");
  }
  Bytes twice;
  if (!r::EncodeCdr(again, twice).has_value() || twice != once) {
    Fail("CDR: encoding is not idempotent");
  }
}

void RunCovarianceMessage(int type, std::span<const std::uint8_t> in, bool ros1) {
  namespace r = semgraph::ros;
  switch (type) {
    case 0:
      return Run<r::Point>(in, ros1);
    case 1:
      return Run<r::Pose>(in, ros1);
    case 2:
      return Run<r::Twist>(in, ros1);
    case 3:
      return Run<r::PoseWithCovariance>(in, ros1);
    case 4:
      return Run<r::PoseWithCovarianceStamped>(in, ros1);
    case 5:
      return Run<r::TwistWithCovariance>(in, ros1);
    default:
      return Run<r::Odometry>(in, ros1);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  namespace r = semgraph::ros;
  const std::span<const std::uint8_t> in(data + 1, size - 1);
  if (data[0] >= 18) {
    const int k = data[0] - 18;
    RunCovarianceMessage(k % 7, in, (k / 7) % 2 == 1);
    return 0;
  }
  const bool ros1 = (data[0] / 9) % 2 == 1;
  switch (data[0] % 9) {
    case 0:
      Run<r::Time>(in, ros1);
      break;
    case 1:
      Run<r::Header>(in, ros1);
      break;
    case 2:
      Run<r::Vector3>(in, ros1);
      break;
    case 3:
      Run<r::Quaternion>(in, ros1);
      break;
    case 4:
      Run<r::Transform>(in, ros1);
      break;
    case 5:
      Run<r::TransformStamped>(in, ros1);
      break;
    case 6:
      Run<r::TFMessage>(in, ros1);
      break;
    case 7:
      Run<r::JointState>(in, ros1);
      break;
    default:
      Run<r::String>(in, ros1);
      break;
  }
  return 0;
}
