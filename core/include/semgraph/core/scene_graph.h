// File: semgraph/core/scene_graph.h
//
// SceneGraph<B>: the constrained directed forest of De Laet et al. (IROS 2013, §IV), with the
// rules of docs/rules.md. Body nodes contain frame nodes; pose edges {t} -> {h} store
// PoseCoord({h}|H, {t}|T, [t]); twist edges D -> {h}|H store the screw twist
// TwistCoord(h|H, D, [h]). Every add is checked against the invariants P1-P4, W1-W4 and is
// atomic; queries follow the paper's Algorithms 1-3 in natural order. B is the coordinate
// backend (quaternion by default, homogeneous).
//
// This header is the API. The parts behind it (docs/architecture.md): the topology and the
// rules (topology/scene_topology.h, topology/rules.h; no numbers), the edge values
// (edge_values.h), query plans (query_plan.h: names resolved and semantics checked once) and
// the one evaluator of the algorithms (evaluate.h), shared by one-shot queries, compiled
// queries (compiled_query.h) and the edge-form conversion of adds.
//
// Invariants (kept by every accepted operation; CheckInvariants(graph) in scene_graph_debug.h
// verifies them):
//  P1 a frame has at most one pose parent; P2 pose edges form a forest; P3 in every pose tree
//  the frames of one body are connected through same-body edges only; P4 same-body edges are
//  constant; W1 a frame has at most one twist parent; W2 no twist from a body to itself; W3 per
//  pose tree the body-level twist graph TG(P) is a forest; W4 (pose merges keep W3).
//
// Costs (n = frames, d = depth of the frames involved, |T| = frames of an affected pose tree,
// b = bodies in a tree's body set, k = twist edges on a path):
//   AddBody, AddFrame                   O(|name|) amortized
//   AddPose, new leaf frame             O(1) amortized (jump pointer, body-set lookup)
//   AddPose, linking tree T under t     O(log n) amortized (the smaller tree's depths and jumps,
//                                       whatever the order of the adds) + O(min(b1, b2)) (P3
//                                       check, body-set merge smaller into larger)
//                                       + O(twist edges) (W4)
//   AddPose in non-edge form            + the conversion: three basic-pose queries
//   AddPose, update of an existing edge O(1) after name lookup (no topology change)
//   AddTwist                            O(depth in TG) + conversion query when [r] != [h]
//   RemovePose                          O(|T|) for the tree being split (rebuilds its sets)
//   RemoveTwist                         O(size of the detached part of TG)
//   rejection of P1, P2, P3, W3         O(log n) + O(min(b1, b2)); never walks a pose tree
//   GetPose/Position/Orientation        O(log n + d) compositions (common ancestor by jumps)
//   GetTwist and velocities             O(k (log n + d))
// Build-time calls allocate and return Expected<Ok, BuildError> with a formatted message. Out
// of memory, they throw std::bad_alloc and leave the graph exactly as it was: each makes every
// allocation it needs before its first change (tests/core/add_out_of_memory_test.cc).
// Queries are noexcept, allocation-free, lock-free; they return a small QueryError.
// Thread safety (docs/realtime.md, "Topology changes while readers run"): one writer thread
// makes every add, remove, Reserve and value update. Concurrently with it, any number of reader
// threads may evaluate compiled queries, ask the one-shot pose and twist queries (GetPose,
// GetPosition, GetOrientation, GetTwist, GetLinearVelocity, GetAngularVelocity: by name or ids,
// untimed or timed, extrapolating too) and compile pose and twist queries (CompilePose,
// CompilePosition, CompileOrientation, CompileTwist): these read the topology optimistically,
// validated by its change counter, and retry when a change overlapped; a query that never
// finds the topology quiet (32 attempts) returns kQueryInvalidated. Everything else
// (Jacobians, Find*Edge, FindJoint, Explain*, Describe, the inspection views) runs on the
// writer thread or is ordered with the changes by the caller.
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
#include "semgraph/core/accelerations.h"
#include "semgraph/core/compiled_acceleration.h"
#include "semgraph/core/compiled_covariance.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/compiled_twist_covariance.h"
#include "semgraph/core/converting_handles.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/export.h"
#include "semgraph/core/jacobian.h"
#include "semgraph/core/joints.h"
#include "semgraph/core/specs.h"
#include "semgraph/core/time.h"
#include "semgraph/core/uncertainty.h"
#include "semgraph/core/update_error.h"
#include "semgraph/core/wrenches.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core {

namespace internal {
// The one door of the debug unit (scene_graph_debug.h: Dump, CheckInvariants) into a graph's
// private state; defined in scene_graph_debug.cc only, so nothing else can use it.
struct DebugAccess;
// The one add pipeline's plan and result (core/src/add_plan.h; private to the .cc files).
struct AddPlan;
struct AddedEdges;
}  // namespace internal

template <coord::Backend B = coord::QuaternionBackend>
class SEMGRAPH_CORE_EXPORT SceneGraph {
 public:
  using Backend = B;
  using Pose = coord::Pose<B>;
  using Orientation = coord::Orientation<B>;

  SceneGraph() = default;
  /// A graph with time options (docs/time.md). A window that is not positive, or a sample
  /// capacity below 2, is refused (invalid_number) and no graph is made.
  [[nodiscard]] static Expected<SceneGraph, BuildError> Create(const TimeOptions& options);
  [[nodiscard]] const TimeOptions& time_options() const noexcept { return values_.history.options; }
  SceneGraph(const SceneGraph&) = delete;
  SceneGraph& operator=(const SceneGraph&) = delete;
  SceneGraph(SceneGraph&&) = default;
  SceneGraph& operator=(SceneGraph&&) = default;

  // ---------------------------------------------------------------- build (allocates)

  /// Reserves room for `frames` frames and `bodies` bodies in total (and their names, at
  /// `name_bytes` bytes each on average), so that building a scene of known size does not
  /// reallocate as it grows.
  void Reserve(std::size_t frames, std::size_t bodies);

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
  /// Same, from an Eigen isometry: X.linear() the rotation matrix, X.translation() the position
  /// (e.g. coord::Pose<B>::ToIsometry() of a query's answer).
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Isometry3d& X) {
    return AddPose(spec, Eigen::Matrix3d(X.linear()), Eigen::Vector3d(X.translation()));
  }
  /// Adds TwistCoord(point|body, ref_body, [coord]) as the twist edge ref_body -> {point}|body,
  /// converted to the screw twist at {point} when coord != point, or updates that edge.
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular);
  /// The same adds with repair of a rejected relation (docs/repair.md): P1 -> the inverse pose
  /// (after re-rooting the inverse's head tree if needed); W1 -> the inverse twist on a frame of
  /// the reference body; an already determined relation (pose_cycle, or P1 within one tree;
  /// duplicate_twist_path) -> accepted as a no-op when it equals the derived value within the
  /// policy's tolerances, else refused with the discrepancy. Without a repair the result and
  /// the graph are exactly those of the plain add.
  Expected<RepairReport, BuildError> AddPose(const PoseSpec& spec,
                                             const Eigen::Quaterniond& q_rotation,
                                             const Eigen::Vector3d& p_position,
                                             const RepairPolicy& repair);
  Expected<RepairReport, BuildError> AddTwist(const TwistSpec& spec,
                                              const Eigen::Vector3d& v_linear,
                                              const Eigen::Vector3d& w_angular,
                                              const RepairPolicy& repair);
  /// Removes the pose edge {relative_to} -> {of}. invalid_name -> unknown_frame -> no_such_edge.
  BuildResult RemovePose(std::string_view of, std::string_view relative_to);
  /// Removes the twist edge {relative_to} -> {of} (a body to a frame). invalid_name ->
  /// unknown_frame/unknown_body -> no_such_edge.
  BuildResult RemoveTwist(std::string_view of, std::string_view relative_to);

  // ---------------------------------------------------------------- time (docs/time.md)
  // A stamped value: the edge becomes stamped on its first value (its history is allocated
  // then, `sample_capacity` samples), or gets a new sample. Same checks as the unstamped adds,
  // then stamp_mismatch -> stamp_too_old -> duplicate_stamp; a value in another form is
  // converted with the graph's values at the stamp (extrapolation when there are none). A
  // same-body (constant) edge is timeless: the stamp then only serves the conversion.
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                      const Eigen::Vector3d& p_position, Stamp stamp);
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                      const Eigen::Vector3d& p_position, Stamp stamp);
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular, Stamp stamp);
  /// A stamped value with a covariance (docs/uncertainty.md, "Time"): the sample carries it
  /// (converted to the edge form with the values at the stamp); the checks of both adds. The
  /// covariance is part of the sample's value for duplicate_stamp.
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                      const Eigen::Vector3d& p_position, Stamp stamp,
                      const CovarianceInput& covariance);
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                      const Eigen::Vector3d& p_position, Stamp stamp,
                      const CovarianceInput& covariance);
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular, Stamp stamp,
                       const CovarianceInput& covariance);
  /// A stamped sample of a stamped edge by handle: O(1) amortized in order, O(later samples)
  /// out of order; never allocates. Codes as SetPose, then kStampMismatch (a timeless edge),
  /// kStampTooOld, kDuplicateStamp (policy reject, another value at that stamp).
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                  UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                  const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                  UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                   const Eigen::Vector3d& w_DH_H, Stamp stamp,
                                   UpdateError* why = nullptr) noexcept;

  /// Queries under a time policy: the same queries with every edge's value as the policy
  /// selects, and what was read (TimeReport). Error order: as the untimed query, invalid_number
  /// (a negative horizon) after invalid_name, then ... -> extrapolation -> stale.
  [[nodiscard]] QueryResult<Timed<Pose>> GetPose(const PoseSpec& spec,
                                                 const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<coord::Position>> GetPosition(
      const PoseSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<Orientation>> GetOrientation(
      const PoseSpec& spec, const TimePolicy& policy) const noexcept;
  /// Time travel: the point side at travel.time, the reference side at travel.ref_time, through
  /// travel.fixed_frame (unknown_frame, or no_pose_path when not in the query's pose tree).
  [[nodiscard]] QueryResult<Timed<Pose>> GetPose(const PoseSpec& spec,
                                                 const TimeTravel& travel) const noexcept;
  [[nodiscard]] QueryResult<Timed<coord::Position>> GetPosition(
      const PoseSpec& spec, const TimeTravel& travel) const noexcept;
  [[nodiscard]] QueryResult<Timed<Orientation>> GetOrientation(
      const PoseSpec& spec, const TimeTravel& travel) const noexcept;
  /// Twists from the twist edges (default) or differentiated from the pose history.
  [[nodiscard]] QueryResult<Timed<coord::Twist>> GetTwist(
      const TwistSpec& spec, const TimePolicy& policy,
      TwistSource source = TwistSource::kTwists) const noexcept;
  [[nodiscard]] QueryResult<Timed<coord::LinearVelocity>> GetLinearVelocity(
      const TwistSpec& spec, const TimePolicy& policy,
      TwistSource source = TwistSource::kTwists) const noexcept;
  [[nodiscard]] QueryResult<Timed<coord::AngularVelocity>> GetAngularVelocity(
      const TwistSpec& spec, const TimePolicy& policy,
      TwistSource source = TwistSource::kTwists) const noexcept;
  /// Diagnostics (allocates): every edge the query uses, with its samples and the ones read.
  [[nodiscard]] Expected<std::vector<EdgeUse>, QueryError> ExplainPose(
      const PoseSpec& spec, const TimePolicy& policy) const;
  [[nodiscard]] Expected<std::vector<EdgeUse>, QueryError> ExplainTwist(
      const TwistSpec& spec, const TimePolicy& policy,
      TwistSource source = TwistSource::kTwists) const;
  /// A compiled twist whose twists come from `source` (CompileTwist(spec) = kTwists).
  [[nodiscard]] Expected<CompiledTwist<B>, QueryError> CompileTwist(const TwistSpec& spec,
                                                                    TwistSource source) const;
  /// Heap bytes of one stored pose sample (a stamped edge preallocates sample_capacity of them).
  [[nodiscard]] static constexpr std::size_t BytesPerPoseSample() noexcept {
    return PoseHistory::BytesPerSample();
  }

  // ---------------------------------------------------------------- real-time path
  // See docs/realtime.md. Handles and compiled queries are made at build time (they allocate
  // and may fail with a rich error); afterwards SetPose/SetTwist and CompiledX::Evaluate are
  // noexcept, allocation-free, lock-free and string-free. One writer thread may call
  // SetPose/SetTwist while other threads evaluate compiled queries (per-edge sequence locks);
  // the same writer thread may also change the topology (Add*, Remove*) meanwhile: untimed
  // compiled evaluations then answer for the graph they were compiled on or return
  // kQueryInvalidated (docs/realtime.md, "Topology changes while readers run"). One-shot pose
  // and twist queries and CompilePose/Position/Orientation/Twist may run on reader threads too
  // (validated optimistic reads); Find*Edge (handles) and Jacobians read the topology
  // unvalidated: same thread as the changes.

  /// Handle of the existing pose edge {relative_to} -> {of}: invalid_name, unknown_frame,
  /// no_such_edge, or constant_pose_change for a same-body (constant) edge, which cannot be
  /// updated.
  [[nodiscard]] Expected<PoseHandle, BuildError> FindPoseEdge(std::string_view of,
                                                              std::string_view relative_to) const;
  /// Handle of the existing twist edge {relative_to} (a body) -> {of}: invalid_name,
  /// unknown_frame, unknown_body, no_such_edge.
  [[nodiscard]] Expected<TwistHandle, BuildError> FindTwistEdge(std::string_view of,
                                                                std::string_view relative_to) const;
  /// New value X_TH of the edge (rotation of the head in the tail, position of the head's origin
  /// in the tail, both in [tail]). O(1). Codes: kOk, kInvalidNumber, kInvalidRotation
  /// (normalized within 1e-6), kNoSuchEdge (the edge was removed since the handle was made, or
  /// the handle is not one of this graph's pose handles: another graph's, default or forged,
  /// naming no frame or a root frame), kConstantPoseChange (a forged handle naming a same-body
  /// edge). On any code but kOk nothing is written.
  /// Every real-time setter takes an optional last argument `why` (update_error.h): when given,
  /// it receives the code and, for kInvalidNumber / kInvalidRotation / kJointLimit, which input,
  /// which number, its value and the limit it broke. No allocation, as the setter itself.
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ToHo_T,
                                  UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                  const Eigen::Vector3d& p_ToHo_T,
                                  UpdateError* why = nullptr) noexcept;
  /// SetPose from an Eigen isometry X_TH (linear() = R_TH, translation() = p_ToHo_T).
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Isometry3d& X_TH,
                                  UpdateError* why = nullptr) noexcept {
    return SetPose(edge, Eigen::Matrix3d(X_TH.linear()), Eigen::Vector3d(X_TH.translation()), why);
  }
  /// SetPose for a caller that guarantees the input: finite numbers, |position| <= 1e12, and a
  /// unit quaternion (|q| within 1e-12 of 1, e.g. one this graph returned or one normalized by
  /// the caller). Skips validation: about half of SetPose's cost. Debug builds check the
  /// guarantee (SEMGRAPH_DEMAND). Codes: kOk, and the handle checks of SetPose
  /// (kNoSuchEdge, kConstantPoseChange).
  [[nodiscard]] ErrorCode SetPoseUnchecked(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                           const Eigen::Vector3d& p_ToHo_T) noexcept;
  /// New value V_DH of the screw twist of the edge D -> {h}|H: velocity of h's origin and
  /// angular velocity of H relative to D, both in [h]. O(1); codes as SetPose (kNoSuchEdge for
  /// a removed edge, a free slot, or a handle not made by this graph's FindTwistEdge).
  [[nodiscard]] ErrorCode SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                   const Eigen::Vector3d& w_DH_H,
                                   UpdateError* why = nullptr) noexcept;

  /// Values in another form than the edge's, converted on the real-time path through a plan
  /// made here (converting_handles.h, docs/realtime.md). The twist edge {relative_to} (a body)
  /// -> {of}, taking twists in [expressed_in] (a frame of of's pose tree): the errors of
  /// FindTwistEdge, then invalid_name / unknown_frame (expressed_in), twist_not_convertible.
  [[nodiscard]] Expected<ConvertingTwistHandle<B>, BuildError> FindTwistEdge(
      std::string_view of, std::string_view relative_to, std::string_view expressed_in) const;
  /// The pose edge that AddPose(spec, ...) would update ([ref_orientation] -> [orientation]),
  /// taking poses in the form of `spec`: the query errors of the spec (as GetPose), then those
  /// of FindPoseEdge, representation_constraint, and pose_not_convertible when [r] lies below
  /// the edge itself (the conversion would read the value being set).
  [[nodiscard]] Expected<ConvertingPoseHandle<B>, BuildError> FindPoseEdge(
      const PoseSpec& spec) const;
  /// TwistCoord(h|H, D, [r]) in [r], rotated into [h] by R_HR and written as SetTwist(edge.edge())
  /// writes. Codes: kInvalidNumber (the input), kQueryInvalidated (an edge of the conversion was
  /// removed; nothing written), then SetTwist's. O(edges between r and h).
  [[nodiscard]] ErrorCode SetTwist(const ConvertingTwistHandle<B>& edge,
                                   const Eigen::Vector3d& v_DHo_R, const Eigen::Vector3d& w_DH_R,
                                   UpdateError* why = nullptr) noexcept;
  /// With the covariance of (v, w) in [r] (CovarianceInput: any order, `coordinates`): rotated
  /// into [h] with the value (diag(R_HR, R_HR) S diag(R_HR, R_HR)^T), then as SetTwist(edge.edge(),
  /// ..., covariance). Codes: kInvalidNumber / kInvalidCovariance (the input), kQueryInvalidated,
  /// then that SetTwist's. noexcept, allocation-free.
  [[nodiscard]] ErrorCode SetTwist(const ConvertingTwistHandle<B>& edge,
                                   const Eigen::Vector3d& v_DHo_R, const Eigen::Vector3d& w_DH_R,
                                   const CovarianceInput& covariance,
                                   UpdateError* why = nullptr) noexcept;
  /// The pose in the handle's form, converted to the edge form as AddPose converts it, then
  /// written as SetPose(edge.edge()) writes. Codes: kInvalidNumber / kInvalidRotation (the
  /// input), kQueryInvalidated, then SetPose's. O(edges of the conversion).
  [[nodiscard]] ErrorCode SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Quaterniond& q,
                                  const Eigen::Vector3d& p, UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Matrix3d& R,
                                  const Eigen::Vector3d& p, UpdateError* why = nullptr) noexcept;
  /// With the covariance of the given pose (CovarianceInput: order and convention as AddPose's):
  /// converted to the edge form with the value, through the Jacobian AddPose uses for the same
  /// conversion, then as SetPose(edge.edge(), ..., covariance). Codes: kInvalidNumber /
  /// kInvalidRotation / kInvalidCovariance (the input), kQueryInvalidated, then that SetPose's.
  [[nodiscard]] ErrorCode SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Quaterniond& q,
                                  const Eigen::Vector3d& p, const CovarianceInput& covariance,
                                  UpdateError* why = nullptr) noexcept;

  /// Compiled queries: the semantics are checked and the path resolved once (the same errors
  /// as the one-shot queries); Evaluate() then costs the compositions on the path only. A
  /// compiled query refers to this graph, which must outlive it and must not move.
  /// CompilePose, CompilePosition and CompileOrientation may run on reader threads while the
  /// writer changes the topology (then also kQueryInvalidated: see Thread safety above), and
  /// so may CompileTwist.
  [[nodiscard]] Expected<CompiledPose<B>, QueryError> CompilePose(const PoseSpec& spec) const;
  [[nodiscard]] Expected<CompiledPosition<B>, QueryError> CompilePosition(
      const PoseSpec& spec) const;
  [[nodiscard]] Expected<CompiledOrientation<B>, QueryError> CompileOrientation(
      const PoseSpec& spec) const;
  /// Twist, linear velocity and angular velocity (use the parts of the result).
  [[nodiscard]] Expected<CompiledTwist<B>, QueryError> CompileTwist(const TwistSpec& spec) const;

  // ---------------------------------------------------------------- queries (noexcept)

  /// The pose of (e,[a])|C wrt (f,[b])|D in [r] (@retval X with R_BA re-expressed in [r] and
  /// p_FoEo_R; for PoseSpec::Of("a").RelativeTo("b") that is X_BA).
  /// Error order: invalid_name (a required name empty or invalid, or a given body name invalid)
  /// -> unknown_frame -> unknown_body -> frame_body_mismatch -> no_pose_path ->
  /// representation_constraint. On a reader thread while the writer changes the topology, also
  /// query_invalidated: every attempt overlapped a change (see Thread safety above).
  [[nodiscard]] QueryResult<Pose> GetPose(const PoseSpec& spec) const noexcept;
  /// @retval p_FoEo_R: the position of point e wrt point f, in [r].
  [[nodiscard]] QueryResult<coord::Position> GetPosition(const PoseSpec& spec) const noexcept;
  /// @retval R_BA in [r]: the orientation of [a] wrt [b], as an operator in [r].
  [[nodiscard]] QueryResult<Orientation> GetOrientation(const PoseSpec& spec) const noexcept;
  /// @retval V_DC_R at e (v_DCe_R, w_DC_R): the twist of body C relative to D, at the point of
  /// C coinciding with e, in [r].
  /// ... -> no_pose_path (point and coordinate frame in different trees) -> no_twist_path.
  [[nodiscard]] QueryResult<coord::Twist> GetTwist(const TwistSpec& spec) const noexcept;
  /// @retval v_DCe_R.
  [[nodiscard]] QueryResult<coord::LinearVelocity> GetLinearVelocity(
      const TwistSpec& spec) const noexcept;
  /// @retval w_DC_R. Uses body, ref_body and coordinate_frame only.
  [[nodiscard]] QueryResult<coord::AngularVelocity> GetAngularVelocity(
      const TwistSpec& spec) const noexcept;

  /// The same queries on semantics made of this graph's name ids (see names()).
  [[nodiscard]] QueryResult<Pose> GetPose(const semantics::PoseSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<coord::Position> GetPosition(
      const semantics::PositionSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<Orientation> GetOrientation(
      const semantics::OrientationSemantics& q) const noexcept;
  [[nodiscard]] QueryResult<coord::Twist> GetTwist(
      const semantics::TwistSemantics& q) const noexcept;

  // ---------------------------------------------------------------- uncertainty
  // docs/uncertainty.md (uncertainty.cc). A value with a covariance: the checks of the plain add,
  // with invalid_number (an entry not finite or above 1e12) and invalid_covariance (not
  // symmetric within 1e-9 max(1, max|S|), or an eigenvalue below minus that) right after
  // invalid_rotation; then as the plain add. A value in another form than the edge's is stored
  // with a covariance converted through the conversion's values, taken as exact; a restated
  // constant pose needs the same covariance (constant_pose_change). Atomic as every add.
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                      const Eigen::Vector3d& p_position, const CovarianceInput& covariance);
  BuildResult AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                      const Eigen::Vector3d& p_position, const CovarianceInput& covariance);
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular, const CovarianceInput& covariance);
  /// The queries with the first-order covariance of their answer (docs/uncertainty.md §3), in
  /// `order` (6x6 answers). Errors as the plain queries. O(d log n) for poses; twists
  /// O(k d (d + log n)) (k twist edges, d edges on the chains). noexcept, allocation-free.
  [[nodiscard]] QueryResult<WithCovariance<Pose, 6>> GetPoseWithCovariance(
      const PoseSpec& spec, CovarianceOrder order = CovarianceOrder::kLinearAngular) const noexcept;
  [[nodiscard]] QueryResult<WithCovariance<coord::Position, 3>> GetPositionWithCovariance(
      const PoseSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<WithCovariance<Orientation, 3>> GetOrientationWithCovariance(
      const PoseSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<WithCovariance<coord::Twist, 6>> GetTwistWithCovariance(
      const TwistSpec& spec,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) const noexcept;
  [[nodiscard]] QueryResult<WithCovariance<coord::LinearVelocity, 3>>
  GetLinearVelocityWithCovariance(const TwistSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<WithCovariance<coord::AngularVelocity, 3>>
  GetAngularVelocityWithCovariance(const TwistSpec& spec) const noexcept;
  /// The same under a time policy or a time travel (time_uncertainty.cc; docs/uncertainty.md,
  /// "Time"): the timed query's answer and report, and the covariance of that answer with each
  /// edge's covariance at the time it is read (a sample's, or the interpolation (1 - l) S_i +
  /// l S_i+1 of two, a held twist's, an extrapolated pose edge's propagated with its
  /// integration twist's); a time travel's two sides independent. Errors as the timed queries.
  /// Twists from twist edges (TwistSource::kTwists, the default) or from the pose history
  /// (kPoses: each differentiated pose edge's twist with the covariance from its two
  /// bracketing samples, independent; docs/uncertainty.md, "Twists from poses").
  /// noexcept, allocation-free.
  [[nodiscard]] QueryResult<Timed<WithCovariance<Pose, 6>>> GetPoseWithCovariance(
      const PoseSpec& spec, const TimePolicy& policy,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<coord::Position, 3>>> GetPositionWithCovariance(
      const PoseSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<Orientation, 3>>> GetOrientationWithCovariance(
      const PoseSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<Pose, 6>>> GetPoseWithCovariance(
      const PoseSpec& spec, const TimeTravel& travel,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<coord::Position, 3>>> GetPositionWithCovariance(
      const PoseSpec& spec, const TimeTravel& travel) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<Orientation, 3>>> GetOrientationWithCovariance(
      const PoseSpec& spec, const TimeTravel& travel) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<coord::Twist, 6>>> GetTwistWithCovariance(
      const TwistSpec& spec, const TimePolicy& policy,
      CovarianceOrder order = CovarianceOrder::kLinearAngular,
      TwistSource source = TwistSource::kTwists) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<coord::LinearVelocity, 3>>>
  GetLinearVelocityWithCovariance(const TwistSpec& spec, const TimePolicy& policy,
                                  TwistSource source = TwistSource::kTwists) const noexcept;
  [[nodiscard]] QueryResult<Timed<WithCovariance<coord::AngularVelocity, 3>>>
  GetAngularVelocityWithCovariance(const TwistSpec& spec, const TimePolicy& policy,
                                   TwistSource source = TwistSource::kTwists) const noexcept;
  /// Real-time updates with a covariance (edge form: the handle's edge), noexcept and
  /// allocation-free: the codes of SetPose / SetTwist, then kInvalidNumber / kInvalidCovariance
  /// for the covariance (kInvalidCovariance too for a twist given a convention). A null matrix:
  /// the plain update (the value exact).
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ToHo_T,
                                  const CovarianceInput& covariance,
                                  UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                   const Eigen::Vector3d& w_DH_H, const CovarianceInput& covariance,
                                   UpdateError* why = nullptr) noexcept;
  /// A stamped sample with its covariance (the checks of both: SetPose / SetTwist with a
  /// covariance, then the stamp rules of the stamped SetPose / SetTwist). The handle's finder made
  /// room for a covariance in every sample of the stamped edge (21 doubles a sample of the
  /// history's capacity, once per history), so these never allocate.
  [[nodiscard]] ErrorCode SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                  const CovarianceInput& covariance,
                                  UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                   const Eigen::Vector3d& w_DH_H, Stamp stamp,
                                   const CovarianceInput& covariance,
                                   UpdateError* why = nullptr) noexcept;
  /// A compiled pose query with covariance (compiled_covariance.h): the errors of CompilePose.
  [[nodiscard]] Expected<CompiledPoseWithCovariance<B>, QueryError> CompilePoseWithCovariance(
      const PoseSpec& spec) const;
  /// Compiled position / orientation queries with covariance: the errors of CompilePosition /
  /// CompileOrientation.
  [[nodiscard]] Expected<CompiledPositionWithCovariance<B>, QueryError>
  CompilePositionWithCovariance(const PoseSpec& spec) const;
  [[nodiscard]] Expected<CompiledOrientationWithCovariance<B>, QueryError>
  CompileOrientationWithCovariance(const PoseSpec& spec) const;
  /// Compiled twist, linear and angular velocity queries with covariance
  /// (compiled_twist_covariance.h): the errors of CompileTwist / GetLinearVelocity /
  /// GetAngularVelocity (current values).
  [[nodiscard]] Expected<CompiledTwistWithCovariance<B>, QueryError> CompileTwistWithCovariance(
      const TwistSpec& spec) const;
  [[nodiscard]] Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>
  CompileLinearVelocityWithCovariance(const TwistSpec& spec) const;
  [[nodiscard]] Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>
  CompileAngularVelocityWithCovariance(const TwistSpec& spec) const;
  /// The same whose twists come from `source` (kTwists: as above; kPoses: the pose edges'
  /// derivatives, as GetTwistWithCovariance(spec, policy, order, kPoses); the errors of
  /// CompileTwist(spec, source)).
  [[nodiscard]] Expected<CompiledTwistWithCovariance<B>, QueryError> CompileTwistWithCovariance(
      const TwistSpec& spec, TwistSource source) const;
  [[nodiscard]] Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>
  CompileLinearVelocityWithCovariance(const TwistSpec& spec, TwistSource source) const;
  [[nodiscard]] Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>
  CompileAngularVelocityWithCovariance(const TwistSpec& spec, TwistSource source) const;
  /// The covariance stored with the pose edge into f / the twist edge into f, in the edge form
  /// (zero: exact, or no edge). Writer thread. O(1).
  [[nodiscard]] Covariance6 pose_covariance(FrameIndex f) const noexcept;
  [[nodiscard]] Covariance6 twist_covariance(FrameIndex f) const noexcept;

  // ---------------------------------------------------------------- joints (joints.cc)
  // A joint owns a pose edge and a twist edge whose values follow its state (joints.h,
  // docs/kinematics.md). Adds and removals are build time; setting states by group is the
  // real-time path (O(joints), noexcept, no allocation, lock-free for readers).

  /// Adds a joint. invalid_name -> invalid_number / invalid_rotation -> invalid_model (axis,
  /// limits, mimic) -> duplicate_joint -> node resolution -> self_edge / twist_same_body ->
  /// joint_edge -> P1, P2, P3, W4 -> W1, W3 (its twist edge). Atomic.
  BuildResult AddJoint(const JointSpec& spec);
  /// unknown_joint (no joint of that name).
  [[nodiscard]] Expected<JointHandle, BuildError> FindJoint(std::string_view name) const;
  /// The layout of a joint-state vector: these joints in this order. unknown_joint (no such
  /// movable joint), mimic_joint (a mimic: it follows its master), duplicate_joint (named twice).
  [[nodiscard]] Expected<JointGroup, BuildError> MakeJointGroup(
      std::span<const std::string_view> names) const;
  /// Every independent movable joint (no fixed, no mimic joints), in the order they were added.
  [[nodiscard]] JointGroup AllJoints() const;
  /// Sets positions and velocities by name, all or nothing: invalid_number -> unknown_joint ->
  /// mimic_joint -> joint_limit. A joint keeps the fields it is not given. Build time (messages).
  BuildResult SetJoints(std::span<const JointValue> positions,
                        std::span<const JointValue> velocities);
  /// The same with accelerations qddot (docs/dynamics.md): each joint given one (and its mimics,
  /// m qddot) makes its twist edge carry the acceleration it produces, kept until set again
  /// (a later qdot keeps it). Accelerations are not limited; a joint that is stamped already is
  /// stamp_mismatch, as any unstamped set of it.
  BuildResult SetJoints(std::span<const JointValue> positions,
                        std::span<const JointValue> velocities,
                        std::span<const JointValue> accelerations);
  /// Real-time setters: values in the group's order (size must equal group.size()). All or
  /// nothing: kInvalidNumber -> kUnknownJoint (a joint removed since the group was made) ->
  /// kJointLimit. O(joints + mimics), noexcept, allocation-free.
  /// `why` (as SetPose's) names the first joint in the group's order that breaks the rule of the
  /// code (why->joint), its number and the limit.
  [[nodiscard]] ErrorCode SetJointPositions(const JointGroup& group, std::span<const double> q,
                                            UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointVelocities(const JointGroup& group, std::span<const double> qdot,
                                             UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointState(const JointGroup& group, std::span<const double> q,
                                        std::span<const double> qdot,
                                        UpdateError* why = nullptr) noexcept;
  /// Accelerations qddot (as SetJoints with accelerations): the same codes but kJointLimit
  /// (accelerations are not limited), then kStampMismatch for a stamped joint; `why` names a
  /// non-finite qddot with ValueRole::kJointAcceleration. noexcept, allocation-free.
  [[nodiscard]] ErrorCode SetJointAccelerations(const JointGroup& group,
                                                std::span<const double> qddot,
                                                UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointState(const JointGroup& group, std::span<const double> q,
                                        std::span<const double> qdot, std::span<const double> qddot,
                                        UpdateError* why = nullptr) noexcept;
  /// Stamped joint states (joint_time.cc; docs/kinematics.md, docs/time.md): a sample of
  /// (q, qdot) at `stamp` for each joint given and its mimics; a field not given keeps its value
  /// of the joint's newest sample. A joint's first state decides what its edges are: set
  /// without a stamp they are timeless, with one they keep histories (allocated by this call on
  /// a joint's first stamped state). invalid_number -> unknown_joint -> mimic_joint ->
  /// joint_limit -> stamp_mismatch -> stamp_too_old -> duplicate_stamp; all or nothing.
  BuildResult SetJoints(std::span<const JointValue> positions,
                        std::span<const JointValue> velocities, Stamp stamp);
  /// With accelerations qddot (docs/dynamics.md "Stamped accelerations"): each sample carries
  /// the acceleration of its qddot (a joint given none: its newest sample's, if it ever had
  /// one, as for q and qdot), mimics m qddot; the rules and order above, a different qddot at a
  /// stored stamp being a duplicate under the reject policy. The real-time stamped setters
  /// without qddot keep the joint's qddot in their samples; those with qddot are below.
  BuildResult SetJoints(std::span<const JointValue> positions,
                        std::span<const JointValue> velocities,
                        std::span<const JointValue> accelerations, Stamp stamp);
  /// Real-time stamped setters, for joints that are stamped already (their first stamped state
  /// given by SetJoints with a stamp, else kStampMismatch; a mimic added since then too): codes
  /// as the unstamped ones, then kStampMismatch -> kStampTooOld -> kDuplicateStamp. All or
  /// nothing; O(joints + mimics) in order; noexcept, allocation-free, lock-free for readers.
  [[nodiscard]] ErrorCode SetJointPositions(const JointGroup& group, std::span<const double> q,
                                            Stamp stamp, UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointVelocities(const JointGroup& group, std::span<const double> qdot,
                                             Stamp stamp, UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointState(const JointGroup& group, std::span<const double> q,
                                        std::span<const double> qdot, Stamp stamp,
                                        UpdateError* why = nullptr) noexcept;
  /// With accelerations qddot (docs/dynamics.md "Stamped accelerations"): each sample carries
  /// the acceleration of its qddot (mimics m qddot), exactly as SetJoints with accelerations and
  /// a stamp; SetJointAccelerations keeps each joint's newest q and qdot in its sample. Codes as
  /// above (a non-finite qddot: kInvalidNumber, why->value.role kJointAcceleration); a different
  /// qddot at a stored stamp is kDuplicateStamp under the reject policy. Allocation-free: a
  /// stamped joint's twist history has room for accelerations from its first stamped state.
  [[nodiscard]] ErrorCode SetJointAccelerations(const JointGroup& group,
                                                std::span<const double> qddot, Stamp stamp,
                                                UpdateError* why = nullptr) noexcept;
  [[nodiscard]] ErrorCode SetJointState(const JointGroup& group, std::span<const double> q,
                                        std::span<const double> qdot, std::span<const double> qddot,
                                        Stamp stamp, UpdateError* why = nullptr) noexcept;
  /// Joint state and names (a stale handle: NaN / empty).
  [[nodiscard]] double joint_position(JointHandle j) const noexcept;
  [[nodiscard]] double joint_velocity(JointHandle j) const noexcept;
  /// NaN also when the joint's acceleration was never given.
  [[nodiscard]] double joint_acceleration(JointHandle j) const noexcept;
  [[nodiscard]] std::string_view joint_name(JointHandle j) const noexcept;
  [[nodiscard]] std::size_t num_joints() const noexcept { return joints_.num_alive; }
  [[nodiscard]] const internal::JointTable& joint_table() const noexcept { return joints_; }

  /// The semantic Jacobian of TwistCoord(point|body, ref_body, [coord]) (jacobian.h): one
  /// column per independent joint on the twist path, in path order from ref_body. The errors
  /// of GetTwist. Allocates the result (use CompileJacobian on the real-time path).
  [[nodiscard]] Expected<Jacobian, QueryError> GetJacobian(const TwistSpec& spec) const;
  /// The same under a time policy (docs/time.md): the poses, and the joints' twist edges, at the
  /// policy's time; the errors of a timed twist query. Allocates the result.
  [[nodiscard]] Expected<Timed<Jacobian>, QueryError> GetJacobian(const TwistSpec& spec,
                                                                  const TimePolicy& policy) const;
  [[nodiscard]] Expected<CompiledJacobian<B>, QueryError> CompileJacobian(
      const TwistSpec& spec) const;

  // ---------------------------------------------------------------- wrenches (wrenches.h)
  // docs/dynamics.md: at most one wrench per ordered pair (on C, by D), stored at the origin
  // of a frame s of C in [s] (wrenches.h: how s is chosen). wrenches.cc, wrench_query.cc.

  /// Adds (or updates) WrenchCoord(point|on, by, [coordinate_frame]) = (f, m), converted to
  /// (s, [s]) with the current poses. spec.by is required. invalid_name -> invalid_number ->
  /// unknown_frame (point, coordinate frame) -> unknown_body (on, by) -> self_wrench ->
  /// wrench_not_convertible (point, frame and s not in one pose tree) -> duplicate_wrench (the
  /// wrench on D by C is stored: this one is its reaction). Graph unchanged on any error.
  BuildResult AddWrench(const WrenchSpec& spec, const Eigen::Vector3d& f, const Eigen::Vector3d& m);
  /// The same with a stamp (nullopt: the call above): a sample of the pair, converted with the
  /// poses at its stamp (none there: extrapolation, in the place of wrench_not_convertible). The
  /// pair becomes stamped with its first value (a history of the graph's TimeOptions); then
  /// duplicate_wrench -> stamp_mismatch (stamped and timeless values of one pair) ->
  /// stamp_too_old -> duplicate_stamp, as for edges. Graph unchanged on any error.
  BuildResult AddWrench(const WrenchSpec& spec, const Eigen::Vector3d& f, const Eigen::Vector3d& m,
                        std::optional<Stamp> stamp);
  /// Removes the wrench on `on` by `by`: invalid_name -> unknown_body -> self_wrench ->
  /// no_wrench.
  BuildResult RemoveWrench(std::string_view on, std::string_view by);
  /// Handle of the stored wrench on `on` by `by` (errors of RemoveWrench).
  [[nodiscard]] Expected<WrenchHandle, BuildError> FindWrench(std::string_view on,
                                                              std::string_view by) const;
  /// New stored value (f_S, m_So_S) in the handle's storage frame [s], moment about s's origin.
  /// O(1), noexcept, allocation-free. Codes: kNoWrench (removed, another graph's or forged
  /// handle), kInvalidNumber (nothing written on either), kStampMismatch (a stamped pair).
  [[nodiscard]] ErrorCode SetWrench(WrenchHandle handle, const Eigen::Vector3d& f_S,
                                    const Eigen::Vector3d& m_So_S,
                                    UpdateError* why = nullptr) noexcept;
  /// A stamped sample (f_S, m_So_S) of a stamped pair: the codes above, then kStampMismatch (a
  /// timeless pair), kStampTooOld, kDuplicateStamp (nothing written). O(1) in order (out of
  /// order: a shift, edge_history.h), noexcept, allocation-free.
  [[nodiscard]] ErrorCode SetWrench(WrenchHandle handle, const Eigen::Vector3d& f_S,
                                    const Eigen::Vector3d& m_So_S, Stamp stamp,
                                    UpdateError* why = nullptr) noexcept;
  /// WrenchCoord(point|on, by, [coordinate_frame]): the stored wrench of the pair or the
  /// reaction of the stored one; without `by`, the net wrench on C (every stored wrench on C
  /// and the reaction of every stored wrench by C). Force and moment are the answer's parts.
  /// invalid_name -> unknown_frame -> unknown_body -> self_wrench -> no_wrench -> no_pose_path.
  [[nodiscard]] QueryResult<coord::Wrench> GetWrench(const WrenchSpec& spec) const noexcept;
  /// The same under a time policy (docs/time.md): every stored wrench (interpolated linearly in
  /// its stored form; a nearest sample held within the horizon) and the poses moving it read at
  /// the policy's time; latest common over the stamped wrenches and pose edges used. Errors: the
  /// query's (invalid_number: a negative horizon, after invalid_name), then extrapolation, stale
  /// (of a wrench: QueryTimeDetail::wrench, name/other its bodies).
  [[nodiscard]] QueryResult<Timed<coord::Wrench>> GetWrench(
      const WrenchSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] Expected<CompiledWrench<B>, QueryError> CompileWrench(const WrenchSpec& spec) const;
  [[nodiscard]] std::string Describe(const QueryError& e, const WrenchSpec& spec) const;
  [[nodiscard]] std::size_t num_wrenches() const noexcept { return wrenches_.num_live; }
  [[nodiscard]] const internal::WrenchStore& wrench_store() const noexcept { return wrenches_; }

  // ---------------------------------------------------------------- accelerations
  // docs/dynamics.md §7 (accelerations.h): a twist edge may carry AccelerationCoord(h|H, D, [h]).
  // accelerations.cc (adds), acceleration_query.cc (queries).

  /// AddTwist, with the acceleration AccelerationCoord(point|body, ref_body, [coord]) given in the
  /// same point and frame: both stored, the acceleration rotated into [point] as the twist.
  /// Errors: AddTwist's, with invalid_number for the acceleration after the twist's.
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular, const AccelerationInput& acceleration);
  /// A stamped twist sample with its acceleration (the sample's; docs/dynamics.md "Stamped
  /// accelerations"): AddTwist at a stamp, the acceleration converted with the same rotation.
  /// A stamped sample given without one carries none (never the previous sample's).
  BuildResult AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                       const Eigen::Vector3d& w_angular, Stamp stamp,
                       const AccelerationInput& acceleration);
  /// Sets the acceleration of the existing twist edge ref_body -> {h}|body (the one in the pose
  /// tree of {point}) to AccelerationCoord(point|body, ref_body, [coord]) = (a, alpha), converted
  /// to the edge form with the current poses and the edge's twist; on an edge body -> {h}|ref_body
  /// the value is the inverse relation's, inverted (not negated: Coriolis). body empty: the body
  /// of {point}. invalid_name -> invalid_number -> unknown_frame (point, coord) -> unknown_body
  /// (body, ref_body) -> no_such_edge (no twist edge between them in that tree) -> joint_edge
  /// -> stamp_mismatch (a stamped edge: its values need a stamp) -> acceleration_not_convertible
  /// ([coord] not in that tree). Graph unchanged on any error.
  BuildResult AddAcceleration(const TwistSpec& spec, const Eigen::Vector3d& a_linear,
                              const Eigen::Vector3d& alpha_angular);
  /// The acceleration of a stamped twist edge's sample at `stamp`, converted with the poses at
  /// that stamp and that sample's twist. Errors as above, with stamp_mismatch for a timeless
  /// edge, acceleration_not_convertible when the edge has no twist sample at `stamp` or a pose
  /// needed has no value there, and duplicate_stamp for another acceleration already on that
  /// sample under the reject policy (replace: replaced).
  BuildResult AddAcceleration(const TwistSpec& spec, const Eigen::Vector3d& a_linear,
                              const Eigen::Vector3d& alpha_angular, Stamp stamp);
  /// AccelerationCoord(point|body, ref_body, [coord]): the accelerations of the twist path's
  /// edges composed (accelerations.h). The errors of GetTwist, then no_acceleration (an edge on
  /// the path carries none; the error names its head frame and tail body). body == ref_body:
  /// zero.
  [[nodiscard]] QueryResult<coord::Acceleration> GetAcceleration(
      const TwistSpec& spec) const noexcept;
  [[nodiscard]] QueryResult<LinearAcceleration> GetLinearAcceleration(
      const TwistSpec& spec) const noexcept;
  /// Uses body, ref_body and coordinate_frame only (as GetAngularVelocity).
  [[nodiscard]] QueryResult<AngularAcceleration> GetAngularAcceleration(
      const TwistSpec& spec) const noexcept;
  /// Under a time policy (docs/dynamics.md "Stamped accelerations"): every edge's twist and
  /// acceleration, and the poses moving them, read at the policy's time as a timed twist query
  /// reads them (between two samples: interpolated linearly, component-wise, an acceleration
  /// present only when both samples carry one; outside within the horizon: the nearest sample
  /// held). The errors of the timed GetTwist, then no_acceleration.
  [[nodiscard]] QueryResult<Timed<coord::Acceleration>> GetAcceleration(
      const TwistSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<LinearAcceleration>> GetLinearAcceleration(
      const TwistSpec& spec, const TimePolicy& policy) const noexcept;
  [[nodiscard]] QueryResult<Timed<AngularAcceleration>> GetAngularAcceleration(
      const TwistSpec& spec, const TimePolicy& policy) const noexcept;
  /// GetAcceleration compiled (compiled_acceleration.h): the errors of GetAcceleration but
  /// no_acceleration, which Evaluate reports (kNoAcceleration) when an edge carries none then.
  [[nodiscard]] Expected<CompiledAcceleration<B>, QueryError> CompileAcceleration(
      const TwistSpec& spec) const;
  /// New acceleration of the handle's twist edge D -> {h}|H in the edge form (a_DHo_H,
  /// alpha_DH_H: at h, in [h]), stored with the edge's current twist. O(1), noexcept,
  /// allocation-free. Codes: kNoSuchEdge (as SetTwist), kJointEdge (a joint's edge),
  /// kStampMismatch (a stamped edge: its values need a stamp), kInvalidNumber; nothing written
  /// on any code but kOk. A later twist without an acceleration clears it.
  [[nodiscard]] ErrorCode SetAcceleration(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                          const Eigen::Vector3d& alpha_DH_H,
                                          UpdateError* why = nullptr) noexcept;
  /// The acceleration of a stamped twist edge's sample at `stamp` (set the twist sample first,
  /// SetTwist at the same stamp), in the edge form. The codes above, kStampMismatch also for a
  /// timeless edge or no twist sample at `stamp`, kDuplicateStamp for another acceleration on
  /// that sample under the reject policy. O(log samples), noexcept, allocation-free.
  [[nodiscard]] ErrorCode SetAcceleration(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                          const Eigen::Vector3d& alpha_DH_H, Stamp stamp,
                                          UpdateError* why = nullptr) noexcept;
  /// The acceleration stored on the twist edge into f, in the edge form (nullopt: none, or no
  /// twist edge). Writer thread. O(1).
  [[nodiscard]] std::optional<coord::Acceleration> acceleration_value(FrameIndex f) const noexcept;

  // ---------------------------------------------------------------- inspection

  [[nodiscard]] const semantics::NameTable& names() const noexcept { return topology_.names(); }
  [[nodiscard]] std::size_t num_frames() const noexcept { return topology_.num_frames(); }
  [[nodiscard]] std::size_t num_bodies() const noexcept { return topology_.num_bodies(); }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return topology_.num_pose_edges(); }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return topology_.num_twist_edges(); }
  [[nodiscard]] FrameIndex FindFrame(std::string_view name) const noexcept {
    return topology_.FindFrame(name);
  }
  [[nodiscard]] BodyIndex FindBody(std::string_view name) const noexcept {
    return topology_.FindBody(name);
  }
  [[nodiscard]] std::string_view frame_name(FrameIndex f) const noexcept {
    return topology_.frame_name(f);
  }
  [[nodiscard]] std::string_view body_name(BodyIndex b) const noexcept {
    return topology_.body_name(b);
  }
  [[nodiscard]] BodyIndex body_of(FrameIndex f) const noexcept { return topology_.body_of(f); }
  /// Pose parent P of f (invalid for a root) and the stored edge value X_PF in [P]. These
  /// inspection calls read the topology without validation: writer thread (or quiet topology).
  [[nodiscard]] FrameIndex pose_parent(FrameIndex f) const noexcept {
    return topology_.pose_parent(f);
  }
  [[nodiscard]] typename B::PoseCoords pose_value(FrameIndex f) const noexcept {
    return values_.X_PF[f.value()].Load();
  }
  /// Twist parent body of f (invalid if none) and the stored screw twist (v, w) at f in [f].
  [[nodiscard]] BodyIndex twist_parent(FrameIndex f) const noexcept;
  [[nodiscard]] std::optional<coord::Twist> twist_value(FrameIndex f) const noexcept;
  [[nodiscard]] FrameIndex tree_root(FrameIndex f) const noexcept {
    return topology_.forest().Root(f);
  }
  /// The sample history of the pose edge into f / of the twist edge slot (docs/time.md): nullptr
  /// for a timeless or constant edge (and for no edge). The writer thread may read it with the
  /// writer-side calls (ValueAt, newest_stamp); other threads with the lock-free ones. O(1).
  [[nodiscard]] const PoseHistory* pose_history(FrameIndex f) const noexcept {
    return values_.history.pose_of(f.value());
  }
  [[nodiscard]] const TwistHistory* twist_history(TwistEdgeIndex e) const noexcept {
    return values_.history.twist_of(e.value());
  }

  /// Text for a query error (describe.cc). Pass the spec of the failed query, so that an
  /// argument whose name was never interned (an unknown name) can be named in the text.
  [[nodiscard]] std::string Describe(const QueryError& e) const;
  [[nodiscard]] std::string Describe(const QueryError& e, const PoseSpec& spec) const;
  [[nodiscard]] std::string Describe(const QueryError& e, const TwistSpec& spec) const;

  /// Heap bytes of the graph's structures, excluding the name strings and name index.
  [[nodiscard]] std::size_t ApproximateBytesExcludingNames() const noexcept;

  /// The topology (nodes, names, pose and twist edges, iteration over edges), read-only.
  [[nodiscard]] const topology::SceneTopology& topology() const noexcept { return topology_; }

 private:
  friend struct internal::DebugAccess;

  template <class R>
  BuildResult AddPoseImpl(const PoseSpec& spec, const R& rotation,
                          const Eigen::Vector3d& p_position,
                          std::optional<Stamp> stamp = std::nullopt,
                          const CovarianceInput* covariance = nullptr);
  BuildResult AddAccelerationImpl(const TwistSpec& spec, const Eigen::Vector3d& a_linear,
                                  const Eigen::Vector3d& alpha_angular, std::optional<Stamp> stamp);
  ErrorCode StoreSampleAcceleration(TwistEdgeIndex edge, Stamp stamp,
                                    const AccelerationNumbers& A) noexcept;
  ErrorCode SetAccelerationImpl(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                const Eigen::Vector3d& alpha_DH_H, std::optional<Stamp> stamp,
                                UpdateError* why) noexcept;
  BuildResult AddTwistImpl(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                           const Eigen::Vector3d& w_angular, std::optional<Stamp> stamp,
                           const CovarianceInput* covariance = nullptr,
                           const AccelerationInput* acceleration = nullptr);
  template <class R>
  ErrorCode SetPoseImpl(PoseHandle edge, const R& rotation, const Eigen::Vector3d& p_ToHo_T,
                        std::optional<Stamp> stamp, UpdateError* why) noexcept;
  ErrorCode SetTwistImpl(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                         const Eigen::Vector3d& w_DH_H, std::optional<Stamp> stamp,
                         UpdateError* why) noexcept;
  // Time (time_query.cc): every timed one-shot query runs the evaluator through RunTimed.
  template <class Eval>
  std::optional<QueryError> RunTimed(const TimePolicy& policy, TimeReport& report,
                                     internal::EdgeRecorder* recorder, Eval&& eval) const noexcept;
  // run(report, eval): RunTimed at the policy, eval(ForestSource) at its time (pose queries).
  auto AtPolicy(const TimePolicy& policy) const noexcept;
  std::optional<QueryError> TimeTravelPose(FrameIndex e, FrameIndex a, FrameIndex f, FrameIndex b,
                                           FrameIndex r, FrameIndex x, const TimeTravel& travel,
                                           typename B::PoseCoords& X,
                                           TimeReport& report) const noexcept;
  // Covariances at a time (time_uncertainty.cc): the pose answer's of frames k at a policy, and
  // a time travel's (both sides).
  // `extrapolated`: the answer was (an edge shared with an integration twist: perturbed once).
  std::optional<QueryError> TimedPoseCovariance(const FrameIndex (&k)[5], const TimePolicy& policy,
                                                Covariance6& S, bool extrapolated) const noexcept;
  std::optional<QueryError> TimeTravelCovariance(const FrameIndex (&k)[5], FrameIndex x,
                                                 const TimeTravel& travel,
                                                 Covariance6& S) const noexcept;
  std::optional<QueryError> TimeTravelCovarianceOnce(const FrameIndex (&k)[5], FrameIndex x,
                                                     const TimeTravel& travel,
                                                     Covariance6& S) const noexcept;
  QueryResult<Timed<coord::Twist>> TimedTwist(const TwistSpec& spec, const TimePolicy& policy,
                                              TwistSource source,
                                              internal::EdgeRecorder* recorder) const noexcept;
  // Time (time_add.cc): the stamp rules of an update, then the store (value and history).
  internal::TimeContext ConversionContext(std::optional<Stamp> stamp) const noexcept;
  std::string DescribeConversionGap(const internal::TimeContext& tc, Stamp stamp) const;
  PoseHistoryLease NewPoseHistory();
  TwistHistoryLease NewTwistHistory();
  void InstallPoseHistory(FrameIndex head, PoseHistoryLease h, const typename B::PoseCoords& X,
                          Stamp s, const coord::Covariance6* S = nullptr);
  void InstallTwistHistory(TwistEdgeIndex edge, TwistHistoryLease h, const TwistNumbers& V, Stamp s,
                           const coord::Covariance6* S = nullptr,
                           const AccelerationNumbers* A = nullptr);
  void ReservePoseSampleCovariance(FrameIndex head);
  void ReserveTwistSampleCovariance(TwistEdgeIndex edge);
  void DropPoseHistory(FrameIndex head) noexcept;
  void DropTwistHistory(TwistEdgeIndex edge) noexcept;
  ErrorCode CheckPoseSample(FrameIndex head, const typename B::PoseCoords& X,
                            std::optional<Stamp> stamp,
                            const coord::Covariance6* S = nullptr) const noexcept;
  void StorePoseSample(FrameIndex head, const typename B::PoseCoords& X, std::optional<Stamp> stamp,
                       const coord::Covariance6* S = nullptr) noexcept;
  ErrorCode CheckTwistSample(TwistEdgeIndex edge, const TwistNumbers& V, std::optional<Stamp> stamp,
                             const coord::Covariance6* S = nullptr,
                             const AccelerationNumbers* A = nullptr) const noexcept;
  // The sample with its acceleration (A null: none); for a timeless edge or a sample that
  // becomes the newest, the acceleration record first (edge_values.h).
  void StoreTwistSample(TwistEdgeIndex edge, const TwistNumbers& V, std::optional<Stamp> stamp,
                        const coord::Covariance6* S = nullptr,
                        const AccelerationNumbers* A = nullptr) noexcept;
  ErrorCode SetPoseWithCovariance(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                  const Eigen::Vector3d& p_ToHo_T, std::optional<Stamp> stamp,
                                  const CovarianceInput& covariance, UpdateError* why) noexcept;
  ErrorCode SetTwistWithCovariance(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                   const Eigen::Vector3d& w_DH_H, std::optional<Stamp> stamp,
                                   const CovarianceInput& covariance, UpdateError* why) noexcept;
  ErrorCode SetTwistSample(TwistHandle edge, const TwistNumbers& V,
                           std::optional<Stamp> stamp) noexcept;
  std::string DescribeSampleRejection(ErrorCode code, bool twist, std::uint32_t index,
                                      std::optional<Stamp> stamp) const;
  FrameIndex CreateFrame(NameId name, BodyIndex body);
  // The apply step of every add (add.cc): every allocation, then (after the caller's last
  // check and its NameRollback::Commit) the nodes and links, allocation-free.
  void ReserveAdd(const internal::AddPlan& plan);
  internal::AddedEdges CommitAdd(const internal::AddPlan& plan);
  // Removal by index, after the edge finder (edge_lookup.h) found the edge.
  void RemovePoseEdge(FrameIndex head);
  void RemoveTwistEdge(TwistEdgeIndex edge);
  template <class R>
  ErrorCode SetConvertedPose(const ConvertingPoseHandle<B>& edge, const R& rotation,
                             const Eigen::Vector3d& p, UpdateError* why) noexcept;
  void RerootAt(FrameIndex v);  // repair.cc: reverse the path to the root, values inverted
  internal::ForestSource<B> source() const noexcept { return {topology_, values_}; }
  // Joints (joints.cc): removal of a joint's pose edge, state application; Jacobians
  // (jacobian.cc).
  BuildResult RemoveJoint(const internal::JointRecord& joint);
  void ApplyJoint(JointIndex index, const double* q, const double* qdot,
                  const double* qddot) noexcept;
  // SetJoints' rules in order (invalid_number, unknown_joint, mimic_joint, joint_limit), stamped or
  // not.
  BuildResult CheckJointValues(std::span<const JointValue> positions,
                               std::span<const JointValue> velocities,
                               std::span<const JointValue> accelerations) const;
  ErrorCode SetGroup(const JointGroup& group, const double* q, const double* qdot,
                     const double* qddot, UpdateError* why) noexcept;
  // A refused joint set: `code`, with the first joint in the group's order that breaks its rule
  // (joint_time.cc).
  ErrorCode RefuseJoints(ErrorCode code, const JointGroup& group, const double* q,
                         const double* qdot, const double* qddot, UpdateError* why) const noexcept;
  // Stamped joint states (joint_time.cc).
  ErrorCode SetGroupStamped(const JointGroup& group, const double* q, const double* qdot,
                            const double* qddot, Stamp stamp, UpdateError* why) noexcept;
  // qddot: the sample's joint acceleration (null: none).
  ErrorCode CheckJointSample(const internal::JointRecord& j, double q, double qdot,
                             const double* qddot, std::int64_t s) const noexcept;
  void StoreJointSample(JointIndex index, const double* q, const double* qdot, const double* qddot,
                        std::int64_t s) noexcept;
  Expected<internal::JacobianPlan, QueryError> PlanJacobian(const TwistSpec& spec) const;

  topology::SceneTopology topology_;
  EdgeValues<B> values_;
  internal::JointTable joints_;
  GraphId id_;  // stamped into handles; SetPose/SetTwist refuse other graphs' handles
  internal::WrenchStore wrenches_;  // wrenches.h
};

extern template class SceneGraph<coord::QuaternionBackend>;
extern template class SceneGraph<coord::HomogeneousBackend>;

}  // namespace semgraph::core
