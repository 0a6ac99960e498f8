// File: semgraph/ros_dds/broadcaster.h
//
// Broadcaster: publishes a scene graph's pose edges as ROS 2 tf over Cyclone DDS (docs/ros.md,
// "Live ROS 2"), so that RViz, tf2 and semgraph listeners see the scene. Each pose edge
// {tail} -> {head} goes out in its edge form: parent = the tail frame, child = the head frame,
// the transform X_TH (translation p_ToHo_T, rotation as (x, y, z, w)):
//   - a stamped edge (one with a sample history, docs/time.md): each sample newer than the last
//     one sent for that edge, with its stamp, on rt/tf; the samples of one Broadcast() go out in
//     one TFMessage (edges in frame order, each edge's samples oldest first);
//   - timeless edges, inter-body and constant (same body) alike, joints' edges included: all in
//     one TFMessage on rt/tf_static (transient local, keep-last 1: a late joiner gets it),
//     re-sent whole when any of them was added, removed or changed; stamped with the clock's
//     time of that change (tf2 ignores static stamps).
// Twist edges have no tf counterpart and are not sent. A graph read back from what a
// broadcaster sends (a Listener in mode same_body, with the same bodies map when inter-body
// timeless edges must stay inter-body, and the same time options) answers every pose query as
// the original: the samples, stamps and values are the original's, bit for bit.
//
// Invariants: Broadcast() never changes the graph. A sample inserted into a history older than
// the newest one already sent for its edge is not sent (tf readers keep their own order).
// Costs: Broadcast O(frames + new samples · log(history)) plus the DDS writes (allocates: build
// time, not the real-time path). Thread safety: one thread calls Broadcast, and that thread
// (or one synchronized with it) is the graph's writer.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/ros/body_plan.h"
#include "semgraph/ros/messages.h"
#include "semgraph/ros_dds/export.h"

namespace semgraph::ros_dds {

struct BroadcasterOptions {
  /// The DDS domain; default: ROS_DOMAIN_ID, else 0 (ros_topics.h).
  std::optional<std::uint32_t> domain;
  /// The stamp of a static message, nanoseconds since the epoch; default: DDS's clock.
  std::function<std::int64_t()> clock;
};

/// What one Broadcast() sent.
struct BroadcastCounts {
  std::size_t tf_transforms = 0;      ///< samples sent on rt/tf (0: no message)
  std::size_t static_transforms = 0;  ///< transforms of the static message (0: not re-sent)
};

class SEMGRAPH_ROS_DDS_EXPORT Broadcaster {
 public:
  /// Joins the domain and creates the rt/tf and rt/tf_static writers. Fails (message) when the
  /// domain is invalid or DDS refuses. The graph must outlive the broadcaster and not move.
  static base::Expected<std::unique_ptr<Broadcaster>, std::string> Create(
      const core::SceneGraph<>& graph, BroadcasterOptions options = {});
  ~Broadcaster();
  Broadcaster(const Broadcaster&) = delete;
  Broadcaster& operator=(const Broadcaster&) = delete;

  /// Sends what changed since the last call (see the file comment). Fails when DDS refuses a
  /// write or a stamp does not fit ROS 2's Time (int32 seconds); nothing is marked sent then.
  base::Expected<BroadcastCounts, std::string> Broadcast();

  /// Forgets which samples were sent on rt/tf: the next Broadcast() sends every stored sample
  /// again (rt/tf is volatile: e.g. for a subscriber that matched after they went out; those
  /// matched before receive identical restatements).
  void Rewind() noexcept;

  /// The messages Broadcast() would send now, without sending or marking anything (tests,
  /// dry runs): the new samples, and the whole static message (stamp: the clock's now).
  void Pending(ros::TFMessage& tf, ros::TFMessage& tf_static) const;
  /// The static message last sent (empty before the first).
  [[nodiscard]] const ros::TFMessage& last_static() const noexcept;
  /// Waits, at most `timeout`, until at least `count` readers are matched on rt/tf (the
  /// writer's side) and each reader matched then is in sync with this broadcaster: every
  /// sample sent afterwards reaches it. rt/tf is volatile: a sample sent before the writer
  /// matched a reader never reaches it (the reader's own matched status may show the writer
  /// earlier), and a reader drops data until it has had the writer's first heartbeat
  /// (docs/ros.md, "/tf is volatile"). Use it before the first Broadcast() when a listener is
  /// expected, or after a new subscriber appeared and before Rewind() and Broadcast().
  /// Event-driven (a waitset on the matched status, no polling, no sleep); when a reader is
  /// matched, sends one message on rt/tf without data (an unregister, which tf readers skip)
  /// and waits for every matched reader's acknowledgement. Fails (message with the counts) on
  /// timeout. Blocks the calling thread; call it on the thread that calls Broadcast().
  base::Expected<base::Ok, std::string> WaitForSubscribers(std::uint32_t count,
                                                           std::chrono::milliseconds timeout);
  /// Readers matched on rt/tf now (a sample sent before a reader matched never reaches it;
  /// WaitForSubscribers() waits for readers).
  [[nodiscard]] std::uint32_t subscribers() const noexcept;
  /// Readers ever matched on rt/tf (grows by one per new subscriber, even one that left).
  [[nodiscard]] std::uint32_t subscribers_matched() const noexcept;
  /// The DDS domain joined.
  [[nodiscard]] std::uint32_t domain() const noexcept;

 private:
  struct Impl;
  explicit Broadcaster(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// The bodies map of a graph ({body: [its frames]}, every frame listed): a Listener given it
/// puts every frame on the original's body, so inter-body timeless edges stay inter-body.
[[nodiscard]] SEMGRAPH_ROS_DDS_EXPORT ros::BodiesMap BodiesOf(const core::SceneGraph<>& graph);

}  // namespace semgraph::ros_dds
