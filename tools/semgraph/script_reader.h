// File: tools/semgraph/script_reader.h
//
// Reads a scene script (docs/scene-script.md) into a list of typed operations. The whole
// document is parsed and validated here, before anything touches a scene graph, so that a
// malformed script (bad YAML, unknown op, missing or mistyped field, a field of the wrong op,
// wrong array length, non-numeric number, unknown representation, a rotation with zero or
// several forms) applies nothing: ReadScript() then returns a ScriptError with the 1-based line
// and column of the offending node.
//
// Time fields (docs/scene-script.md, Time) are checked for shape and placement here: a time
// field on an op that does not take it, time travel without both `ref_at` and `fixed` or with
// an `at` that is not a number, and a `time` map with a bad entry (a window that is not a
// finite positive time included) make the script malformed. The values of stamps and query
// times are kept in seconds as written; their range is the runner's (invalid_number).
//
// What is deliberately *not* checked here: names (empty, unprintable, too long) and numbers
// (NaN, Inf, non-unit quaternions). Those are the scene graph's rules and are reported per op as
// invalid_name / invalid_number / invalid_rotation, so that the script and the C++ API agree.
// `.nan`, `.inf` and `-.inf` are numbers to YAML and are passed through for that reason.
//
// The text is parsed into the compact YAML tree of yaml_tree.h, within kScriptLimits, so that
// hostile input cannot crash the tool: at most 16 MiB of UTF-8 text, nesting at most 64 levels
// deep (checked while parsing, so yaml-cpp never recurses deeper), at most 2^23 nodes, and at
// most 32 MiB with the aliases expanded (an alias bomb is refused at the alias that crosses
// it; the reader copies names out of shared nodes, so this also bounds the Script's size).
//
// Cost: O(size of the text). Thread safety: ReadScript is a pure function.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "semgraph/base/expected.h"
#include "semgraph/yaml_tree.h"

namespace semgraph::script {

inline constexpr YamlLimits kScriptLimits{};
inline constexpr std::size_t kMaxScriptBytes = kScriptLimits.max_bytes;  // 16 MiB
inline constexpr int kMaxNestingDepth = kScriptLimits.max_depth;
inline constexpr std::size_t kMaxYamlNodes = kScriptLimits.max_nodes;
inline constexpr std::size_t kMaxExpandedBytes = kScriptLimits.max_expanded_bytes;  // 32 MiB

enum class Representation : std::uint8_t { kQuaternion, kHomogeneous };

enum class OpKind : std::uint8_t {
  kBody,
  kFrame,
  kPose,
  kTwist,
  kRemovePose,
  kRemoveTwist,
  kQuery,
  kUrdf,    // load a robot model (docs/kinematics.md)
  kJoint,   // add one joint
  kJoints,  // set joint states
  kBag,     // apply a ROS bag's tf and joint states (docs/ros.md)
  kWrench,  // a wrench on a body by another (docs/dynamics.md)
  kRemoveWrench,
  kAcceleration,  // an acceleration on its twist edge (docs/dynamics.md §7)
};

enum class QueryKind : std::uint8_t {
  kPose,
  kPosition,
  kOrientation,
  kTwist,
  kLinearVelocity,
  kAngularVelocity,
  kJacobian,
  kWrench,  // on, by (optional), point, coord: "force" and "moment"
  kForce,
  kMoment,
  kAcceleration,  // the twist fields: "linear" and "angular"
  kLinearAcceleration,
  kAngularAcceleration,  // body, ref_body, coord: "angular"
};

enum class JointKind : std::uint8_t { kRevolute, kContinuous, kPrismatic, kFixed };

/// A query's time policy as written: none (latest), `at: <seconds>`, `at: latest_common`.
enum class AtKind : std::uint8_t { kLatest, kTime, kLatestCommon };

/// The names of an op's semantics after the shorthand is applied (`of: X` sets point and
/// orientation, `wrt: Y` sets ref_point, ref_orientation and coord; explicit fields override).
/// An empty string means "not given". Which fields an op uses is fixed by its kind:
///   pose op / pose query          all seven (body and ref_body optional)
///   position query                point, body, ref_point, ref_body, coord
///   orientation query             orientation, body, ref_orientation, ref_body, coord
///   twist op, twist / linear_velocity query   point, body, ref_body, coord
///   angular_velocity query        body, ref_body, coord
///   acceleration op, acceleration / linear_acceleration query   as a twist
///   angular_acceleration query    body, ref_body, coord
///   remove pose                   orientation (of, the edge's head), ref_orientation (wrt, tail)
///   remove twist                  point, ref_body
///   frame op                      body (may be empty: the op error frame_without_body)
///   wrench op / wrench queries    body (on), ref_body (by; optional in queries), point, coord
///   remove wrench                 body (on), ref_body (by)
struct SemanticNames {
  std::string point, orientation, body;
  std::string ref_point, ref_orientation, ref_body;
  std::string coord;
};

enum class RotationForm : std::uint8_t { kIdentity, kQuaternion, kRpy, kMatrix };

/// A rotation exactly as written; its numbers are validated by the scene graph.
struct RotationValue {
  RotationForm form = RotationForm::kIdentity;
  std::array<double, 4> quaternion{1.0, 0.0, 0.0, 0.0};  // w, x, y, z
  std::array<double, 3> rpy{};                           // roll, pitch, yaw (radians)
  std::array<std::array<double, 3>, 3> matrix{};         // rows
};

struct ScriptOp {
  OpKind kind = OpKind::kBody;
  QueryKind query_kind = QueryKind::kPose;  // kQuery only
  SourceLocation location;                  // of the op's map
  std::string name;                         // kBody, kFrame
  SemanticNames names;
  RotationValue rotation;            // kPose
  std::array<double, 3> position{};  // kPose (metres)
  std::array<double, 3> linear{};    // kTwist (m/s)
  std::array<double, 3> angular{};   // kTwist (rad/s)
  std::array<double, 3> force{};     // kWrench (N), about `point`, in [coord]
  std::array<double, 3> moment{};    // kWrench (N m)
  // kTwist: an optional `acceleration: {linear, angular}` (has_acceleration); kAcceleration: its
  // `linear` / `angular` (m/s^2, rad/s^2) in acceleration_linear / acceleration_angular. A
  // missing part is zero.
  bool has_acceleration = false;
  std::array<double, 3> acceleration_linear{}, acceleration_angular{};
  // kUrdf: the file as written (resolved by the runner) and the name prefix.
  std::string file, prefix;
  // kJoint: name in `name`; parent / parent_body / child / child_body in names.ref_orientation,
  // names.ref_body, names.orientation, names.body; X_origin in `position` + `rotation`.
  JointKind joint_type = JointKind::kFixed;
  std::array<double, 3> axis{1.0, 0.0, 0.0};
  double lower = 0.0, upper = 0.0;
  bool has_mimic = false;
  std::string mimic_joint;
  double mimic_multiplier = 1.0, mimic_offset = 0.0;
  // kJoints: the maps as written, in document order.
  bool has_positions = false, has_velocities = false, has_accelerations = false;
  std::vector<std::pair<std::string, double>> positions, velocities, accelerations;
  bool repair = false;  // kPose, kTwist: repair a rejected relation (docs/repair.md)
  // Time (docs/scene-script.md, "Time"), in seconds as written: the runner converts them to
  // nanoseconds (a non-finite or out-of-range time is then the op error invalid_number).
  std::optional<double> stamp;  // kPose, kTwist, kJoints
  AtKind at = AtKind::kLatest;  // queries: the time policy
  double at_seconds = 0;        // AtKind::kTime
  std::optional<double> max_extrapolation, not_before;
  std::optional<double> ref_at;  // time travel: with `fixed`, and at = kTime
  std::string fixed;
  bool source_poses = false;  // velocity kinds: differentiate the poses
  // kBag (file in `file`): the topics (has_topics: given), `static` mode as written (empty:
  // same_body), the bodies map in document order, the pose topics (geometry_msgs/
  // PoseWithCovarianceStamped topic -> the frame it gives), the log-time window in seconds.
  bool has_topics = false;
  std::vector<std::string> topics;
  std::string static_mode;
  std::vector<std::pair<std::string, std::vector<std::string>>> bodies;
  std::vector<std::pair<std::string, std::string>> pose_topics;  // TOPIC -> frame, as written
  std::optional<double> start, end;
  // Uncertainty (docs/uncertainty.md). kPose, kTwist: the covariance given with the value, as
  // written (checked by the scene graph: invalid_number, invalid_covariance), its order and,
  // for a pose in edge form, the body convention. Queries: `covariance: true` asks for the
  // answer's covariance, in `covariance_order` for a pose or twist.
  bool has_covariance = false;
  std::array<std::array<double, 6>, 6> covariance{};
  bool covariance_angular_first = false;
  bool covariance_body = false;
  bool query_covariance = false;
};

/// The document's `time` map: the graph's time options (docs/time.md). Checked here: a window
/// that is not a finite positive time is a malformed script.
struct TimeSettings {
  bool given = false;
  std::int64_t window_ns = 10'000'000'000;  // 10 s
  bool linear = false;                      // interpolation: screw (false) or linear
  bool reject_duplicates = false;           // duplicate_stamp: replace (false) or reject
};

struct Script {
  Representation representation = Representation::kQuaternion;
  TimeSettings time;
  std::vector<ScriptOp> ops;
};

/// Why a script is malformed, and where.
struct ScriptError {
  SourceLocation location;
  std::string message;
};

/// Parses and validates a whole script. Never throws; never applies anything.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT base::Expected<Script, ScriptError> ReadScript(
    std::string_view text);

/// "FILE:LINE:COLUMN: message", the tool's stderr line for a malformed script.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string FormatScriptError(std::string_view file_name,
                                                                   const ScriptError& error);

/// The spelling of an op kind or query kind in scripts ("pose", "linear_velocity", ...).
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string_view ToString(OpKind kind) noexcept;
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string_view ToString(QueryKind kind) noexcept;

}  // namespace semgraph::script
