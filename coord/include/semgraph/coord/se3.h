// File: semgraph/coord/se3.h
//
// The SE(3) exponential and logarithm, and the two interpolations of one pose edge's motion
// (docs/time.md), as raw kernels and as checked semantic operations.
//
// Convention: a pose edge {t}|T -> {h}|H stores X = (R, p) = (R[t<-h], p(h/t) in [t]). Its
// body-fixed (screw) twist is xi = (v, w) = TwistCoord(h|H, T, [h]): for a motion X(s),
// X^-1 dX/ds = ([w]x, v) with w = R^T dR/ds (vee) and v = R^T dp/ds.
//   Exp(v, w) = (exp([w]x), V(w) v),  V = I + (1 - cos th)/th^2 [w]x + (th - sin th)/th^3 [w]x^2
//   Log = Exp^-1 with the rotation angle th = |w| in [0, pi] (at exactly pi either axis sign).
// Interpolation of two samples X0 (at s0), X1 (at s1), lambda = (s - s0)/(s1 - s0):
//   screw:   X0 Exp(lambda Log(X0^-1 X1))        (the constant-screw-twist motion)
//   linear:  p = lerp(p0, p1), R = slerp(R0, R1) on the shorter arc (tf2's interpolation)
// and their derivatives, the edge's screw twist at s:
//   screw:   Log(X0^-1 X1) / (s1 - s0)            (constant over the segment)
//   linear:  w = Log(R0^T R1) / (s1 - s0),  v = R(s)^T (p1 - p0) / (s1 - s0)
//
// Kernels work on (unit quaternion, vector) whatever the backend; the checked operations take
// coord::Pose<B> / coord::Twist, check the semantics (semantics/time_operations.h: the twist
// must be the screw twist of that very edge, the two samples of one edge), then compute.
// Accuracy: series expansions below th = 0.1 keep every coefficient to full double precision
// (no cancellation at small angles); slerp between close rotations uses an exact series instead
// of trigonometry (SlerpSeriesWeights: within 3e-16 relative). Cost: O(1), a few transcendental
// calls (none for slerp at small angles); noexcept, allocation-free.
#pragma once

#include <cmath>

#include "semgraph/coord/operations.h"
#include "semgraph/semantics/time_operations.h"

namespace semgraph::coord {

/// How a pose edge moves between two samples.
enum class Interpolation : std::uint8_t { kScrew, kLinear };

namespace kernels {

/// A pose as a unit quaternion and a translation: the time kernels' working form.
struct QuatPose {
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
};

/// (1 - cos th) / th^2 and (th - sin th) / th^3, accurate at small th.
inline void ExpCoefficients(double th, double& a, double& b) noexcept {
  const double t2 = th * th;
  if (th < 0.1) {
    a = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0));
    b = 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0));
  } else {
    const double s = std::sin(0.5 * th);
    a = 2.0 * s * s / t2;
    b = (th - std::sin(th)) / (t2 * th);
  }
}

/// exp([w]x) as a unit quaternion.
inline Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& w) noexcept {
  const double th = w.norm();
  const double half = 0.5 * th;
  // sin(th/2)/th, accurate at small th.
  const double k = th < 1e-4 ? 0.5 - th * th / 48.0 : std::sin(half) / th;
  return Eigen::Quaterniond(std::cos(half), k * w.x(), k * w.y(), k * w.z());
}

/// Log of a unit quaternion: w with |w| in [0, pi] (the quaternion's sign is chosen with w >= 0).
inline Eigen::Vector3d LogSO3(const Eigen::Quaterniond& q_in) noexcept {
  const Eigen::Quaterniond q = q_in.w() < 0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const double n = q.vec().norm();
  if (n == 0.0) return Eigen::Vector3d::Zero();
  // th = 2 atan2(n, w): no cancellation at small or large angles.
  return (2.0 * std::atan2(n, q.w()) / n) * q.vec();
}

/// Exp(v, w) of SE(3) (convention above).
inline QuatPose Exp(const Eigen::Vector3d& v, const Eigen::Vector3d& w) noexcept {
  double a = 0.0, b = 0.0;
  ExpCoefficients(w.norm(), a, b);
  const Eigen::Vector3d wv = w.cross(v);
  return {ExpSO3(w), v + a * wv + b * w.cross(wv)};
}

/// c of the inverse of SO(3)'s left Jacobian (SE(3)'s V^-1), I - [w]/2 + c [w]^2:
/// c = (1 - (th/2) cot(th/2)) / th^2, by its series below th = 0.1.
inline double LeftJacobianInverseC(double th) noexcept {
  if (th < 0.1) {
    const double t2 = th * th;
    return 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0;
  }
  const double half = 0.5 * th;
  return (1.0 - half * std::cos(half) / std::sin(half)) / (th * th);
}

/// Log of SE(3): the twist (v, w) with Exp(v, w) = (q, p), |w| in [0, pi].
inline void Log(const QuatPose& X, Eigen::Vector3d& v, Eigen::Vector3d& w) noexcept {
  w = LogSO3(X.q);
  const double c = LeftJacobianInverseC(w.norm());  // V^-1 = I - [w]/2 + c [w]^2
  const Eigen::Vector3d wp = w.cross(X.p);
  v = X.p - 0.5 * wp + c * w.cross(wp);
}

/// X0^-1 X1 in the chain form.
inline QuatPose Between(const QuatPose& X0, const QuatPose& X1) noexcept {
  const Eigen::Quaterniond q0_inv = X0.q.conjugate();
  return {q0_inv * X1.q, q0_inv * (X1.p - X0.p)};
}
/// X0 X1 in the chain form.
inline QuatPose Chain(const QuatPose& X0, const QuatPose& X1) noexcept {
  return {X0.q * X1.q, X0.q * X1.p + X0.p};
}

/// X Exp(dt xi): the pose after moving for dt with the constant screw twist xi = (v, w).
inline QuatPose Integrate(const QuatPose& X, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                          double dt) noexcept {
  QuatPose X_out = Chain(X, Exp(dt * v, dt * w));
  X_out.q.normalize();
  return X_out;
}

/// The slerp weights of a small angle without trigonometry: with x = cos th (th in [0, pi/2],
/// the half angle between the rotations) and u = 1 - x, for t in [0, 1]
///   sin(t th) / sin th = t sum_i b_i(t) u^i,  b_0 = 1,  b_i = b_(i-1) (i^2 - t^2) / (i (2i + 1)),
/// the Taylor series at x = 1 of the solution of (1 - x^2) f'' - 3x f' + (t^2 - 1) f = 0 with
/// f(1) = t (as in Eberly, "A Fast and Accurate Algorithm for Computing SLERP", 2011; here the
/// series itself, not a fitted approximation). Every term is >= 0 and each is at most u/2 times
/// the one before, and f >= t, so stopping after term K leaves a relative error of at most
///   E(K, u) = prod_(j=1..K+1) j/(2j+1) u^(K+1) / (1 - u/2),
/// and K is the fewest terms with E <= 1.4e-17 (terms below): K = 1 up to u = 1e-8, 2 up to
/// 5e-6, 3 up to 1.4e-4 (a rotation of 0.033 rad between the samples), 4 up to 1e-3, 8 up to
/// kSlerpSeriesMaxU = 0.03 (th <= 0.2456, a rotation of 0.49 rad). The Horner sum of positive
/// terms adds about 2 ulp of rounding: each weight is within 3e-16 of sin(t th) / sin th
/// relative (tests/coord/se3_test.cc checks 1e-15 against long double trigonometry).
inline constexpr double kSlerpSeriesMaxU = 0.03;
[[gnu::always_inline]] inline void SlerpSeriesWeights(double t0, double t1, double u, double& w0,
                                                      double& w1) noexcept {
  // Both weights at once (one SIMD lane each): r = 1 + (i^2 - t^2) u / (i (2i + 1)) r.
  const Eigen::Array2d t(t0, t1), a = t * t;
  Eigen::Array2d r = Eigen::Array2d::Ones();
  const auto term = [&](double ii, double inv) noexcept { r = ((ii - a) * (u * inv)) * r + 1.0; };
  const int terms = u <= 1e-8 ? 1 : u <= 5e-6 ? 2 : u <= 1.4e-4 ? 3 : u <= 1e-3 ? 4 : 8;
  switch (terms) {  // i = K down to 1
    case 8:
      term(64.0, 1.0 / 136.0);
      term(49.0, 1.0 / 105.0);
      term(36.0, 1.0 / 78.0);
      term(25.0, 1.0 / 55.0);
      [[fallthrough]];
    case 4:
      term(16.0, 1.0 / 36.0);
      [[fallthrough]];
    case 3:
      term(9.0, 1.0 / 21.0);
      [[fallthrough]];
    case 2:
      term(4.0, 1.0 / 10.0);
      [[fallthrough]];
    default:
      term(1.0, 1.0 / 3.0);
  }
  w0 = t0 * r[0];
  w1 = t1 * r[1];
}

/// Slerp weights from the angle, for rotations farther apart than the series covers (out of
/// line: the common case stays small enough to inline).
[[gnu::noinline]] inline Eigen::Quaterniond SlerpFar(const Eigen::Quaterniond& q0,
                                                     const Eigen::Quaterniond& q1, double d,
                                                     double sign, double lambda) noexcept {
  // The half angle between the rotations: atan2(sin, cos), accurate near pi/2.
  const double theta = std::atan2((sign * q1.coeffs() - d * q0.coeffs()).norm(), d);
  const double s = 1.0 / std::sin(theta);
  const double s0 = std::sin((1.0 - lambda) * theta) * s;
  const double s1 = std::sin(lambda * theta) * s * sign;
  return Eigen::Quaterniond(s0 * q0.coeffs() + s1 * q1.coeffs());
}

/// Slerp on the shorter arc (as tf2's Quaternion::slerp), lambda in [0, 1]. Consecutive samples
/// are close: their weights come from the series above (a few dozen flops); farther apart,
/// from atan2 and three sines (SlerpFar).
[[gnu::always_inline]] inline Eigen::Quaterniond Slerp(const Eigen::Quaterniond& q0,
                                                       const Eigen::Quaterniond& q1,
                                                       double lambda) noexcept {
  double d = q0.coeffs().dot(q1.coeffs());
  const double sign = d < 0 ? -1.0 : 1.0;
  d = std::abs(d);
  if (!(1.0 - d <= kSlerpSeriesMaxU)) return SlerpFar(q0, q1, d, sign, lambda);
  double s0 = 0.0, s1 = 0.0;
  SlerpSeriesWeights(1.0 - lambda, lambda, 1.0 - d, s0, s1);
  return Eigen::Quaterniond(s0 * q0.coeffs() + (s1 * sign) * q1.coeffs());
}

/// Screw interpolation X0 Exp(lambda Log(X0^-1 X1)).
inline QuatPose InterpolateScrew(const QuatPose& X0, const QuatPose& X1, double lambda) noexcept {
  Eigen::Vector3d v, w;
  Log(Between(X0, X1), v, w);
  return Integrate(X0, v, w, lambda);
}

/// Linear interpolation: lerp of p, slerp of q.
inline QuatPose InterpolateLinear(const QuatPose& X0, const QuatPose& X1, double lambda) noexcept {
  return {Slerp(X0.q, X1.q, lambda), X0.p + lambda * (X1.p - X0.p)};
}

inline QuatPose Interpolate(Interpolation mode, const QuatPose& X0, const QuatPose& X1,
                            double lambda) noexcept {
  return mode == Interpolation::kScrew ? InterpolateScrew(X0, X1, lambda)
                                       : InterpolateLinear(X0, X1, lambda);
}

/// The edge's screw twist at lambda of the segment X0 -> X1 of duration dt (> 0), per mode.
inline void SegmentTwist(Interpolation mode, const QuatPose& X0, const QuatPose& X1, double dt,
                         double lambda, Eigen::Vector3d& v, Eigen::Vector3d& w) noexcept {
  if (mode == Interpolation::kScrew) {
    Log(Between(X0, X1), v, w);
    v /= dt;
    w /= dt;
    return;
  }
  w = LogSO3(X0.q.conjugate() * X1.q) / dt;
  const Eigen::Quaterniond q = Slerp(X0.q, X1.q, lambda);
  v = q.conjugate() * ((X1.p - X0.p) / dt);
}

}  // namespace kernels

// ============================================================ checked operations

namespace internal {
template <Backend B>
kernels::QuatPose ToQuatPose(const typename B::PoseCoords& X) noexcept {
  return {B::ToQuaternion(B::RotationOf(X)), B::TranslationOf(X)};
}
template <Backend B>
typename B::PoseCoords FromQuatPose(const kernels::QuatPose& X) noexcept {
  return B::MakePose(B::FromQuaternion(X.q), X.p);
}
}  // namespace internal

/// X Exp(dt xi): integrate the edge X for dt with its screw twist xi = TwistCoord(h|H, T, [h]).
template <Backend B>
[[nodiscard]] Result<Pose<B>> Integrate(const Pose<B>& X, const Twist& xi, double dt) noexcept {
  auto s = semantics::Integrate(X.semantics, xi.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Pose<B>{*s, internal::FromQuatPose<B>(kernels::Integrate(internal::ToQuatPose<B>(X.value),
                                                                  xi.linear, xi.angular, dt))};
}

/// Log(X0^-1 X1) / dt: the constant screw twist taking sample X0 to X1 of the same edge in dt
/// (> 0; a non-positive or non-finite dt is invalid_number).
template <Backend B>
[[nodiscard]] Result<Twist> Differentiate(const Pose<B>& X0, const Pose<B>& X1,
                                          double dt) noexcept {
  auto s = semantics::Differentiate(X0.semantics, X1.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    Error e;
    e.code = ErrorCode::kInvalidNumber;
    e.value.problem = ValueProblem::kNotFinite;
    return Unexpected{e};
  }
  Twist xi{*s, {}, {}};
  kernels::SegmentTwist(Interpolation::kScrew, internal::ToQuatPose<B>(X0.value),
                        internal::ToQuatPose<B>(X1.value), dt, 0.0, xi.linear, xi.angular);
  return xi;
}

/// The motion between two samples of one edge at lambda in [0, 1] (0: X0, 1: X1).
template <Backend B>
[[nodiscard]] Result<Pose<B>> Interpolate(const Pose<B>& X0, const Pose<B>& X1, double lambda,
                                          Interpolation mode) noexcept {
  auto s = semantics::Interpolate(X0.semantics, X1.semantics, mode == Interpolation::kScrew);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Pose<B>{
      *s, internal::FromQuatPose<B>(kernels::Interpolate(
              mode, internal::ToQuatPose<B>(X0.value), internal::ToQuatPose<B>(X1.value), lambda))};
}

/// Twists of one edge interpolated componentwise.
[[nodiscard]] inline Result<Twist> Interpolate(const Twist& X0, const Twist& X1,
                                               double lambda) noexcept {
  auto s = semantics::Interpolate(X0.semantics, X1.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Twist{*s, X0.linear + lambda * (X1.linear - X0.linear),
               X0.angular + lambda * (X1.angular - X0.angular)};
}

}  // namespace semgraph::coord
