// File: semgraph/coord/dynamics_operations.h
//
// Checked operations on accelerations and wrenches (semantics: semantics/dynamics_operations.h;
// the math: docs/dynamics.md). As in operations.h, each operation checks the semantics first
// (semgraph::semantics), then computes the numbers; accelerations and wrenches are 3-vector
// pairs in every backend, so only the changes of coordinate frame depend on the backend (its
// rotation). The raw arithmetic is in namespace `kernels`, for callers that checked the
// semantics once already (the scene graph's evaluator).
//
// Monograms (docs/notation.md): A_DCe_R = (a_DCe_R, alpha_DC_R) the acceleration of C relative to
// D at (the point of C at) e in [r], a_DCe the classical acceleration of that point; V_DCe_R the
// twist; F_DCe_R = (f_DC_R, m_DCe_R) the wrench on C by D about e, so that the power is
// F_DCe_R . V_DCe_R, letters matching.
// Cost: O(1), a few cross products; noexcept, allocation-free, string-free (real-time safe).
#pragma once

#include "semgraph/coord/operations.h"
#include "semgraph/semantics/dynamics_operations.h"

namespace semgraph::coord {

// ============================================================ kernels (unchecked arithmetic)
namespace kernels {

/// The point of C at old point p -> the point of C at new point q, with p_A = p - q (old point
/// wrt new point, as for twists): a_q = a_p + alpha x (q - p) + w x (w x (q - p)).
inline Eigen::Vector3d ShiftAcceleration(const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                                         const Eigen::Vector3d& w,
                                         const Eigen::Vector3d& p_A) noexcept {
  return a + p_A.cross(alpha) - w.cross(w.cross(p_A));
}

/// X = C rel B, Y = B rel M at one point e in one frame; v_X, w_X the twist of X at e, w_Y the
/// angular velocity of Y: alpha = alpha_Y + alpha_X + w_Y x w_X, a = a_Y + a_X + 2 w_Y x v_X.
struct AccelerationPair {
  Eigen::Vector3d linear;
  Eigen::Vector3d angular;
};
inline AccelerationPair ComposeAccelerations(const Eigen::Vector3d& a_X,
                                             const Eigen::Vector3d& alpha_X,
                                             const Eigen::Vector3d& a_Y,
                                             const Eigen::Vector3d& alpha_Y,
                                             const Eigen::Vector3d& v_X, const Eigen::Vector3d& w_X,
                                             const Eigen::Vector3d& w_Y) noexcept {
  return {a_Y + a_X + 2.0 * w_Y.cross(v_X), alpha_Y + alpha_X + w_Y.cross(w_X)};
}

/// The inverse relation at the same point: alpha' = -alpha, a' = -a + 2 w x v (v, w the twist of
/// the relation inverted, at that point).
inline AccelerationPair InvertAcceleration(const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                                           const Eigen::Vector3d& v,
                                           const Eigen::Vector3d& w) noexcept {
  return {-a + 2.0 * w.cross(v), -alpha};
}

/// Moment about the new point q, p_A = p - q: m_q = m_p + (p - q) x f (the dual of ShiftLinear).
inline Eigen::Vector3d ShiftMoment(const Eigen::Vector3d& m, const Eigen::Vector3d& f,
                                   const Eigen::Vector3d& p_A) noexcept {
  return ShiftLinear(m, f, p_A);
}

}  // namespace kernels

// ============================================================ Acceleration

/// (e|D, C, [r]): alpha' = -alpha, a' = -a + 2 w x v, with V the twist of X at e.
[[nodiscard]] inline Result<Acceleration> Inverse(const Acceleration& X, const Twist& V) noexcept {
  auto s = semantics::Inverse(X.semantics, V.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  const auto r = kernels::InvertAcceleration(X.linear, X.angular, V.linear, V.angular);
  return Acceleration{*s, r.linear, r.angular};
}

/// A_MC = A_MB (Y) composed with A_BC (X) at e: alpha_MC = alpha_MB + alpha_BC + w_MB x w_BC,
/// a_MCe = a_MBe + a_BCe + 2 w_MB x v_BCe. V_X = V_BCe, W_Y = w_MB.
[[nodiscard]] inline Result<Acceleration> Compose(const Acceleration& X, const Acceleration& Y,
                                                  const Twist& V_X,
                                                  const AngularVelocity& W_Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics, V_X.semantics, W_Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  const auto r = kernels::ComposeAccelerations(X.linear, X.angular, Y.linear, Y.angular, V_X.linear,
                                               V_X.angular, W_Y.value);
  return Acceleration{*s, r.linear, r.angular};
}

/// A = p(old point wrt new point) in [r], W = w of X's relation:
/// a' = a + p_A x alpha - w x (w x p_A), alpha' = alpha.
[[nodiscard]] inline Result<Acceleration> ChangePoint(const Acceleration& X, const Position& A,
                                                      const AngularVelocity& W) noexcept {
  auto s = semantics::ChangePoint(X.semantics, A.semantics, W.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Acceleration{*s, kernels::ShiftAcceleration(X.linear, X.angular, W.value, A.value),
                      X.angular};
}

/// O = [old r] wrt [new r]: both vectors rotated by R[new<-old].
template <Backend B>
[[nodiscard]] Result<Acceleration> ChangeCoordinateFrame(const Acceleration& X,
                                                         const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Acceleration{*s, B::Rotate(O.value, X.linear), B::Rotate(O.value, X.angular)};
}

// ============================================================ Wrench

/// A = p(old point wrt new point) in [r]: m' = m + p_A x f, f' = f.
[[nodiscard]] inline Result<Wrench> ChangePoint(const Wrench& X, const Position& A) noexcept {
  auto s = semantics::ChangePoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Wrench{*s, X.force, kernels::ShiftMoment(X.moment, X.force, A.value)};
}

/// O = [old r] wrt [new r]: f and m rotated by R[new<-old].
template <Backend B>
[[nodiscard]] Result<Wrench> ChangeCoordinateFrame(const Wrench& X,
                                                   const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Wrench{*s, B::Rotate(O.value, X.force), B::Rotate(O.value, X.moment)};
}

/// P = Pose((e,[a]), (f,[b]), [b]) (KDL Frame*Wrench): f' = R f, m' = R m + p(e/f) x f'.
template <Backend B>
[[nodiscard]] Result<Wrench> ScrewTransform(const Wrench& X, const Pose<B>& P) noexcept {
  auto s = semantics::ScrewTransform(X.semantics, P.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  const auto R = B::RotationOf(P.value);
  const Eigen::Vector3d f = B::Rotate(R, X.force);
  return Wrench{*s, f, kernels::ShiftMoment(B::Rotate(R, X.moment), f, B::TranslationOf(P.value))};
}

/// The wrench on D by C: -(f, m), same point, same frame.
[[nodiscard]] inline Result<Wrench> Reaction(const Wrench& X) noexcept {
  auto s = semantics::Reaction(X.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Wrench{*s, -X.force, -X.moment};
}

/// Same body acted on, same point, same frame: (f_X + f_Y, m_X + m_Y).
[[nodiscard]] inline Result<Wrench> Sum(const Wrench& X, const Wrench& Y) noexcept {
  auto s = semantics::Sum(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Wrench{*s, X.force + Y.force, X.moment + Y.moment};
}

/// f.v + m.w with V the twist of W.on relative to W.by at W's point in W's frame.
[[nodiscard]] inline Result<Power> PowerOf(const Wrench& W, const Twist& V) noexcept {
  auto s = semantics::PowerOf(W.semantics, V.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Power{*s, W.force.dot(V.linear) + W.moment.dot(V.angular)};
}

}  // namespace semgraph::coord
