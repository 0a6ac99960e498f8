// File: semgraph/topology/rules.h
//
// The structural rules of the scene graph, one check each, in the order a rejection reports
// them (docs/rules.md, "order of checks"). A check looks at the topology only (no numbers, no
// strings) and returns the first rule an edge would break as a RuleViolation: the code and the
// nodes involved, from which core/describe.cc writes the message.
//
//   pose edge tail -> head (frames that do not exist yet are invalid indices, with their bodies)
//     P4  constant_pose_change   an existing same-body edge may only be re-set to its value
//                                (the value comparison is numeric: CheckP4 says whether the
//                                edge is constant; the caller compares)
//     P1  multiple_pose_parents  the head already has a pose parent
//     P2  pose_cycle             the tail is already in the head's tree (below it)
//     P3  duplicate_pose_path    a body would have frames in both trees (unless the edge is
//                                the same-body edge joining them)
//     W4  twist_merge_conflict   the union of the two trees' twist graphs is not a forest
//   twist edge D -> {h}|H
//     W2  twist_same_body        D == H
//     W1  multiple_twist_parents {h} already has a twist edge from another body
//     W3  duplicate_twist_path   H and D are already joined in the TG of {h}'s tree
//   joint: pose edge {p} -> {c} and twist edge P -> {c}|C, added together
//     P1 -> P2 -> P3 -> W4 of the pose edge, then for the twist edge
//     W1  multiple_twist_parents {c} already has a twist edge (a joint's edge is new)
//     W3  duplicate_twist_path   P and C are already joined in TG(P1) U TG(P2), the twist
//                                graph of the tree the pose edge makes
// Self edges (a pose edge from a frame to itself) are caught by name, before the others.
//
// Costs: P1, P2, W1, W2 O(1); P3 O(min(b1, b2)) body-set lookups; W3 O(depth in TG);
// W4 O(twist edges of the smaller TG); a joint's W3 O(twist edges of both TGs). All
// allocation-free and noexcept except W4 and a joint's W3 (a temporary union-find); none
// walks a pose tree.
#pragma once

#include <optional>

#include "semgraph/base/error_code.h"
#include "semgraph/topology/export.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::topology {

/// A broken rule: its code and the nodes the message names (which ones: per check below).
struct RuleViolation {
  base::ErrorCode code = base::ErrorCode::kOk;
  FrameIndex frame;  ///< P1: the head's existing parent; P2: the root of the tail's tree;
                     ///< P3: a frame of `body` in the tail's tree (invalid if none yet)
  FrameIndex other;  ///< P3: a frame of `body` in the head's tree (invalid if none yet)
  BodyIndex body;    ///< P3: the shared body; W1: the existing twist parent
};

/// The ends of a pose edge being added: tail {b}|D -> head {a}|C. Frames and bodies that do
/// not exist yet are invalid; `same_body` when C and D are one body (by name).
struct NewPoseEdge {
  FrameIndex tail, head;
  BodyIndex tail_body, head_body;
  bool same_body = false;
};

/// P4: true when the pose edge tail -> head exists and joins two frames of one body, so its
/// value is constant.
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT bool IsConstantEdge(const SceneTopology& t, FrameIndex tail,
                                                           FrameIndex head) noexcept;
/// True when the pose edge tail -> head exists (the add is then a value update).
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT bool PoseEdgeExists(const SceneTopology& t, FrameIndex tail,
                                                           FrameIndex head) noexcept;

[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckP1(
    const SceneTopology& t, const NewPoseEdge& e) noexcept;
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckP2(
    const SceneTopology& t, const NewPoseEdge& e) noexcept;
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckP3(
    const SceneTopology& t, const NewPoseEdge& e) noexcept;
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckW4(const SceneTopology& t,
                                                                            const NewPoseEdge& e);
/// P1 -> P2 -> P3 -> W4, for a new pose edge (not an update of an existing one).
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckNewPoseEdge(
    const SceneTopology& t, const NewPoseEdge& e);

/// The ends of a twist edge being added: D -> {h}|H (head and bodies invalid when new).
struct NewTwistEdge {
  BodyIndex tail;
  FrameIndex head;
  BodyIndex head_body;
};
/// W2 is decided on names by the caller (bodies may not exist yet): kTwistSameBody.
/// W1: {h} has a twist edge from a body other than D (an edge from D is a value update).
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckW1(
    const SceneTopology& t, const NewTwistEdge& e) noexcept;
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckW3(
    const SceneTopology& t, const NewTwistEdge& e) noexcept;
/// W1 -> W3.
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckNewTwistEdge(
    const SceneTopology& t, const NewTwistEdge& e) noexcept;

/// A joint's twist edge tail_body -> {head}|head_body of the pose edge `e`. W1: {head} has a
/// twist edge (`body`: its tail). W3: the bodies are joined in the union of the TGs of the two
/// trees the pose edge joins (W2 is decided on names by the caller, as for twists).
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckJointW1(
    const SceneTopology& t, const NewPoseEdge& e) noexcept;
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckJointW3(
    const SceneTopology& t, const NewPoseEdge& e);
/// P1 -> P2 -> P3 -> W4 -> W1 -> W3, for a joint's new pose and twist edges.
[[nodiscard]] SEMGRAPH_TOPOLOGY_EXPORT std::optional<RuleViolation> CheckNewJointEdges(
    const SceneTopology& t, const NewPoseEdge& e);

}  // namespace semgraph::topology
