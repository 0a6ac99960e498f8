// File: semgraph/core/timed_read.h
//
// The time dimension of the one evaluator (evaluate.h): how an edge's value is read at a query's
// time. Both chain sources (ForestSource, FlatSource) read each edge through these functions
// when given a TimeContext, so one-shot, compiled and conversion paths share them:
//   timeless edge        its value (X_PF / V_DH)
//   policy latest        the newest sample
//   policy at t          inside the samples: interpolated (pose: screw or linear, twist: linear;
//                        at a stamp only that sample); outside: within the horizon a twist
//                        edge holds its nearest sample and a pose edge is integrated with its
//                        screw twist at the nearest sample (ExtrapolationTwist, evaluate.h),
//                        else an extrapolation failure naming the edge and its range
//   pose derivative      (twist source `poses`) the edge's screw twist on the segment at t;
//                        the query's other edges read with no horizon (WithoutExtrapolation);
//                        with covariance, from its two samples' (DerivativeCovariance)
//   with acceleration    ReadTwistAt<B, false, true>: the same read of a twist edge, plus its
//                        acceleration record (docs/dynamics.md, "Stamped accelerations"): a
//                        sample's, the component-wise linear interpolation of two (present only
//                        when both are), a held sample's
//   with covariance      ReadPoseAt / ReadTwistAt<B, true>: the same read, plus the covariance
//                        of the value read (docs/uncertainty.md, "Time"): a sample's, (1 - l)
//                        S_i + l S_i+1 between two, a held twist's, an extrapolated pose edge's
//                        (ExtrapolationCovariance, timed_covariance.h); the flag is a template
//                        parameter so the plain reads compile exactly as before
// The context collects what the answer reports (oldest / newest stamp read, extrapolated), the
// minimum newest stamp of the stamped edges read (latest common), the first extrapolation and
// the first stale failure, and optionally records each edge read (the diagnostic call).
// A failure does not stop the evaluation (the numbers are then not used); the caller reports it.
// Costs: O(log samples) per stamped edge; noexcept, allocation-free, lock-free.
// Thread safety: a history pointer is loaded once per edge read (acquire) and may be a history
// the writer retires or reuses meanwhile (edge_history.h HistoryTable): the numbers are then
// those of another edge, so a caller racing topology changes must check the edge's epoch after
// the read (FlatSource does); extrapolation reads the topology (not safe against changes).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>

#include "semgraph/base/error_code.h"
#include "semgraph/coord/jacobians.h"
#include "semgraph/coord/se3.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/time.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core::internal {

/// Which edge failed and why (turned into a QueryError by the caller, who has the names).
struct TimeFailure {
  base::ErrorCode code = base::ErrorCode::kOk;
  bool twist_edge = false;  ///< index is a twist edge slot (else a frame: the pose edge into it)
  std::uint32_t index = 0;
  std::int64_t first = 0, last = 0, asked = 0;  ///< the edge's samples and the time asked
  bool single_sample = false;                   ///< a derivative of an edge with one sample
  bool wrench = false;  ///< index is a stored wrench's slot (wrenches.h; twist_edge also set)
};

/// One edge read, for the diagnostic call (SceneGraph::ExplainPose / ExplainTwist).
struct EdgeRead {
  enum class Kind : std::uint8_t { kPose, kTwist, kPoseDerivative } kind = Kind::kPose;
  std::uint32_t index = 0;
  bool stamped = false, extrapolated = false, has_read = false;
  std::int64_t first = 0, last = 0, read_from = 0, read_to = 0;
};
class EdgeRecorder {
 public:
  virtual void Record(const EdgeRead& r) noexcept = 0;

 protected:
  ~EdgeRecorder() = default;
};

struct IntegrationTwistPlans;  // evaluate.h: a compiled query's precomputed integration twists

struct TimeContext {
  // The policy.
  bool at = false;           ///< false: each edge's newest sample
  std::int64_t t = 0;        ///< at: the time
  std::int64_t horizon = 0;  ///< at: extrapolation allowed up to this many ns
  bool nested = false;       ///< the twist read to extrapolate an edge: no further extrapolation
  bool has_not_before = false;
  std::int64_t not_before = 0;
  const EdgeHistories* histories = nullptr;
  const topology::SceneTopology* topology = nullptr;  ///< for extrapolation (twist plans)
  /// Where an extrapolated pose edge's integration twist plan comes from (IntegrationTwistPlan,
  /// evaluate.h): nullptr, planned on the topology (PlanTwist); else a compiled query's plans,
  /// made at compile time (no planning at evaluation).
  const IntegrationTwistPlans* twist_plans = nullptr;
  EdgeRecorder* recorder = nullptr;

  // What was read.
  bool read_any = false;
  std::int64_t oldest = INT64_MAX, newest = INT64_MIN;
  bool any_stamped = false;
  std::int64_t min_newest = INT64_MAX;  ///< over the stamped edges used
  bool extrapolated = false;
  TimeFailure extrapolation, stale;

  void Read(std::int64_t s) noexcept {
    read_any = true;
    oldest = std::min(oldest, s);
    newest = std::max(newest, s);
  }
  /// A used stamped edge with newest sample `last`: latest common and not_before.
  void Used(bool twist_edge, std::uint32_t index, std::int64_t first, std::int64_t last) noexcept {
    any_stamped = true;
    min_newest = std::min(min_newest, last);
    if (has_not_before && last < not_before && stale.code == base::ErrorCode::kOk) {
      stale =
          TimeFailure{base::ErrorCode::kStale, twist_edge, index, first, last, not_before, false};
    }
  }
  void Fail(bool twist_edge, std::uint32_t index, std::int64_t first, std::int64_t last,
            bool single = false) noexcept {
    if (extrapolation.code == base::ErrorCode::kOk) {
      extrapolation =
          TimeFailure{base::ErrorCode::kExtrapolation, twist_edge, index, first, last, t, single};
    }
  }
  [[nodiscard]] base::ErrorCode error() const noexcept {
    if (extrapolation.code != base::ErrorCode::kOk) return extrapolation.code;
    return stale.code;
  }
  [[nodiscard]] const TimeFailure& failure() const noexcept {
    return extrapolation.code != base::ErrorCode::kOk ? extrapolation : stale;
  }
};

/// Seconds between two stamps a <= b (exact difference in unsigned arithmetic, then rounded).
[[nodiscard]] inline double SecondsBetween(std::int64_t a, std::int64_t b) noexcept {
  return static_cast<double>(static_cast<std::uint64_t>(b) - static_cast<std::uint64_t>(a)) * 1e-9;
}
/// (t - s0) / (s1 - s0) for s0 <= t <= s1, s0 < s1.
[[nodiscard]] inline double Fraction(std::int64_t s0, std::int64_t t, std::int64_t s1) noexcept {
  return static_cast<double>(static_cast<std::uint64_t>(t) - static_cast<std::uint64_t>(s0)) /
         static_cast<double>(static_cast<std::uint64_t>(s1) - static_cast<std::uint64_t>(s0));
}

inline coord::kernels::QuatPose PoseFromWords(const double (&w)[7]) noexcept {
  return {Eigen::Quaterniond(w[3], w[0], w[1], w[2]), Eigen::Vector3d(w[4], w[5], w[6])};
}
inline void WordsFromPose(const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                          double (&w)[7]) noexcept {
  w[0] = q.x();
  w[1] = q.y();
  w[2] = q.z();
  w[3] = q.w();
  w[4] = p.x();
  w[5] = p.y();
  w[6] = p.z();
}
inline TwistNumbers TwistFromWords(const double (&w)[6]) noexcept {
  return {Eigen::Vector3d(w[0], w[1], w[2]), Eigen::Vector3d(w[3], w[4], w[5])};
}
inline void WordsFromTwist(const TwistNumbers& V, double (&w)[6]) noexcept {
  for (int k = 0; k < 3; ++k) {
    w[k] = V.v_DHo_H[k];
    w[3 + k] = V.w_DH_H[k];
  }
}

/// An acceleration as a twist history's 7 side words (a, alpha, present = 1) and back (a record
/// with present 0 when the words say none).
inline void WordsFromAcceleration(const AccelerationNumbers& A, double (&w)[7]) noexcept {
  for (int k = 0; k < 3; ++k) {
    w[k] = A.a_DHo_H[k];
    w[3 + k] = A.alpha_DH_H[k];
  }
  w[6] = 1.0;
}
inline void AccelerationFromWords(const double (&w)[7], TwistAndAcceleration& R) noexcept {
  R.A.a_DHo_H = Eigen::Vector3d(w[0], w[1], w[2]);
  R.A.alpha_DH_H = Eigen::Vector3d(w[3], w[4], w[5]);
  R.present = w[6] != 0.0 ? 1.0 : 0.0;
}

/// A covariance (symmetric 6x6) as a history's 21 words (upper triangle, row by row) and back.
inline void WordsFromCovariance(const coord::Covariance6& S, double (&w)[21]) noexcept {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) w[k++] = S(i, j);
  }
}
inline void CovarianceFromWords(const double (&w)[21], coord::Covariance6& S) noexcept {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) S(i, j) = S(j, i) = w[k++];
  }
}

/// The screw twist of the pose edge into `frame` at stamp s, from the twist edges (no
/// extrapolation); false when there is no twist path or no twist data at s. Defined in
/// evaluate.h (it runs the evaluator).
template <coord::Backend B>
bool ExtrapolationTwist(const EdgeValues<B>& v, std::uint32_t frame, std::int64_t s,
                        TimeContext& parent, Eigen::Vector3d& v_out,
                        Eigen::Vector3d& w_out) noexcept;

/// The newest sample of history `h` of edge `index` (the latest policy), noted in the context
/// and in the record. The first half of both edge reads (ReadPoseAt, ReadTwistAt).
template <class History>
void ReadNewest(const History& h, bool twist, std::uint32_t index, TimeContext& tc, EdgeRead& rec,
                double (&w)[History::kValueWords],
                typename History::CovarianceBracket* cov = nullptr,
                typename History::AccelerationBracket* acc = nullptr) noexcept {
  std::int64_t s = 0, first = 0;
  h.Newest(s, w, first, cov, acc);
  tc.Read(s);
  if (!tc.nested) tc.Used(twist, index, first, s);
  rec.first = first;
  rec.last = s;
  rec.read_from = rec.read_to = s;
  rec.has_read = true;
}

/// The samples of history `h` of edge `index` around the context's time, their span noted in
/// the context and in the record (what is read of them is the caller's).
template <class History>
[[gnu::always_inline]] inline typename History::Bracket FindAtTime(
    const History& h, bool twist, std::uint32_t index, TimeContext& tc, EdgeRead& rec,
    typename History::CovarianceBracket* cov = nullptr,
    typename History::AccelerationBracket* acc = nullptr) noexcept {
  typename History::Bracket b;
  h.Find(tc.t, b, cov, acc);
  rec.first = b.first;
  rec.last = b.last;
  if (!tc.nested) tc.Used(twist, index, b.first, b.last);
  return b;
}

/// X from a pose (quaternion, vector) in the backend's form.
template <coord::Backend B>
void SetPose(typename B::PoseCoords& X, const Eigen::Quaterniond& q,
             const Eigen::Vector3d& p) noexcept {
  X = B::MakePose(B::FromQuaternion(q), p);
}

/// The sample (at lambda = 0) or the interpolation of two samples' words at lambda, into X.
/// Linear interpolation, the common case, goes straight from the words to X (no QuatPose
/// copies, Slerp inlined); numbers as coord::kernels::Interpolate's.
template <coord::Backend B>
[[gnu::noinline]] void InterpolateScrewWords(const double (&w0)[7], const double (&w1)[7],
                                             double lambda, typename B::PoseCoords& X) noexcept {
  const coord::kernels::QuatPose out =
      coord::kernels::InterpolateScrew(PoseFromWords(w0), PoseFromWords(w1), lambda);
  SetPose<B>(X, out.q, out.p);
}
template <coord::Backend B>
[[gnu::always_inline]] inline void InterpolateWords(coord::Interpolation mode,
                                                    const double (&w0)[7], const double (&w1)[7],
                                                    double lambda,
                                                    typename B::PoseCoords& X) noexcept {
  if (mode != coord::Interpolation::kLinear) return InterpolateScrewWords<B>(w0, w1, lambda, X);
  const Eigen::Quaterniond q0(w0[3], w0[0], w0[1], w0[2]), q1(w1[3], w1[0], w1[1], w1[2]);
  SetPose<B>(X, coord::kernels::Slerp(q0, q1, lambda),
             Eigen::Vector3d(w0[4] + lambda * (w1[4] - w0[4]), w0[5] + lambda * (w1[5] - w0[5]),
                             w0[6] + lambda * (w1[6] - w0[6])));
}

/// The covariance of a sample (c0), or of the interpolation at lambda of two (docs/uncertainty.md,
/// "Time": (1 - lambda) S0 + lambda S1, in the edge form); zero when the edge has none.
template <class Bracket>
void SampleCovariance(const Bracket& cb, bool interpolated, double lambda,
                      coord::Covariance6& S) noexcept {
  if (!cb.any) {
    S.setZero();
    return;
  }
  CovarianceFromWords(cb.c0, S);
  if (interpolated) {
    coord::Covariance6 S1;
    CovarianceFromWords(cb.c1, S1);
    S = (1.0 - lambda) * S + lambda * S1;
  }
}

/// The covariance of an extrapolated pose edge X_k Exp(dt xi) (docs/uncertainty.md, "Time"):
/// the sample's covariance S_k and that of the integration twist xi at s (its twist edges and
/// the pose edges that move them), to first order. Defined in timed_covariance.h (it runs the
/// propagation); used only by the covariance reads (ReadPoseAt<B, true>).
template <coord::Backend B>
void ExtrapolationCovariance(const EdgeValues<B>& v, std::uint32_t frame, std::int64_t s,
                             TimeContext& parent, const coord::kernels::QuatPose& X_k,
                             const Eigen::Vector3d& v_xi, const Eigen::Vector3d& w_xi, double dt,
                             const coord::Covariance6& S_k, coord::Covariance6& S) noexcept;

/// The value of the pose edge into `frame` under the context's policy; with kCovariance, also
/// the covariance of that value into *S (the same samples, one read).
template <coord::Backend B, bool kCovariance = false>
void ReadPoseAt(const EdgeValues<B>& v, std::uint32_t frame, TimeContext& tc,
                typename B::PoseCoords& X, coord::Covariance6* S = nullptr) noexcept {
  const PoseHistory* h = v.history.pose_of(frame);
  EdgeRead rec;
  rec.kind = EdgeRead::Kind::kPose;
  rec.index = frame;
  PoseHistory::CovarianceBracket cb;
  PoseHistory::CovarianceBracket* const cov = kCovariance ? &cb : nullptr;
  if (h == nullptr) {
    if constexpr (kCovariance) {
      v.LoadPose(frame, X, *S);
    } else {
      X = v.X_PF[frame].Load();
    }
    if (tc.recorder) tc.recorder->Record(rec);
    return;
  }
  rec.stamped = true;
  if (!tc.at) {
    double w0[7];
    ReadNewest(*h, false, frame, tc, rec, w0, cov);
    if constexpr (kCovariance) SampleCovariance(cb, false, 0.0, *S);
    SetPose<B>(X, Eigen::Quaterniond(w0[3], w0[0], w0[1], w0[2]),
               Eigen::Vector3d(w0[4], w0[5], w0[6]));
  } else {
    const PoseHistory::Bracket b = FindAtTime(*h, false, frame, tc, rec, cov);
    using Where = PoseHistory::Bracket::Where;
    if (b.where == Where::kInside) {
      rec.has_read = true;
      rec.read_from = b.s0;
      tc.Read(b.s0);
      if (b.exact) {
        SetPose<B>(X, Eigen::Quaterniond(b.v0[3], b.v0[0], b.v0[1], b.v0[2]),
                   Eigen::Vector3d(b.v0[4], b.v0[5], b.v0[6]));
        rec.read_to = b.s0;
        if constexpr (kCovariance) SampleCovariance(cb, false, 0.0, *S);
      } else {
        const double lambda = Fraction(b.s0, tc.t, b.s1);
        InterpolateWords<B>(v.history.options.interpolation, b.v0, b.v1, lambda, X);
        tc.Read(b.s1);
        rec.read_to = b.s1;
        if constexpr (kCovariance) SampleCovariance(cb, true, lambda, *S);
      }
    } else {
      coord::kernels::QuatPose out = PoseFromWords(b.v0);  // the nearest sample
      const std::int64_t gap =
          b.where == Where::kBefore ? SaturatingSub(b.s0, tc.t) : SaturatingSub(tc.t, b.s0);
      Eigen::Vector3d vv, ww;
      if (!tc.nested && gap <= tc.horizon && ExtrapolationTwist<B>(v, frame, b.s0, tc, vv, ww)) {
        const double dt =
            b.where == Where::kBefore ? -SecondsBetween(tc.t, b.s0) : SecondsBetween(b.s0, tc.t);
        if constexpr (kCovariance) {
          coord::Covariance6 S_k;
          SampleCovariance(cb, false, 0.0, S_k);
          ExtrapolationCovariance<B>(v, frame, b.s0, tc, out, vv, ww, dt, S_k, *S);
        }
        out = coord::kernels::Integrate(out, vv, ww, dt);
        tc.Read(b.s0);
        tc.extrapolated = true;
        rec.extrapolated = true;
        rec.has_read = true;
        rec.read_from = rec.read_to = b.s0;
      } else {
        tc.Fail(false, frame, b.first, b.last);
        if constexpr (kCovariance) S->setZero();
      }
      SetPose<B>(X, out.q, out.p);
    }
  }
  if (tc.recorder) tc.recorder->Record(rec);
}

/// The acceleration of a sample (c0), or the component-wise interpolation at lambda of two
/// (present only when both samples carry one); none when the edge was never given one.
inline void SampleAcceleration(const TwistHistory::AccelerationBracket& ab, bool interpolated,
                               double lambda, TwistAndAcceleration& R) noexcept {
  R.present = 0.0;
  if (!ab.any) return;
  AccelerationFromWords(ab.c0, R);
  if (interpolated && R.present != 0.0) {
    TwistAndAcceleration R1;
    AccelerationFromWords(ab.c1, R1);
    R.present = R1.present;
    R.A.a_DHo_H += lambda * (R1.A.a_DHo_H - R.A.a_DHo_H);
    R.A.alpha_DH_H += lambda * (R1.A.alpha_DH_H - R.A.alpha_DH_H);
  }
}

/// The value at the context's time of a history read linearly word by word (twist edges,
/// stamped wrenches: wrenches.h), into w: latest, the newest sample; at t inside the samples,
/// the bracket's linear interpolation (t a stamp: that sample only); outside, within the horizon
/// the nearest sample held (extrapolated), beyond it an extrapolation failure of (twist, index).
/// Returns the fraction of the interpolation (0 when one sample was read), for the caller's
/// covariance and acceleration (`cov`, `acc`: the samples' side words, as Find reads them).
template <class History>
double ReadLinearAt(const History& h, bool twist, std::uint32_t index, TimeContext& tc,
                    EdgeRead& rec, double (&w)[History::kValueWords],
                    typename History::CovarianceBracket* cov = nullptr,
                    typename History::AccelerationBracket* acc = nullptr) noexcept {
  constexpr std::size_t N = History::kValueWords;
  rec.stamped = true;
  if (!tc.at) {
    ReadNewest(h, twist, index, tc, rec, w, cov, acc);
    return 0.0;
  }
  const typename History::Bracket b = FindAtTime(h, twist, index, tc, rec, cov, acc);
  using Where = typename History::Bracket::Where;
  for (std::size_t k = 0; k < N; ++k) w[k] = b.v0[k];
  if (b.where == Where::kInside) {
    rec.has_read = true;
    rec.read_from = rec.read_to = b.s0;
    tc.Read(b.s0);
    if (b.exact) return 0.0;
    const double lambda = Fraction(b.s0, tc.t, b.s1);
    for (std::size_t k = 0; k < N; ++k) w[k] += lambda * (b.v1[k] - w[k]);
    tc.Read(b.s1);
    rec.read_to = b.s1;
    return lambda;
  }
  const std::int64_t gap =
      b.where == Where::kBefore ? SaturatingSub(b.s0, tc.t) : SaturatingSub(tc.t, b.s0);
  if (!tc.nested && gap <= tc.horizon) {  // hold the nearest sample
    tc.Read(b.s0);
    tc.extrapolated = true;
    rec.extrapolated = rec.has_read = true;
    rec.read_from = rec.read_to = b.s0;
  } else {
    tc.Fail(twist, index, b.first, b.last);
  }
  return 0.0;
}

/// The value of twist edge `slot` under the context's policy (ReadLinearAt); with kCovariance,
/// also the covariance of that value into *S (a held sample keeps its covariance); with
/// kAcceleration, also the acceleration going with that value into *R (R->V = V; a held sample
/// keeps its acceleration, as it keeps its twist).
template <coord::Backend B, bool kCovariance = false, bool kAcceleration = false>
void ReadTwistAt(const EdgeValues<B>& v, std::uint32_t slot, TimeContext& tc, TwistNumbers& V,
                 coord::Covariance6* S = nullptr, TwistAndAcceleration* R = nullptr) noexcept {
  const TwistHistory* h = v.history.twist_of(slot);
  EdgeRead rec;
  rec.kind = EdgeRead::Kind::kTwist;
  rec.index = slot;
  TwistHistory::CovarianceBracket cb;
  TwistHistory::CovarianceBracket* const cov = kCovariance ? &cb : nullptr;
  TwistHistory::AccelerationBracket ab;
  TwistHistory::AccelerationBracket* const acc = kAcceleration ? &ab : nullptr;
  if (h == nullptr) {
    if constexpr (kCovariance) {
      v.LoadTwist(slot, V, *S);
    } else if constexpr (kAcceleration) {
      *R = v.A_DH[slot].Load();
      V = R->V;
    } else {
      V = v.V_DH[slot].Load();
    }
    if (tc.recorder && !tc.nested) tc.recorder->Record(rec);
    return;
  }
  double w[6];
  const double lambda = ReadLinearAt(*h, true, slot, tc, rec, w, cov, acc);
  V = TwistFromWords(w);
  if constexpr (kCovariance) SampleCovariance(cb, lambda != 0.0, lambda, *S);
  if constexpr (kAcceleration) {
    SampleAcceleration(ab, lambda != 0.0, lambda, *R);
    R->V = V;
  }
  if (tc.recorder && !tc.nested) tc.recorder->Record(rec);
}

/// The covariance of a pose edge's derivative on the segment X0 -> X1 (docs/uncertainty.md,
/// "Twists from poses"): J0 S0 J0^T + J1 S1 J1^T, the two samples independent, J0 and J1 from
/// coord/jacobians.h for the history's interpolation; zero when the edge has no covariances.
inline void DerivativeCovariance(coord::Interpolation mode, const coord::kernels::QuatPose& X0,
                                 const coord::kernels::QuatPose& X1, double dt, double lambda,
                                 const PoseHistory::CovarianceBracket& cb,
                                 coord::Covariance6& S) noexcept {
  namespace jac = coord::jacobians;
  S.setZero();
  if (!cb.any) return;
  const Eigen::Matrix3d R0 = X0.q.toRotationMatrix();
  jac::Matrix6 J0, J1;
  if (mode == coord::Interpolation::kScrew) {
    Eigen::Vector3d rho, phi;
    coord::kernels::Log(coord::kernels::Between(X0, X1), rho, phi);
    jac::ScrewSegmentTwistJacobians(R0, X1.p - X0.p, rho, phi, dt, J0, J1);
  } else {
    const Eigen::Vector3d phi = coord::kernels::LogSO3(X0.q.conjugate() * X1.q);
    const Eigen::Matrix3d R_l = coord::kernels::Slerp(X0.q, X1.q, lambda).toRotationMatrix();
    jac::LinearSegmentTwistJacobians(R0, R_l, phi, X1.p - X0.p, dt, lambda, J0, J1);
  }
  coord::Covariance6 S0, S1;
  CovarianceFromWords(cb.c0, S0);
  CovarianceFromWords(cb.c1, S1);
  jac::AddPropagated(J0, S0, S);
  jac::AddPropagated(J1, S1, S);
}

/// The screw twist TwistCoord(h|H, T, [h]) of the pose edge into `frame` from its history at
/// the policy's time (latest: the newest sample, the segment before it); zero for a timeless
/// edge. Never extrapolates. With kCovariance, also the derivative's covariance into *S
/// (DerivativeCovariance; zero for a timeless edge, whose derivative is exactly zero).
template <coord::Backend B, bool kCovariance = false>
void DerivePoseAt(const EdgeValues<B>& v, std::uint32_t frame, TimeContext& tc, TwistNumbers& V,
                  coord::Covariance6* S = nullptr) noexcept {
  const PoseHistory* h = v.history.pose_of(frame);
  EdgeRead rec;
  rec.kind = EdgeRead::Kind::kPoseDerivative;
  rec.index = frame;
  V = TwistNumbers{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if constexpr (kCovariance) S->setZero();
  if (h == nullptr) {
    if (tc.recorder) tc.recorder->Record(rec);
    return;
  }
  rec.stamped = true;
  const std::int64_t t = tc.at ? tc.t : h->NewestStamp();
  PoseHistory::Bracket b;
  PoseHistory::CovarianceBracket cb;
  const bool ok = h->FindSegment(t, b, kCovariance ? &cb : nullptr);
  rec.first = b.first;
  rec.last = b.last;
  tc.Used(false, frame, b.first, b.last);
  if (!ok) {
    tc.Fail(false, frame, b.first, b.last, b.first == b.last);
  } else {
    const coord::kernels::QuatPose X0 = PoseFromWords(b.v0), X1 = PoseFromWords(b.v1);
    const double dt = SecondsBetween(b.s0, b.s1), lambda = Fraction(b.s0, t, b.s1);
    coord::kernels::SegmentTwist(v.history.options.interpolation, X0, X1, dt, lambda, V.v_DHo_H,
                                 V.w_DH_H);
    if constexpr (kCovariance) {
      DerivativeCovariance(v.history.options.interpolation, X0, X1, dt, lambda, cb, *S);
    }
    tc.Read(b.s0);
    tc.Read(b.s1);
    rec.has_read = true;
    rec.read_from = b.s0;
    rec.read_to = b.s1;
  }
  if (tc.recorder) tc.recorder->Record(rec);
}

/// A policy as the context's fields.
struct PolicyParts {
  bool at = false, latest_common = false;
  std::int64_t t = 0, horizon = 0;
  std::optional<Stamp> not_before;
  [[nodiscard]] bool valid() const noexcept { return horizon >= 0; }  ///< else invalid_number
};
[[nodiscard]] inline PolicyParts PartsOf(const TimePolicy& policy) noexcept {
  PolicyParts p;
  if (const auto* a = std::get_if<At>(&policy)) {
    p.at = true;
    p.t = a->time.nanoseconds();
    p.horizon = a->max_extrapolation.nanoseconds();
    p.not_before = a->not_before;
  } else if (const auto* c = std::get_if<LatestCommon>(&policy)) {
    p.latest_common = true;
    p.horizon = c->max_extrapolation.nanoseconds();
    p.not_before = c->not_before;
  } else {
    p.not_before = std::get<Latest>(policy).not_before;
  }
  return p;
}

/// The policy of a twist from poses (TwistSource::kPoses): nothing is extrapolated, so the
/// horizon is ignored (zero); a negative one is kept, as it is still invalid_number.
[[nodiscard]] inline TimePolicy WithoutExtrapolation(TimePolicy policy) noexcept {
  const auto ignore = [](Duration& h) { h = std::min(h, Duration{}); };
  if (auto* a = std::get_if<At>(&policy)) ignore(a->max_extrapolation);
  if (auto* c = std::get_if<LatestCommon>(&policy)) ignore(c->max_extrapolation);
  return policy;
}

/// Runs `eval(TimeContext&)` (one evaluation of a plan) under the policy: latest common first
/// probes the newest stamps of the used edges (a second evaluation), then evaluates at their
/// minimum. Fills the report; returns kOk, kExtrapolation or kStale (then *failure says which
/// edge), or what eval returned (a compiled query's kQueryInvalidated). `base` carries the
/// histories, topology and recorder.
template <class Eval>
base::ErrorCode RunPolicy(const PolicyParts& p, const TimeContext& base, Eval&& eval,
                          TimeReport& report, TimeFailure* failure = nullptr) noexcept {
  report = TimeReport{};
  TimeContext tc = base;
  tc.at = p.at;
  tc.t = p.t;
  tc.horizon = p.horizon;
  tc.has_not_before = p.not_before.has_value();
  tc.not_before = p.not_before ? p.not_before->nanoseconds() : 0;
  if (p.latest_common) {
    TimeContext probe = base;  // latest, nothing recorded, no staleness
    probe.recorder = nullptr;
    if (const base::ErrorCode code = eval(probe); code != base::ErrorCode::kOk) return code;
    if (probe.any_stamped) {
      tc.at = true;
      tc.t = probe.min_newest;
    }
  }
  if (tc.at) report.time = Stamp::Nanoseconds(tc.t);
  if (const base::ErrorCode code = eval(tc); code != base::ErrorCode::kOk) return code;
  if (const base::ErrorCode code = tc.error(); code != base::ErrorCode::kOk) {
    if (failure) *failure = tc.failure();
    return code;
  }
  if (tc.read_any) {
    report.oldest = Stamp::Nanoseconds(tc.oldest);
    report.newest = Stamp::Nanoseconds(tc.newest);
  }
  report.extrapolated = tc.extrapolated;
  return base::ErrorCode::kOk;
}

}  // namespace semgraph::core::internal
