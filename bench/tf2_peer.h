// File: bench/tf2_peer.h
//
// The tf2 side of the benchmarks behind a plain interface. tf2 here is ROS 1 geometry2 0.7.6
// (Debian's libtf2-dev); its ROS 1 message headers use std::allocator<void>::rebind, which C++20
// removed, so tf2 is compiled in its own C++17 translation unit (tf2_peer.cc) and the benchmark
// code (C++20, semgraph) sees only this header. Every timed tf2 call (the lookups, the inserts)
// runs inside tf2_peer.cc; crossing into it costs one out-of-line call per query.
// Thread safety: none needed (single-threaded benchmarks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace semgraph_bench::tf2peer {

/// A pose: unit quaternion (w, x, y, z) and translation, child in parent.
struct Pose7 {
  double qw, qx, qy, qz, x, y, z;
};

/// A tf2::BufferCore (default 10 s cache) holding the chain f0 <- f1 <- ... <- fd, d =
/// links.size(). Static when links_at_2s is null: each link set once with setTransform(msg,
/// "bench", true); lookups at ros::Time(0). Dynamic otherwise: link i at t = 1 s (links) and t = 2
/// s (links_at_2s), is_static = false; lookups at ros::Time(1.5).
class Chain {
 public:
  Chain(const std::vector<Pose7>& links, const std::vector<Pose7>* links_at_2s);
  ~Chain();
  Chain(const Chain&) = delete;
  Chain& operator=(const Chain&) = delete;

  /// lookupTransform("f0", "fd", t): the pose of fd in f0. Throws tf2's exception on failure.
  [[nodiscard]] Pose7 Lookup() const;
  /// The timed kernel: one lookupTransform("f0", "fd", t) with its result passed to
  /// benchmark::DoNotOptimize (const overload). Frame names are std::strings built beforehand.
  void LookupOnce() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Pregenerated static messages of a tree: message i-1 sets frames[i] under frames[parent[i]]
/// with poses[i], for i = 1 .. frames.size()-1 (index 0 is the root).
class TreeMessages {
 public:
  TreeMessages(const std::vector<std::string>& frames, const std::vector<std::uint32_t>& parent,
               const std::vector<Pose7>& poses);
  ~TreeMessages();
  TreeMessages(const TreeMessages&) = delete;
  TreeMessages& operator=(const TreeMessages&) = delete;
  [[nodiscard]] std::size_t size() const;

 private:
  friend class Buffer;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A fresh tf2::BufferCore (default 10 s cache).
class Buffer {
 public:
  Buffer();
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  /// setTransform(msg, "bench", is_static = true) for every message in order (the timed part of
  /// tf2_build_tree_static). False if tf2 rejected one.
  bool InsertAllStatic(const TreeMessages& messages);
  /// The timed kernel of the cold-cache benchmark: lookupTransform(target, source, Time(0)),
  /// its result passed to benchmark::DoNotOptimize.
  void LookupOnce(const std::string& target, const std::string& source) const;
  /// The same lookup, returned (for the set-up check against semgraph).
  [[nodiscard]] Pose7 Lookup(const std::string& target, const std::string& source) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph_bench::tf2peer
