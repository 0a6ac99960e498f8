// Private to core/src: the one finder of an existing edge by names, shared by the handle
// finders (FindPoseEdge, FindTwistEdge: realtime.cc) and the removals (RemovePose,
// RemoveTwist: add.cc), which then act on what it found (a handle, or a removal by index).
// Codes and ids only; the text is written by text::EdgeReason (describe.cc) on rejection.
#pragma once

#include <string_view>

#include "semgraph/base/error_code.h"
#include "semgraph/semantics/names.h"
#include "semgraph/topology/rules.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core::internal {

/// The first failing check of invalid_name -> unknown_frame / unknown_body -> no_such_edge
/// (kOk: the edge exists), and what the message names.
struct EdgeLookup {
  base::ErrorCode code = base::ErrorCode::kOk;
  bool twist = false;
  std::string_view bad_name;        ///< invalid_name, unknown_frame, unknown_body: that name
  semantics::NameError name_error;  ///< invalid_name
  topology::FrameIndex head, tail;  ///< the frames (twist: head only)
  topology::BodyIndex tail_body;    ///< twist: the reference body
  topology::TwistEdgeIndex edge;    ///< twist: the edge into head (from any body), if any
};

/// Checks {of} then {relative_to}; on the first invalid one records invalid_name in {l} and
/// returns false. Allocation-free.
[[nodiscard]] inline bool NamesValid(EdgeLookup& l, std::string_view of,
                                     std::string_view relative_to) noexcept {
  for (std::string_view n : {of, relative_to}) {
    if (auto ok = semantics::ValidateName(n); !ok) {
      l.code = base::ErrorCode::kInvalidName;
      l.bad_name = n;
      l.name_error = ok.error();
      return false;
    }
  }
  return true;
}

/// The pose edge {relative_to} -> {of}. O(|names|), allocation-free.
[[nodiscard]] inline EdgeLookup LookUpPoseEdge(const topology::SceneTopology& t,
                                               std::string_view of,
                                               std::string_view relative_to) noexcept {
  EdgeLookup l;
  if (!NamesValid(l, of, relative_to)) return l;
  l.head = t.FindFrame(of);
  l.tail = t.FindFrame(relative_to);
  if (!l.head.is_valid() || !l.tail.is_valid()) {
    l.code = base::ErrorCode::kUnknownFrame;
    l.bad_name = l.head.is_valid() ? relative_to : of;
  } else if (!topology::PoseEdgeExists(t, l.tail, l.head)) {
    l.code = base::ErrorCode::kNoSuchEdge;
  }
  return l;
}

/// The twist edge relative_to (a body) -> {of}. O(|names|), allocation-free.
[[nodiscard]] inline EdgeLookup LookUpTwistEdge(const topology::SceneTopology& t,
                                                std::string_view of,
                                                std::string_view relative_to) noexcept {
  EdgeLookup l;
  l.twist = true;
  if (!NamesValid(l, of, relative_to)) return l;
  l.head = t.FindFrame(of);
  if (!l.head.is_valid()) {
    l.code = base::ErrorCode::kUnknownFrame;
    l.bad_name = of;
    return l;
  }
  l.tail_body = t.FindBody(relative_to);
  if (!l.tail_body.is_valid()) {
    l.code = base::ErrorCode::kUnknownBody;
    l.bad_name = relative_to;
    return l;
  }
  l.edge = t.twist_edge_of(l.head);
  if (!l.edge.is_valid() || t.twist_edge(l.edge).tail != l.tail_body)
    l.code = base::ErrorCode::kNoSuchEdge;
  return l;
}

}  // namespace semgraph::core::internal
