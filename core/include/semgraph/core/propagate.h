// File: semgraph/core/propagate.h
//
// The first-order covariance of a query's answer (docs/uncertainty.md, "Propagation"): the sum
// over the edges the query uses of J_i S_i J_i^T, J_i from coord/jacobians.h. One routine per
// answer kind, over any edge reader, so every query (one-shot or compiled, at any time) runs
// the same code:
//   PoseCovariance    the frames e, [a], f, [b], [r] of Algorithm 1 (a position: e, e, f, f, r;
//                     an orientation: a, a, b, b, r). Z = their youngest common ancestor; each
//                     frame's pose in Z (one walk up each), then each edge of the union of the
//                     five chains once (a chain stops where it meets an earlier one), with the
//                     frames it moves read off depths: an edge at depth d on frame k's chain
//                     moves frame i iff d <= depth(common ancestor of k and i).
//   TwistCovariance   e, [r] and the head h of each twist edge of Algorithm 3: each twist
//                     edge's own covariance, and each pose edge below Z that moves e, [r] or
//                     an h (the points that move twists and the rotations).
//   PoseTwistCovariance  the same for a twist from poses (source `poses`): each inter-body
//                     pose edge's derivative stands for a twist edge, with the covariance
//                     from its two bracketing samples (timed_read.h DerivativeCovariance).
// A reader is read(FrameIndex g, X_PG, S_PG) (pose edges) / read(TwistEdgeIndex, V, S).
// Each edge's Jacobian goes to a sink (Add(PerturbedEdge, J, S), then Finish): DirectSink forms
// sum J S J^T at once; the timed queries' KeyedSink (timed_covariance.h) sums the Jacobians of
// one perturbation first (an edge shared by an extrapolation's integration twist and the query).
// Costs: pose O(d log n) (d: edges on the five chains), twist O(k d (d + log n)) for k twist
// edges; noexcept, allocation-free, lock-free.
#pragma once

#include <algorithm>
#include <cstdint>

#include "semgraph/coord/jacobians.h"
#include "semgraph/core/covariance_lanes.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/query_plan.h"
#include "semgraph/core/time_plan.h"

namespace semgraph::core::internal {

/// A pose in the Jacobians' working form.
struct Rigid {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Rigid Then(const Rigid& b) const noexcept { return {R * b.R, R * b.p + p}; }
};
template <coord::Backend B>
Rigid ToRigid(const typename B::PoseCoords& X) noexcept {
  return {B::ToMatrix(B::RotationOf(X)), B::TranslationOf(X)};
}

/// X_ZK for K below Z, with each edge read through `read`.
template <coord::Backend B, class Read>
Rigid PoseInAncestor(const topology::SceneTopology& t, FrameIndex k, FrameIndex z,
                     Read& read) noexcept {
  Rigid acc;
  typename B::PoseCoords X;
  coord::Covariance6 S;
  for (FrameIndex g = k; g != z; g = t.pose_parent(g)) {
    read(g, X, S);
    acc = ToRigid<B>(X).Then(acc);
  }
  return acc;
}

/// Walks frame k's chain up to z, stopping at the edges at depth <= `counted` (those lie on
/// an earlier frame's chain): calls f(g, X_PG, S_PG, X_ZG, d) for each edge (g its head, d its
/// depth). X_Zk: k in Z.
template <coord::Backend B, class Read, class F>
void ForEachNewEdge(const topology::SceneTopology& t, FrameIndex k, FrameIndex z,
                    std::int64_t counted, const Rigid& X_Zk, Read& read, F&& f) noexcept {
  Rigid X_Gk;
  std::int64_t d = t.forest().depth(k);
  typename B::PoseCoords X;
  coord::Covariance6 S;
  for (FrameIndex g = k; g != z && d > counted; g = t.pose_parent(g), --d) {
    read(g, X, S);
    Rigid X_ZG;
    X_ZG.R = X_Zk.R * X_Gk.R.transpose();
    X_ZG.p = X_Zk.p - X_ZG.R * X_Gk.p;
    const Rigid X_PG = ToRigid<B>(X);
    f(g, X_PG, S, X_ZG, d);
    X_Gk = X_PG.Then(X_Gk);
  }
}
/// The depth at or above which k's chain meets the chains of `earlier` frames (-1: none).
inline std::int64_t MeetDepth(const topology::PoseForest& forest, FrameIndex k,
                              const FrameIndex* earlier, int n) noexcept {
  std::int64_t counted = -1;
  for (int i = 0; i < n; ++i) {
    counted = std::max<std::int64_t>(counted, forest.depth(forest.CommonAncestor(k, earlier[i])));
  }
  return counted;
}

/// What a Jacobian is taken by: the pose edge into frame `index`, twist edge `index`, or the
/// derivative of the pose edge into frame `index` (twist source `poses`).
struct PerturbedEdge {
  enum class Kind : std::uint8_t { kPose, kTwist, kDerivative } kind = Kind::kPose;
  std::uint32_t index = 0;
};

/// Where the routines below put each edge's Jacobian J (rows: the answer, in the routine's
/// working axes) with the covariance S of the value read: Add(ref, J, S), or, for a pose edge
/// on a pose answer with rows in Z, AddPoseEdge(ref, q, edge, m, S) (J = EdgeOnPoseInZ(q, edge,
/// m)); then Finish(S_out). This one makes every edge read one independent perturbation:
/// S_out = sum J S J^T, formed at once; pose edges with the edges in SIMD lanes
/// (covariance_lanes.h). (SharedPerturbations, timed_covariance.h, sums the Jacobians of one
/// perturbation first.)
struct DirectSink {
  coord::Covariance6 S = coord::Covariance6::Zero();
  PoseCovarianceLanes pose_lanes;
  void Add(PerturbedEdge, const coord::jacobians::Matrix6& J,
           const coord::Covariance6& S_i) noexcept {
    coord::jacobians::AddPropagated(J, S_i, S);
  }
  void AddPoseEdge(PerturbedEdge, const coord::jacobians::PoseInZ& q,
                   const coord::jacobians::EdgeInZ& edge, const coord::jacobians::PoseMoves& m,
                   const coord::Covariance6& S_i) noexcept {
    const coord::jacobians::PoseEdgeFactors k = coord::jacobians::EdgeOnPoseFactors(q, edge, m);
    pose_lanes.Add(edge.R_ZP, k.lever, k.s, k.c, k.d, q.O_Z, S_i);
  }
  void Finish(coord::Covariance6& S_out) noexcept {
    S_out = S;
    pose_lanes.AddTo(S_out);
  }
};

/// The covariance of the pose answer (e,[a]) wrt (f,[b]) in [r] (frames k = {e, a, f, b, r},
/// all of one pose tree), rows (dp, dth) in [r]. `attached` (optional): the answer's frames are
/// rigidly attached to k[i] at these poses (in [k[i]]), taken as exact: they move with k[i] (a
/// time travel's side at the reference time, whose point side is frozen at the fixed frame).
/// `sink`: where each edge's Jacobian goes (DirectSink: summed at once).
template <coord::Backend B, class Read, class Sink = DirectSink>
void PoseCovariance(const topology::SceneTopology& t, const FrameIndex (&k)[5], Read&& read,
                    coord::Covariance6& S_out, const Rigid* attached = nullptr,
                    Sink&& sink = Sink{}) noexcept {
  const topology::PoseForest& forest = t.forest();
  FrameIndex z = k[0];
  for (int i = 1; i < 5; ++i) z = forest.CommonAncestor(z, k[i]);
  Rigid X_Z[5], A_Z[5];  // k[i] in Z; the answer's frames in Z
  for (int i = 0; i < 5; ++i) {
    X_Z[i] = PoseInAncestor<B>(t, k[i], z, read);
    A_Z[i] = attached ? X_Z[i].Then(attached[i]) : X_Z[i];
  }
  coord::jacobians::PoseInZ q;
  q.R_RZ = A_Z[4].R.transpose();
  q.p_ZoEo_Z = A_Z[0].p;
  q.p_ZoFo_Z = A_Z[2].p;
  q.O_Z = A_Z[1].R * A_Z[3].R.transpose();
  S_out.setZero();
  for (int j = 0; j < 5; ++j) {
    std::int64_t lca[5];  // depth of k[j]'s common ancestor with each frame
    for (int i = 0; i < 5; ++i) lca[i] = forest.depth(forest.CommonAncestor(k[j], k[i]));
    ForEachNewEdge<B>(
        t, k[j], z, MeetDepth(forest, k[j], k, j), X_Z[j], read,
        [&](FrameIndex g, const Rigid& X_PG, const coord::Covariance6& S, const Rigid& X_ZG,
            std::int64_t d) {
          if (S.isZero(0.0)) return;  // an exact edge adds nothing
          const coord::jacobians::EdgeInZ edge{X_ZG.R * X_PG.R.transpose(), X_ZG.p};
          const coord::jacobians::PoseMoves m{d <= lca[0], d <= lca[2], d <= lca[1], d <= lca[3],
                                              d <= lca[4]};
          sink.AddPoseEdge(PerturbedEdge{PerturbedEdge::Kind::kPose, g.value()}, q, edge, m, S);
        });
  }
  sink.Finish(S_out);
  S_out = coord::jacobians::RotateRows(q.R_RZ, S_out);  // rows in Z -> [r], once
}

/// A twist step's contribution seen from Z, and its edge's covariance: head h and
/// read_step(step, V, S) give the step's twist TwistCoord(h|H, D, [h]) and covariance.
template <coord::Backend B, class ReadPose, class ReadStep>
coord::jacobians::TwistStepInZ StepInZ(const topology::SceneTopology& t,
                                       const TwistStep<ForestChain>& step, FrameIndex h,
                                       FrameIndex z, ReadPose& read_pose, ReadStep& read_step,
                                       Eigen::Matrix3d& R_ZH, coord::Covariance6& S) noexcept {
  const Rigid X_ZH = PoseInAncestor<B>(t, h, z, read_pose);
  TwistNumbers V;
  read_step(step, V, S);
  const double s = step.invert ? -1.0 : 1.0;
  R_ZH = X_ZH.R;
  return {s * (X_ZH.R * V.v_DHo_H), s * (X_ZH.R * V.w_DH_H), X_ZH.p, false};
}

/// The covariance of a twist answer at e in [r], rows (dv, dw), over the steps
/// for_each_step(f) (f(step) per step), head_of(step) the frame h of a step's twist and
/// read_step(step, V, S) its twist and covariance: a twist edge's, or a pose edge's derivative
/// (twist source `poses`). Each step's twist is an independent perturbation; each pose edge on
/// the chains of e, [r] and the heads counts once, its Jacobian summed over the steps.
/// ref_of(step): the PerturbedEdge of a step's twist; `sink` as PoseCovariance's.
template <coord::Backend B, class ForEachStep, class HeadOf, class RefOf, class ReadPose,
          class ReadStep, class Sink>
void TwistCovarianceOver(const topology::SceneTopology& t, FrameIndex e, FrameIndex r,
                         ForEachStep&& for_each_step, HeadOf&& head_of, RefOf&& ref_of,
                         ReadPose&& read_pose, ReadStep&& read_step, Sink& sink,
                         coord::Covariance6& S_out) noexcept {
  namespace jac = coord::jacobians;
  S_out.setZero();
  const topology::PoseForest& forest = t.forest();
  FrameIndex z = forest.CommonAncestor(e, r);
  for_each_step(
      [&](const TwistStep<ForestChain>& step) { z = forest.CommonAncestor(z, head_of(step)); });
  const Rigid X_Ze = PoseInAncestor<B>(t, e, z, read_pose);
  const Rigid X_Zr = PoseInAncestor<B>(t, r, z, read_pose);
  const Eigen::Matrix3d R_RZ = X_Zr.R.transpose();
  // The answer in Z, and each step's own covariance.
  Eigen::Vector3d v_Z = Eigen::Vector3d::Zero(), w_Z = Eigen::Vector3d::Zero();
  for_each_step([&](const TwistStep<ForestChain>& step) {
    Eigen::Matrix3d R_ZH;
    coord::Covariance6 S;
    const jac::TwistStepInZ st =
        StepInZ<B>(t, step, head_of(step), z, read_pose, read_step, R_ZH, S);
    v_Z += st.a_Z + st.w_Z.cross(X_Ze.p - st.p_ZoHo_Z);
    w_Z += st.w_Z;
    if (S.isZero(0.0)) return;
    sink.Add(ref_of(step),
             jac::TwistEdgeOnTwist(R_RZ, R_ZH, st.p_ZoHo_Z, X_Ze.p, step.invert ? -1 : 1), S);
  });
  // Each pose edge on the chains of e, r and the heads, once: its Jacobian sums over the steps.
  const auto pose_edges_of = [&](FrameIndex k, std::int64_t counted, const Rigid& X_Zk) {
    ForEachNewEdge<B>(t, k, z, counted, X_Zk, read_pose,
                      [&](FrameIndex g, const Rigid& X_PG, const coord::Covariance6& S,
                          const Rigid& X_ZG, std::int64_t) {
                        if (S.isZero(0.0)) return;
                        const jac::EdgeInZ edge{X_ZG.R * X_PG.R.transpose(), X_ZG.p};
                        jac::PoseEdgeOnTwistSum sum;
                        for_each_step([&](const TwistStep<ForestChain>& step) {
                          Eigen::Matrix3d R_ZH;
                          coord::Covariance6 S_step;
                          const FrameIndex h = head_of(step);
                          jac::TwistStepInZ st =
                              StepInZ<B>(t, step, h, z, read_pose, read_step, R_ZH, S_step);
                          st.moves = forest.IsAncestor(g, h);
                          sum.Add(st, X_Ze.p, edge, forest.IsAncestor(g, e));
                        });
                        sink.Add(PerturbedEdge{PerturbedEdge::Kind::kPose, g.value()},
                                 sum.Finish(R_RZ, v_Z, w_Z, edge, forest.IsAncestor(g, r)), S);
                      });
  };
  const FrameIndex er[2] = {e, r};
  pose_edges_of(e, -1, X_Ze);
  pose_edges_of(r, MeetDepth(forest, r, er, 1), X_Zr);
  int index = 0;
  for_each_step([&](const TwistStep<ForestChain>& step) {
    const FrameIndex h = head_of(step);
    std::int64_t counted = MeetDepth(forest, h, er, 2);
    int other = 0;  // the heads of the steps before this one
    for_each_step([&](const TwistStep<ForestChain>& earlier) {
      if (other++ >= index) return;
      counted =
          std::max<std::int64_t>(counted, forest.depth(forest.CommonAncestor(h, head_of(earlier))));
    });
    ++index;
    pose_edges_of(h, counted, PoseInAncestor<B>(t, h, z, read_pose));
  });
  sink.Finish(S_out);
}

/// The covariance of the twist answer of `plan` (at e in [r]), rows (dv, dw), from its twist
/// edges: read_twist(TwistEdgeIndex, V, S).
template <coord::Backend B, class ReadPose, class ReadTwist, class Sink = DirectSink>
void TwistCovariance(const topology::SceneTopology& t, const TwistPlan& plan, ReadPose&& read_pose,
                     ReadTwist&& read_twist, coord::Covariance6& S_out,
                     Sink&& sink = Sink{}) noexcept {
  S_out.setZero();
  if (plan.tg == nullptr) return;  // C == D: the zero twist, exact
  TwistCovarianceOver<B>(
      t, plan.point, plan.frame, [&](auto&& f) { ForEachTwistStep(t, plan, f); },
      [&](const TwistStep<ForestChain>& s) { return t.twist_edge(s.edge).head; },
      [](const TwistStep<ForestChain>& s) {
        return PerturbedEdge{PerturbedEdge::Kind::kTwist, s.edge.value()};
      },
      read_pose,
      [&](const TwistStep<ForestChain>& s, TwistNumbers& V, coord::Covariance6& S) {
        read_twist(s.edge, V, S);
      },
      sink, S_out);
}

/// The covariance of the twist answer of a twist from poses (twist source `poses`,
/// time_plan.h): each inter-body pose edge's derivative with its covariance,
/// read_derivative(FrameIndex g, V, S) (DerivePoseAt with kCovariance), as a twist edge's.
template <coord::Backend B, class ReadPose, class ReadDerivative>
void PoseTwistCovariance(const topology::SceneTopology& t, const PoseTwistPlan& plan,
                         ReadPose&& read_pose, ReadDerivative&& read_derivative,
                         coord::Covariance6& S_out) noexcept {
  S_out.setZero();
  if (!plan.c.is_valid()) return;  // C == D: the zero twist, exact
  DirectSink sink;
  TwistCovarianceOver<B>(
      t, plan.point, plan.frame, [&](auto&& f) { ForEachPoseDerivativeStep(t, plan, f); },
      [](const TwistStep<ForestChain>& s) { return s.pose_edge; },
      [](const TwistStep<ForestChain>& s) {
        return PerturbedEdge{PerturbedEdge::Kind::kDerivative, s.pose_edge.value()};
      },
      read_pose,
      [&](const TwistStep<ForestChain>& s, TwistNumbers& V, coord::Covariance6& S) {
        read_derivative(s.pose_edge, V, S);
      },
      sink, S_out);
}

/// The covariance of a pose given in another form, in the edge form (ToEdgeForm's steps, with
/// the conversion's values exact): re-expressed [r] -> [b], the reference point moved (exact,
/// no change), the point moved e -> a with the pose's rotation. X_BA: ToEdgeForm's answer.
/// Any source (the forest at an add, a converting handle's flattened chains); false when a
/// compiled chain's edge changed epoch (S_out then unspecified).
template <coord::Backend B, class Source>
bool ToEdgeFormCovariance(const Source& src, const PoseSteps<typename Source::Chain>& s,
                          const typename B::PoseCoords& X_BA, const coord::Covariance6& S_given,
                          coord::Covariance6& S_out) noexcept {
  namespace jac = coord::jacobians;
  jac::Matrix6 J = jac::Matrix6::Identity();
  if (s.change_frame) {
    typename B::PoseCoords X_RB;
    if (!EvalBasic<B>(src, s.br, X_RB)) return false;
    J = jac::Reexpress(B::ToMatrix(B::RotationOf(X_RB)).transpose());
  }
  if (s.change_point) {  // p_BA = p - R_BA p_AE_A
    typename B::PoseCoords X_AE;
    if (!EvalBasic<B>(src, s.ea, X_AE)) return false;
    J = jac::MovePoint(-B::Rotate(B::RotationOf(X_BA), B::TranslationOf(X_AE))) * J;
  }
  coord::Covariance6 S = coord::Covariance6::Zero();
  jac::AddPropagated(J, S_given, S);
  S_out = S;
  return true;
}

}  // namespace semgraph::core::internal
