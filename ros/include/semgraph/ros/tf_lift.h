// File: semgraph/ros/tf_lift.h
//
// The semantic lift's second half (docs/ros.md, "Transforms into the graph"): tf transforms
// and joint states applied to a scene graph, every rule of the graph checked, each refusal a
// finding. One TfLift serves a bag (after a first pass has fed the plan every static transform)
// and a live stream (the plan grows as static transforms arrive).
//   /tf transform          a stamped sample of the pose of {child} wrt {header.frame_id}
//   /tf_static transform   timeless (its stamp ignored, as tf2 does): a constant pose when the
//                          plan puts both frames on one body, else a timeless inter-body pose
//   covered transform      one between the parent and child link frames of a joint of the
//                          robot model: not added, compared with the model's pose at its stamp;
//                          over 1e-6 m or 1e-6 rad apart it is the finding model_mismatch. A
//                          dynamic one stamped after the latest joint state waits (kDeferred)
//                          until a joint state at or after its stamp arrives, or Flush(): in a
//                          recorded bag robot_state_publisher's /tf often comes before the
//                          /joint_states message it was computed from (two connections)
//   rotation               |‖q‖² − 1| ≤ 0.01 accepted and normalized (counted `normalized` when
//                          ‖q‖ is more than 1e-6 from 1), worse invalid_rotation; NaN/Inf
//                          invalid_number
//   /joint_states          SetJoints at header.stamp with the names, the positions and (when as
//                          many) the velocities; skipped when the graph has no joints
// A refused transform changes nothing; the other transforms of its message still apply.
//   PoseWithCovarianceStamped  a stamped sample with covariance of the pose of the frame the
//                          user names with the topic (LiftOptions::pose_topics) wrt
//                          {header.frame_id}; the covariance read as semgraph's default edge
//                          form (coordinates convention, at the pose's origin, (x, y, z, rx, ry,
//                          rz): docs/uncertainty.md)
//   Odometry               the same for {child_frame_id} wrt {header.frame_id}, then a stamped
//                          sample with covariance of the twist of the child's body relative to the
//                          header frame's body, at the child's origin, in [child]
//   covariance messages    the numbers, the quaternion (as a transform's) and each covariance
//                          (coord::CheckCovariance: finite, symmetric, PSD) are checked before
//                          the graph is touched: a bad one is a finding, the graph unchanged for
//                          that message. A graph rule refusing the odometry twist after its pose
//                          was added leaves the pose (a finding names the twist).
//
// Costs: a /tf transform of an edge the lift added before is one SetPose by handle, found by
// comparing its names with the edge after the last one used (a publisher's order) or else by
// one hash lookup (no allocation once the key buffer has grown); any other
// transform is one graph add by names (or one pose query for a covered transform); build time.
// Not thread-safe: one lift per graph, used by the graph's one writer.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/ros/body_plan.h"
#include "semgraph/ros/export.h"
#include "semgraph/ros/findings.h"
#include "semgraph/ros/messages.h"

namespace semgraph::models {
struct Robot;
}

namespace semgraph::ros {

/// What became of one transform.
enum class LiftOutcome : std::uint8_t {
  kApplied,   ///< added or updated (an identical restatement of a constant pose too)
  kRefused,   ///< the graph refused it: a finding with its code
  kCovered,   ///< covered by the robot model and equal to its pose
  kMismatch,  ///< covered by the robot model and different: a model_mismatch finding
  kDeferred,  ///< covered, stamped after the latest joint state: compared later (see above)
};

struct LiftCounts {
  std::uint64_t transforms = 0;  ///< transforms seen (applied + refused + covered + mismatched)
  std::uint64_t applied = 0;
  std::uint64_t refused = 0;
  std::uint64_t covered = 0;     ///< covered by the model, equal or not
  std::uint64_t mismatched = 0;  ///< covered and different (model_mismatch)
  std::uint64_t normalized = 0;
  std::uint64_t joint_states = 0;           ///< joint state messages applied
  std::uint64_t joint_states_refused = 0;   ///< refused (a finding each)
  std::uint64_t joint_states_skipped = 0;   ///< the graph has no joints
  std::uint64_t poses_with_covariance = 0;  ///< PoseWithCovarianceStamped messages applied
  std::uint64_t odometry = 0;               ///< Odometry messages applied (pose and twist)
  std::uint64_t covariance_refused = 0;     ///< of both kinds refused (a finding each)
};

/// tf2's quaternion tolerance on |‖q‖² − 1| for ROS input.
inline constexpr double kRosQuaternionTolerance = 0.01;
/// Over this apart a covered transform is model_mismatch (metres, radians).
inline constexpr double kModelTolerance = 1e-6;
/// Stamped edges remembered for the by-handle path (beyond, transforms take the add by names).
inline constexpr std::size_t kMaxCachedEdges = std::size_t{1} << 16;
/// Covered transforms waiting for their joint state; beyond this many the oldest is compared at
/// once (memory stays bounded when no joint state ever comes).
inline constexpr std::size_t kMaxDeferredCovers = 4096;

template <coord::Backend B>
class SEMGRAPH_ROS_EXPORT TfLift {
 public:
  TfLift(core::SceneGraph<B>& graph, BodyPlan plan) : graph_(graph), plan_(std::move(plan)) {}

  /// Marks the joints of a robot model loaded into the graph as covering the tf transforms
  /// between their link frames (floating joints are ordinary edges: not covered).
  void CoverModel(const models::Robot& robot);
  /// Applies one transform of `topic` (is_static: it came on a static topic).
  LiftOutcome Apply(const TransformStamped& transform, bool is_static, std::string_view topic,
                    std::int64_t log_time_ns);
  /// Every transform of a message, in order.
  void Apply(const TFMessage& message, bool is_static, std::string_view topic,
             std::int64_t log_time_ns);
  /// A joint state message; a refusal is a finding with empty parent and child frames.
  /// Then compares the deferred covered transforms stamped at or before it.
  void Apply(const JointState& state, std::string_view topic, std::int64_t log_time_ns);
  /// A pose with covariance of `child_frame` (the frame pose_topics names for `topic`).
  LiftOutcome Apply(const PoseWithCovarianceStamped& message, std::string_view child_frame,
                    std::string_view topic, std::int64_t log_time_ns);
  /// An odometry message: its pose and its twist, with their covariances.
  LiftOutcome Apply(const Odometry& message, std::string_view topic, std::int64_t log_time_ns);
  /// Compares every deferred covered transform now (the end of a bag or of a stream).
  void Flush();

  [[nodiscard]] BodyPlan& plan() noexcept { return plan_; }
  [[nodiscard]] const Findings& findings() const noexcept { return findings_; }
  [[nodiscard]] const LiftCounts& counts() const noexcept { return counts_; }

 private:
  /// Apply's full path: every check, the add by names, the findings.
  [[gnu::noinline]] LiftOutcome ApplyByNames(const TransformStamped& transform, bool is_static,
                                             std::string_view topic, std::int64_t log_time_ns);
  LiftOutcome Refuse(core::ErrorCode code, std::string message, std::string_view parent,
                     std::string_view child, const TransformOrigin& origin);
  LiftOutcome CompareWithModel(std::string_view parent, std::string_view child,
                               const Eigen::Quaterniond& q_PC, const Eigen::Vector3d& p_PoCo_P,
                               bool is_static, const TransformOrigin& origin);
  std::string BodyOf(std::string_view frame) const;
  /// A covariance message's pose (and the odometry twist, when `twist`): checked, then added.
  LiftOutcome ApplyWithCovariance(const Header& header, std::string_view child_frame,
                                  const PoseWithCovariance& pose, const TwistWithCovariance* twist,
                                  std::string_view topic, std::int64_t log_time_ns);
  /// A covered transform waiting for the joint state at its stamp (its strings owned).
  struct DeferredCover {
    std::string topic, parent, child;
    std::int64_t log_time_ns = 0, stamp_ns = 0;
    Eigen::Quaterniond q_PC;
    Eigen::Vector3d p_PoCo_P;
  };
  LiftOutcome Defer(std::string_view parent, std::string_view child, const Eigen::Quaterniond& q_PC,
                    const Eigen::Vector3d& p_PoCo_P, const TransformOrigin& origin);
  void CompareDeferred(const DeferredCover& d);
  /// Compares the deferred covers stamped at or before `up_to_ns` (all of them: INT64_MAX).
  void CompareDeferredUpTo(std::int64_t up_to_ns);

  core::SceneGraph<B>& graph_;
  BodyPlan plan_;
  Findings findings_;
  LiftCounts counts_;
  std::set<std::pair<std::string, std::string>, std::less<>> covered_;  ///< (parent, child)
  std::deque<DeferredCover> deferred_;                                  ///< in arrival order
  /// The stamped edges {parent} -> {child} this lift added, in the order they were added.
  struct CachedEdge {
    std::string parent, child;
    core::PoseHandle edge;
  };
  static constexpr std::size_t kNotCached = static_cast<std::size_t>(-1);
  /// The index in edges_ of (parent, child), or kNotCached.
  std::size_t FindCachedEdge(std::string_view parent, std::string_view child);
  std::vector<CachedEdge> edges_;
  std::unordered_map<std::string, std::size_t> edge_index_;  ///< "parent\nchild" -> index
  std::size_t next_edge_ = 0;  ///< the entry after the last one used: the likely next
  std::string key_;            ///< the lookup key's buffer
  std::optional<std::int64_t> latest_joint_stamp_ns_;  ///< of the joint states applied
};

extern template class TfLift<coord::QuaternionBackend>;
extern template class TfLift<coord::HomogeneousBackend>;

}  // namespace semgraph::ros
