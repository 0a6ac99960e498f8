// File: semgraph/core/time_plan.h
//
// The plan of a twist differentiated from the pose history (twist source `poses`,
// docs/time.md): no twist edge is read; each inter-body pose edge on the pose-tree path between
// a frame c of C and a frame d of D contributes its own screw twist TwistCoord(g|G, P, [g]) at
// the query time, as a TwistStep with pose_edge = g, which the one evaluator then moves to the
// point e and re-expresses in [r] exactly as a twist edge's (evaluate.h AccumulateTwistStep).
// By P3 any frames of C and D in the tree give the same path up to constant edges, which
// contribute zero and are skipped. Costs: O(log n + path) per step enumeration, no allocation.
#pragma once

#include "semgraph/core/export.h"
#include "semgraph/core/query_plan.h"

namespace semgraph::core {

struct PoseTwistPlan {
  semantics::TwistSemantics semantics;  ///< TwistCoord(e|C, D, [r])
  FrameIndex point, frame;              ///< e and [r]
  FrameIndex c, d;                      ///< a frame of C and of D in e's tree (invalid when C == D)
};

/// Names resolved and checked as PlanTwist does, except that no twist path is needed; C or D
/// without a frame in e's pose tree: no_pose_path (name: e, other: the body).
[[nodiscard]] SEMGRAPH_CORE_EXPORT Expected<PoseTwistPlan, QueryError> PlanPoseTwist(
    const topology::SceneTopology& t, const TwistSpec& spec) noexcept;

/// The steps: c's side up to the common ancestor (along), then d's side (inverted).
template <class F>
void ForEachPoseDerivativeStep(const topology::SceneTopology& t, const PoseTwistPlan& plan, F&& f) {
  if (!plan.c.is_valid()) return;
  const FrameIndex top = t.forest().CommonAncestor(plan.c, plan.d);
  const auto walk = [&](FrameIndex from, bool invert) {
    for (FrameIndex g = from; g != top; g = t.pose_parent(g)) {
      const FrameIndex p = t.pose_parent(g);
      if (t.body_of(g) == t.body_of(p)) continue;  // constant: no motion
      TwistStep<ForestChain> step;
      step.pose_edge = g;
      step.invert = invert;
      if ((step.move_point = g != plan.point)) step.eh = PlanBasic(t, plan.point, g);
      if ((step.change_frame = g != plan.frame)) step.hr = PlanBasic(t, g, plan.frame);
      f(step);
    }
  };
  walk(plan.c, false);
  walk(plan.d, true);
}

}  // namespace semgraph::core
