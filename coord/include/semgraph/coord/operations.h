// File: semgraph/coord/operations.h
//
// Checked operations on relation values. Every operation, in this order:
//   1. checks the semantics (semgraph::semantics; independent of the backend),
//   2. checks that the backend can represent the result (representation_constraint naming it),
//   3. computes the numbers with the backend's arithmetic.
// So adding a backend never touches a semantic check. Math and preconditions per operation:
// docs/semantics.md. The raw arithmetic (no checks) is in namespace `kernels`, for callers that
// checked the semantics once already (the scene graph's evaluator, core/evaluate.h).
//
// Monograms in comments: X_FE pose of E in F; p_FE position of E wrt F; R_FE rotation.
// Cost: each operation is O(1): a few ids compared, then at most a handful of 3x3 / quaternion
// products. All noexcept, allocation-free, string-free: safe on a real-time path.
#pragma once

#include "semgraph/coord/validate.h"
#include "semgraph/semantics/operations.h"

namespace semgraph::coord {

template <class T>
using Result = base::Expected<T, Error>;

namespace internal {
inline Error SemanticError(const semantics::Mismatch& m) noexcept {
  Error e;
  e.code = m.code;
  e.mismatch = m;
  return e;
}
}  // namespace internal

// ============================================================ kernels (unchecked arithmetic)
namespace kernels {

/// Same-frame form: M = M_X M_Y, p = p_X + p_Y (both in one [r]).
template <Backend B>
typename B::PoseCoords ComposeSameFrame(const typename B::PoseCoords& X,
                                        const typename B::PoseCoords& Y) noexcept {
  return B::MakePose(B::Multiply(B::RotationOf(X), B::RotationOf(Y)),
                     B::TranslationOf(X) + B::TranslationOf(Y));
}
/// Generic inverse, keeps [r]: (M^T, -p).
template <Backend B>
typename B::PoseCoords InverseSameFrame(const typename B::PoseCoords& X) noexcept {
  return B::MakePose(B::Transpose(B::RotationOf(X)), -B::TranslationOf(X));
}
/// Re-express a pose with R = R[new<-old]: p' = R p, M' = R M R^T.
template <Backend B>
typename B::PoseCoords Reexpress(const typename B::PoseCoords& X,
                                 const typename B::Rotation& R) noexcept {
  return B::MakePose(B::Multiply(B::Multiply(R, B::RotationOf(X)), B::Transpose(R)),
                     B::Rotate(R, B::TranslationOf(X)));
}
/// Velocity reference point moved by p_A = (old point wrt new point): v' = v + p_A x w.
inline Eigen::Vector3d ShiftLinear(const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                                   const Eigen::Vector3d& p_A) noexcept {
  return v + p_A.cross(w);
}

}  // namespace kernels

// ============================================================ Position

[[nodiscard]] inline Position Inverse(const Position& X) noexcept {
  return {semantics::Inverse(X.semantics), -X.value};
}

/// p_GE = p_FE + p_GF.
[[nodiscard]] inline Result<Position> Compose(const Position& X, const Position& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Position{*s, X.value + Y.value};
}

/// A = p(e' wrt e): p' = p_A + p.
[[nodiscard]] inline Result<Position> ChangePoint(const Position& X, const Position& A) noexcept {
  auto s = semantics::ChangePoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Position{*s, A.value + X.value};
}

/// A = p(f wrt f'): p' = p + p_A.
[[nodiscard]] inline Result<Position> ChangeRefPoint(const Position& X,
                                                     const Position& A) noexcept {
  auto s = semantics::ChangeRefPoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Position{*s, X.value + A.value};
}

/// O = [old r] wrt [new r]: p' = R[new<-old] p.
template <Backend B>
[[nodiscard]] Result<Position> ChangeCoordinateFrame(const Position& X,
                                                     const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Position{*s, B::Rotate(O.value, X.value)};
}

// ============================================================ Orientation

/// Generic inverse, keeps [r]: M^T.
template <Backend B>
[[nodiscard]] Result<Orientation<B>> Inverse(const Orientation<B>& X) noexcept {
  const auto s = semantics::Inverse(X.semantics);
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s, B::Transpose(X.value)};
}

/// R_AB = R_BA^T, expressed in [a].
template <Backend B>
[[nodiscard]] Result<Orientation<B>> InverseInNewRef(const Orientation<B>& X) noexcept {
  auto s = semantics::InverseInNewRef(X.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{*s, B::Transpose(X.value)};
}

namespace internal {
template <Backend B>
typename B::Rotation ComposeRotations(semantics::CoordinateForm form,
                                      const typename B::Rotation& M_X,
                                      const typename B::Rotation& M_Y) noexcept {
  return form == semantics::CoordinateForm::kChain ? B::Multiply(M_Y, M_X) : B::Multiply(M_X, M_Y);
}
}  // namespace internal

/// Chain: R_CA = R_CB R_BA; same frame: M = M_X M_Y.
template <Backend B>
[[nodiscard]] Result<Orientation<B>> Compose(const Orientation<B>& X,
                                             const Orientation<B>& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s->result, internal::ComposeRotations<B>(s->form, X.value, Y.value)};
}

/// A = [a'] wrt [a]: Compose(A, X).
template <Backend B>
[[nodiscard]] Result<Orientation<B>> ChangeOrientationFrame(const Orientation<B>& X,
                                                            const Orientation<B>& A) noexcept {
  auto s = semantics::ChangeOrientationFrame(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s->result, internal::ComposeRotations<B>(s->form, A.value, X.value)};
}

/// A = [b] wrt [b']: Compose(X, A).
template <Backend B>
[[nodiscard]] Result<Orientation<B>> ChangeRefOrientationFrame(const Orientation<B>& X,
                                                               const Orientation<B>& A) noexcept {
  auto s = semantics::ChangeRefOrientationFrame(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s->result, internal::ComposeRotations<B>(s->form, X.value, A.value)};
}

/// M' = R M R^T with R = R[new<-old].
template <Backend B>
[[nodiscard]] Result<Orientation<B>> ChangeCoordinateFrame(const Orientation<B>& X,
                                                           const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{*s, B::Multiply(B::Multiply(O.value, X.value), B::Transpose(O.value))};
}

// ============================================================ Pose

/// Generic inverse, keeps [r]: (M^T, -p).
template <Backend B>
[[nodiscard]] Result<Pose<B>> Inverse(const Pose<B>& X) noexcept {
  const auto s = semantics::Inverse(X.semantics);
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Pose<B>{s, kernels::InverseSameFrame<B>(X.value)};
}

/// X_AB = X_BA^-1 = (R^T, -R^T p), expressed in [a].
template <Backend B>
[[nodiscard]] Result<Pose<B>> InverseInNewRef(const Pose<B>& X) noexcept {
  auto s = semantics::InverseInNewRef(X.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Pose<B>{*s, B::InvertChain(X.value)};
}

/// Chain: X_CA = X_CB X_BA; same frame: (M_X M_Y, p_X + p_Y).
template <Backend B>
[[nodiscard]] Result<Pose<B>> Compose(const Pose<B>& X, const Pose<B>& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  if (s->form == semantics::CoordinateForm::kChain) {
    return Pose<B>{s->result, B::ComposeChain(X.value, Y.value)};
  }
  return Pose<B>{s->result, kernels::ComposeSameFrame<B>(X.value, Y.value)};
}

/// A = p(e' wrt e) in [r]: p' = p_A + p.
template <Backend B>
[[nodiscard]] Result<Pose<B>> ChangePoint(const Pose<B>& X, const Position& A) noexcept {
  auto s = semantics::ChangePoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Pose<B>{*s, B::MakePose(B::RotationOf(X.value), A.value + B::TranslationOf(X.value))};
}

/// A = p(f wrt f') in [r]: p' = p + p_A.
template <Backend B>
[[nodiscard]] Result<Pose<B>> ChangeRefPoint(const Pose<B>& X, const Position& A) noexcept {
  auto s = semantics::ChangeRefPoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Pose<B>{*s, B::MakePose(B::RotationOf(X.value), B::TranslationOf(X.value) + A.value)};
}

/// A = [a'] wrt [a]: chain R' = R_X R_A; same frame M' = M_A M_X. Position unchanged.
template <Backend B>
[[nodiscard]] Result<Pose<B>> ChangeOrientationFrame(const Pose<B>& X,
                                                     const Orientation<B>& A) noexcept {
  auto s = semantics::ChangeOrientationFrame(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  return Pose<B>{s->result, B::MakePose(internal::ComposeRotations<B>(s->form, A.value,
                                                                      B::RotationOf(X.value)),
                                        B::TranslationOf(X.value))};
}

/// A = [b] wrt [b']: chain R' = R_A R_X and p' = R_A p (now in [b']); same frame M' = M_X M_A.
template <Backend B>
[[nodiscard]] Result<Pose<B>> ChangeRefOrientationFrame(const Pose<B>& X,
                                                        const Orientation<B>& A) noexcept {
  auto s = semantics::ChangeRefOrientationFrame(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(s->result); !ok) return Unexpected{ok.error()};
  const auto M = internal::ComposeRotations<B>(s->form, B::RotationOf(X.value), A.value);
  const Eigen::Vector3d p = s->form == semantics::CoordinateForm::kChain
                                ? B::Rotate(A.value, B::TranslationOf(X.value))
                                : B::TranslationOf(X.value);
  return Pose<B>{s->result, B::MakePose(M, p)};
}

/// O = [old r] wrt [new r]: p' = R p, M' = R M R^T with R = R[new<-old].
template <Backend B>
[[nodiscard]] Result<Pose<B>> ChangeCoordinateFrame(const Pose<B>& X,
                                                    const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Pose<B>{*s, kernels::Reexpress<B>(X.value, O.value)};
}

template <Backend B>
[[nodiscard]] Position PositionOf(const Pose<B>& X) noexcept {
  return {semantics::PositionOf(X.semantics), B::TranslationOf(X.value)};
}

template <Backend B>
[[nodiscard]] Result<Orientation<B>> OrientationOf(const Pose<B>& X) noexcept {
  const auto s = semantics::OrientationOf(X.semantics);
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s, B::RotationOf(X.value)};
}

template <Backend B>
[[nodiscard]] Result<Pose<B>> Combine(const Position& P, const Orientation<B>& O) noexcept {
  auto s = semantics::Combine(P.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  if (auto ok = CheckRepresentation<B>(*s); !ok) return Unexpected{ok.error()};
  return Pose<B>{*s, B::MakePose(O.value, P.value)};
}

// ============================================================ Linear / angular velocity

[[nodiscard]] inline LinearVelocity Inverse(const LinearVelocity& X) noexcept {
  return {semantics::Inverse(X.semantics), -X.value};
}
[[nodiscard]] inline Result<LinearVelocity> Compose(const LinearVelocity& X,
                                                    const LinearVelocity& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return LinearVelocity{*s, X.value + Y.value};
}
template <Backend B>
[[nodiscard]] Result<LinearVelocity> ChangeCoordinateFrame(const LinearVelocity& X,
                                                           const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return LinearVelocity{*s, B::Rotate(O.value, X.value)};
}

[[nodiscard]] inline AngularVelocity Inverse(const AngularVelocity& X) noexcept {
  return {semantics::Inverse(X.semantics), -X.value};
}
[[nodiscard]] inline Result<AngularVelocity> Compose(const AngularVelocity& X,
                                                     const AngularVelocity& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return AngularVelocity{*s, X.value + Y.value};
}
template <Backend B>
[[nodiscard]] Result<AngularVelocity> ChangeCoordinateFrame(const AngularVelocity& X,
                                                            const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return AngularVelocity{*s, B::Rotate(O.value, X.value)};
}

// ============================================================ Twist

/// (e|D, C, [r]): (-v, -w).
[[nodiscard]] inline Twist Inverse(const Twist& X) noexcept {
  return {semantics::Inverse(X.semantics), -X.linear, -X.angular};
}

/// V_E_CE = V_E_CD + V_E_DE at one point, in one frame: sums.
[[nodiscard]] inline Result<Twist> Compose(const Twist& X, const Twist& Y) noexcept {
  auto s = semantics::Compose(X.semantics, Y.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Twist{*s, X.linear + Y.linear, X.angular + Y.angular};
}

/// A = p(old point wrt new point) in [r]: v' = v + p_A x w, w' = w.
[[nodiscard]] inline Result<Twist> ChangePoint(const Twist& X, const Position& A) noexcept {
  auto s = semantics::ChangePoint(X.semantics, A.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Twist{*s, kernels::ShiftLinear(X.linear, X.angular, A.value), X.angular};
}

template <Backend B>
[[nodiscard]] Result<Twist> ChangeCoordinateFrame(const Twist& X,
                                                  const Orientation<B>& O) noexcept {
  auto s = semantics::ChangeCoordinateFrame(X.semantics, O.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Twist{*s, B::Rotate(O.value, X.linear), B::Rotate(O.value, X.angular)};
}

/// P = Pose((e,[a]), (f,[b]), [b]): w' = R w, v' = R v + p(e/f) x w'.
template <Backend B>
[[nodiscard]] Result<Twist> ScrewTransform(const Twist& X, const Pose<B>& P) noexcept {
  auto s = semantics::ScrewTransform(X.semantics, P.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  const auto R = B::RotationOf(P.value);
  const Eigen::Vector3d w = B::Rotate(R, X.angular);
  const Eigen::Vector3d v = B::Rotate(R, X.linear) + B::TranslationOf(P.value).cross(w);
  return Twist{*s, v, w};
}

[[nodiscard]] inline LinearVelocity LinearOf(const Twist& X) noexcept {
  return {semantics::LinearOf(X.semantics), X.linear};
}
[[nodiscard]] inline AngularVelocity AngularOf(const Twist& X) noexcept {
  return {semantics::AngularOf(X.semantics), X.angular};
}
[[nodiscard]] inline Result<Twist> Combine(const LinearVelocity& L,
                                           const AngularVelocity& W) noexcept {
  auto s = semantics::Combine(L.semantics, W.semantics);
  if (!s) return Unexpected{internal::SemanticError(s.error())};
  return Twist{*s, L.value, W.value};
}

}  // namespace semgraph::coord
