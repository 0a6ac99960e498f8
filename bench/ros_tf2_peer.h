// File: bench/ros_tf2_peer.h
//
// tf2 (ROS 1 geometry2, Debian's libtf2-dev) for the ROS bag benchmarks, behind a plain
// interface: its headers need C++17 (std::allocator<void>::rebind), so it lives in its own
// translation unit (ros_tf2_peer.cc), like bench/tf2_peer.h. The transforms are converted to
// geometry_msgs::TransformStamped once, before anything is timed, so that the timed ingest is
// tf2's setTransform alone (as the timed semgraph ingest is TfLift::Apply of decoded messages).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace semgraph_bench::rostf2 {

struct Pose7 {
  double qw, qx, qy, qz, x, y, z;  ///< unit quaternion (w, x, y, z), translation: child in parent
};

/// One transform as a bag holds it (frame names as on the wire).
struct Transform {
  std::string parent, child;
  std::int64_t stamp_ns = 0;
  bool is_static = false;
  Pose7 X_PC;
};

/// The transforms as tf2 messages, built once.
class Messages {
 public:
  explicit Messages(const std::vector<Transform>& transforms);
  ~Messages();
  Messages(const Messages&) = delete;
  Messages& operator=(const Messages&) = delete;
  [[nodiscard]] std::size_t size() const;

 private:
  friend class Buffer;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A tf2::BufferCore with a cache of `cache_s` seconds (tf2's default: 10).
class Buffer {
 public:
  explicit Buffer(double cache_s = 10.0);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  /// setTransform(message, "bag", is_static) for each message in order (the timed ingest);
  /// returns how many tf2 accepted.
  std::size_t Ingest(const Messages& messages);
  /// lookupTransform(relative_to, of, t): the pose of `of` in `relative_to` (false: tf2 threw).
  bool Lookup(const std::string& relative_to, const std::string& of, std::int64_t t_ns,
              Pose7& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph_bench::rostf2
