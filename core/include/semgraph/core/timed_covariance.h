// File: semgraph/core/timed_covariance.h
//
// Covariances under a time policy (docs/uncertainty.md, "Time"): the readers that give the one
// propagation (propagate.h) each edge's value and covariance at the policy's time
// (ReadPoseAt / ReadTwistAt with kCovariance, timed_read.h: a sample's covariance, the
// interpolation of two, a held twist's), and the covariance of an extrapolated pose edge
// X_k Exp(dt xi): J_X S_k J_X^T + J_xi S_xi J_xi^T (coord/jacobians.h ExtrapolateJacobians),
// S_xi the covariance of the integration twist TwistCoord(h|H, T, [h]) at s_k, propagated
// from its twist edges and the pose edges that move them (read at s_k, no extrapolation).
// An edge used both by the integration twist and by the query is perturbed once
// (SharedPerturbations, KeyedSink): when the answer was extrapolated, every Jacobian is keyed
// by the value it is taken by (the edge and the samples read: a timeless edge's one value, a
// sample, or two samples at one fraction), an extrapolated pose edge's Jacobian is split into
// its sample's and, through J_xi, those of its integration twist's edges (read at s_k), and
// the Jacobians of one key are summed before J S J^T is formed.
// The integration twist's plan comes from IntegrationTwistPlan (evaluate.h): planned on the
// topology (one-shot queries), or a compiled query's plan made at compile time (the context's
// twist_plans), so one-shot and compiled queries run this same code.
// Costs: as the propagation, plus per extrapolated edge one twist propagation (twice with
// keyed Jacobians, plus a linear search over at most kMaxPerturbations keys per edge).
// noexcept, allocation-free (SharedPerturbations lives on the stack: about 20 KB), lock-free.
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
  const std::optional<TwistPlan> plan = IntegrationTwistPlan(parent, frame);
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

/// The value an edge's Jacobian is taken by: one perturbation. s0 = s1 = kTimeless for a
/// timeless edge's one value; s0 = s1 a sample (at its stamp, held, or the latest); s0 < s1 two
/// samples at fraction lambda.
struct PerturbationKey {
  static constexpr std::int64_t kTimeless = INT64_MIN;
  PerturbedEdge::Kind kind = PerturbedEdge::Kind::kPose;
  std::uint32_t index = 0;
  std::int64_t s0 = kTimeless, s1 = kTimeless;
  double lambda = 0.0;
  [[nodiscard]] bool operator==(const PerturbationKey& o) const noexcept {
    return kind == o.kind && index == o.index && s0 == o.s0 && s1 == o.s1 && lambda == o.lambda;
  }
};

/// The Jacobians of each perturbation, summed (J = sum of the Jacobians of one key), then
/// S = sum J S_key J^T. Beyond kMaxPerturbations keys a perturbation is added on its own
/// (independent, as DirectSink).
struct SharedPerturbations {
  static constexpr std::size_t kMaxPerturbations = 32;
  struct Entry {
    PerturbationKey key;
    coord::jacobians::Matrix6 J;
    coord::Covariance6 S;
  };
  Entry entries[kMaxPerturbations];
  std::size_t n = 0;
  coord::Covariance6 overflow = coord::Covariance6::Zero();

  void Add(const PerturbationKey& key, const coord::jacobians::Matrix6& J,
           const coord::Covariance6& S) noexcept {
    for (std::size_t i = 0; i < n; ++i) {
      if (entries[i].key == key) {
        entries[i].J += J;
        return;
      }
    }
    if (n == kMaxPerturbations) {
      coord::jacobians::AddPropagated(J, S, overflow);
      return;
    }
    entries[n++] = Entry{key, J, S};
  }
  void Finish(coord::Covariance6& S_out) const noexcept {
    S_out = overflow;
    for (std::size_t i = 0; i < n; ++i) {
      coord::jacobians::AddPropagated(entries[i].J, entries[i].S, S_out);
    }
  }
};

/// The key of a read of history h (null: timeless) at the context's time; false when the time
/// is outside the samples (then s0 = s1 = the nearest sample: a held twist, an extrapolated
/// pose edge's X_k).
template <class History>
bool KeyAt(const History* h, const TimeContext& tc, PerturbationKey& k,
           typename History::Bracket* b_out = nullptr,
           typename History::CovarianceBracket* cov = nullptr) noexcept {
  if (h == nullptr) return true;
  typename History::Bracket b;
  if (!tc.at) {
    double w[History::kValueWords];
    std::int64_t first = 0;
    h->Newest(k.s0, w, first);
    k.s1 = k.s0;
    return true;
  }
  h->Find(tc.t, b, cov);
  if (b_out) *b_out = b;
  k.s0 = b.s0;
  k.s1 = b.s0;
  if (b.where != History::Bracket::Where::kInside) return false;
  if (!b.exact) {
    k.s1 = b.s1;
    k.lambda = Fraction(b.s0, tc.t, b.s1);
  }
  return true;
}

/// A sink (propagate.h) that keys each Jacobian by the value it is taken by at the context's
/// time, premultiplied by P (the identity at the top; J_outer J_xi inside an integration
/// twist), into `acc`; an extrapolated pose edge (top level only) is split into its sample and
/// its integration twist's edges, read at s_k (as ReadPoseAt / ExtrapolationCovariance do).
template <coord::Backend B>
struct KeyedSink {
  const EdgeValues<B>* v;
  TimeContext* tc;
  SharedPerturbations* acc;
  coord::jacobians::Matrix6 P = coord::jacobians::Matrix6::Identity();
  bool top = true;

  void Add(PerturbedEdge ref, const coord::jacobians::Matrix6& J_in,
           const coord::Covariance6& S) noexcept {
    const coord::jacobians::Matrix6 J = top ? J_in : coord::jacobians::Matrix6(P * J_in);
    PerturbationKey k;
    k.kind = ref.kind;
    k.index = ref.index;
    if (ref.kind == PerturbedEdge::Kind::kTwist) {
      KeyAt(v->history.twist_of(ref.index), *tc, k);
    } else if (ref.kind == PerturbedEdge::Kind::kPose) {
      PoseHistory::Bracket b;
      PoseHistory::CovarianceBracket cb;
      if (!KeyAt(v->history.pose_of(ref.index), *tc, k, &b, &cb) && top) {
        return Extrapolated(ref.index, b, cb, J);
      }
    } else {
      k.s0 = k.s1 = 0;  // a derivative: its own perturbation (source poses never extrapolates)
    }
    acc->Add(k, J, S);
  }
  void AddPoseEdge(PerturbedEdge ref, const coord::jacobians::PoseInZ& q,
                   const coord::jacobians::EdgeInZ& edge, const coord::jacobians::PoseMoves& m,
                   const coord::Covariance6& S) noexcept {
    Add(ref, coord::jacobians::EdgeOnPoseInZ(q, edge, m), S);
  }
  /// The top sink forms the sum (before the routine's last rotation); an inner one adds nothing.
  void Finish(coord::Covariance6& S_out) const noexcept {
    if (top) acc->Finish(S_out);
  }

  // X_k Exp(dt xi): J J_X on the sample, J J_xi on the integration twist's edges.
  void Extrapolated(std::uint32_t frame, const PoseHistory::Bracket& b,
                    const PoseHistory::CovarianceBracket& cb,
                    const coord::jacobians::Matrix6& J) noexcept {
    namespace jac = coord::jacobians;
    using Where = PoseHistory::Bracket::Where;
    const coord::kernels::QuatPose X_k = PoseFromWords(b.v0);
    Eigen::Vector3d vv, ww;
    TimeContext probe = *tc;  // ExtrapolationTwist notes its reads in the context it is given
    probe.recorder = nullptr;
    if (!ExtrapolationTwist<B>(*v, frame, b.s0, probe, vv, ww)) return;
    const double dt =
        b.where == Where::kBefore ? -SecondsBetween(tc->t, b.s0) : SecondsBetween(b.s0, tc->t);
    jac::Matrix6 J_X, J_xi;
    jac::ExtrapolateJacobians(X_k.q.toRotationMatrix(), vv, ww, dt, J_X, J_xi);
    coord::Covariance6 S_k;
    SampleCovariance(cb, false, 0.0, S_k);
    PerturbationKey k;
    k.kind = PerturbedEdge::Kind::kPose;
    k.index = frame;
    k.s0 = k.s1 = b.s0;
    acc->Add(k, J * J_X, S_k);
    const topology::SceneTopology& t = *tc->topology;
    const std::optional<TwistPlan> plan = IntegrationTwistPlan(*tc, frame);
    if (!plan) return;
    TimeContext nested;
    nested.at = true;
    nested.t = b.s0;
    nested.nested = true;
    nested.histories = tc->histories;
    nested.topology = tc->topology;
    KeyedSink inner{v, &nested, acc, J * J_xi, false};
    coord::Covariance6 unused;
    TwistCovariance<B>(t, *plan, TimedPoseCovarianceReader(*v, nested),
                       TimedTwistCovarianceReader(*v, nested), unused, inner);
  }
};

}  // namespace semgraph::core::internal
