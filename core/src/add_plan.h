// Private to core/src: the one add pipeline of AddPose, AddTwist and AddJoint (add.cc,
// joints.cc), as plain data. Every add runs
//   names (LookUpNames: each distinct name once; only names not interned yet are validated)
//   -> its own number checks -> InternNames -> ResolveEnd for each end (node resolution)
//   -> its own semantic checks -> the rules (topology/rules.h) on the AddPlan's ends
//   -> SceneGraph::ReserveAdd(plan) (every allocation) -> NameRollback::Commit
//   -> SceneGraph::CommitAdd(plan) (create the nodes, link the edges; allocation-free)
// so node resolution, rollback and node creation are written once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "semgraph/semantics/names.h"
#include "semgraph/topology/rules.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core::internal {

using semantics::NameId;
using topology::BodyIndex;
using topology::FrameIndex;
using topology::TwistEdgeIndex;

/// A name an add reads: empty is allowed only when not required (an optional body).
struct NamedField {
  std::string_view value;
  bool required = true;
};

/// The names of an add, looked up before any check that could reject it and interned after
/// the number checks (the caller's NameRollback drops them on a later rejection).
template <std::size_t N>
struct AddNames {
  NameId id[N];
  std::uint32_t hash[N] = {};
  int first[N];  ///< the first field with the same name (same view or same text)

  /// Looks each distinct name up once; a name not interned yet is validated. Returns the index
  /// of the first invalid field (its error in `error`), or -1. O(sum of name lengths).
  int LookUp(const semantics::NameTable& names, const NamedField (&fields)[N],
             semantics::NameError& error) noexcept {
    // Same view (the builders copy one view into several fields) before same text; the last
    // and first bytes decide most mismatches of names that share a prefix or a suffix.
    const auto same_name = [](std::string_view x, std::string_view y) {
      return x.size() == y.size() && (x.data() == y.data() || (!x.empty() && x.back() == y.back() &&
                                                               x.front() == y.front() && x == y));
    };
    for (int i = 0; i < static_cast<int>(N); ++i) {
      const NamedField& n = fields[i];
      first[i] = i;
      if (n.value.empty() && !n.required) continue;
      // An empty name is never shared: it must reach ValidateName (invalid_name), not borrow
      // the unset id of an empty optional field.
      for (int j = 0; j < i && first[i] == i && !n.value.empty(); ++j) {
        if (same_name(fields[j].value, n.value)) first[i] = j;
      }
      if (first[i] < i) {
        id[i] = id[first[i]];
        hash[i] = hash[first[i]];
        continue;
      }
      const semantics::NameTable::Lookup lookup = names.FindWithHash(n.value);
      id[i] = lookup.id;
      hash[i] = lookup.hash;
      if (id[i].is_valid()) continue;
      if (auto ok = semantics::ValidateName(n.value); !ok) {
        error = ok.error();
        return i;
      }
    }
    return -1;
  }
  /// Interns the names LookUp did not find (valid by then).
  void Intern(semantics::NameTable& names, const NamedField (&fields)[N]) {
    for (int i = 0; i < static_cast<int>(N); ++i) {
      if (id[i].is_valid() || fields[i].value.empty()) continue;
      id[i] = first[i] < i ? id[first[i]] : names.InternNew(fields[i].value, hash[i]);
    }
  }
};

/// One end of an edge being added: a frame {x} and its body, each existing or created by the
/// add (invalid index). A twist's tail is a body only (frame_name invalid).
struct AddEnd {
  NameId frame_name;
  FrameIndex frame;
  NameId body_name;
  BodyIndex body;
};

/// Node resolution of {x}|given (given invalid: no body named): an existing frame must be on
/// the given body and brings its own; a new frame needs a body to be attached to.
enum class EndProblem : std::uint8_t { kNone, kFrameBodyMismatch, kFrameWithoutBody };
[[nodiscard]] inline EndProblem ResolveEnd(const topology::SceneTopology& t, NameId frame,
                                           NameId given, AddEnd& end) noexcept {
  end.frame_name = frame;
  end.frame = t.FrameOfName(frame);
  end.body_name = given;
  end.body = t.BodyOfName(given);
  if (end.frame.is_valid()) {
    if (given.is_valid() && end.body != t.body_of(end.frame)) return EndProblem::kFrameBodyMismatch;
    end.body = t.body_of(end.frame);
    end.body_name = t.body_name_id(end.body);
    return EndProblem::kNone;
  }
  return given.is_valid() ? EndProblem::kNone : EndProblem::kFrameWithoutBody;
}

/// What an add creates and links: the pose edge tail.frame -> head.frame and/or the twist edge
/// tail.body -> head.frame (a joint: both). Bodies and frames are created when invalid: bodies
/// first (a pose's tail body is its head body when they share a name), then the head frame,
/// then the tail frame. `tail_body_first`: a joint creates its parent body before its child
/// body, as it always did (node indices are observable: dumps, AllJoints' order).
struct AddPlan {
  AddEnd tail, head;
  bool pose_edge = false;
  bool twist_edge = false;
  bool tail_body_first = false;

  [[nodiscard]] bool same_body() const noexcept {
    return pose_edge && tail.body_name == head.body_name;
  }
  [[nodiscard]] std::size_t new_bodies() const noexcept {
    return (head.body.is_valid() ? 0 : 1) + (tail.body.is_valid() || same_body() ? 0 : 1);
  }
  [[nodiscard]] std::size_t new_frames() const noexcept {
    return (head.frame.is_valid() ? 0 : 1) + (!pose_edge || tail.frame.is_valid() ? 0 : 1);
  }
  /// The pose edge's ends as the rules see them.
  [[nodiscard]] topology::NewPoseEdge pose_ends() const noexcept {
    return {tail.frame, head.frame, tail.body, head.body, same_body()};
  }
  [[nodiscard]] topology::NewTwistEdge twist_ends() const noexcept {
    return {tail.body, head.frame, head.body};
  }
};

/// The nodes and edges CommitAdd made or used.
struct AddedEdges {
  FrameIndex tail, head;
  BodyIndex tail_body, head_body;
  TwistEdgeIndex twist;
};

}  // namespace semgraph::core::internal
