// File: semgraph/models/urdf.h
//
// Robot models in URDF (the ROS robot description format), parsed by Debian's urdfdom and
// loaded into a SceneGraph as bodies, frames and joints (docs/kinematics.md, "URDF mapping"):
//   <link name="L">        body prefix+L with one frame prefix+L (the link frame)
//   <joint name="J">       joint prefix+J between the link frames of its parent and child:
//                          X_origin from <origin xyz rpy> (R = Rz(y) Ry(p) Rx(r)), axis from
//                          <axis> (default x), limits from <limit>, mimic from <mimic>
//   floating joints        an ordinary pose edge (identity) and twist edge (zero), updated
//                          with ordinary adds; not a joint (no joint name)
//   planar joints          invalid_model (unsupported)
// The root link's frame is the root of a new pose tree: attach the robot with an ordinary pose
// (e.g. base_link wrt world). Several robots of one model load side by side with prefixes.
//
// A load is one atomic operation: a file that cannot be read or that urdfdom refuses (its
// message is in the error), a `package://` URI, a non-finite number, an axis of norm < 1e-12,
// limits with lower > upper, a bad mimic, a prefixed name that breaks the name rules or an
// unsupported joint is invalid_model; then a joint name that exists is duplicate_joint, a body
// duplicate_body, a frame duplicate_frame. On any of them nothing is created.
// Costs: parsing O(file size); loading O(links + joints) adds. Build time (allocates).
// Thread safety: as any add (exclusive access to the graph). urdfdom reports through
// console_bridge's process-wide output handler, which a load replaces for its duration: do not
// load models from two threads at once.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/models/export.h"

namespace semgraph::models {

/// What a load created, with prefixed names.
struct Robot {
  std::string name;  ///< the URDF's robot name
  std::string prefix;
  std::string root;                 ///< the root link's frame (and body)
  std::vector<std::string> links;   ///< depth-first from the root; siblings by joint name
  std::vector<std::string> joints;  ///< independent movable joints, depth-first (= group)
  std::vector<std::string> mimic_joints;
  std::vector<std::string> fixed_joints;
  std::vector<std::string> floating_joints;  ///< ordinary edges: "child wrt parent" by link frames
  core::JointGroup group;                    ///< `joints`, for SetJointPositions / State
};

/// Loads a URDF file: an absolute or relative path (relative to the working folder) or a
/// file:// URI. An empty prefix is no prefix.
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_MODELS_EXPORT base::Expected<Robot, core::BuildError> LoadUrdfFile(
    core::SceneGraph<B>& graph, std::string_view file, std::string_view prefix = {});
/// Loads a URDF document given as text.
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_MODELS_EXPORT base::Expected<Robot, core::BuildError> LoadUrdfString(
    core::SceneGraph<B>& graph, std::string_view xml, std::string_view prefix = {});

extern template base::Expected<Robot, core::BuildError> LoadUrdfFile(
    core::SceneGraph<coord::QuaternionBackend>&, std::string_view, std::string_view);
extern template base::Expected<Robot, core::BuildError> LoadUrdfFile(
    core::SceneGraph<coord::HomogeneousBackend>&, std::string_view, std::string_view);
extern template base::Expected<Robot, core::BuildError> LoadUrdfString(
    core::SceneGraph<coord::QuaternionBackend>&, std::string_view, std::string_view);
extern template base::Expected<Robot, core::BuildError> LoadUrdfString(
    core::SceneGraph<coord::HomogeneousBackend>&, std::string_view, std::string_view);

}  // namespace semgraph::models
