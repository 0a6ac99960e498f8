// File: semgraph/core/scene_graph.h
//
// SceneGraph<B>: the constrained directed forest of De Laet et al. (IROS 2013, §IV), with the
// rules of spec/scene-graph.md. Body nodes contain frame nodes; pose edges {t} -> {h} store
// PoseCoord({h}|H, {t}|T, [t]); twist edges D -> {h}|H store the screw twist
// TwistCoord(h|H, D, [h]). Every add is checked against the invariants P1-P4, W1-W4 and is
// atomic; queries follow the paper's Algorithms 1-3 in natural order, each step a checked
// semantics/coord operation. B is the coordinate backend (quaternion by default, homogeneous).
//
// Invariants (kept by every accepted operation; CheckInvariants() verifies them):
//  P1 a frame has at most one pose parent; P2 pose edges form a forest; P3 in every pose tree
//  the frames of one body are connected through same-body edges only; P4 same-body edges are
//  constant; W1 a frame has at most one twist parent; W2 no twist from a body to itself; W3 per
//  pose tree the body-level twist graph TG(P) is a forest; W4 (pose merges keep W3).
//
// Costs (n = frames, d = depth of the frames involved, |T| = frames of an affected pose tree,
// b = bodies in a tree's body set, k = twist edges on a path):
//   AddBody, AddFrame                   O(|name|) amortized
//   AddPose, new leaf frame             O(log n) (union-find, jump pointer, body-set lookup)
//   AddPose, linking tree T under t     O(|T|) (depths and jumps of T) + O(min(b1, b2)) (P3 check,
//                                       body-set merge smaller into larger) + O(twist edges) (W4)
//   AddPose in non-edge form            + the conversion: three basic-pose queries
//   AddPose, update of an existing edge O(1) after name lookup (no topology change)
//   AddTwist                            O(depth in TG) + conversion query when [r] != [h]
//   RemovePose                          O(|T|) for the tree being split (rebuilds its sets)
//   RemoveTwist                         O(size of the detached part of TG)
//   rejection of P1, P2, P3, W3         O(log n) + O(min(b1, b2)); never walks a pose tree
//   GetPose/Position/Orientation        O(log n + d) compositions (common ancestor by jumps)
//   GetTwist and velocities             O(k (log n + d))
// Build-time calls allocate and return Expected<Ok, BuildError> with a formatted message.
// Queries are noexcept, allocation-free, lock-free; they return a small QueryError.
// Thread safety: const queries may run concurrently with each other; any add/remove needs
// exclusive access.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/core/disjoint_sets.h"
#include "semgraph/core/flat_map.h"
#include "semgraph/core/ids.h"
#include "semgraph/core/pose_forest.h"
#include "semgraph/core/seqlock_value.h"
#include "semgraph/core/twist_forest.h"
#include "semgraph/semantics/names.h"

namespace semgraph::core {

using semantics::ErrorCode;
using semantics::Expected;
using semantics::NameId;
using semantics::Ok;

/// A rejected build-time operation: a stable code (spec §4) and a message naming the frames /
/// bodies involved and the existing relation it conflicts with.
struct BuildError {
  ErrorCode code = ErrorCode::kOk;
  std::string message;
};
using BuildResult = Expected<Ok, BuildError>;

/// A failed query: small, trivially copyable, no strings (formatted later by Describe).
struct QueryError {
  ErrorCode code = ErrorCode::kOk;
  semantics::Field field = semantics::Field::kPoint;  ///< the argument that is unknown/mismatched
  NameId name;   ///< that argument's name (invalid if the name was never interned)
  NameId other;  ///< frame_body_mismatch: the frame's actual body; no_pose_path: the other frame
  NameId asked;  ///< frame_body_mismatch: the body the query named for that frame
  coord::Error detail;  ///< representation_constraint / semantic_mismatch details
};
template <class T>
using QueryResult = Expected<T, QueryError>;

/// The names of a pose, position or orientation, by role. Build with the helpers:
///   PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2").ExpressedIn("c")
/// Of(x) sets point = orientation = x; RelativeTo(y) sets ref point = ref orientation =
/// coordinate frame = y; ExpressedIn(r) then overrides the coordinate frame. Bodies may be empty
/// when the frames exist (they are then taken from the frames, and checked when given).
struct PoseSpec {
  std::string_view point, orientation, body;
  std::string_view ref_point, ref_orientation, ref_body;
  std::string_view coordinate_frame;

  static PoseSpec Of(std::string_view frame, std::string_view body_name = {}) {
    PoseSpec s;
    s.point = s.orientation = frame;
    s.body = body_name;
    return s;
  }
  PoseSpec& RelativeTo(std::string_view frame, std::string_view body_name = {}) {
    ref_point = ref_orientation = coordinate_frame = frame;
    ref_body = body_name;
    return *this;
  }
  PoseSpec& ExpressedIn(std::string_view frame) {
    coordinate_frame = frame;
    return *this;
  }
  PoseSpec& AtPoint(std::string_view p) {
    point = p;
    return *this;
  }
  PoseSpec& RelativeToPoint(std::string_view p) {
    ref_point = p;
    return *this;
  }
};

/// The names of a twist / linear / angular velocity: point e (any frame's origin: the point of
/// `body` coinciding with it), body C (default: the body of e's frame), ref body D, [r].
///   TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2")
struct TwistSpec {
  std::string_view point, body, ref_body, coordinate_frame;

  static TwistSpec Of(std::string_view point_name, std::string_view body_name = {}) {
    TwistSpec s;
    s.point = point_name;
    s.body = body_name;
    return s;
  }
  TwistSpec& RelativeTo(std::string_view body_name) {
    ref_body = body_name;
    return *this;
  }
  TwistSpec& ExpressedIn(std::string_view frame) {
    coordinate_frame = frame;
    return *this;
  }
};

/// Bytes of B::PoseCoords that carry data (B::kPosePayloadBytes when the backend declares it).
template <coord::Backend B>
constexpr std::size_t PosePayloadBytes() noexcept {
  if constexpr (requires { B::kPosePayloadBytes; }) {
    return B::kPosePayloadBytes;
  } else {
    return sizeof(typename B::PoseCoords);
  }
}
template <coord::Backend B>
using PoseValue = SeqLockValue<typename B::PoseCoords, PosePayloadBytes<B>()>;

/// A resolved pose edge, for O(1) value updates from a control loop (see SetPose).
struct PoseHandle {
  FrameIndex child;         ///< the edge's head frame
  std::uint32_t epoch = 0;  ///< the edge's epoch when the handle was made
};
/// A resolved twist edge, for O(1) value updates (see SetTwist).
struct TwistHandle {
  std::uint32_t slot = 0xFFFFFFFFu;
  std::uint32_t epoch = 0;
};

template <coord::Backend B>
class CompiledPose;
template <coord::Backend B>
class CompiledPosition;
template <coord::Backend B>
class CompiledOrientation;
template <coord::Backend B>
class CompiledTwist;
template <coord::Backend B>
class CompiledQuery;

template <coord::Backend B = coord::QuaternionBackend>
class SceneGraph {
 public:
  using Backend = B;
  using Pose = coord::Pose<B>;
  using Orientation = coord::Orientation<B>;

  SceneGraph() = default;
  SceneGraph(const SceneGraph&) = delete;
  SceneGraph& operator=(const SceneGraph&) = delete;
  SceneGraph(SceneGraph&&) = default;
  SceneGraph& operator=(SceneGraph&&) = default;

  // ---------------------------------------------------------------- build (allocates)

  /// invalid_name -> duplicate_body.
  BuildResult AddBody(std::string_view name);
  /// invalid_name -> frame_without_body (empty body) -> duplicate_frame -> unknown_body.
  BuildResult AddFrame(std::string_view name, std::string_view body);

  /// Adds PoseCoord((point,[orientation])|body, (ref_point,[ref_orientation])|ref_body, [coord])
  /// as the edge [ref_orientation]'s frame -> [orientation]'s frame, converting a non-edge form
  /// once, or updates the value of that existing edge. Creates missing frames/bodies named with
  /// their body. Order of checks: spec §4.
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                      const Eigen::Vector3d& p_position);
  /// Same, rotation given as a matrix (columns: axes of [orientation] in [ref_orientation] when
  /// coord = ref_orientation).
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                      const Eigen::Vector3d& p_position);
  /// Adds TwistCoord(point|body, ref_body, [coord]) as the twist edge ref_body -> {point}|body,
  /// converted to the screw twist at {point} when coord != point, or updates that edge.
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular);
  /// Removes the pose edge {wrt} -> {of}. invalid_name -> unknown_frame -> no_such_edge.
  BuildResult RemovePose(std::string_view of, std::string_view wrt);
  /// Removes the twist edge ref_body -> {point}. invalid_name -> unknown_frame/unknown_body ->
  /// no_such_edge.
  BuildResult RemoveTwist(std::string_view point, std::string_view ref_body);

  // ---------------------------------------------------------------- real-time path
  // See docs/realtime.md. Handles and compiled queries are made at build time (they allocate
  // and may fail with a rich error); afterwards SetPose/SetTwist and CompiledX::Evaluate are
  // noexcept, allocation-free, lock-free and string-free. One writer thread may call
  // SetPose/SetTwist while other threads evaluate compiled queries (per-edge sequence locks).

  /// Handle of the existing pose edge {wrt} -> {of}: unknown_frame, no_such_edge, or
  /// constant_pose_change for a same-body (constant) edge, which cannot be updated.
  [[nodiscard]] Expected<PoseHandle, BuildError> FindPoseEdge(std::string_view of,
                                                             std::string_view wrt) const;
  /// Handle of the existing twist edge ref_body -> {point}: unknown_frame, unknown_body,
  /// no_such_edge.
  [[nodiscard]] Expected<TwistHandle, BuildError> FindTwistEdge(std::string_view point,
                                                               std::string_view ref_body) const;
  /// New value X_TH of the edge (rotation of the head in the tail, position of the head's origin
  /// in the tail, both in [tail]). O(1). Codes: kOk, kInvalidNumber, kInvalidRotation
  /// (normalized within 1e-6), kNoSuchEdge (the edge was removed since the handle was made).
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ThHo_T) noexcept;
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                  const Eigen::Vector3d& p_ThHo_T) noexcept;
  /// New value of the screw twist of the edge: velocity of the head origin and angular velocity
  /// of the head's body relative to the tail body, both in [head]. O(1); codes as SetPose.
  [[nodiscard]] ErrorCode SetTwist(TwistHandle edge, const Eigen::Vector3d& v_linear,
                                   const Eigen::Vector3d& w_angular) noexcept;

  /// Compiled queries: the semantics are checked and the path resolved once (the same errors
  /// as the one-shot queries); Evaluate() then costs the compositions on the path only. A
  /// compiled query refers to this graph, which must outlive it and must not move.
  [[nodiscard]] Expected<CompiledPose<B>, QueryError> CompilePose(const PoseSpec& spec) const;
  [[nodiscard]] Expected<CompiledPosition<B>, QueryError> CompilePosition(const PoseSpec& spec) const;
  [[nodiscard]] Expected<CompiledOrientation<B>, QueryError> CompileOrientation(
      const PoseSpec& spec) const;
  /// Twist, linear velocity and angular velocity (use the parts of the result).
  [[nodiscard]] Expected<CompiledTwist<B>, QueryError> CompileTwist(const TwistSpec& spec) const;

  // ---------------------------------------------------------------- queries (noexcept)

  /// Error order: invalid_name (a required name empty or invalid, or a given body name invalid)
  /// -> unknown_frame -> unknown_body ->
  /// frame_body_mismatch -> no_pose_path -> representation_constraint.
  [[nodiscard]] QueryResult<Pose> GetPose(const PoseSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<coord::Position> GetPosition(const PoseSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<Orientation> GetOrientation(const PoseSpec& spec) const noexcept;
  /// ... -> no_pose_path (point and coordinate frame in different trees) -> no_twist_path.
  [[nodiscard]] QueryResult<coord::Twist> GetTwist(const TwistSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<coord::LinearVelocity> GetLinearVelocity(
      const TwistSpec& spec) const noexcept;
  /// Uses body, ref_body and coordinate_frame only.
  [[nodiscard]] QueryResult<coord::AngularVelocity> GetAngularVelocity(
      const TwistSpec& spec) const noexcept;

  /// The same queries on semantics made of this graph's name ids (see names()).
  [[nodiscard]] QueryResult<Pose> GetPose(const semantics::PoseSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<coord::Position> GetPosition(
      const semantics::PositionSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<Orientation> GetOrientation(
      const semantics::OrientationSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<coord::Twist> GetTwist(const semantics::TwistSemantics& q) const noexcept;

  // ---------------------------------------------------------------- inspection

  [[nodiscard]] const semantics::NameTable& names() const noexcept { return names_; }
  [[nodiscard]] std::size_t num_frames() const noexcept { return frames_.size(); }
  [[nodiscard]] std::size_t num_bodies() const noexcept { return bodies_.size(); }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return num_pose_edges_; }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return num_twist_edges_; }
  [[nodiscard]] FrameIndex FindFrame(std::string_view name) const noexcept;
  [[nodiscard]] BodyIndex FindBody(std::string_view name) const noexcept;
  [[nodiscard]] std::string_view frame_name(FrameIndex f) const noexcept;
  [[nodiscard]] std::string_view body_name(BodyIndex b) const noexcept;
  [[nodiscard]] BodyIndex body_of(FrameIndex f) const noexcept { return frames_[f.value()].body; }
  /// Pose parent of f (invalid for a root) and the stored edge value X_PF in [P].
  [[nodiscard]] FrameIndex pose_parent(FrameIndex f) const noexcept { return forest_.parent(f); }
  [[nodiscard]] typename B::PoseCoords pose_value(FrameIndex f) const noexcept {
    return X_PF_[f.value()].Load();
  }
  /// Twist parent body of f (invalid if none) and the stored screw twist (v, w) at f in [f].
  [[nodiscard]] BodyIndex twist_parent(FrameIndex f) const noexcept;
  [[nodiscard]] std::optional<coord::Twist> twist_value(FrameIndex f) const noexcept;
  [[nodiscard]] FrameIndex tree_root(FrameIndex f) const noexcept { return forest_.Root(f); }

  /// Text for a query error. `spec_name` is the name of the argument when it was never interned
  /// (unknown names passed by string); pass the offending string from your spec.
  [[nodiscard]] std::string Describe(const QueryError& e) const;
  [[nodiscard]] std::string Describe(const QueryError& e, const PoseSpec& spec) const;
  [[nodiscard]] std::string Describe(const QueryError& e, const TwistSpec& spec) const;

  /// A canonical, complete text dump of the graph (names, ids, topology, values, twist trees),
  /// for tests and fuzzers comparing state before and after a rejected operation.
  [[nodiscard]] std::string Dump() const;
  /// Verifies every invariant from scratch (slow; tests). Empty string when all hold.
  [[nodiscard]] std::string CheckInvariants() const;
  /// Heap bytes of the graph's structures, excluding the name strings and name index.
  [[nodiscard]] std::size_t ApproximateBytesExcludingNames() const noexcept;

  // Graphviz export support: iterate edges.
  template <class F>
  void ForEachPoseEdge(F&& f) const {
    for (std::uint32_t i = 0; i < frames_.size(); ++i) {
      const FrameIndex child(i);
      if (forest_.parent(child).is_valid()) f(forest_.parent(child), child);
    }
  }
  template <class F>
  void ForEachTwistEdge(F&& f) const {
    for (const TwistEdge& e : twist_edges_) {
      if (e.alive) f(e.tail, e.head);
    }
  }

 private:
  friend class CompiledQuery<B>;
  struct TwistNumbers {
    Eigen::Vector3d v;  // velocity of the head origin, in [head]
    Eigen::Vector3d w;  // angular velocity, in [head]
  };
  struct FrameNode {
    NameId name;
    BodyIndex body;
    std::uint32_t twist_edge = kNone;      // index into twist_edges_ of the edge into this frame
    std::uint32_t next_in_body = kNone;    // intrusive list of a body's frames
  };
  struct BodyNode {
    NameId name;
    std::uint32_t first_frame = kNone;
  };
  struct TwistEdge {
    BodyIndex tail;
    FrameIndex head;
    bool alive = false;
    semantics::TwistSemantics semantics;  // screw twist TwistCoord(h|H, D, [h])
    SeqLockValue<TwistNumbers> value;
  };
  coord::Twist LoadTwist(const TwistEdge& te) const noexcept {
    const TwistNumbers n = te.value.Load();
    return coord::Twist{te.semantics, n.v, n.w};
  }
  struct TreeRecord {
    FlatMap<std::uint32_t> body_counts;  // body -> number of its frames in this tree
    TwistForest twists;                  // TG(P), edge ids = twist_edges_ indices
  };
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;

  // Resolution of one named frame of an add: existing node, or to be created on `body`.
  struct FrameRef {
    NameId name;
    FrameIndex index;  // invalid when the frame does not exist yet
    NameId body_name;
    BodyIndex body;    // invalid when the body does not exist yet
  };

  template <class R>
  BuildResult AddPoseImpl(const PoseSpec& spec, const R& rotation, const Eigen::Vector3d& p);
  template <class R>
  ErrorCode SetPoseImpl(PoseHandle edge, const R& rotation, const Eigen::Vector3d& p) noexcept;

  std::optional<QueryError> ResolveFrameNames(std::span<const std::string_view> fields,
                                              std::span<const semantics::Field> kinds,
                                              std::span<NameId> ids, std::string_view body,
                                              std::string_view ref_body) const noexcept;
  std::optional<QueryError> ResolveBodyName(std::string_view body, NameId frame, semantics::Field field,
                                            NameId& id) const noexcept;

  // Semantics ids of frame nodes / bodies.
  semantics::Frame FrameSem(FrameIndex f) const noexcept {
    return semantics::Frame(frames_[f.value()].name);
  }
  semantics::Body BodySem(BodyIndex b) const noexcept { return semantics::Body(bodies_[b.value()].name); }
  semantics::Body BodyOfSem(FrameIndex f) const noexcept { return BodySem(frames_[f.value()].body); }

  // Query building blocks. All noexcept; every step a checked coord operation.
  Pose EdgePose(FrameIndex child) const noexcept;
  Pose IdentityPose(FrameIndex f) const noexcept;
  coord::Result<Pose> PoseUpTo(FrameIndex f, FrameIndex ancestor) const noexcept;
  /// PoseCoord({a}|A, {b}|B, [b]); a and b in one tree.
  coord::Result<Pose> BasicPose(FrameIndex a, FrameIndex b) const noexcept;
  coord::Result<coord::Twist> TwistUpTo(FrameIndex e, FrameIndex r, const TreeRecord& rec,
                                        std::uint32_t body, std::uint32_t ancestor) const noexcept;
  coord::Result<coord::Twist> EdgeTwistAt(std::uint32_t edge, std::uint32_t from_body,
                                          FrameIndex e, FrameIndex r) const noexcept;

  // Tree records.
  const TreeRecord* RecordOf(FrameIndex f) const noexcept;
  TreeRecord& EnsureRecord(FrameIndex f);
  TreeRecord& NewRecord(std::uint32_t rep, FrameIndex f);
  bool TreeHasBody(FrameIndex f, BodyIndex body) const noexcept;
  /// P3: a body in both trees, other than `allowed` (invalid if none).
  BodyIndex SharedBody(FrameIndex t, FrameIndex h, BodyIndex allowed) const noexcept;
  FrameIndex SomeFrameOfBodyInTree(BodyIndex body, FrameIndex tree_member) const noexcept;
  void RebuildTree(FrameIndex root, std::vector<std::uint32_t>& twist_edges);

  // Nodes.
  BodyIndex CreateBody(NameId name);
  FrameIndex CreateFrame(NameId name, BodyIndex body);
  void GrowNameMaps();
  FrameIndex FrameOfName(NameId id) const noexcept {
    return id.is_valid() && id.value() < frame_of_name_.size() ? FrameIndex(frame_of_name_[id.value()])
                                                                : FrameIndex();
  }
  BodyIndex BodyOfName(NameId id) const noexcept {
    return id.is_valid() && id.value() < body_of_name_.size() ? BodyIndex(body_of_name_[id.value()])
                                                               : BodyIndex();
  }

  // Text.
  std::string FrameText(FrameIndex f) const;
  std::string PoseText(const semantics::PoseSemantics& s) const;

  semantics::NameTable names_;
  std::vector<std::uint32_t> frame_of_name_;  // NameId -> FrameIndex (kNone if not a frame)
  std::vector<std::uint32_t> body_of_name_;   // NameId -> BodyIndex
  std::vector<FrameNode> frames_;
  std::vector<BodyNode> bodies_;
  // Value (and epoch) of each frame's parent pose edge, X_PF in [P]: a sequence lock each, so
  // a control loop can update joint poses while queries read them.
  std::vector<PoseValue<B>> X_PF_;
  PoseForest forest_;
  DisjointSets trees_;                        // which pose tree a frame is in
  FlatMap<std::uint32_t> record_of_rep_;      // union-find representative -> records_ index
  std::vector<TreeRecord> records_;
  std::vector<std::uint32_t> free_records_;
  std::vector<TwistEdge> twist_edges_;
  std::vector<std::uint32_t> free_twist_edges_;
  std::size_t num_pose_edges_ = 0;
  std::size_t num_twist_edges_ = 0;
};

extern template class SceneGraph<coord::QuaternionBackend>;
extern template class SceneGraph<coord::HomogeneousBackend>;

}  // namespace semgraph::core
