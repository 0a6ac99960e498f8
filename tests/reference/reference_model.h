// File: tests/reference/reference_model.h
//
// ReferenceModel: a deliberately naive executable reading of docs/rules.md, the oracle of
// the fuzzers and of the exhaustive small-scope check (fuzz/). It shares no code with core/:
// plain containers, every invariant recomputed from scratch by graph search over the whole
// scene after each tentative operation, queries by brute-force path search. Short enough to
// check by eye against the spec; speed is irrelevant.
//
// State (names are std::string; bodies and frames live in separate name spaces):
//   bodies_   std::set of body names
//   frames_   std::map frame -> body
//   poses_    vector of pose edges {tail, head, X_TH}: X_TH = (R_TH, p_TH) is the pose of {head}
//             wrt {tail} expressed in [tail], i.e. PoseCoord({h}|H, {t}|T, [t]) (docs/rules.md §2)
//   twists_   vector of twist edges {tail body D, head frame h, v, w}: the screw twist
//             TwistCoord(h|H, D, [h]) (docs/rules.md §3)
//   a stamped edge also keeps its samples (sorted by stamp; the plain value is the newest);
//   each edge also keeps its covariance S in the edge form (zero: exact; docs/uncertainty.md);
//   joints_   live joints {name, type, parent, child, X_origin, axis, limits, mimic, q, qdot}:
//             their edges are ordinary entries of poses_ / twists_ whose values Drive() writes.
//
// How an add works (docs/rules.md §6: "every build operation either succeeds completely or
// leaves the graph exactly as it was"): the argument checks run in the order of docs/rules.md §7;
// then the operation is applied to a COPY of the state, and Violation() recomputes P1, P2, P3, W3
// on the copy from scratch; the first violated rule in the §4 order is the error, and the copy is
// dropped. Otherwise the copy becomes the state.
//   P1 multiple_pose_parents  a frame is the head of at most one pose edge
//   P2 pose_cycle             the undirected pose graph is a forest (self_edge checked earlier)
//   P3 duplicate_pose_path    in every pose tree, the frames of one body are connected through
//                             same-body edges only
//   W3 duplicate_twist_path   for every pose tree P, TG(P) (one undirected body edge D-H per
//      (twist adds) /         twist edge D -> {h}|H with h in P) has no cycle and no parallel
//      twist_merge_conflict   edge; a pose add that breaks it is W4 (twist_merge_conflict)
//      (pose adds)
//   W1 multiple_twist_parents and W2 twist_same_body are argument checks (they need no search).
//
// SCOPE (what the model does NOT cover; callers must not send it):
//   - pose adds in edge form only: point = orientation frame = head, reference point =
//     reference orientation = coordinate frame = tail. Hence an add never hits
//     representation_constraint or pose_not_convertible.
//   - twist adds with coordinate frame = the point's frame, or another frame (converted with
//     the orientation of [r] wrt [point]; twist_not_convertible when [r] is not in the point's
//     pose tree, including when the point's frame is created by this add).
//   - names are ASCII: "valid" means non-empty, at most 255 bytes, no byte < 0x20 and no 0x7F.
//     Non-ASCII bytes are treated as invalid (the library accepts UTF-8; the fuzzers send none).
// AMBIGUITY, resolved like the library: the order of checks lists "node resolution
// (frame_body_mismatch, frame_without_body)" as one step. When the head and the tail break
// different ones (head missing and no body given, tail on another body than the one named),
// the model reports the head's error: frames are resolved one at a time, head first.
//
// Queries (all six kinds, any point / orientation / reference / coordinate frame) are covered
// fully, including the homogeneous representation's constraints.
//
// REPAIR (docs/repair.md), covered for the edge-form pose adds and the twist adds above:
// invert (P1, W1), re-root (the inverse refused by P1; never through a joint's or a stamped
// edge), consistency checks (P1 within one tree, P2, W3) with their discrepancy, every policy
// switch and tolerance. Not covered: repair of pose adds in other forms (the library converts
// them to the edge form first). Left open by the docs and taken from the caller: WHICH frame
// of the reference body carries an inverted twist (AddTwistRepair's `choose`).
// JOINTS (docs/kinematics.md): revolute, continuous, prismatic, fixed; limits, mimic joints,
// protection of a joint's edges, removal through its pose edge, state by name and by group,
// semantic Jacobians (one column formula of the model's own, no finite differences). Not
// covered: origins given as matrices, URDF loading (models/), joint handles' generations
// beyond "a group made before a removal is stale".
// TIME (docs/time.md): stamped edge-form pose adds and twist adds (converted at their stamp),
// window, capacity, duplicate policies, out-of-order samples; policies latest, at (with a
// horizon: twist edges held, pose edges integrated with the twist edges' screw twist),
// latest common, not_before, for every query kind. Not covered: time travel, twist source
// `poses` (differentiation), stamped SetPose/SetTwist by handle (the same Check/Store as the
// stamped add), Explain*; the stamps read are compared only for answers not extrapolated (the
// spec also counts the stamps the integrating twist reads).
// ACCELERATIONS (docs/dynamics.md §1): on twist edges, given with a twist or on their own,
// converted, cleared by any twist value stored without one (adds, SetTwist by handle, removal),
// SetAcceleration and SetTwist by handle, queries (acceleration, linear, angular) composed along
// the twist path. Stamped (docs/dynamics.md §7.2): each twist sample may carry one (a stamped
// twist with one, AddAcceleration / SetAcceleration at a sample's stamp), timed queries
// (AskAccelerationAt). Joint accelerations by SetJoints. Stamped joint states (by name and
// by group, with q''): their samples written into the joints' edges. Not covered: acceleration
// covariances.
// WRENCHES (docs/dynamics.md §7): adds (storage frame, conversion, the errors self_wrench,
// duplicate_wrench, wrench_not_convertible, unknown_frame / unknown_body, invalid_name,
// invalid_number), removals, handles and SetWrench, and one-shot queries (a pair, its
// reaction, a net wrench; compiled ones kept across later ops by the differential).
//
// Numbers: a quaternion rotation is normalized to q/|q| and turned into a matrix; a matrix
// rotation is replaced by its nearest rotation (polar decomposition by Newton iteration
// R <- (R + R^-T)/2, independent of the library's SVD). Values are stored as 3x3 matrices.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "semgraph/base/error_code.h"

namespace semgraph::reference {

using base::ErrorCode;

/// Pose of frame X wrt frame Y, expressed in [Y]: R_YX, p_YX.
struct Transform {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
};

/// A rotation as the user gave it (validated and normalized by the model).
struct RotationInput {
  bool is_matrix = false;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
};

/// The coordinate representation: changes only which queries are representation_constraint.
enum class Representation { kQuaternion, kHomogeneous };

enum class QueryKind { kPose, kPosition, kOrientation, kTwist, kLinearVelocity, kAngularVelocity };

/// Query arguments by name; an empty body / ref_body means "the body of the frame". Which fields
/// a kind reads: pose all; position point, body, ref_point, ref_body, coord; orientation
/// orientation, body, ref_orientation, ref_body, coord; twist and linear velocity point, body,
/// ref_body, coord; angular velocity body (required), ref_body, coord.
struct Query {
  QueryKind kind = QueryKind::kPose;
  std::string point, orientation, body, ref_point, ref_orientation, ref_body, coord;
};

/// A query's outcome: code kOk and the value parts of its kind (M: orientation operator in [r];
/// p: position in [r]; v, w: twist in [r] at the point).
struct Answer {
  ErrorCode code = ErrorCode::kOk;
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
};

/// Time (docs/time.md): a stamped edge keeps its samples sorted by stamp (nanoseconds); its
/// untimed value (X_TH, v/w) is the newest sample's.
struct PoseSample {
  std::int64_t t = 0;
  Transform X;
};
/// A twist sample may carry its own acceleration (docs/dynamics.md, "Stamped accelerations"), in
/// the edge form as TwistEdge's; has_A false: none (a sample given without one carries none).
struct TwistSample {
  std::int64_t t = 0;
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  bool has_A = false;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
};

/// A 6x6 covariance (docs/uncertainty.md): rows and columns (dp, dtheta) / (dv, dw).
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// A covariance given with an add: the matrix as given, its order (angular first when
/// `angular_linear`) and, for a pose, the body convention (X_true = X Exp(xi)).
struct CovarianceIn {
  Matrix6 S = Matrix6::Zero();
  bool angular_linear = false;
  bool body = false;
};

struct PoseEdge {
  std::string tail, head;
  Transform X_TH;
  bool stamped = false;
  std::vector<PoseSample> samples;
  Matrix6 S = Matrix6::Zero();  // the edge form's covariance (zero: exact)
};

struct TwistEdge {
  std::string tail_body, head;
  Eigen::Vector3d v, w;  // at {head}, in [head]
  bool stamped = false;
  std::vector<TwistSample> samples;
  Matrix6 S = Matrix6::Zero();  // at {head} in [head], linear first (zero: exact)
  /// The edge's acceleration AccelerationCoord(h|H, D, [h]) (docs/dynamics.md §1): a = the
  /// classical acceleration of h's origin as a point of H relative to D, alpha = the angular
  /// acceleration of H relative to D, both in [h]. has_A false: none (every twist value stored
  /// without an acceleration clears it). A stamped edge's is its newest sample's.
  bool has_A = false;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
  std::uint64_t serial = 0;  ///< unique per edge made: a handle of a removed edge stays dead
};

/// An acceleration given with a twist or on its own: (a, alpha) at the op's point, in its frame.
struct AccelerationIn {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
};
/// An acceleration query's outcome: a (classical, of the point of C at e) and alpha, in [r].
struct AccelerationAnswer {
  ErrorCode code = ErrorCode::kOk;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();
};

/// The model's copy of the graph's time options.
struct TimeOptions {
  std::int64_t window_ns = 10'000'000'000;
  std::size_t capacity = 1024;
  bool linear = false;             // interpolation: screw (false) or linear (lerp + slerp)
  bool reject_duplicates = false;  // duplicate stamps: replace (false) or reject
};

/// A query's time policy: latest, at t (horizon), latest common; not_before with any.
struct TimeQuery {
  enum class Kind { kLatest, kAt, kLatestCommon } kind = Kind::kLatest;
  std::int64_t t = 0, horizon = 0;
  std::optional<std::int64_t> not_before;
};
/// What a timed answer reports (docs/time.md), and whether its value may be compared: an
/// interpolation across a half turn is implementation-defined (the spec says tests avoid it).
struct TimedAnswer {
  Answer answer;
  std::optional<std::int64_t> time, oldest, newest;
  bool extrapolated = false;
  bool ambiguous = false;
};

/// Joints (docs/kinematics.md): the model's own reading. A joint owns the pose edge
/// parent -> child with X_origin M(q) and the twist edge parent body -> {child} with xi(qdot).
enum class JointType { kRevolute, kContinuous, kPrismatic, kFixed };
struct JointInput {
  std::string name, parent, parent_body, child, child_body, mimic;
  JointType type = JointType::kFixed;
  Eigen::Quaterniond q_origin = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double lower = 0, upper = 0, multiplier = 1, offset = 0;
};
struct Joint {
  std::string name, parent, child, parent_body, master;  // master: empty unless a mimic
  JointType type = JointType::kFixed;
  Transform X_origin;
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();  // unit axis in [child]
  double lower = 0, upper = 0, multiplier = 1, offset = 0;
  double q = 0, qdot = 0;
  double qddot = 0;  // with has_qddot: the joint's acceleration (never given: none)
  bool has_qddot = false;
  std::uint64_t serial = 0;  // unique per add: a group made before a removal goes stale
  /// Time: set without a stamp at least once (and the mimics it had then): timeless edges.
  bool timeless = false;
  /// Stamped (its edges keep histories): its samples, sorted by stamp; the edges' samples are
  /// made of them (X_origin M(q), the twist of qdot, the acceleration of qddot when it has one).
  struct Sample {
    std::int64_t t = 0;
    double q = 0, qdot = 0, qddot = 0;
    bool has_qddot = false;
  };
  std::vector<Sample> samples;
  bool movable() const { return type != JointType::kFixed; }
  bool limited() const { return type == JointType::kRevolute || type == JointType::kPrismatic; }
};
/// A Jacobian answer: the columns' joints (masters) in column order, rows v then w.
struct JacobianAnswer {
  ErrorCode code = ErrorCode::kOk;
  std::vector<std::string> joints;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
};

/// A stored wrench (docs/dynamics.md §7): on body `on` by body `by`, force f and moment m about
/// the origin of `frame` (a frame of `on`), both in [frame]. `scale`: the size of the numbers
/// that made it (|f| + |m|)(1 + lever arm), for tolerances.
struct WrenchEntry {
  std::string on, by, frame;
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  double scale = 0;
  std::uint64_t serial = 0;  ///< unique per pair made: a handle of a removed pair stays dead
};
/// A wrench query's outcome: f, m about the query's point in its frame, and the size of the
/// numbers summed (for tolerances: terms may cancel).
struct WrenchAnswer {
  ErrorCode code = ErrorCode::kOk;
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  double scale = 0;
};

/// Repair of a rejected add (docs/repair.md), the model's own copy of the policy.
struct RepairPolicy {
  bool invert = true;
  bool reroot = true;
  bool check_consistency = true;
  double position_tolerance = 1e-9;  // m (m/s for twists)
  double angle_tolerance = 1e-9;     // rad (rad/s for twists)
};
enum class RepairKind { kNone, kInverted, kRerooted, kConsistent };

/// What a repairing add did, or why it was refused.
struct RepairOutcome {
  ErrorCode code = ErrorCode::kOk;         // kOk: accepted (as given or repaired)
  RepairKind applied = RepairKind::kNone;  // with code kOk
  std::size_t reversed_edges = 0;          // kRerooted
  std::vector<std::string>
      reversed_keys;               // kRerooted: PoseKey of each reversed edge, old direction
  bool has_discrepancy = false;    // a consistency check ran (kConsistent, or refused)
  double position = 0, angle = 0;  // its discrepancy
  /// The discrepancy is within a rounding error of a tolerance: the check may go either way
  /// (both outcomes leave the graph unchanged).
  bool borderline = false;
};

class ReferenceModel {
 public:
  explicit ReferenceModel(Representation representation = Representation::kQuaternion,
                          const TimeOptions& time = TimeOptions{})
      : representation_(representation), time_(time) {}

  // Spec §4 orders, per operation:
  //   body:   invalid_name -> duplicate_body
  //   frame:  invalid_name -> frame_without_body -> duplicate_frame -> unknown_body
  //   pose:   invalid_name -> invalid_number -> invalid_rotation -> node resolution (head:
  //           frame_body_mismatch / frame_without_body, then the same for the tail) ->
  //           self_edge -> constant_pose_change (or a value update) ->
  //           multiple_pose_parents -> pose_cycle -> duplicate_pose_path -> twist_merge_conflict
  //   twist:  invalid_name -> invalid_number -> frame_body_mismatch -> frame_without_body ->
  //           twist_same_body -> twist_not_convertible -> multiple_twist_parents (or update) ->
  //           duplicate_twist_path
  //   remove: invalid_name -> unknown_frame -> unknown_body -> no_such_edge
  // Empty head_body / tail_body / body mean "not given".
  // UNCERTAINTY (docs/uncertainty.md §1-§2), untimed adds only: a covariance `cov` (null: none,
  // the value exact: an update then sets the edge's covariance to zero). Its checks on the matrix
  // as given: invalid_number (an entry not finite or |x| > 1e12) in invalid_number's place, i.e.
  // before invalid_rotation; invalid_covariance (|S(i,j) - S(j,i)| > tol, or an eigenvalue of
  // (S + S^T)/2 below -tol, tol = 1e-9 max(1, max|S|), eigenvalues by the model's own cyclic
  // Jacobi; for a twist also: the body convention, which has no meaning there, as the library
  // reads it) right after invalid_rotation (twists: after invalid_number). Stored in the edge
  // form: reordered to linear-angular, symmetrized, body -> diag(R, R) S diag(R, R)^T; a twist
  // given in [r] != [h]: diag(R_hr, R_hr) S diag(R_hr, R_hr)^T. A constant pose restated needs
  // the same covariance too (every entry within 1e-9 max(1, max|S_stored|); none = zero), else
  // constant_pose_change. A re-rooted edge's covariance is the inverse's, J S J^T with
  // J = [[-R^T, -R^T [p]x], [0, -R^T]] (derived in the .cc). Not covered: stamped adds with a
  // covariance (the library has no public call for them yet), covariance queries.
  ErrorCode AddBody(const std::string& name);
  ErrorCode AddFrame(const std::string& name, const std::string& body);
  // Time: an add with a stamp gives a stamped edge (a new edge between bodies) or a sample
  // (an existing one); same-body edges ignore it. After every other rule: stamp_mismatch (a
  // stamped value for a timeless edge or the reverse) -> stamp_too_old (older than newest -
  // window) -> duplicate_stamp (policy reject, another value at a stamp: P4's tolerance for
  // poses, 1e-6 max(1, |stored|) per vector for twists; the same value is a no-op). Then the
  // sample is inserted; when over capacity the oldest goes; samples older than newest - window
  // go. A stamped twist given in another frame is converted at its stamp (no values there:
  // extrapolation, in twist_not_convertible's place).
  ErrorCode AddPose(const std::string& head, const std::string& head_body, const std::string& tail,
                    const std::string& tail_body, const RotationInput& rotation,
                    const Eigen::Vector3d& p, std::optional<std::int64_t> stamp = std::nullopt,
                    const CovarianceIn* cov = nullptr);
  // ACCELERATIONS: `acc` (null: none, and the edge's acceleration is cleared) is checked for
  // invalid_number right after the twist's numbers, rotated into [point] with the twist (the
  // same point) and stored with it; with a stamp it is the sample's (converted with the same
  // rotation at the stamp), and the duplicate rule compares it too (both none, or each vector
  // within 1e-6 max(1, |stored|)). Not covered: an acceleration with a covariance.
  ErrorCode AddTwist(const std::string& point, const std::string& body, const std::string& ref_body,
                     const std::string& coord, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                     std::optional<std::int64_t> stamp = std::nullopt,
                     const CovarianceIn* cov = nullptr, const AccelerationIn* acc = nullptr);
  /// The smallest eigenvalue of a symmetric 6x6 matrix (cyclic Jacobi), for callers that need
  /// to tell a borderline case (an eigenvalue within rounding of the check's bound).
  static double SmallestEigenvalue(const Matrix6& S);

  /// A query under a time policy: the codes of Ask, with invalid_number (negative horizon)
  /// right after invalid_name, then extrapolation (a used stamped edge without a value at the
  /// time), then stale (not_before). The value: Ask on the graph whose used edges hold their
  /// values at the time: inside a sample range interpolated (screw: X_i Exp(lambda Log(X_i^-1
  /// X_i+1)) by the model's own SE(3) Exp/Log; linear: lerp + slerp; twists componentwise);
  /// outside, within the horizon, a twist edge holds its nearest sample and a pose edge is
  /// integrated X_k Exp((t - s_k) xi) with xi = TwistCoord(h|H, T, [h]) at s_k from the twist
  /// edges (no extrapolation). Used edges: as UsedEdges (none for a velocity of C wrt C).
  TimedAnswer AskAt(const Query& q, const TimeQuery& policy) const;
  /// The same adds with repair (docs/repair.md), the rule table read literally:
  ///   pose, plain add refused by
  ///     P1 or P2 with both frames in one pose tree (already determined): consistency check of
  ///        the given X_TH against the derived pose (|dp| and the rotation angle of R_derived^T R
  ///        against the tolerances); kConsistent, no change; else the plain error + discrepancy;
  ///     P1 otherwise: the inverse edge head -> tail with X_TH^-1 through the plain add; if
  ///        that is refused by P1 (the tail has a pose parent), the tail's tree is re-rooted at
  ///        the tail (each edge on the path tail..root reversed, value inverted) and the inverse
  ///        added again; refused again -> the re-rooting is undone, the plain error.
  ///   twist, plain add refused by
  ///     W3 duplicate_twist_path: consistency check against the derived twist (|dv|, |dw|);
  ///     W1 multiple_twist_parents: the inverse twist (-v, -w, moved to the new point h:
  ///        v_h = v_e + w' x (p_h - p_e)) on a frame h of ref_body in the point's tree with no
  ///        twist parent. WHICH such frame is not specified (docs/repair.md says "a frame"):
  ///        `choose` picks one of the candidates (the differential passes the kernel's choice).
  ///   Anything else, or a strategy switched off, or a repair add refused: the plain error.
  RepairOutcome AddPoseRepair(const std::string& head, const std::string& head_body,
                              const std::string& tail, const std::string& tail_body,
                              const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                              const RepairPolicy& policy);
  RepairOutcome AddTwistRepair(
      const std::string& point, const std::string& body, const std::string& ref_body,
      const std::string& coord, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
      const RepairPolicy& policy,
      const std::function<std::string(const std::vector<std::string>&)>& choose);
  ErrorCode RemovePose(const std::string& of, const std::string& wrt);

  /// Joints. AddJoint: invalid_name (name, parent, parent body, child, child body, mimic) ->
  /// invalid_number / invalid_rotation (origin position, origin rotation, axis, limits,
  /// multiplier, offset) -> invalid_model (|axis| < 1e-12 for a movable joint; lower > upper
  /// for revolute/prismatic; mimic: a fixed mimic, or a master missing, fixed or a mimic) ->
  /// duplicate_joint -> node resolution (child, then parent) -> self_edge -> twist_same_body ->
  /// joint_edge -> the pose edge's P1, P2, P3, W4 -> W1, W3 of the twist edge. Initial state:
  /// q = clamp(0, lower, upper) (limited) or 0, qdot = 0; a mimic follows its master.
  /// Edges: a joint's pose edge re-added / its twist edge re-added or removed: joint_edge; its
  /// pose edge removed: the joint is removed (joint_edge while live mimics follow it).
  ErrorCode AddJoint(const JointInput& in);
  /// By name, all or nothing: invalid_number (positions, velocities, accelerations) ->
  /// unknown_joint (missing or fixed) -> mimic_joint -> joint_limit (outside [lower - 1e-9,
  /// upper + 1e-9]). An acceleration q'' gives the joint's twist edge its acceleration
  /// (docs/dynamics.md: revolute alpha = u q'', prismatic a = u q''); a joint never given one
  /// gives its edge none; q and q' set later keep it.
  ErrorCode SetJoints(const std::vector<std::pair<std::string, double>>& positions,
                      const std::vector<std::pair<std::string, double>>& velocities,
                      const std::vector<std::pair<std::string, double>>& accelerations = {});
  /// A joint-state vector layout: each name's serial. unknown_joint -> mimic_joint ->
  /// duplicate_joint, per name in order.
  ErrorCode MakeGroup(const std::vector<std::string>& names,
                      std::vector<std::uint64_t>* serials) const;
  /// Sets a group (q and/or qdot may be null): invalid_number -> unknown_joint (a joint removed
  /// since the group was made) -> joint_limit.
  ErrorCode SetGroup(const std::vector<std::uint64_t>& group, const double* q, const double* qdot);
  /// Stamped joint states (docs/kinematics.md "Time", docs/dynamics.md "Stamped accelerations"):
  /// a sample at `stamp` of each joint given and of its mimics (m q + offset, m qdot, m qddot); a
  /// field not given is the joint's newest sample's (qddot only if it has one). By name: the
  /// checks of SetJoints, then the stamp rules over the joints that are stamped already or
  /// timeless (a joint never set, or a mimic added since, gets its first sample): stamp_mismatch
  /// (timeless) -> stamp_too_old -> duplicate_stamp (reject policy: q within 1e-9 max(1, |q|),
  /// a revolute angle modulo a full turn, qdot too, qddot both none or within 1e-6), the first in
  /// that order over all. By group (the real-time setters, q / qdot / qddot null: not given):
  /// SetGroup's checks, then the same stamp rules, a joint (or mimic) not stamped yet being
  /// stamp_mismatch. All or nothing; the joint state is its newest sample's.
  ErrorCode SetJoints(const std::vector<std::pair<std::string, double>>& positions,
                      const std::vector<std::pair<std::string, double>>& velocities,
                      const std::vector<std::pair<std::string, double>>& accelerations,
                      std::int64_t stamp);
  ErrorCode SetGroup(const std::vector<std::uint64_t>& group, const double* q, const double* qdot,
                     const double* qddot, std::int64_t stamp);
  /// Jacobian(e|C, D, [r]) of a twist query: its errors; columns from the TG path (D to C) as
  /// the unit twists of its movable joints' edges moved to e, in [r], signed by direction; a
  /// mimic adds multiplier x its column to its master's (placed at the first of them met).
  JacobianAnswer Jacobian(const Query& q) const;
  const std::vector<Joint>& joints() const { return s_.joints; }

  ErrorCode RemoveTwist(const std::string& point, const std::string& ref_body);

  /// WRENCHES (docs/dynamics.md §7; the library's contract in core/.../wrenches.h): at most one
  /// per ordered pair (on C, by D), stored about the origin of a frame s of C in [s]. s is
  /// chosen when the pair is first given: the point if a frame of C, else the coordinate frame
  /// if a frame of C, else the most recently made frame of C in the point's pose tree (frames
  /// in the order they were made: AddFrame, a pose add's head then tail, a joint's child then
  /// parent, a twist add's point); an update keeps s. Pose removals leave wrenches (and s) as
  /// they are. The model stores its own conversion (f_S = R_SR f, m_S = R_SR m + p_SE x f_S).
  /// AddWrench: invalid_name (on, by, point, coord) -> invalid_number (f, m: finite, |x| <=
  /// 1e12) -> unknown_frame (point, coord) -> unknown_body (on, by) -> self_wrench ->
  /// wrench_not_convertible (no s, or s not in the tree of the point and of coord) ->
  /// duplicate_wrench (the pair (by, on) is stored).
  ErrorCode AddWrench(const std::string& on, const std::string& by, const std::string& point,
                      const std::string& coord, const Eigen::Vector3d& f, const Eigen::Vector3d& m);
  /// invalid_name -> unknown_body (on, by) -> self_wrench -> no_wrench.
  ErrorCode RemoveWrench(const std::string& on, const std::string& by);
  /// A handle's lookup: the errors of RemoveWrench; *serial receives the pair's serial.
  ErrorCode FindWrench(const std::string& on, const std::string& by, std::uint64_t* serial) const;
  /// SetWrench by a handle of the pair made with `serial`: no_wrench (that pair was removed)
  /// -> invalid_number (f_S, m_S as for adds); the value is the stored form (about s, in [s]).
  ErrorCode SetWrench(const std::string& on, const std::string& by, std::uint64_t serial,
                      const Eigen::Vector3d& f_S, const Eigen::Vector3d& m_S);
  /// WrenchCoord(point|on, by, [coord]); `by` empty: the net wrench on `on` (every stored
  /// wrench on it, plus the negation of every stored wrench by it). invalid_name ->
  /// unknown_frame (point, coord) -> unknown_body (on, by) -> self_wrench -> no_wrench ->
  /// no_pose_path (a term's s, the point and coord not in one tree).
  WrenchAnswer AskWrench(const std::string& on, const std::string& by, const std::string& point,
                         const std::string& coord) const;
  /// The serials of the stored wrenches AskWrench sums for (on, by) (by empty: every one on or
  /// by `on`), and the answer of those alone, each with its current value (a compiled wrench
  /// query: its terms are fixed when compiled). @pre AskWrench(on, by, ...) is kOk.
  std::vector<std::uint64_t> WrenchTerms(const std::string& on, const std::string& by) const;
  WrenchAnswer AskWrenchTerms(const std::vector<std::uint64_t>& serials, const std::string& on,
                              const std::string& point, const std::string& coord) const;
  const std::vector<WrenchEntry>& wrenches() const { return s_.wrenches; }

  /// ACCELERATIONS (docs/dynamics.md §1; the library's contract in core/.../accelerations.h).
  /// AddAcceleration: AccelerationCoord(point|body, ref_body, [coord]) = (a, alpha) set on the
  /// twist edge ref_body -> {h}|C (C = body, or the body of {point} when empty) in the pose tree
  /// of {point}. invalid_name (point, body when given, ref_body, coord) -> invalid_number
  /// (finite, |x| <= 1e12) -> unknown_frame (point, coord) -> unknown_body (body, ref_body) ->
  /// no_such_edge (no such edge in that tree; also C == ref_body) -> joint_edge ->
  /// stamp_mismatch (a stamped edge without a stamp, or a timeless one with one) ->
  /// acceleration_not_convertible ([coord] not in the tree; stamped: no twist sample at exactly
  /// the stamp, or a pose needed without a value there) -> duplicate_stamp (reject policy,
  /// another acceleration on that sample; the same one again: ok, no change). Converted to the
  /// edge form with the model's own formulas (see the .cc); stamped, with the poses at the stamp
  /// and that sample's twist, and stored on that sample (the newest's is the edge's).
  ErrorCode AddAcceleration(const std::string& point, const std::string& body,
                            const std::string& ref_body, const std::string& coord,
                            const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                            std::optional<std::int64_t> stamp = std::nullopt);
  /// A twist handle's lookup (FindTwistEdge(of, wrt)): invalid_name -> unknown_frame ->
  /// unknown_body -> no_such_edge -> joint_edge; *serial receives the edge's serial.
  ErrorCode FindTwist(const std::string& of, const std::string& wrt, std::uint64_t* serial) const;
  /// SetTwist by the handle of the edge made with `serial` (edge form): no_such_edge (removed)
  /// -> invalid_number -> stamp_mismatch (a stamped edge). Clears the acceleration and the
  /// covariance (a plain value is exact).
  ErrorCode SetTwist(std::uint64_t serial, const Eigen::Vector3d& v, const Eigen::Vector3d& w);
  /// SetAcceleration by handle (edge form, stored as given): no_such_edge -> joint_edge ->
  /// stamp_mismatch (a stamped edge without a stamp; a timeless one with one; no twist sample
  /// at the stamp) -> invalid_number -> duplicate_stamp (as AddAcceleration's).
  ErrorCode SetAcceleration(std::uint64_t serial, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& alpha,
                            std::optional<std::int64_t> stamp = std::nullopt);
  /// An acceleration query, with the fields of the twist query of the same kind: kTwist asks
  /// the acceleration, kLinearVelocity the linear, kAngularVelocity the angular one (body
  /// required, no point). The errors of Ask, then no_acceleration (an edge of the twist path
  /// without one). C == D: zero. Composed along the TG path by the model's own formulas.
  AccelerationAnswer AskAcceleration(const Query& q) const;
  /// An acceleration query under a time policy: AskAt's codes and report (the same used edges,
  /// time and stamps read), then no_acceleration; the value is AskAcceleration on the graph
  /// whose used edges hold their values at the time, each twist edge with its acceleration
  /// read as its twist: a sample's; between two, each component interpolated linearly, present
  /// only when both samples carry one; outside within the horizon, the nearest sample's (held).
  struct TimedAcceleration {
    AccelerationAnswer answer;
    std::optional<std::int64_t> time, oldest, newest;
    bool extrapolated = false;
    bool ambiguous = false;
  };
  TimedAcceleration AskAccelerationAt(const Query& q, const TimeQuery& policy) const;

  /// Queries: invalid_name -> unknown_frame -> unknown_body -> frame_body_mismatch ->
  /// no_pose_path -> representation_constraint -> no_twist_path.
  Answer Ask(const Query& q) const;

  /// The edges a query depends on, as "pose t->h" / "twist D->h": the pose edges of the
  /// smallest subtree joining the query's frames (and the heads of its twist path), and the
  /// twist edges of its TG path. Removing one of them makes the query unanswerable.
  /// @pre Ask(q).code == kOk.
  std::set<std::string> UsedEdges(const Query& q) const;

  static bool ValidName(const std::string& name);
  static std::string PoseKey(const std::string& tail, const std::string& head) {
    return "pose " + tail + "->" + head;
  }
  static std::string TwistKey(const std::string& body, const std::string& head) {
    return "twist " + body + "->" + head;
  }

  const std::set<std::string>& bodies() const { return s_.bodies; }
  const std::map<std::string, std::string>& frames() const { return s_.frames; }
  const std::vector<PoseEdge>& poses() const { return s_.poses; }
  const std::vector<TwistEdge>& twists() const { return s_.twists; }

 private:
  struct State {
    std::set<std::string> bodies;
    std::map<std::string, std::string> frames;  // frame -> body
    std::vector<PoseEdge> poses;
    std::vector<TwistEdge> twists;
    std::vector<Joint> joints;             // live joints, in add order
    std::vector<std::string> frame_order;  // frames in the order they were made
    std::vector<WrenchEntry> wrenches;     // stored wrenches, in add order
    std::uint64_t next_wrench_serial = 1;
    std::uint64_t next_twist_serial = 1;
  };
  /// Makes (or re-labels) a frame, recording the order frames are made in.
  static void PutFrame(State& s, const std::string& frame, const std::string& body);
  /// Pose tree labels (Trees) of two frames agree.
  bool SameTree(const std::string& x, const std::string& y) const;
  static const Joint* JointOfChild(const State& s, const std::string& child);
  /// Writes joint j's pose and twist edge values from its q, qdot (and its mimics').
  static void Drive(State& s, const std::string& joint);
  /// X_origin M(q), by the model's own Rodrigues formula.
  static Transform JointPose(const Joint& j, double q);
  /// SetJoints' checks before time: invalid_number -> unknown_joint -> mimic_joint -> joint_limit.
  ErrorCode CheckJointValues(
      const std::vector<std::pair<std::string, double>>& positions,
      const std::vector<std::pair<std::string, double>>& velocities,
      const std::vector<std::pair<std::string, double>>& accelerations) const;
  /// The stamp rules of a sample (q, qdot, qddot: null none) of joint j at s (kOk: none broken).
  ErrorCode CheckJointSample(const Joint& j, double q, double qdot, const double* qddot,
                             std::int64_t s) const;
  /// Inserts joint j's sample at s (a field null: the state's) and its mimics', and writes the
  /// samples into the joint's edges (then stamped).
  void StoreJointSample(const std::string& joint, const double* q, const double* qdot,
                        const double* qddot, std::int64_t s);
  /// A set without a stamp: the joint and its mimics become timeless.
  void MarkTimeless(const std::string& joint);
  std::uint64_t next_serial_ = 1;
  enum class Rule { kNone, kP1, kP2, kP3, kW3 };

  /// First violated invariant of `s` in the order P1, P2, P3, W3 (from scratch).
  static Rule Violation(const State& s);
  /// Pose tree label of every frame: the smallest frame name of its undirected component.
  static std::map<std::string, std::string> Trees(const State& s);
  /// Pose of frame x wrt frame y in [y], by breadth-first search over the undirected pose edges
  /// from y. False when x and y are in different trees.
  bool Find(const std::string& x, const std::string& y, Transform* X_YX) const;
  /// The twist edges (indices) on the path from body C to body D in TG(tree of frame e), with
  /// a sign each (+1 when the path crosses the edge from its head's body to its tail body).
  bool TwistPath(const std::string& e, const std::string& C, const std::string& D,
                 std::vector<std::pair<int, double>>* path) const;

  /// Reverses the pose edges on the path from `frame` to its tree's root (values inverted);
  /// returns their PoseKeys in the old direction.
  std::vector<std::string> Reroot(const std::string& frame);

  /// The value of every used stamped edge at time t written into a copy of the state; false
  /// (and *failure = extrapolation) when one has none. Records the stamps read.
  bool ValuesAt(std::int64_t t, std::int64_t horizon, const std::set<std::string>& used, State* at,
                TimedAnswer* report) const;
  /// AskAt's work: *at receives the model whose used edges hold their values at the time.
  TimedAnswer AskAtWith(const Query& q, const TimeQuery& policy, ReferenceModel* at) const;
  /// The acceleration of twist edge t's sample at stamp s: duplicate_stamp under the reject
  /// policy when the sample has another one; the newest sample's also becomes the edge's.
  ErrorCode StoreSampleAcceleration(TwistEdge& t, std::size_t sample, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& alpha) const;
  Representation representation_;
  TimeOptions time_;
  State s_;
};

}  // namespace semgraph::reference
