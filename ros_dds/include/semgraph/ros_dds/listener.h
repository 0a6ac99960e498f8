// File: semgraph/ros_dds/listener.h
//
// Listener: the semantic tf2_ros::TransformListener (docs/ros.md, "Live ROS 2"). It subscribes
// to rt/tf, rt/tf_static, rt/joint_states and rt/robot_description over Cyclone DDS (no ROS
// library; types, QoS and domain of ros_topics.h) and applies what arrives to a scene graph
// through semgraph::ros's TfLift, so every rule of the graph is checked and each refused or
// model-mismatched transform is a finding, reported as it happens:
//   - rt/tf_static (transient local: a listener started late still gets every static
//     broadcaster's last message): timeless transforms; in mode same_body a static link puts
//     the child on its parent's body when the child is first seen (live, a frame's body is
//     decided when it is first seen: a later static link to a frame on another body is
//     frame_body_mismatch);
//   - rt/tf: stamped samples (header.stamp) into the graph's histories (the graph's time
//     options decide the window, e.g. tf2's 10 s buffer);
//   - rt/robot_description: the first URDF is loaded into the graph (models::LoadUrdfString)
//     and its joints cover the tf transforms between their link frames (TfLift::CoverModel);
//     a different later URDF is not applied (logged); a URDF that does not load is logged;
//   - rt/joint_states: SetJoints at header.stamp (skipped while the graph has no joints);
//   - the pose topics of lift.pose_topics (geometry_msgs/PoseWithCovarianceStamped: the pose of
//     the frame named with the topic) and the odometry_topics (nav_msgs/Odometry): stamped
//     samples with covariance, through the same TfLift::Apply as a bag's; a message with a
//     NaN, a bad quaternion or a covariance that is not symmetric PSD is a finding and changes
//     nothing.
// Within one wake-up of the receive thread, robot descriptions are applied first, then static
// transforms, then tf, then joint states, then the pose topics, then the odometry topics.
//
// Threads. The listener's receive thread is the graph's one writer. Other threads may:
//   - evaluate compiled queries and use handles made inside WithGraph(), at any time: they are
//     safe under value updates and topology changes (docs/realtime.md);
//   - run one-shot queries by name (GetPose(...), Find*, Compile*) only inside WithGraph(fn),
//     which runs fn under the listener's lock while no message is being applied. One-shot
//     queries are not (yet) safe concurrently with the topology changes a new frame brings;
//     WithGraph is the interim discipline until the core makes them so.
// The callbacks run on the receive thread, outside the lock (they may call WithGraph).
// Costs: per message, the conversion from the DDS sample (allocates) and one TfLift::Apply per
// transform or covariance message (build time); WithGraph blocks the receive thread for fn's
// duration. One DDS reader per topic (4 + the user's pose and odometry topics).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/ros/body_plan.h"
#include "semgraph/ros/findings.h"
#include "semgraph/ros/tf_lift.h"
#include "semgraph/ros_dds/export.h"
#include "semgraph/ros_dds/ros_topics.h"

namespace semgraph::ros_dds {

/// One applied message (for latency measurements and monitors).
struct Arrival {
  RosTopic topic = RosTopic::kTf;
  std::int64_t source_timestamp_ns = 0;  ///< the writer's dds_write time (DDS's clock)
  std::int64_t applied_ns = 0;           ///< when the graph had it (DDS's clock)
  std::size_t transforms = 0;            ///< transforms in the message (0 for other topics)
};

struct ListenerOptions {
  /// The DDS domain; default: ROS_DOMAIN_ID, else 0.
  std::optional<std::uint32_t> domain;
  ros::LiftOptions lift;  ///< static mode, bodies map, pose topics {topic: frame} (docs/ros.md)
  /// nav_msgs/Odometry topics to subscribe to (fully qualified ROS names, e.g. "/odom"; a name
  /// may not also be a pose topic).
  std::vector<std::string> odometry_topics;
  bool joint_states = true;       ///< subscribe to rt/joint_states
  bool robot_description = true;  ///< subscribe to rt/robot_description
  /// Each finding occurrence, with its group as it is now (count, last times); `first`: the
  /// group is new. On the receive thread, outside the lock.
  std::function<void(const ros::FindingGroup& group, bool first)> on_finding;
  /// After each applied message. On the receive thread, outside the lock.
  std::function<void(const Arrival&)> on_arrival;
  /// A log line (a URDF that does not load, a changed robot_description); default: stderr with
  /// the prefix "semgraph-ros: ".
  std::function<void(const std::string&)> log;
};

/// Messages received per topic.
struct ListenerStats {
  std::uint64_t tf = 0, tf_static = 0, joint_states = 0, robot_descriptions = 0;
  std::uint64_t poses_with_covariance = 0;  ///< messages on the pose topics
  std::uint64_t odometry = 0;               ///< messages on the odometry topics
  bool robot_loaded = false;                ///< a URDF from rt/robot_description is in the graph
  ros::LiftCounts counts;  ///< the lift's counts (transforms applied, refused, ...)
};

class SEMGRAPH_ROS_DDS_EXPORT Listener {
 public:
  /// Joins the domain, subscribes and starts the receive thread. The graph must outlive the
  /// listener and not move; no other thread may change it while the listener runs. Fails
  /// (message) when the domain or the bodies map is invalid, a pose or odometry topic is not a
  /// ROS 2 topic name (or is both, or a pose topic has no frame), or DDS refuses.
  static base::Expected<std::unique_ptr<Listener>, std::string> Create(
      core::SceneGraph<>& graph, ListenerOptions options = {});
  /// Stops the receive thread and leaves the domain.
  ~Listener();
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  /// Runs fn with the graph while no message is applied (one-shot queries, Compile*).
  void WithGraph(const std::function<void(const core::SceneGraph<>&)>& fn) const;
  [[nodiscard]] ListenerStats stats() const;
  /// The finding groups so far (docs/ros.md, "Findings").
  [[nodiscard]] std::vector<ros::FindingGroup> findings() const;
  /// Waits (polling every 2 ms) until pred() or the timeout; returns pred().
  bool WaitUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout) const;
  /// Writers matched on rt/tf now, as this listener sees them. rt/tf is volatile: a sample a
  /// writer sends before it matched this listener never arrives, and the writer's side may
  /// match later than this count shows; the sending side waits where that matters
  /// (Broadcaster::WaitForSubscribers, docs/ros.md "/tf is volatile").
  [[nodiscard]] std::uint32_t tf_publishers() const noexcept;
  /// Writers matched now on one of this listener's pose or odometry topics (its ROS name, e.g.
  /// "/odom"; 0 for a topic it does not read). Those readers are best effort: a sample sent
  /// before both sides matched is lost, so a sender waits for this and its own match first.
  [[nodiscard]] std::uint32_t publishers(std::string_view ros_topic) const noexcept;
  [[nodiscard]] std::uint32_t domain() const noexcept;

 private:
  struct Impl;
  explicit Listener(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semgraph::ros_dds
