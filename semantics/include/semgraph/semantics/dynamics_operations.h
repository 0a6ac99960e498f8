// File: semgraph/semantics/dynamics_operations.h
//
// The checked operations of accelerations and wrenches (docs/dynamics.md has the math), on
// names only, like operations.h: each checks its preconditions, in the order its comment lists
// them, and returns the result semantics or a Mismatch naming the first field that fails. The
// numbers are computed in semgraph::coord (coord/operations.h), which calls these first.
//
// Accelerations are classical (a = d2/dt2 of the point of C at e, seen from D; alpha = d/dt of
// omega, seen from D). Their operations need velocities, which are checked too:
//   Inverse(X, V)            V the twist of X's relation at X's point (VelocityOf(X))
//   Compose(X, Y, V_X, W_Y)  X = C rel B, Y = B rel M at one point e in one [r]; V_X = twist of
//                            C rel B at e, W_Y = angular velocity of B rel M (Coriolis terms)
//   ChangePoint(X, A, W)     A = Position(old point wrt new point), as for twists; W = the
//                            angular velocity of X's relation (centripetal term)
//   ChangeCoordinateFrame    as for twists; no velocity needed (a rotation at one instant)
// Wrenches (f, m about e) on C by D:
//   ChangePoint(X, A)        A = Position(old point wrt new point): m' = m + p_A x f
//   ChangeCoordinateFrame(X, O), ScrewTransform(X, P) as for twists
//   Reaction(X)              the wrench on D by C: refused for a sum by several bodies
//   Sum(X, Y)                same body acted on, same point, same frame
//   PowerOf(W, V)            V the twist of W.on relative to W.by, at W's point, in W's frame
//
// Cost: every function is O(1), noexcept, allocation-free and string-free.
#pragma once

#include "semgraph/semantics/export.h"
#include "semgraph/semantics/operations.h"

namespace semgraph::semantics {

// ---------------------------------------------------------------- Acceleration
/// (e|C, D, [r]) -> (e|D, C, [r]); value alpha' = -alpha, a' = -a + 2 w x v.
/// Checks V against X: point, body, ref body, coordinate frame.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AccelerationSemantics> Inverse(
    const AccelerationSemantics& X, const TwistSemantics& V) noexcept;
/// X = (e|C, B, [r]), Y = (e|B, M, [r]) -> (e|C, M, [r]).
/// Checks: X.point = Y.point, X.ref_body = Y.body, X.[r] = Y.[r]; then V_X against X (point,
/// body, ref body, coordinate frame); then W_Y against Y (body, ref body, coordinate frame).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AccelerationSemantics> Compose(
    const AccelerationSemantics& X, const AccelerationSemantics& Y, const TwistSemantics& V_X,
    const AngularVelocitySemantics& W_Y) noexcept;
/// A = Position(old point e wrt new point f, [r]). Checks: A.point = X.point, A.[r] = X.[r]
/// (A's bodies are not checked, as for twists: docs/semantics.md D3); then W against X (body,
/// ref body, coordinate frame). Result point f (the point of X.body coinciding with f).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AccelerationSemantics> ChangePoint(
    const AccelerationSemantics& X, const PositionSemantics& A,
    const AngularVelocitySemantics& W) noexcept;
/// Checks: O.orientation = X.[r], O.[r] in {O.orientation, O.ref_orientation}.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AccelerationSemantics> ChangeCoordinateFrame(
    const AccelerationSemantics& X, const OrientationSemantics& O) noexcept;

// ---------------------------------------------------------------- Wrench
/// A = Position(old point e wrt new point f, [r]). Checks: A.point = X.point, A.[r] = X.[r].
/// Result point f; value m' = m + p_A x f, force unchanged.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<WrenchSemantics> ChangePoint(
    const WrenchSemantics& X, const PositionSemantics& A) noexcept;
/// Checks: O.orientation = X.[r], O.[r] in {O.orientation, O.ref_orientation}.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<WrenchSemantics> ChangeCoordinateFrame(
    const WrenchSemantics& X, const OrientationSemantics& O) noexcept;
/// By a pose P = Pose((e,[a]), (f,[b]), [b]) (KDL Frame*Wrench). Checks: X.point = P.point,
/// X.[r] = P.orientation, P.[r] = P.ref_orientation. Result (f, on, by, [b]); value
/// f' = R f, m' = R m + p(e/f) x f'.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<WrenchSemantics> ScrewTransform(
    const WrenchSemantics& X, const PoseSemantics& P) noexcept;
/// (e|C by D, [r]) -> (e|D by C, [r]); value -(f, m). Checks: X is by one body.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<WrenchSemantics> Reaction(
    const WrenchSemantics& X) noexcept;
/// Checks: X.on = Y.on, X.point = Y.point, X.[r] = Y.[r]. Result on X.on at X.point in X.[r],
/// by X.by when both are by that one body (two parts of one interaction), else by several.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<WrenchSemantics> Sum(
    const WrenchSemantics& X, const WrenchSemantics& Y) noexcept;
/// Checks V against W: V.point = W.point, V.body = W.on, V.ref_body = W.by (W by one body),
/// V.[r] = W.[r]. Result (W.on, W.by).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PowerSemantics> PowerOf(
    const WrenchSemantics& W, const TwistSemantics& V) noexcept;

}  // namespace semgraph::semantics
