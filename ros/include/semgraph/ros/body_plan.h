// File: semgraph/ros/body_plan.h
//
// The semantic lift's first half (docs/ros.md, "Frames and bodies"): tf knows frames only, a
// scene graph needs every frame on a body. A BodyPlan decides the body of each tf frame from
// the static transforms seen, the mode and an optional bodies map:
//   - a frame listed in the map lies on its listed body;
//   - mode same_body (default), or any mode when a map is given: an unlisted frame that is the
//     child of a static transform lies on the body of its static parent (so a static tree is
//     one body, named after its root frame);
//   - every other frame lies on a body named after itself (mode own_body: all frames but the
//     listed ones).
// A frame already in the graph keeps its body: callers pass a lookup of existing bodies.
//
// Invariants: a frame has at most one static parent in the plan (the first one seen; a second
// one is refused by the graph later, multiple_pose_parents); BodyOf terminates on static loops
// (a loop's body is named after the frame where the walk met itself).
// Costs: AddStatic O(1) expected; BodyOf O(depth of the static tree) expected. Build time only
// (allocates). Not thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "semgraph/base/expected.h"
#include "semgraph/ros/export.h"

namespace semgraph::ros {

/// How static transforms map onto bodies (spec: `static: same_body | own_body`).
enum class StaticMode : std::uint8_t {
  kSameBody,  ///< frames joined by /tf_static are one rigid body (constant poses)
  kOwnBody,   ///< every frame its own body; a static transform is a timeless inter-body pose
};

/// "same_body", "own_body".
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string_view ToString(StaticMode mode) noexcept;
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::optional<StaticMode> StaticModeFromString(
    std::string_view name) noexcept;

/// BODY -> its frames (names as lifted: no leading '/').
using BodiesMap = std::map<std::string, std::vector<std::string>, std::less<>>;

/// TOPIC -> the frame whose pose its geometry_msgs/PoseWithCovarianceStamped messages give (the
/// message names only its header frame), e.g. {"/amcl_pose": "base_footprint"}.
using PoseTopicsMap = std::map<std::string, std::string, std::less<>>;

struct LiftOptions {
  StaticMode static_mode = StaticMode::kSameBody;
  BodiesMap bodies;
  PoseTopicsMap pose_topics{};  // ({}: aggregates of the two fields above stay warning-free)
};

/// tf2's frame name rule: one leading '/' removed ("/base" -> "base", "//x" -> "/x").
[[nodiscard]] constexpr std::string_view LiftFrameName(std::string_view frame_id) noexcept {
  return !frame_id.empty() && frame_id.front() == '/' ? frame_id.substr(1) : frame_id;
}

class SEMGRAPH_ROS_EXPORT BodyPlan {
 public:
  /// The body of a frame that exists already (nullopt: not in the graph).
  using ExistingBody = std::function<std::optional<std::string>(std::string_view frame)>;

  /// A plan for `options`; a frame listed under two bodies, or an empty body or frame name in
  /// the map, is an error naming them.
  [[nodiscard]] static base::Expected<BodyPlan, std::string> Make(const LiftOptions& options);

  [[nodiscard]] StaticMode mode() const noexcept { return mode_; }
  /// Records a static transform parent -> child (lifted names). The first static parent of a
  /// frame wins.
  void AddStatic(std::string_view parent, std::string_view child);
  /// The static parent recorded for `frame`, or empty.
  [[nodiscard]] std::string_view StaticParent(std::string_view frame) const;
  /// The body `frame` lies on (see the file comment); `existing` answers for frames in the graph.
  [[nodiscard]] std::string BodyOf(std::string_view frame, const ExistingBody& existing) const;
  /// Whether a static transform parent -> child joins its frames into one body (same_body mode
  /// or a map that does not list the child elsewhere), i.e. is a constant pose.
  [[nodiscard]] bool JoinsBodies(std::string_view child) const;

 private:
  BodyPlan() = default;
  StaticMode mode_ = StaticMode::kSameBody;
  bool has_map_ = false;
  std::unordered_map<std::string, std::string> listed_;         ///< frame -> body (the map)
  std::unordered_map<std::string, std::string> static_parent_;  ///< child -> parent
};

}  // namespace semgraph::ros
