// File: tools/semgraph/script_reader.h
//
// Reads a scene script (spec/scene-script.md) into a list of typed operations. The whole
// document is parsed and validated here, before anything touches a scene graph, so that a
// malformed script (bad YAML, unknown op, missing or mistyped field, a field of the wrong op,
// wrong array length, non-numeric number, unknown representation, a rotation with zero or
// several forms) applies nothing: ReadScript() then returns a ScriptError with the 1-based line
// and column of the offending node.
//
// What is deliberately *not* checked here: names (empty, unprintable, too long) and numbers
// (NaN, Inf, non-unit quaternions). Those are the scene graph's rules and are reported per op as
// invalid_name / invalid_number / invalid_rotation, so that the script and the C++ API agree.
// `.nan`, `.inf` and `-.inf` are numbers to YAML and are passed through for that reason.
//
// Limits, so that hostile input cannot crash the tool: at most kMaxScriptBytes of text, YAML
// nesting at most kMaxNestingDepth deep (checked while parsing, so yaml-cpp never recurses
// deeper), at most kMaxYamlNodes nodes (more than a 16 MiB script can hold: a guard, not a
// rule). yaml-cpp's own node tree (hundreds of bytes a node) is never built: a compact tree
// (~40 bytes a node) is built from the parser's events instead. Aliases are shared, not
// copied, so alias bombs cost nothing.
//
// Cost: O(size of the text). Thread safety: ReadScript is a pure function.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/base/expected.h"

namespace semgraph::tools {

inline constexpr std::size_t kMaxScriptBytes = std::size_t{16} << 20;  // 16 MiB
inline constexpr int kMaxNestingDepth = 64;
inline constexpr std::size_t kMaxYamlNodes = std::size_t{1} << 23;

/// A position in the script text, both 1-based.
struct SourceLocation {
  int line = 1;
  int column = 1;
};

enum class Representation : std::uint8_t { kQuaternion, kHomogeneous };

enum class OpKind : std::uint8_t {
  kBody,
  kFrame,
  kPose,
  kTwist,
  kRemovePose,
  kRemoveTwist,
  kQuery
};

enum class QueryKind : std::uint8_t {
  kPose,
  kPosition,
  kOrientation,
  kTwist,
  kLinearVelocity,
  kAngularVelocity,
};

/// The names of an op's semantics after the shorthand is applied (`of: X` sets point and
/// orientation, `wrt: Y` sets ref_point, ref_orientation and coord; explicit fields override).
/// An empty string means "not given". Which fields an op uses is fixed by its kind:
///   pose op / pose query          all seven (body and ref_body optional)
///   position query                point, body, ref_point, ref_body, coord
///   orientation query             orientation, body, ref_orientation, ref_body, coord
///   twist op, twist / linear_velocity query   point, body, ref_body, coord
///   angular_velocity query        body, ref_body, coord
///   remove pose                   orientation (of, the edge's head), ref_orientation (wrt, tail)
///   remove twist                  point, ref_body
///   frame op                      body (may be empty: the op error frame_without_body)
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
};

struct Script {
  Representation representation = Representation::kQuaternion;
  std::vector<ScriptOp> ops;
};

/// Why a script is malformed, and where.
struct ScriptError {
  SourceLocation location;
  std::string message;
};

/// Parses and validates a whole script. Never throws; never applies anything.
[[nodiscard]] base::Expected<Script, ScriptError> ReadScript(std::string_view text);

/// "FILE:LINE:COLUMN: message", the tool's stderr line for a malformed script.
[[nodiscard]] std::string FormatScriptError(std::string_view file_name, const ScriptError& error);

/// The spelling of an op kind or query kind in scripts ("pose", "linear_velocity", ...).
[[nodiscard]] std::string_view ToString(OpKind kind) noexcept;
[[nodiscard]] std::string_view ToString(QueryKind kind) noexcept;

}  // namespace semgraph::tools
