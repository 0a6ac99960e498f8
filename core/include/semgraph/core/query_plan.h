// File: semgraph/core/query_plan.h
//
// Query plans: a query's names resolved and its semantics checked once, turned into plain data
// that says which compositions answer it (the way Pinocchio separates Model from Data). The
// evaluator (evaluate.h) runs a plan over edge values; one-shot queries, compiled queries and
// the edge-form conversion of AddPose all run the same plan through the same evaluator.
//
// The paper's algorithms as plan data:
//   basic pose X_BA (frame a relative to frame b, in [b]) = the chain up from a to the youngest
//     common ancestor c, composed with the inverse of the chain up from b: X_BA = X_CA X_CB^-1
//     (Algorithm 2). A BasicPath holds the two chains.
//   pose of (e,[a])|C wrt (f,[b])|D in [r] (Algorithm 1) = PoseSteps: X_BA, then move the
//     reference point b -> f (p -= p_BF), the point a -> e (p += R_BA p_AE_A), and re-express
//     [b] -> [r] (X_RB). A position of e wrt f in [r] is the translation of the pose plan of
//     {e} wrt {f} in [r]; an orientation [a] wrt [b] in [r] the rotation of {a} wrt {b} in [r].
//   twist of e|C wrt D in [r] (Algorithm 3) = the TG path from C up to the youngest common
//     ancestor X of C and D, and from D up to X (subtracted): one TwistStep per twist edge, each
//     moved to point e and re-expressed in [r] by two basic poses.
// Plans are templated on the Chain type only: ForestChain (two frames: the one-shot evaluator
// walks parent pointers) or FlatChain (a range of flattened edges of a compiled query).
//
// Error order of the planners = the queries' (docs/rules.md): invalid_name -> unknown_frame ->
// unknown_body -> frame_body_mismatch -> no_pose_path -> (representation_constraint: checked by
// SceneGraph<B>, the only backend-dependent check) -> no_twist_path.
// Costs: planning O(names) lookups + O(log n) per basic pose (common ancestor by jumps);
// noexcept, allocation-free (a twist plan holds its TG end points, not its steps: see
// ForEachTwistStep). Thread safety: plans are plain values; planning reads the topology only.
#pragma once

#include <cstdint>

#include "semgraph/core/export.h"
#include "semgraph/core/specs.h"
#include "semgraph/semantics/relations.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core {

using topology::BodyIndex;
using topology::FrameIndex;
using topology::TwistEdgeIndex;

/// X_AF for a frame F below its ancestor A: the pose edges from F up to A (none when F == A).
struct ForestChain {
  FrameIndex from, to;
};
/// X_BA through the common ancestor C: chains up from a and from b.
template <class Chain>
struct BasicPath {
  Chain up_a, up_b;
};

/// Algorithm 1 as data (see the file comment).
template <class Chain>
struct PoseSteps {
  BasicPath<Chain> ab;  ///< X_BA
  BasicPath<Chain> fb;  ///< X_BF, when change_ref_point
  BasicPath<Chain> ea;  ///< X_AE, when change_point
  BasicPath<Chain> br;  ///< X_RB, when change_frame
  bool change_ref_point = false, change_point = false, change_frame = false;
};

/// One twist edge of Algorithm 3: its stored screw twist TwistCoord(h|H, D, [h]), traversed
/// along (invert = false) or against its direction, moved to point e and re-expressed in [r].
/// A step may instead be a pose edge's own screw twist, differentiated from its history (twist
/// source `poses`, time_plan.h): then pose_edge is the edge's head frame and `edge` is unused.
template <class Chain>
struct TwistStep {
  TwistEdgeIndex edge;
  FrameIndex pose_edge;     ///< valid: the derivative of the pose edge into this frame
  std::uint32_t epoch = 0;  ///< compiled queries: the edge's epoch when compiled
  bool invert = false;
  bool ref_side = false;      ///< on D's side of the path (walked from D up to the ancestor)
  bool move_point = false;    ///< h != e: v += p_EH x w, with X_HE
  bool change_frame = false;  ///< h != r: rotate by R_RH
  BasicPath<Chain> eh;        ///< X_HE: e wrt h in [h]
  BasicPath<Chain> hr;        ///< X_RH: h wrt r in [r]
};

struct PosePlan {
  semantics::PoseSemantics semantics;  ///< @retval X: PoseCoord((e,[a])|C, (f,[b])|D, [r])
  PoseSteps<ForestChain> steps;
};
struct PositionPlan {
  semantics::PositionSemantics semantics;  ///< @retval p_FE_R: PositionCoord(e|C, f|D, [r])
  PoseSteps<ForestChain> steps;            ///< of {e} wrt {f} in [r]; translation only
};
struct OrientationPlan {
  semantics::OrientationSemantics
      semantics;                 ///< @retval R_BA_R: OrientationCoord([a]|C, [b]|D, [r])
  PoseSteps<ForestChain> steps;  ///< of {a} wrt {b} in [r]; rotation only
};
struct TwistPlan {
  semantics::TwistSemantics semantics;        ///< @retval V_DC_R at e: TwistCoord(e|C, D, [r])
  FrameIndex point, frame;                    ///< e and [r]
  BodyIndex body, ref_body, ancestor;         ///< C, D and their youngest common ancestor in TG
  const topology::TwistForest* tg = nullptr;  ///< TG of e's tree; nullptr when C == D
};

/// The basic-pose path of a wrt b (same tree). O(log n).
[[nodiscard]] SEMGRAPH_CORE_EXPORT BasicPath<ForestChain> PlanBasic(
    const topology::SceneTopology& t, FrameIndex a, FrameIndex b) noexcept;

/// Algorithm 1's steps for (e,[a]) wrt (f,[b]) in [r], all frames of one tree. O(log n) each.
[[nodiscard]] SEMGRAPH_CORE_EXPORT PoseSteps<ForestChain> PlanPoseSteps(
    const topology::SceneTopology& t, FrameIndex e, FrameIndex a, FrameIndex f, FrameIndex b,
    FrameIndex r) noexcept;
/// The same steps without the basic pose ab (left empty): what the edge-form conversion of an
/// add needs, where a or b may not exist yet. Only the frames of a change that is made (f != b,
/// e != a, r != b) must exist.
[[nodiscard]] SEMGRAPH_CORE_EXPORT PoseSteps<ForestChain> PlanChanges(
    const topology::SceneTopology& t, FrameIndex e, FrameIndex a, FrameIndex f, FrameIndex b,
    FrameIndex r) noexcept;

/// Planners by names (the spec's fields) and by this graph's name ids.
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<PosePlan, QueryError> PlanPose(
    const topology::SceneTopology& t, const PoseSpec& spec) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<PosePlan, QueryError> PlanPose(
    const topology::SceneTopology& t, const semantics::PoseSemantics& q) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<PositionPlan, QueryError> PlanPosition(
    const topology::SceneTopology& t, const PoseSpec& spec) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<PositionPlan, QueryError> PlanPosition(
    const topology::SceneTopology& t, const semantics::PositionSemantics& q) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<OrientationPlan, QueryError> PlanOrientation(
    const topology::SceneTopology& t, const PoseSpec& spec) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<OrientationPlan, QueryError> PlanOrientation(
    const topology::SceneTopology& t, const semantics::OrientationSemantics& q) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<TwistPlan, QueryError> PlanTwist(
    const topology::SceneTopology& t, const TwistSpec& spec) noexcept;
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<TwistPlan, QueryError> PlanTwist(
    const topology::SceneTopology& t, const semantics::TwistSemantics& q) noexcept;

/// The steps of a twist plan, in order (C's side up to the ancestor, then D's side), each
/// passed to f(const TwistStep<ForestChain>&). O(k log n) for k twist edges; no allocation.
/// On a reader thread under a concurrent writer (docs/realtime.md) the walk stays bounded
/// (tg.num_bodies() steps a side) and stops at an edge or frame that no longer exists; the
/// steps passed so far then describe no consistent topology, which the reader's validation
/// rejects. In a consistent topology neither bound is reached.
template <class F>
void ForEachTwistStep(const topology::SceneTopology& t, const TwistPlan& plan, F&& f) {
  if (plan.tg == nullptr) return;
  const topology::TwistForest& tg = *plan.tg;
  const auto walk = [&](BodyIndex from, bool negate) {
    std::size_t budget = tg.num_bodies();
    for (BodyIndex body = from; body != plan.ancestor && budget > 0;
         body = tg.parent(body), --budget) {
      const TwistEdgeIndex edge = tg.parent_edge(body);
      if (edge.value() >= t.num_twist_edge_slots()) return;
      const FrameIndex h = t.twist_edge(edge).head;
      if (h.value() >= t.num_frames()) return;
      TwistStep<ForestChain> step;
      step.edge = edge;
      // Stored as TwistCoord(h|H, D, [h]): used as is when walking up from H, else inverted;
      // D's side is subtracted (the inverse twist).
      step.invert = (t.body_of(h) != body) != negate;
      step.ref_side = negate;
      if ((step.move_point = h != plan.point)) step.eh = PlanBasic(t, plan.point, h);
      if ((step.change_frame = h != plan.frame)) step.hr = PlanBasic(t, h, plan.frame);
      f(step);
    }
  };
  walk(plan.body, false);
  walk(plan.ref_body, true);
}

}  // namespace semgraph::core
