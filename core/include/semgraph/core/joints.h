// File: semgraph/core/joints.h
//
// Joints: a pose edge {p} -> {c} and a twist edge P -> {c}|C whose values are functions of a
// joint state (q, qdot, and an optional qddot), computed on the write side, so a compiled query
// reads a joint's edges exactly as any other edge and costs what it costs today
// (docs/kinematics.md).
//
//   type        state            M(q)                                twist of the edge, in [c]
//   revolute    q (rad), limited rotation by q about the unit axis u  (0, u qdot)
//   continuous  q (rad)          same                                 (0, u qdot)
//   prismatic   q (m), limited   translation q u                      (u qdot, 0)
//   fixed       none             identity                             (0, 0)
// The pose edge stores X_PC(q) = X_origin M(q) (X_origin: {c} wrt {p} at q = 0); u is given in
// [c] and normalized. A mimic joint follows its master: q = m q_master + o, qdot = m qdot_master,
// qddot = m qddot_master.
// Accelerations (docs/dynamics.md): a joint given qddot makes its twist edge carry the edge form
// AccelerationCoord(c|C, P, [c]) = (a, alpha): revolute and continuous (0, u qddot) (the child
// origin is on the axis), prismatic (u qddot, 0); it does not depend on q or qdot. A joint whose
// qddot was never given (since it was added) gives its edge no acceleration; once given, qddot
// is kept, as q and qdot are, until it is set again. Stamped joints take no qddot (not yet).
//
// Invariants of a JointTable (kept by SceneGraph's joint operations):
//  - a live joint's pose edge is the pose parent edge of its child frame and its twist edge the
//    twist edge into the child frame; `joint_of_child` maps exactly the live joints' children;
//  - joint names are interned in the table's own NameTable (`names`; a joint and a frame may
//    share a name, and the scene's frame and body name ids stay those its node operations
//    made); `of_name` maps a name id to the live joint of that name, so live names are
//    unique; a removed joint's slot is dead and its generation was bumped, so old handles
//    are refused (unknown_joint);
//  - a mimic's master is a live movable joint that is not a mimic; `mimics` of a master lists
//    exactly its live mimics; the stored edge values equal X_origin M(q) and the twist of qdot;
//    the twist edge carries an acceleration exactly when has_qddot, and then that of qddot
//    (stored with the twist of qdot, edge_values.h); a mimic's has_qddot is its master's.
// Costs: lookups by name O(|name|), allocation-free (one hash); by handle O(1). Setting the state
// of n joints (SceneGraph::SetJointPositions/Velocities/Accelerations/State) is O(n + their
// mimics), noexcept,
// allocation-free and lock-free for readers (each edge value is written through its sequence
// lock: readers see either the old or the new value of an edge, never a torn one).
// Thread safety: one writer sets joint states while readers evaluate queries; joint adds and
// removals need exclusive access (as every topology change).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "semgraph/base/index.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/export.h"
#include "semgraph/semantics/names.h"
#include "semgraph/topology/ids.h"

namespace semgraph::core {

enum class JointType : std::uint8_t { kRevolute, kContinuous, kPrismatic, kFixed };

/// "revolute", "continuous", "prismatic", "fixed".
[[nodiscard]] SEMGRAPH_CORE_EXPORT std::string_view ToString(JointType type) noexcept;

/// The joint a SceneGraph::AddJoint adds, by role. Frames and bodies are created as for a pose
/// add (a missing frame needs its body). Names are views: they must outlive the call.
struct JointSpec {
  std::string_view name;
  JointType type = JointType::kFixed;
  std::string_view parent, parent_body;                          ///< {p}|P
  std::string_view child, child_body;                            ///< {c}|C
  Eigen::Quaterniond q_origin = Eigen::Quaterniond::Identity();  ///< R_PC at q = 0
  Eigen::Vector3d p_origin = Eigen::Vector3d::Zero();            ///< p_PoCo_P at q = 0
  std::optional<Eigen::Matrix3d> R_origin;  ///< when set, R_PC at q = 0 as a matrix (not q_origin)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< u in [c]; normalized
  double lower = 0, upper = 0;                      ///< position limits (revolute, prismatic)
  std::string_view mimic;                           ///< master joint's name; empty: not a mimic
  double multiplier = 1, offset = 0;                ///< q = multiplier * q_master + offset
};

/// A joint's slot in its graph's joint table (slots of removed joints are reused).
struct JointTag {};
using JointIndex = base::StrongIndex<JointTag>;

/// A resolved joint, for O(1) access on the real-time path.
struct JointHandle {
  JointIndex index;
  std::uint32_t generation = 0;
  friend bool operator==(const JointHandle&, const JointHandle&) = default;
};

/// A joint-state vector's layout: joints in a fixed order (made at build time by
/// SceneGraph::MakeJointGroup; only independent movable joints: no fixed or mimic joints).
struct JointGroup {
  std::vector<JointHandle> joints;
  [[nodiscard]] std::size_t size() const noexcept { return joints.size(); }
};

/// A joint value by name (build-time setting: SceneGraph::SetJoints).
struct JointValue {
  std::string_view joint;
  double value = 0;
};

namespace internal {

/// sin(x) and cos(x) within ~1 ulp (fast for |x| <= 1e5, std::sin/cos beyond). noexcept.
SEMGRAPH_CORE_EXPORT void SinCos(double x, double& s, double& c) noexcept;

struct JointRecord {
  semantics::NameId name;  ///< in JointTable::names
  JointType type = JointType::kFixed;
  bool alive = false;
  std::uint32_t generation = 0;
  topology::FrameIndex parent, child;
  topology::BodyIndex parent_body, child_body;
  Eigen::Quaterniond q_origin = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double lower = 0, upper = 0;
  JointIndex master;  ///< mimic: the master (invalid: not a mimic)
  double multiplier = 1, offset = 0;
  std::vector<JointIndex> mimics;  ///< master: its mimics
  double q = 0, qdot = 0;          ///< the current state (stamped joints: the newest sample's)
  double qddot = 0;                ///< the acceleration, meaningful when has_qddot
  bool has_qddot = false;          ///< qddot was given (its twist edge carries an acceleration)
  /// Set without a stamp at least once (docs/time.md): its edges are timeless and take no
  /// stamped state (stamp_mismatch). A stamped joint is one whose edges have histories.
  bool timeless = false;

  [[nodiscard]] bool movable() const noexcept { return type != JointType::kFixed; }
  [[nodiscard]] bool is_mimic() const noexcept { return master.is_valid(); }
  [[nodiscard]] bool limited() const noexcept {
    return type == JointType::kRevolute || type == JointType::kPrismatic;
  }
  /// X_PC(q) = X_origin M(q): rotation and position of {c} in {p}. O(1) (one sincos).
  void PoseAt(double position, Eigen::Quaterniond& q_PC, Eigen::Vector3d& p_PoCo_P) const noexcept;
  /// The edge's screw twist at velocity qdot: (v, w) of {c}|C wrt P at c, in [c].
  void TwistAt(double velocity, Eigen::Vector3d& v, Eigen::Vector3d& w) const noexcept;
  /// The edge's acceleration at qddot, in the edge form: (a, alpha) of {c}|C wrt P at c, in [c].
  void AccelerationAt(double acceleration, Eigen::Vector3d& a,
                      Eigen::Vector3d& alpha) const noexcept;
};

/// The joints of one scene graph (see the file comment for the invariants).
struct JointTable {
  std::vector<JointRecord> joints;
  semantics::NameTable names;                                    ///< joint names
  std::vector<JointIndex> of_name;                               ///< by name id: live joint
  std::unordered_map<std::uint32_t, JointIndex> joint_of_child;  ///< child frame -> joint
  std::size_t num_alive = 0;

  [[nodiscard]] const JointRecord& operator[](JointIndex j) const noexcept {
    return joints[j.value()];
  }
  [[nodiscard]] JointRecord& operator[](JointIndex j) noexcept { return joints[j.value()]; }
  [[nodiscard]] std::string_view name(const JointRecord& j) const noexcept {
    return names.name(j.name);
  }
  /// The live joint whose child frame is `child` (nullptr if none). O(1) expected.
  [[nodiscard]] const JointRecord* OfChild(topology::FrameIndex child) const noexcept {
    if (joint_of_child.empty()) return nullptr;  // most scenes: no hash on the pose-update path
    const auto it = joint_of_child.find(child.value());
    return it == joint_of_child.end() ? nullptr : &(*this)[it->second];
  }
  /// The live joint named `id` / `name` (nullptr if none). Allocation-free.
  [[nodiscard]] const JointRecord* Find(semantics::NameId id) const noexcept {
    if (!id.is_valid() || id.value() >= of_name.size() || !of_name[id.value()].is_valid())
      return nullptr;
    return &(*this)[of_name[id.value()]];
  }
  [[nodiscard]] const JointRecord* Find(std::string_view name) const noexcept {
    return Find(names.Find(name));
  }
  [[nodiscard]] const JointRecord* Get(JointHandle h) const noexcept {
    if (!h.index.is_valid() || h.index.value() >= joints.size()) return nullptr;
    const JointRecord& j = (*this)[h.index];
    return j.alive && j.generation == h.generation ? &j : nullptr;
  }
  [[nodiscard]] JointIndex IndexOf(const JointRecord& j) const noexcept {
    return JointIndex(static_cast<std::uint32_t>(&j - joints.data()));
  }
  [[nodiscard]] JointHandle HandleOf(const JointRecord& j) const noexcept {
    return JointHandle{IndexOf(j), j.generation};
  }
};

}  // namespace internal
}  // namespace semgraph::core
