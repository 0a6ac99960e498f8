// File: semgraph/core/specs.h
//
// The words of the scene graph's API, with no numbers: the names of a query or an add by role
// (PoseSpec, TwistSpec), and the two error types. Build-time calls return BuildError (a code
// and a formatted message); queries return QueryError (small, trivially copyable, no strings;
// SceneGraph::Describe formats it off the hot path).
// Cost: all O(1) plain values; the builders copy string_views (no allocation, no ownership:
// the names must outlive the spec).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "semgraph/base/error_code.h"
#include "semgraph/base/expected.h"
#include "semgraph/coord/error.h"
#include "semgraph/semantics/mismatch.h"
#include "semgraph/semantics/names.h"

namespace semgraph::core {

using base::ErrorCode;
using base::Expected;
using base::Ok;
using semantics::NameId;

/// How far a relation is from what the graph already determines (repair's consistency check):
/// for poses the position error (m) and the rotation angle error (rad); for twists the linear
/// (m/s) and angular (rad/s) velocity errors, as the norms of the differences.
struct Discrepancy {
  double position = 0;
  double angle = 0;
};

/// A rejected build-time operation: a stable code (docs/rules.md) and a message naming the
/// frames / bodies involved and the existing relation it conflicts with.
struct BuildError {
  ErrorCode code = ErrorCode::kOk;
  std::string message;
  /// Set when a repair's consistency check refused the relation: how far it is from the value
  /// the graph derives (docs/repair.md).
  std::optional<Discrepancy> discrepancy = std::nullopt;
};

/// Opt-in repair of a rejected AddPose / AddTwist (docs/repair.md). Each strategy is tried
/// only for the rule it answers; a relation no strategy accepts keeps its original error.
struct RepairPolicy {
  bool invert = true;             ///< P1 / W1: add the inverse relation instead
  bool reroot = true;             ///< the inverse's head has a pose parent: re-root its tree first
  bool check_consistency = true;  ///< already determined: accept if equal to the derived value
  double position_tolerance = 1e-9;  ///< m (m/s for twists); compared with Discrepancy::position
  double angle_tolerance = 1e-9;     ///< rad (rad/s for twists); compared with Discrepancy::angle
};
enum class RepairKind : std::uint8_t { kNone, kInverted, kRerooted, kConsistent };
/// "none", "inverted", "rerooted", "consistent".
[[nodiscard]] constexpr std::string_view ToString(RepairKind k) noexcept {
  switch (k) {
    case RepairKind::kNone:
      return "none";
    case RepairKind::kInverted:
      return "inverted";
    case RepairKind::kRerooted:
      return "rerooted";
    case RepairKind::kConsistent:
      return "consistent";
  }
  return "none";
}
/// What a repairing add did.
struct RepairReport {
  RepairKind applied = RepairKind::kNone;  ///< kNone: accepted as given
  std::string change;                      ///< the relation actually added, or why it was a no-op
  std::size_t reversed_edges = 0;          ///< kRerooted: pose edges reversed (their handles and
                                           ///< the compiled queries using them are invalidated)
  Discrepancy discrepancy;                 ///< kConsistent: the measured difference
};
using BuildResult = Expected<Ok, BuildError>;

/// A failed query: small, trivially copyable, no strings (formatted later by Describe).
/// What `name`, `other` and `asked` hold depends on the code:
///   invalid_name          field: the argument; no names (the name may be unprintable)
///   unknown_frame/_body   name: the argument's name (invalid if never interned)
///   frame_body_mismatch   name: the frame; other: its actual body; asked: the body the query named
///   no_pose_path          name, other: the two frames in different pose trees
///   no_twist_path         name, other: the two bodies no twist path joins; asked: the point
///   representation_constraint, semantic_mismatch: detail
///   extrapolation, stale  name: the edge's head frame; other: its tail frame (a pose edge) or
///                         tail body (a twist edge, time.twist_edge); time: its samples, the time
///                         (time.wrench: a stored wrench, name: its `on` body, other: its `by`)
///   unknown_frame, no_pose_path with time.fixed_frame: about TimeTravel's fixed frame
struct QueryTimeDetail {
  bool twist_edge = false;
  bool fixed_frame = false;
  bool single_sample = false;  ///< extrapolation: a derivative of an edge with one sample
  bool wrench = false;         ///< extrapolation, stale: of a stored wrench's samples
  std::int64_t first = 0, last = 0, asked = 0;  ///< nanoseconds
};
struct QueryError {
  ErrorCode code = ErrorCode::kOk;
  semantics::Field field = semantics::Field::kPoint;  ///< the argument that is unknown/mismatched
  NameId name;
  NameId other;
  NameId asked;
  coord::Error detail;
  QueryTimeDetail time;
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
  /// The name this spec gives to a role.
  [[nodiscard]] std::string_view field(semantics::Field f) const noexcept {
    switch (f) {
      case semantics::Field::kPoint:
        return point;
      case semantics::Field::kOrientation:
        return orientation;
      case semantics::Field::kBody:
        return body;
      case semantics::Field::kRefPoint:
        return ref_point;
      case semantics::Field::kRefOrientation:
        return ref_orientation;
      case semantics::Field::kRefBody:
        return ref_body;
      case semantics::Field::kCoordinateFrame:
        return coordinate_frame;
    }
    return {};
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

}  // namespace semgraph::core
