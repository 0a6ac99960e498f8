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
//                          over 1e-6 m or 1e-6 rad apart it is the finding model_mismatch
//   rotation               |‖q‖² − 1| ≤ 0.01 accepted and normalized (counted `normalized` when
//                          ‖q‖ is more than 1e-6 from 1), worse invalid_rotation; NaN/Inf
//                          invalid_number
//   /joint_states          SetJoints at header.stamp with the names, the positions and (when as
//                          many) the velocities; skipped when the graph has no joints
// A refused transform changes nothing; the other transforms of its message still apply.
//
// Costs: one graph add (or one pose query for a covered transform) per transform, plus a hash
// lookup of its frame names; build time (allocates). Not thread-safe: one lift per graph, used
// by the graph's one writer.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>

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
};

struct LiftCounts {
  std::uint64_t transforms = 0;  ///< transforms seen (applied + refused + covered + mismatched)
  std::uint64_t applied = 0;
  std::uint64_t refused = 0;
  std::uint64_t covered = 0;     ///< covered by the model, equal or not
  std::uint64_t mismatched = 0;  ///< covered and different (model_mismatch)
  std::uint64_t normalized = 0;
  std::uint64_t joint_states = 0;          ///< joint state messages applied
  std::uint64_t joint_states_refused = 0;  ///< refused (a finding each)
  std::uint64_t joint_states_skipped = 0;  ///< the graph has no joints
};

/// tf2's quaternion tolerance on |‖q‖² − 1| for ROS input.
inline constexpr double kRosQuaternionTolerance = 0.01;
/// Over this apart a covered transform is model_mismatch (metres, radians).
inline constexpr double kModelTolerance = 1e-6;

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
  /// A joint state message; refusals are findings with parent = "" and child = the first name.
  void Apply(const JointState& state, std::string_view topic, std::int64_t log_time_ns);

  [[nodiscard]] BodyPlan& plan() noexcept { return plan_; }
  [[nodiscard]] const Findings& findings() const noexcept { return findings_; }
  [[nodiscard]] const LiftCounts& counts() const noexcept { return counts_; }

 private:
  LiftOutcome Refuse(core::ErrorCode code, std::string message, std::string_view parent,
                     std::string_view child, const TransformOrigin& origin);
  LiftOutcome CompareWithModel(std::string_view parent, std::string_view child,
                               const Eigen::Quaterniond& q_PC, const Eigen::Vector3d& p_PoCo_P,
                               bool is_static, const TransformOrigin& origin);
  std::string BodyOf(std::string_view frame) const;

  core::SceneGraph<B>& graph_;
  BodyPlan plan_;
  Findings findings_;
  LiftCounts counts_;
  std::set<std::pair<std::string, std::string>, std::less<>> covered_;  ///< (parent, child)
};

extern template class TfLift<coord::QuaternionBackend>;
extern template class TfLift<coord::HomogeneousBackend>;

}  // namespace semgraph::ros
