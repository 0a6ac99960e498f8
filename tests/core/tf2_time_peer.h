// File: tests/core/tf2_time_peer.h
//
// tf2's BufferCore behind a plain interface, for time_tf2_test.cc. tf2 (ROS 1 geometry2,
// Debian's libtf2-dev) needs C++17 (its message headers use std::allocator<void>::rebind,
// removed in C++20), so it is compiled in its own translation unit (tf2_time_peer.cc).
// Times are integer nanoseconds, passed to ros::Time(sec, nsec) exactly.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace semgraph_test::tf2time {

struct Pose7 {
  double qw, qx, qy, qz, x, y, z;
};

class Buffer {
 public:
  Buffer();  ///< a BufferCore with a 100 s cache
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  /// setTransform: the pose of `child` in `parent` at t_ns (is_static: a static transform).
  bool Set(const std::string& parent, const std::string& child, const Pose7& x, std::int64_t t_ns,
           bool is_static);
  /// lookupTransform(target, source, t): the pose of source in target; t_ns = 0: latest common.
  /// False when tf2 throws. *stamp_ns gets the stamp tf2 reports.
  bool Lookup(const std::string& target, const std::string& source, std::int64_t t_ns, Pose7& out,
              std::int64_t* stamp_ns = nullptr) const;
  /// The fixed-frame variant: source at t_source, target at t_target, through `fixed`.
  bool LookupFixed(const std::string& target, std::int64_t t_target, const std::string& source,
                   std::int64_t t_source, const std::string& fixed, Pose7& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph_test::tf2time
