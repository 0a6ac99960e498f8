// File: semgraph/core/timed_covariance.h
//
// Covariances under a time policy (docs/uncertainty.md, "Time"): the readers that give the one
// propagation (propagate.h) each edge's value and covariance at the policy's time
// (ReadPoseAt / ReadTwistAt with kCovariance, timed_read.h: a sample's covariance, the
// interpolation of two, a held twist's), and the covariance of an extrapolated pose edge
// X_k Exp(dt xi): J_X S_k J_X^T + J_xi S_xi J_xi^T (coord/jacobians.h ExtrapolateJacobians),
// S_xi the covariance of the integration twist TwistCoord(h|H, T, [h]) at s_k, propagated
// from its twist edges and the pose edges that move them (read at s_k, no extrapolation).
// Limitation: an edge used both by the integration twist and by the query is counted as two
// independent perturbations (the specification perturbs it once).
// Costs: as the propagation, plus per extrapolated edge one twist propagation.
// noexcept, allocation-free, lock-free.
#pragma once

#include "semgraph/core/propagate.h"
#include "semgraph/core/timed_read.h"

namespace semgraph::core::internal {

/// read(FrameIndex, X, S) at the context's time.
template <coord::Backend B>
auto TimedPoseCovarianceReader(const EdgeValues<B>& v, TimeContext& tc) noexcept {
  return [&v, &tc](FrameIndex g, typename B::PoseCoords& X, coord::Covariance6& S) noexcept {
    ReadPoseAt<B, true>(v, g.value(), tc, X, &S);
  };
}
/// read(TwistEdgeIndex, V, S) at the context's time.
template <coord::Backend B>
auto TimedTwistCovarianceReader(const EdgeValues<B>& v, TimeContext& tc) noexcept {
  return [&v, &tc](TwistEdgeIndex e, TwistNumbers& V, coord::Covariance6& S) noexcept {
    ReadTwistAt<B, true>(v, e.value(), tc, V, &S);
  };
}

/// read(FrameIndex g, V, S): the derivative of the pose edge into g at the context's time, with
/// its covariance from the two bracketing samples (twist source `poses`).
template <coord::Backend B>
auto TimedDerivativeCovarianceReader(const EdgeValues<B>& v, TimeContext& tc) noexcept {
  return [&v, &tc](FrameIndex g, TwistNumbers& V, coord::Covariance6& S) noexcept {
    DerivePoseAt<B, true>(v, g.value(), tc, V, &S);
  };
}

template <coord::Backend B>
void ExtrapolationCovariance(const EdgeValues<B>& v, std::uint32_t frame, std::int64_t s,
                             TimeContext& parent, const coord::kernels::QuatPose& X_k,
                             const Eigen::Vector3d& v_xi, const Eigen::Vector3d& w_xi, double dt,
                             const coord::Covariance6& S_k, coord::Covariance6& S) noexcept {
  namespace jac = coord::jacobians;
  jac::Matrix6 J_X, J_xi;
  jac::ExtrapolateJacobians(X_k.q.toRotationMatrix(), v_xi, w_xi, dt, J_X, J_xi);
  S.setZero();
  jac::AddPropagated(J_X, S_k, S);
  // The integration twist's covariance, at the sample's stamp (as ExtrapolationTwist reads it).
  const topology::SceneTopology& t = *parent.topology;
  const FrameIndex h(frame), tail = t.pose_parent(h);
  const semantics::TwistSemantics q{t.FrameSem(h).origin(), t.BodyOfSem(h), t.BodyOfSem(tail),
                                    t.FrameSem(h).axes()};
  auto plan = PlanTwist(t, q);
  if (!plan) return;
  TimeContext nested;
  nested.at = true;
  nested.t = s;
  nested.nested = true;
  nested.histories = parent.histories;
  nested.topology = parent.topology;
  coord::Covariance6 S_xi;
  TwistCovariance<B>(t, *plan, TimedPoseCovarianceReader(v, nested),
                     TimedTwistCovarianceReader(v, nested), S_xi);
  jac::AddPropagated(J_xi, S_xi, S);
}

}  // namespace semgraph::core::internal
