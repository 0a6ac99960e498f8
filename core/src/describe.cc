// Every text of the core: rejection messages of adds and removals, and the description of a
// query error. Formatted off the hot path only; role names come from the one table,
// semantics::FieldName.
#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "text.h"

namespace semgraph::core {

using base::ErrorCode;
using semantics::Field;

namespace text {

std::string Braced(std::string_view frame, std::string_view body) {
  return "{" + std::string(frame) + "}|" + std::string(body);
}

std::string Frame(const topology::SceneTopology& t, topology::FrameIndex f) {
  return Braced(t.frame_name(f), t.body_name(t.body_of(f)));
}

std::string Vector(const Eigen::Vector3d& v) {
  // Round-trip digits (coord::FormatNumber), so the stored value is shown exactly.
  return "[" + coord::FormatNumber(v.x()) + ", " + coord::FormatNumber(v.y()) + ", " + coord::FormatNumber(v.z()) + "]";
}

std::string StampText(std::int64_t ns) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.3f s", static_cast<double>(ns) * 1e-9);
  return buf;
}

std::string StampRange(std::int64_t first_ns, std::int64_t last_ns) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "[%.3f, %.3f] s", static_cast<double>(first_ns) * 1e-9,
                static_cast<double>(last_ns) * 1e-9);
  return buf;
}

BuildResult Reject(ErrorCode code, const std::string& what, const std::string& reason) {
  return base::Unexpected{BuildError{code, what + " rejected (" + std::string(base::ToString(code)) + "): " + reason}};
}

std::string PoseAdd(const PoseSpec& spec) {
  const auto part = [](std::string_view point, std::string_view orientation, std::string_view body) {
    std::string s = point == orientation ? "{" + std::string(point) + "}"
                                         : "(" + std::string(point) + ",[" + std::string(orientation) + "])";
    return body.empty() ? s : s + "|" + std::string(body);
  };
  std::string out = "pose of " + part(spec.point, spec.orientation, spec.body) + " wrt " +
                    part(spec.ref_point, spec.ref_orientation, spec.ref_body);
  if (spec.coordinate_frame != spec.ref_orientation || spec.point != spec.orientation ||
      spec.ref_point != spec.ref_orientation) {
    out += " in [" + std::string(spec.coordinate_frame) + "]";
  }
  return out;
}

std::string TwistAdd(const TwistSpec& spec) {
  return "twist of " + std::string(spec.point) + (spec.body.empty() ? "" : "|" + std::string(spec.body)) +
         " wrt " + std::string(spec.ref_body) + " in [" + std::string(spec.coordinate_frame) + "]";
}

std::string PoseRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                     const topology::NewPoseEdge& ends, const PoseSpec& spec) {
  switch (v.code) {
    case ErrorCode::kMultiplePoseParents:  // P1
      return Frame(t, ends.head) + " already has a pose parent " + Frame(t, v.frame);
    case ErrorCode::kPoseCycle:  // P2
      return Frame(t, ends.tail) + " is already connected below " + Frame(t, ends.head) +
             " (through the pose tree rooted at " + Frame(t, v.frame) + "); the edge would close a cycle";
    case ErrorCode::kDuplicatePosePath: {  // P3
      std::string reason = "body " + std::string(t.body_name(v.body)) + " would be reachable twice: ";
      reason += v.frame.is_valid() ? Frame(t, v.frame) : "{" + std::string(spec.ref_orientation) + "}";
      reason += " is in the pose tree of {" + std::string(spec.ref_orientation) + "} and ";
      reason += v.other.is_valid() ? Frame(t, v.other) : "{" + std::string(spec.orientation) + "}";
      reason += " is in the pose tree of {" + std::string(spec.orientation) + "}";
      return reason;
    }
    case ErrorCode::kTwistMergeConflict:  // W4
      return "joining the pose trees of " + Frame(t, ends.tail) + " and " + Frame(t, ends.head) +
             " would give two twist paths between the same bodies (their twist edges would form a cycle)";
    default:
      return std::string(base::ToString(v.code));
  }
}

std::string TwistRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                      const topology::NewTwistEdge& ends) {
  switch (v.code) {
    case ErrorCode::kMultipleTwistParents:  // W1
      return Frame(t, ends.head) + " already has a twist parent: body " + std::string(t.body_name(v.body));
    case ErrorCode::kDuplicateTwistPath:  // W3
      return "the twist of " + std::string(t.body_name(ends.head_body)) + " relative to " +
             std::string(t.body_name(ends.tail)) + " already follows from the twist edges of the pose tree of " +
             Frame(t, ends.head);
    default:
      return std::string(base::ToString(v.code));
  }
}

}  // namespace text

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e) const {
  return Describe(e, PoseSpec{});
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const TwistSpec& spec) const {
  PoseSpec p;
  p.point = spec.point;
  p.body = spec.body;
  p.ref_body = spec.ref_body;
  p.coordinate_frame = spec.coordinate_frame;
  return Describe(e, p);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const PoseSpec& spec) const {
  const semantics::NameTable& names = topology_.names();
  const std::string role(semantics::FieldName(e.field));
  const std::string name = e.name.is_valid() ? std::string(names.name(e.name)) : std::string(spec.field(e.field));
  const auto frame_text = [&](NameId id) {
    const FrameIndex f = topology_.FrameOfName(id);
    return f.is_valid() ? text::Frame(topology_, f) : "{" + std::string(names.name(id)) + "}";
  };
  const auto edge_text = [&] {
    return (e.time.twist_edge ? "twist of " : "pose of ") + frame_text(e.name) + " wrt " +
           (e.time.twist_edge ? std::string(names.name(e.other)) : frame_text(e.other));
  };
  if (e.time.fixed_frame && e.code == ErrorCode::kUnknownFrame) {
    return "the fixed frame of the time travel " + (e.name.is_valid() ? "{" + name + "} " : std::string()) +
           "does not exist";
  }
  if (e.time.fixed_frame && e.code == ErrorCode::kNoPosePath) {
    return "the fixed frame {" + name + "} is not in the pose tree of the query's frames";
  }
  switch (e.code) {
    case ErrorCode::kExtrapolation:
      if (e.time.single_sample) {
        return edge_text() + " has a single sample (at " + text::StampText(e.time.first) +
               "): no derivative; asked " + text::StampText(e.time.asked);
      }
      return edge_text() + " has samples in " + text::StampRange(e.time.first, e.time.last) + "; asked " +
             text::StampText(e.time.asked);
    case ErrorCode::kStale:
      return edge_text() + " is stale: its newest sample is at " + text::StampText(e.time.last) +
             ", older than not_before " + text::StampText(e.time.asked);
    case ErrorCode::kInvalidNumber:
      if (e.detail.code == ErrorCode::kOk) return "the extrapolation horizon (max_extrapolation) is negative";
      return coord::Describe(e.detail, names);
    case ErrorCode::kInvalidName:
      return "the " + role + " name is missing or invalid";
    case ErrorCode::kUnknownFrame:
      return "the " + role + " names frame {" + name + "}, which does not exist";
    case ErrorCode::kUnknownBody:
      return "the " + role + " names body " + name + ", which does not exist";
    case ErrorCode::kFrameBodyMismatch:
      return "the " + role + " {" + name + "} is attached to body " + std::string(names.name(e.other)) +
             (e.asked.is_valid() ? ", not to body " + std::string(names.name(e.asked)) + " named in the query"
                                 : ", not to the body named in the query");
    case ErrorCode::kNoPosePath:
      return "{" + name + "} and {" + std::string(names.name(e.other)) +
             "} are in different pose trees: no pose path joins them";
    case ErrorCode::kNoTwistPath:
      return "no twist path joins body " + std::string(names.name(e.name)) + " and body " +
             std::string(names.name(e.other)) + " in this pose tree";
    default:
      return coord::Describe(e.detail, names);
  }
}

#define SEMGRAPH_INSTANTIATE_DESCRIBE(B)                                                      \
  template std::string SceneGraph<B>::Describe(const QueryError&) const;                     \
  template std::string SceneGraph<B>::Describe(const QueryError&, const PoseSpec&) const;    \
  template std::string SceneGraph<B>::Describe(const QueryError&, const TwistSpec&) const;
SEMGRAPH_INSTANTIATE_DESCRIBE(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_DESCRIBE(coord::HomogeneousBackend)

}  // namespace semgraph::core
