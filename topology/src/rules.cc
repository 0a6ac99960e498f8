// The structural rules, one function each, in the order of rules.h.
#include "semgraph/topology/rules.h"

#include <unordered_map>

namespace semgraph::topology {

using base::ErrorCode;

bool PoseEdgeExists(const SceneTopology& t, FrameIndex tail, FrameIndex head) noexcept {
  return tail.is_valid() && head.is_valid() && t.pose_parent(head) == tail;
}

bool IsConstantEdge(const SceneTopology& t, FrameIndex tail, FrameIndex head) noexcept {
  return PoseEdgeExists(t, tail, head) && t.body_of(head) == t.body_of(tail);
}

std::optional<RuleViolation> CheckP1(const SceneTopology& t, const NewPoseEdge& e) noexcept {
  if (e.head.is_valid() && t.pose_parent(e.head).is_valid()) {
    return RuleViolation{ErrorCode::kMultiplePoseParents, t.pose_parent(e.head), {}, {}};
  }
  return std::nullopt;
}

// The head is a root (P1 passed); the tail in the head's tree means it descends from the head.
std::optional<RuleViolation> CheckP2(const SceneTopology& t, const NewPoseEdge& e) noexcept {
  if (e.head.is_valid() && e.tail.is_valid() && t.SameTree(e.head, e.tail)) {
    return RuleViolation{ErrorCode::kPoseCycle, t.forest().Root(e.tail), {}, {}};
  }
  return std::nullopt;
}

// On body sets; a frame that does not exist yet forms the tree {x} of its body.
std::optional<RuleViolation> CheckP3(const SceneTopology& t, const NewPoseEdge& e) noexcept {
  BodyIndex shared;
  if (e.head.is_valid() && e.tail.is_valid()) {
    shared = t.SharedBody(e.tail, e.head, e.same_body ? e.tail_body : BodyIndex());
  } else if (e.head.is_valid()) {  // tail new: its tree is {tail_body}
    if (!e.same_body && e.tail_body.is_valid() && t.TreeHasBody(e.head, e.tail_body))
      shared = e.tail_body;
  } else if (e.tail.is_valid()) {  // head new: its tree is {head_body}
    if (!e.same_body && e.head_body.is_valid() && t.TreeHasBody(e.tail, e.head_body))
      shared = e.head_body;
  }
  if (!shared.is_valid()) return std::nullopt;
  return RuleViolation{ErrorCode::kDuplicatePosePath,
                       e.tail.is_valid() ? t.SomeFrameOfBodyInTree(shared, e.tail) : FrameIndex(),
                       e.head.is_valid() ? t.SomeFrameOfBodyInTree(shared, e.head) : FrameIndex(),
                       shared};
}

std::optional<RuleViolation> CheckW4(const SceneTopology& t, const NewPoseEdge& e) {
  if (!e.head.is_valid() || !e.tail.is_valid()) return std::nullopt;
  const TreeRecord* rec_h = t.RecordOf(e.head);
  const TreeRecord* rec_t = t.RecordOf(e.tail);
  if (rec_h && rec_t && !rec_h->twists.empty() && !rec_t->twists.empty() &&
      !rec_t->twists.CanMerge(rec_h->twists)) {
    return RuleViolation{ErrorCode::kTwistMergeConflict, {}, {}, {}};
  }
  return std::nullopt;
}

std::optional<RuleViolation> CheckNewPoseEdge(const SceneTopology& t, const NewPoseEdge& e) {
  if (auto v = CheckP1(t, e)) return v;
  if (auto v = CheckP2(t, e)) return v;
  if (auto v = CheckP3(t, e)) return v;
  return CheckW4(t, e);
}

std::optional<RuleViolation> CheckW1(const SceneTopology& t, const NewTwistEdge& e) noexcept {
  if (!e.head.is_valid()) return std::nullopt;
  const TwistEdgeIndex existing = t.twist_edge_of(e.head);
  if (existing.is_valid() && !(e.tail.is_valid() && t.twist_edge(existing).tail == e.tail)) {
    return RuleViolation{ErrorCode::kMultipleTwistParents, {}, {}, t.twist_edge(existing).tail};
  }
  return std::nullopt;
}

std::optional<RuleViolation> CheckW3(const SceneTopology& t, const NewTwistEdge& e) noexcept {
  if (!e.head.is_valid() || !e.tail.is_valid()) return std::nullopt;
  const TreeRecord* rec = t.RecordOf(e.head);
  if (rec && rec->twists.Connected(e.head_body, e.tail)) {
    return RuleViolation{ErrorCode::kDuplicateTwistPath, {}, {}, {}};
  }
  return std::nullopt;
}

std::optional<RuleViolation> CheckNewTwistEdge(const SceneTopology& t,
                                               const NewTwistEdge& e) noexcept {
  if (auto v = CheckW1(t, e)) return v;
  return CheckW3(t, e);
}

std::optional<RuleViolation> CheckJointW1(const SceneTopology& t, const NewPoseEdge& e) noexcept {
  if (e.head.is_valid() && t.twist_edge_of(e.head).is_valid()) {
    return RuleViolation{
        ErrorCode::kMultipleTwistParents, {}, {}, t.twist_edge(t.twist_edge_of(e.head)).tail};
  }
  return std::nullopt;
}

// Connectivity in the union of two forests: a temporary union-find over their edges (paths may
// alternate between the two; W4 passed, so the union is a forest). Build time only.
std::optional<RuleViolation> CheckJointW3(const SceneTopology& t, const NewPoseEdge& e) {
  if (!e.tail_body.is_valid() || !e.head_body.is_valid()) return std::nullopt;  // a new body
  std::unordered_map<std::uint32_t, std::uint32_t> parent;
  const auto find = [&](std::uint32_t x) {
    for (auto it = parent.find(x); it != parent.end() && it->second != x; it = parent.find(x))
      x = it->second;
    return x;
  };
  for (const FrameIndex f : {e.tail, e.head}) {
    const TreeRecord* rec = f.is_valid() ? t.RecordOf(f) : nullptr;
    if (!rec) continue;
    rec->twists.ForEachEdge([&](TwistEdgeIndex, BodyIndex tail, BodyIndex head) {
      parent.try_emplace(tail.value(), tail.value());
      parent.try_emplace(head.value(), head.value());
      const std::uint32_t a = find(tail.value()), b = find(head.value());
      if (a != b) parent[a] = b;
    });
  }
  if (find(e.tail_body.value()) == find(e.head_body.value())) {
    return RuleViolation{ErrorCode::kDuplicateTwistPath, {}, {}, {}};
  }
  return std::nullopt;
}

std::optional<RuleViolation> CheckNewJointEdges(const SceneTopology& t, const NewPoseEdge& e) {
  if (auto v = CheckNewPoseEdge(t, e)) return v;
  if (auto v = CheckJointW1(t, e)) return v;
  return CheckJointW3(t, e);
}

}  // namespace semgraph::topology
