// Every text of the core: rejection messages of adds and removals, and the description of a
// query error. Formatted off the hot path only; role names come from the one table,
// semantics::FieldName.
#include "semgraph/semantics/describe.h"

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

#include "semgraph/core/scene_graph.h"
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
  return "[" + coord::FormatNumber(v.x()) + ", " + coord::FormatNumber(v.y()) + ", " +
         coord::FormatNumber(v.z()) + "]";
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
  return base::Unexpected{
      BuildError{code, what + " rejected (" + std::string(base::ToString(code)) + "): " + reason}};
}

std::string PoseAdd(const PoseSpec& spec) {
  const auto part = [](std::string_view point, std::string_view orientation,
                       std::string_view body) {
    std::string s = point == orientation
                        ? "{" + std::string(point) + "}"
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
  return "twist of " + std::string(spec.point) +
         (spec.body.empty() ? "" : "|" + std::string(spec.body)) + " wrt " +
         std::string(spec.ref_body) + " in [" + std::string(spec.coordinate_frame) + "]";
}

namespace {

// The frames from `top` down to `bottom` (an ancestor of it, or itself), top first.
std::vector<topology::FrameIndex> DownPath(const topology::SceneTopology& t,
                                           topology::FrameIndex top, topology::FrameIndex bottom) {
  std::vector<topology::FrameIndex> path;
  for (topology::FrameIndex f = bottom; f != top; f = t.pose_parent(f)) path.push_back(f);
  path.push_back(top);
  return {path.rbegin(), path.rend()};
}

std::string Joined(const std::vector<std::string>& frames) {
  std::string s;
  for (const std::string& f : frames) s += (s.empty() ? "" : " -> ") + f;
  return s;
}

// P3: the new edge {b} -> {a} would join two frames x1 (on the tail's side) and x2 (on the
// head's side) of one body X through frames of other bodies. Both routes from their meeting
// point down to X are named: the one the tail's tree already has, and the one through the
// new edge. A frame that does not exist yet is the tree of its own body, so it is X's frame
// on its side.
std::string DuplicatePosePath(const topology::SceneTopology& t, const topology::RuleViolation& v,
                              const topology::NewPoseEdge& ends, const PoseSpec& spec) {
  const std::string X(t.body_name(v.body));
  const std::string new_tail = "{" + std::string(spec.ref_orientation) + "}|" + X;
  const std::string new_head = "{" + std::string(spec.orientation) + "}|" + X;
  std::vector<std::string> existing, through_edge;  // from the meeting point down to X
  std::string meeting, x1;
  // Each route ends at the first frame of X it meets.
  const auto append_until_X = [&](const std::vector<topology::FrameIndex>& path,
                                  std::vector<std::string>& out) {
    for (topology::FrameIndex f : path) {
      out.push_back(Frame(t, f));
      if (t.body_of(f) == v.body) break;
    }
  };
  if (ends.tail.is_valid()) {
    const topology::FrameIndex top = t.forest().CommonAncestor(v.frame, ends.tail);
    meeting = Frame(t, top);
    append_until_X(DownPath(t, top, v.frame), existing);
    for (topology::FrameIndex f : DownPath(t, top, ends.tail)) through_edge.push_back(Frame(t, f));
  } else {  // a new tail frame of X
    meeting = new_tail;
    existing.push_back(new_tail);
    through_edge.push_back(new_tail);
  }
  x1 = existing.back();
  if (ends.head.is_valid()) {  // the head is a root (P1 passed): x2 lies below it
    append_until_X(DownPath(t, ends.head, v.other), through_edge);
  } else {  // a new head frame of X
    through_edge.push_back(new_head);
  }
  const std::string x2 = through_edge.back();
  std::string reason = "body " + X + " would be reachable twice from " + meeting + ": ";
  reason += existing.size() == 1 ? "at " + existing[0] + " itself" : "through " + Joined(existing);
  reason += ", and through the new edge, " + Joined(through_edge) +
            "; the frames of one body may be joined only through that body's own frames. ";
  // The fix: hang the new edge's end on X by a frame of X on the other side.
  if (ends.head_body == v.body) {
    reason += "Give {" + std::string(spec.orientation) + "} its pose relative to a frame of " + X +
              " (such as " + x1 + ") instead";
  } else if (ends.tail_body == v.body) {
    reason += "Give {" + std::string(spec.ref_orientation) + "} its pose relative to a frame of " +
              X + " (such as " + x2 + ") instead";
  } else {
    reason += "Join the two trees through frames of " + X + " (such as " + x1 + " and " + x2 +
              ") instead";
  }
  reason += ", or remove one of the two paths first";
  return reason;
}

}  // namespace

std::string PoseRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                     const topology::NewPoseEdge& ends, const PoseSpec& spec) {
  switch (v.code) {
    case ErrorCode::kMultiplePoseParents:  // P1
      return Frame(t, ends.head) + " already has a pose parent " + Frame(t, v.frame);
    case ErrorCode::kPoseCycle:  // P2
      return Frame(t, ends.tail) + " is already connected below " + Frame(t, ends.head) +
             " (through the pose tree rooted at " + Frame(t, v.frame) +
             "); the edge would close a cycle";
    case ErrorCode::kDuplicatePosePath:  // P3
      return DuplicatePosePath(t, v, ends, spec);
    case ErrorCode::kTwistMergeConflict:  // W4
      return "joining the pose trees of " + Frame(t, ends.tail) + " and " + Frame(t, ends.head) +
             " would give two twist paths between the same bodies (their twist edges would form a "
             "cycle)";
    default:
      return std::string(base::ToString(v.code));
  }
}

std::string TwistRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                      const topology::NewTwistEdge& ends) {
  switch (v.code) {
    case ErrorCode::kMultipleTwistParents:  // W1
      return Frame(t, ends.head) + " already has a twist parent: body " +
             std::string(t.body_name(v.body));
    case ErrorCode::kDuplicateTwistPath:  // W3
      return "the twist of " + std::string(t.body_name(ends.head_body)) + " relative to " +
             std::string(t.body_name(ends.tail)) +
             " already follows from the twist edges of the pose tree of " + Frame(t, ends.head);
    default:
      return std::string(base::ToString(v.code));
  }
}

std::string JointRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                      const topology::NewPoseEdge& ends, const PoseSpec& as_pose) {
  switch (v.code) {
    case ErrorCode::kMultipleTwistParents:  // W1
      return TwistRule(t, v, topology::NewTwistEdge{ends.tail_body, ends.head, ends.head_body});
    case ErrorCode::kDuplicateTwistPath:  // W3, in the tree the pose edge makes
      return "the twist of " + std::string(t.body_name(ends.head_body)) + " relative to " +
             std::string(t.body_name(ends.tail_body)) +
             " already follows from the twist edges of the pose trees it joins";
    default:
      return PoseRule(t, v, ends, as_pose);
  }
}

BuildResult RejectEnd(const topology::SceneTopology& t, internal::EndProblem p,
                      const internal::AddEnd& end, const std::string& what, std::string_view frame,
                      std::string_view body) {
  if (p == internal::EndProblem::kFrameBodyMismatch) {
    return Reject(ErrorCode::kFrameBodyMismatch, what,
                  "frame {" + std::string(frame) + "} is attached to body " +
                      std::string(t.body_name(t.body_of(end.frame))) + ", not " +
                      std::string(body));
  }
  return Reject(
      ErrorCode::kFrameWithoutBody, what,
      "frame {" + std::string(frame) + "} does not exist and no body is given to attach it to");
}

std::string EdgeReason(const topology::SceneTopology& t, const internal::EdgeLookup& l,
                       std::string_view relative_to, bool explain) {
  switch (l.code) {
    case ErrorCode::kInvalidName:
      return semantics::Describe(l.name_error, l.bad_name);
    case ErrorCode::kUnknownFrame:
      return "frame {" + std::string(l.bad_name) + "} does not exist";
    case ErrorCode::kUnknownBody:
      return "body " + std::string(l.bad_name) + " does not exist";
    case ErrorCode::kNoSuchEdge:
      break;
    default:
      return std::string(base::ToString(l.code));
  }
  if (!l.twist) {
    std::string s = "there is no pose edge " + Frame(t, l.tail) + " -> " + Frame(t, l.head);
    if (!explain) return s;
    const topology::FrameIndex p = t.pose_parent(l.head);
    return s + (p.is_valid()
                    ? " (the pose parent of " + Frame(t, l.head) + " is " + Frame(t, p) + ")"
                    : " (" + Frame(t, l.head) + " has no pose parent)");
  }
  std::string s = "there is no twist edge " + std::string(relative_to) + " -> " + Frame(t, l.head);
  if (!explain) return s;
  return s + (!l.edge.is_valid() ? " (" + Frame(t, l.head) + " has no twist parent)"
                                 : " (its twist parent is " +
                                       std::string(t.body_name(t.twist_edge(l.edge).tail)) + ")");
}

}  // namespace text

namespace {

// no_twist_path: C and D are not joined by the twist edges of the pose tree of the query's
// point (e.asked). Names the first link of the pose path from C to D that no twist edge
// spans: two bodies mounted one on the other with no twist between them, typically a static
// mount that needs a zero twist.
std::string NoTwistPath(const topology::SceneTopology& t, const QueryError& e) {
  const topology::BodyIndex C = t.BodyOfName(e.name), D = t.BodyOfName(e.other);
  std::string text = "no twist path joins body " + std::string(t.names().name(e.name)) +
                     " and body " + std::string(t.names().name(e.other));
  const topology::FrameIndex point = t.FrameOfName(e.asked);
  if (!point.is_valid() || !C.is_valid() || !D.is_valid()) return text + " in this pose tree";
  text += " in the pose tree of " + text::Frame(t, point);
  const topology::TreeRecord* rec = t.RecordOf(point);
  const auto connected = [&](topology::BodyIndex u, topology::BodyIndex v) {
    return u == v || (rec != nullptr && rec->twists.Connected(u, v));
  };
  // A frame of the tree on X's side: one of X's own, or the head of a twist edge that X's
  // twist edges reach.
  const auto side = [&](topology::BodyIndex X) {
    topology::FrameIndex f = t.SomeFrameOfBodyInTree(X, point);
    if (!f.is_valid() && rec != nullptr) {
      rec->twists.ForEachEdge(
          [&](topology::TwistEdgeIndex edge, topology::BodyIndex, topology::BodyIndex) {
            const topology::FrameIndex h = t.twist_edge(edge).head;
            if (!f.is_valid() && connected(t.body_of(h), X)) f = h;
          });
    }
    return f;
  };
  const topology::FrameIndex x = side(C), y = side(D);
  for (const auto& [body, frame] : {std::pair{C, x}, std::pair{D, y}}) {
    if (!frame.is_valid()) {
      return text + ": body " + std::string(t.body_name(body)) +
             " has no frame and no twist edge in that tree; a twist relates bodies of one pose "
             "tree only";
    }
  }
  // The pose path x .. y, through their common ancestor; the first hop between two bodies that
  // no twist path joins is a missing twist edge.
  const topology::FrameIndex top = t.forest().CommonAncestor(x, y);
  std::vector<topology::FrameIndex> path = text::DownPath(t, top, x);
  std::reverse(path.begin(), path.end());
  const std::vector<topology::FrameIndex> down = text::DownPath(t, top, y);
  path.insert(path.end(), down.begin() + 1, down.end());
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const topology::BodyIndex U = t.body_of(path[i]), V = t.body_of(path[i + 1]);
    if (connected(U, V)) continue;
    const bool down_edge = t.pose_parent(path[i + 1]) == path[i];
    const topology::FrameIndex parent = down_edge ? path[i] : path[i + 1];
    const topology::FrameIndex child = down_edge ? path[i + 1] : path[i];
    const std::string P(t.body_name(t.body_of(parent))), K(t.body_name(t.body_of(child)));
    return text + ": no twist edge joins body " + K + " and body " + P + " (the mount " +
           text::Frame(t, child) + " wrt " + text::Frame(t, parent) + "); add the twist of " +
           text::Frame(t, child) + " wrt " + P + ", a zero twist if the mount is static";
  }
  return text;
}

// The reason part of a query error's text (no code). `given`: the spec's name for the field.
template <class EdgeText>
std::string Reason(const topology::SceneTopology& t, const QueryError& e, const std::string& role,
                   const std::string& name, bool named, std::string_view given,
                   const EdgeText& edge_text) {
  const semantics::NameTable& names = t.names();
  std::string reason;
  switch (e.code) {
    case ErrorCode::kExtrapolation:
      if (e.time.single_sample) {
        return edge_text() + " has a single sample (at " + text::StampText(e.time.first) +
               "): no derivative; asked " + text::StampText(e.time.asked);
      }
      return edge_text() + " has samples in " + text::StampRange(e.time.first, e.time.last) +
             "; asked " + text::StampText(e.time.asked);
    case ErrorCode::kStale:
      return edge_text() + " is stale: its newest sample is at " + text::StampText(e.time.last) +
             ", older than not_before " + text::StampText(e.time.asked);
    case ErrorCode::kInvalidNumber:
      if (e.detail.code == ErrorCode::kOk)
        return "the extrapolation horizon (max_extrapolation) is negative";
      return coord::Describe(e.detail, names);
    case ErrorCode::kInvalidName:
      reason = "the " + role + " name is missing or invalid";
      if (!given.empty()) {  // the spec says which: name the problem
        if (auto problem = semantics::ValidateName(given); !problem) {
          reason += ": " + semantics::Describe(problem.error(), given);
        }
      }
      break;
    case ErrorCode::kUnknownFrame:
      reason = named ? "the " + role + " names frame {" + name + "}, which does not exist"
                     : "the " + role +
                           " names a frame that does not exist (pass the query's spec to Describe "
                           "for its name)";
      break;
    case ErrorCode::kUnknownBody:
      reason = named
                   ? "the " + role + " names body " + name + ", which does not exist"
                   : "the " + role +
                         " names a body that does not exist (pass the query's spec to Describe for "
                         "its name)";
      break;
    case ErrorCode::kFrameBodyMismatch:
      reason = "the " + role + " {" + name + "} is attached to body " +
               std::string(names.name(e.other)) +
               (e.asked.is_valid()
                    ? ", not to body " + std::string(names.name(e.asked)) + " named in the query"
                    : ", not to the body named in the query");
      break;
    case ErrorCode::kNoPosePath:
      reason = "{" + name + "} and {" + std::string(names.name(e.other)) +
               "} are in different pose trees: no pose path joins them";
      break;
    case ErrorCode::kNoTwistPath:
      reason = NoTwistPath(t, e);
      break;
    case ErrorCode::kNoAcceleration:
      reason = "the twist edge " +
               (e.other.is_valid() ? std::string(names.name(e.other)) : std::string("?")) +
               " -> {" + (e.name.is_valid() ? std::string(names.name(e.name)) : std::string("?")) +
               "} on the twist path carries no acceleration (give it with the twist, or with "
               "AddAcceleration; a joint's edge, as the joint's acceleration)";
      break;
    case ErrorCode::kQueryInvalidated:
      reason =
          "an edge the compiled query reads was removed after it was compiled; compile it again";
      break;
    default:
      reason = coord::Describe(e.detail, names);
      break;
  }
  return reason;
}

// The reason of a query error; `spec` (may be null) gives the names that were never interned.
std::string QueryReasonOf(const topology::SceneTopology& t, const QueryError& e,
                          const PoseSpec* spec) {
  const semantics::NameTable& names = t.names();
  const std::string role(semantics::FieldName(e.field));
  // A time travel's fixed frame is not a field of the spec: never name a field for it.
  const std::string_view given =
      spec != nullptr && !e.time.fixed_frame ? spec->field(e.field) : std::string_view();
  const std::string name = e.name.is_valid() ? std::string(names.name(e.name)) : std::string(given);
  const bool named = e.name.is_valid() || !given.empty();
  const auto frame_text = [&](NameId id) {
    const FrameIndex f = t.FrameOfName(id);
    return f.is_valid() ? text::Frame(t, f) : "{" + std::string(names.name(id)) + "}";
  };
  const auto edge_text = [&] {
    return (e.time.twist_edge ? "twist of " : "pose of ") + frame_text(e.name) + " wrt " +
           (e.time.twist_edge ? std::string(names.name(e.other)) : frame_text(e.other));
  };
  std::string reason;
  if (e.time.fixed_frame && e.code == ErrorCode::kInvalidName) {
    reason = "the name of the time travel's fixed frame is missing or invalid";
  } else if (e.time.fixed_frame && e.code == ErrorCode::kUnknownFrame) {
    reason = "the fixed frame of the time travel " + (named ? "{" + name + "} " : std::string()) +
             "does not exist";
  } else if (e.time.fixed_frame && e.code == ErrorCode::kNoPosePath) {
    reason = "the fixed frame {" + name + "} is not in the pose tree of the query's frames";
  } else {
    reason = Reason(t, e, role, name, named, given, edge_text);
  }
  return reason;
}

// "query failed (<code>): <reason>", as a rejected build call's "... rejected (<code>): ...".
std::string QueryText(const topology::SceneTopology& t, const QueryError& e, const PoseSpec* spec) {
  return "query failed (" + std::string(base::ToString(e.code)) + "): " + QueryReasonOf(t, e, spec);
}

}  // namespace

std::string text::QueryReason(const topology::SceneTopology& t, const QueryError& e,
                              const PoseSpec* spec) {
  return QueryReasonOf(t, e, spec);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e) const {
  return QueryText(topology_, e, nullptr);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const TwistSpec& spec) const {
  PoseSpec p;
  p.point = spec.point;
  p.body = spec.body;
  p.ref_body = spec.ref_body;
  p.coordinate_frame = spec.coordinate_frame;
  return QueryText(topology_, e, &p);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const PoseSpec& spec) const {
  return QueryText(topology_, e, &spec);
}

std::string Describe(const UpdateError& e) {
  const coord::ValueDetail& v = e.value;
  const bool position = v.role == coord::ValueRole::kJointPosition;
  const bool velocity = v.role == coord::ValueRole::kJointVelocity;
  const bool joint = position || velocity || v.role == coord::ValueRole::kJointAcceleration;
  if (joint && (e.code == ErrorCode::kInvalidNumber || e.code == ErrorCode::kJointLimit)) {
    const std::string what = std::string(position   ? "position"
                                         : velocity ? "velocity"
                                                    : "acceleration") +
                             " of joint " + std::to_string(e.joint) + " of the group is " +
                             coord::FormatNumber(v.magnitude);
    if (e.code == ErrorCode::kInvalidNumber) return what + " (must be finite)";
    return what +
           (v.magnitude > e.limit ? ", above the joint's upper limit "
                                  : ", below the joint's lower limit ") +
           coord::FormatNumber(e.limit);
  }
  if (e.code == ErrorCode::kInvalidNumber || e.code == ErrorCode::kInvalidRotation) {
    return coord::Describe(e.error(), semantics::NameTable{});  // a value error names no frame
  }
  return std::string(base::ToString(e.code));
}

#define SEMGRAPH_INSTANTIATE_DESCRIBE(B)                                                  \
  template std::string SceneGraph<B>::Describe(const QueryError&) const;                  \
  template std::string SceneGraph<B>::Describe(const QueryError&, const PoseSpec&) const; \
  template std::string SceneGraph<B>::Describe(const QueryError&, const TwistSpec&) const;
SEMGRAPH_INSTANTIATE_DESCRIBE(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_DESCRIBE(coord::HomogeneousBackend)

}  // namespace semgraph::core
