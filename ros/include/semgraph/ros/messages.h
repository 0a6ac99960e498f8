// File: semgraph/ros/messages.h
//
// The ROS messages semgraph reads and writes (docs/ros.md), as plain wire structs with ROS's
// field names, and their two serializations:
//  - ROS 2 CDR: XCDR1 (plain CDR) with the 4-byte encapsulation header; encoded little-endian
//    (00 01 00 00), decoded little- or big-endian (00 01 / 00 00). Alignment is counted from
//    after the header; a string is a uint32 length that counts its trailing NUL, the bytes, the
//    NUL; a sequence is a uint32 count then its elements (an empty sequence of doubles is not
//    followed by alignment padding, as in Cyclone DDS and Foxglove's writer).
//  - ROS 1: little-endian, no alignment; strings and arrays as a uint32 length then the bytes
//    or elements (a fixed-size array such as a covariance's float64[36]: the elements only, on
//    both wires); a Header starts with `uint32 seq`, and Time is `uint32 secs, uint32 nsecs`.
// Field order is defined once (messages.cc) for decoding and encoding alike.
//
// Invariants: decoding is bounds-checked: a length or count past the end, a missing NUL, or
// bytes left over (CDR: more than 3 bytes of end padding) is a CodecError with the byte offset
// (from the first byte of the span, header included), never undefined behaviour; on error the
// output message holds unspecified but valid values. A count is checked against the bytes left
// before anything is allocated, so memory stays within a small multiple of the input's size.
// Costs: O(bytes); decoding into a reused message reuses its vectors' capacity; encoding
// replaces `out` (reusing its capacity).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "semgraph/base/expected.h"
#include "semgraph/ros/export.h"

namespace semgraph::ros {

using base::Expected;
using base::Ok;
using base::Unexpected;

/// builtin_interfaces/Time (ROS 2: int32 sec, uint32 nanosec) and ROS 1 `time` (uint32 secs,
/// uint32 nsecs). Held wide enough for both; encoding checks the range of the target wire.
struct Time {
  std::int64_t sec = 0;
  std::uint32_t nanosec = 0;
  friend bool operator==(const Time&, const Time&) = default;
};

/// std_msgs/Header. `seq` exists only in ROS 1 (ROS 2 decoding leaves it 0; encoding ignores it).
struct Header {
  std::uint32_t seq = 0;
  Time stamp;
  std::string frame_id;
  friend bool operator==(const Header&, const Header&) = default;
};

struct Vector3 {
  double x = 0, y = 0, z = 0;
  friend bool operator==(const Vector3&, const Vector3&) = default;
};

/// geometry_msgs/Quaternion in ROS's (x, y, z, w) order.
struct Quaternion {
  double x = 0, y = 0, z = 0, w = 1;
  friend bool operator==(const Quaternion&, const Quaternion&) = default;
};

struct Transform {
  Vector3 translation;
  Quaternion rotation;
  friend bool operator==(const Transform&, const Transform&) = default;
};

/// geometry_msgs/TransformStamped: the pose of child_frame_id relative to header.frame_id.
struct TransformStamped {
  Header header;
  std::string child_frame_id;
  Transform transform;
  friend bool operator==(const TransformStamped&, const TransformStamped&) = default;
};

/// tf2_msgs/TFMessage (and ROS 1's tf/tfMessage, the same layout).
struct TFMessage {
  std::vector<TransformStamped> transforms;
  friend bool operator==(const TFMessage&, const TFMessage&) = default;
};

struct JointState {
  Header header;
  std::vector<std::string> name;
  std::vector<double> position;
  std::vector<double> velocity;
  std::vector<double> effort;
  friend bool operator==(const JointState&, const JointState&) = default;
};

/// std_msgs/String (a URDF on /robot_description).
struct String {
  std::string data;
  friend bool operator==(const String&, const String&) = default;
};

struct Point {
  double x = 0, y = 0, z = 0;
  friend bool operator==(const Point&, const Point&) = default;
};

/// geometry_msgs/Pose: the pose of some frame relative to the message's frame.
struct Pose {
  Point position;
  Quaternion orientation;
  friend bool operator==(const Pose&, const Pose&) = default;
};

/// geometry_msgs/Twist.
struct Twist {
  Vector3 linear;
  Vector3 angular;
  friend bool operator==(const Twist&, const Twist&) = default;
};

/// A ROS covariance: float64[36], row-major 6x6 over (x, y, z, rotation about X, Y, Z) for a
/// pose, (linear x, y, z, angular x, y, z) for a twist. On the wire: 36 doubles, no count.
using Covariance36 = std::array<double, 36>;

/// geometry_msgs/PoseWithCovariance. docs/uncertainty.md says how semgraph reads the covariance
/// (the `coordinates` convention, linear-angular order: its edge form, unchanged).
struct PoseWithCovariance {
  Pose pose;
  Covariance36 covariance{};
  friend bool operator==(const PoseWithCovariance&, const PoseWithCovariance&) = default;
};

/// geometry_msgs/PoseWithCovarianceStamped: the pose in header.frame_id of a frame the message
/// does not name (the user names it with the topic).
struct PoseWithCovarianceStamped {
  Header header;
  PoseWithCovariance pose;
  friend bool operator==(const PoseWithCovarianceStamped&,
                         const PoseWithCovarianceStamped&) = default;
};

/// geometry_msgs/TwistWithCovariance.
struct TwistWithCovariance {
  Twist twist;
  Covariance36 covariance{};
  friend bool operator==(const TwistWithCovariance&, const TwistWithCovariance&) = default;
};

/// nav_msgs/Odometry: the pose of child_frame_id in header.frame_id, and the twist of the
/// child's body relative to the header frame's body, at the child's origin, in [child].
struct Odometry {
  Header header;
  std::string child_frame_id;
  PoseWithCovariance pose;
  TwistWithCovariance twist;
  friend bool operator==(const Odometry&, const Odometry&) = default;
};

/// The types the codecs accept.
template <class M>
concept Message = std::is_same_v<M, Time> || std::is_same_v<M, Header> ||
    std::is_same_v<M, Vector3> || std::is_same_v<M, Quaternion> || std::is_same_v<M, Transform> ||
    std::is_same_v<M, TransformStamped> || std::is_same_v<M, TFMessage> ||
    std::is_same_v<M, JointState> || std::is_same_v<M, String> || std::is_same_v<M, Point> ||
    std::is_same_v<M, Pose> || std::is_same_v<M, Twist> || std::is_same_v<M, PoseWithCovariance> ||
    std::is_same_v<M, PoseWithCovarianceStamped> || std::is_same_v<M, TwistWithCovariance> ||
    std::is_same_v<M, Odometry>;

/// Why bytes do not decode to a message, or a message cannot be encoded.
struct CodecError {
  std::size_t offset = 0;  ///< byte offset in the serialized message (encode: bytes written)
  std::string message;     ///< what is wrong, e.g. "string length 300 past the end (12 bytes left)"
};

/// "byte OFFSET: MESSAGE".
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string Describe(const CodecError& error);

/// Nanoseconds since the epoch, sec·10⁹ + nanosec (no overflow for either wire's range).
[[nodiscard]] constexpr std::int64_t ToNanoseconds(const Time& t) noexcept {
  return t.sec * 1'000'000'000 + static_cast<std::int64_t>(t.nanosec);
}

/// Decodes a ROS 2 CDR sample (with its 4-byte encapsulation header) into `out`.
template <Message M>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> DecodeCdr(
    std::span<const std::uint8_t> bytes, M& out);

/// Decodes a ROS 1 serialized message into `out`.
template <Message M>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> DecodeRos1(
    std::span<const std::uint8_t> bytes, M& out);

/// Encodes `msg` as a ROS 2 CDR sample (header 00 01 00 00, little-endian) into `out`. Fails
/// when a value does not fit the wire: Time.sec outside int32, a string holding a NUL byte (a
/// CDR string ends at its first NUL), a string or sequence longer than 2³² − 2.
template <Message M>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> EncodeCdr(
    const M& msg, std::vector<std::uint8_t>& out);

/// Encodes `msg` in ROS 1 serialization into `out`. Fails when Time.sec is outside uint32 or a
/// string or array is longer than 2³² − 1.
template <Message M>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> EncodeRos1(
    const M& msg, std::vector<std::uint8_t>& out);

}  // namespace semgraph::ros
