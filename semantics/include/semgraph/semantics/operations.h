// File: semgraph/semantics/operations.h
//
// Every semantic operation of the geometric relations semantics (semantics-research §3; the
// choices are documented in docs/semantics.md), on names only. Each function checks its
// preconditions and returns the result semantics or a Mismatch naming the fields that fail.
// The numbers are computed in semgraph::coord, which calls these first.
//
// Conventions:
//  - compose is natural order only: Compose(X = a wrt b, Y = b wrt c) = a wrt c.
//  - change operations compose with a relation between two entities of one body:
//      ChangePoint(X, A)               A = Position(new point e' wrt old point e), e, e' on X.body
//      ChangeRefPoint(X, A)            A = Position(old ref f wrt new ref f'), f, f' on X.ref_body
//      ChangeOrientationFrame(X, A)    A = Orientation([a'] wrt [a]), both on X.body
//      ChangeRefOrientationFrame(X, A) A = Orientation([b] wrt [b']), both on X.ref_body
//      ChangeCoordinateFrame(X, O)     O = Orientation([old r] wrt [new r]), expressed in [old r]
//                                      or [new r] (its value is then R[new<-old] either way)
//    Twist ChangePoint takes A = Position(old point wrt new point): the twist's velocity
//    reference point moves from A.point to A.ref_point (v' = v + p_A x w).
//  - Orientations (and the orientation part of poses) compose in one of two coordinate forms
//    (CoordinateForm): both operands expressed in the same [r] (operators multiply, M_X M_Y), or
//    the matrix chain, each operand expressed in its own reference orientation frame
//    (R_Y R_X, result expressed in Y's reference frame). The chain form is preferred when both
//    apply (the results are then equal).
//
// Precondition order (what is reported when several fail): the order of the checks in each
// function's comment.
// Cost: every function is O(1), noexcept, allocation-free and string-free.
#pragma once

#include "semgraph/base/expected.h"
#include "semgraph/semantics/export.h"
#include "semgraph/semantics/mismatch.h"
#include "semgraph/semantics/relations.h"

namespace semgraph::semantics {

enum class CoordinateForm : std::uint8_t {
  kSameFrame,  ///< operands share [r]: M = M_X * M_Y, positions add
  kChain,      ///< each operand in its own reference frame: R = R_Y * R_X, p = R_Y p_X + p_Y
};

template <class S>
struct Composition {
  S result;
  CoordinateForm form = CoordinateForm::kSameFrame;
};

template <class S>
using Checked = Expected<S, Mismatch>;

// ---------------------------------------------------------------- Position
/// PositionCoord(e|C, f|D, [r]) -> PositionCoord(f|D, e|C, [r]).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT PositionSemantics
Inverse(const PositionSemantics& X) noexcept;
/// Checks: X.ref_point = Y.point, X.ref_body = Y.body, X.[r] = Y.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PositionSemantics> Compose(
    const PositionSemantics& X, const PositionSemantics& Y) noexcept;
/// Checks: A.ref_point = X.point, A.ref_body = X.body, A.body = X.body, A.[r] = X.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PositionSemantics> ChangePoint(
    const PositionSemantics& X, const PositionSemantics& A) noexcept;
/// Checks: A.point = X.ref_point, A.body = X.ref_body, A.ref_body = X.ref_body, A.[r] = X.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PositionSemantics> ChangeRefPoint(
    const PositionSemantics& X, const PositionSemantics& A) noexcept;
/// Checks: O.orientation = X.[r], O.[r] in {O.orientation, O.ref_orientation}.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PositionSemantics> ChangeCoordinateFrame(
    const PositionSemantics& X, const OrientationSemantics& O) noexcept;

// ---------------------------------------------------------------- Orientation
/// ([a]|C, [b]|D, [r]) -> ([b]|D, [a]|C, [r]); value M^T.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT OrientationSemantics
Inverse(const OrientationSemantics& X) noexcept;
/// The inverse re-expressed in the new reference frame. Checks: X.[r] = X.ref_orientation.
/// ([a]|C, [b]|D, [b]) -> ([b]|D, [a]|C, [a]); value R^T.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<OrientationSemantics> InverseInNewRef(
    const OrientationSemantics& X) noexcept;
/// Checks: X.ref_orientation = Y.orientation, X.ref_body = Y.body, then the coordinate form.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<OrientationSemantics>> Compose(
    const OrientationSemantics& X, const OrientationSemantics& Y) noexcept;
/// Checks: A.ref_orientation = X.orientation, A.ref_body = X.body, A.body = X.body, then the
/// coordinate form of Compose(A, X).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<OrientationSemantics>>
ChangeOrientationFrame(const OrientationSemantics& X, const OrientationSemantics& A) noexcept;
/// Checks: A.orientation = X.ref_orientation, A.body = X.ref_body, A.ref_body = X.ref_body,
/// then the coordinate form of Compose(X, A).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<OrientationSemantics>>
ChangeRefOrientationFrame(const OrientationSemantics& X, const OrientationSemantics& A) noexcept;
/// Checks: O.orientation = X.[r], O.[r] in {O.orientation, O.ref_orientation}.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<OrientationSemantics> ChangeCoordinateFrame(
    const OrientationSemantics& X, const OrientationSemantics& O) noexcept;

// ---------------------------------------------------------------- Pose
/// ((e,[a])|C, (f,[b])|D, [r]) -> ((f,[b])|D, (e,[a])|C, [r]); value (-p, M^T).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT PoseSemantics Inverse(const PoseSemantics& X) noexcept;
/// Checks: X.[r] = X.ref_orientation. Result expressed in X.orientation; value (-R^T p, R^T).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> InverseInNewRef(
    const PoseSemantics& X) noexcept;
/// Checks: X.ref_point = Y.point, X.ref_orientation = Y.orientation, X.ref_body = Y.body, then the
/// coordinate form. Result ((e,[a])|C, (g,[c])|E, Y.[r]).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<PoseSemantics>> Compose(
    const PoseSemantics& X, const PoseSemantics& Y) noexcept;
/// As Position ChangePoint, on the position part; the orientation is unchanged.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> ChangePoint(
    const PoseSemantics& X, const PositionSemantics& A) noexcept;
/// As Position ChangeRefPoint, on the position part.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> ChangeRefPoint(
    const PoseSemantics& X, const PositionSemantics& A) noexcept;
/// As Orientation ChangeOrientationFrame; the position is unchanged.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<PoseSemantics>> ChangeOrientationFrame(
    const PoseSemantics& X, const OrientationSemantics& A) noexcept;
/// As Orientation ChangeRefOrientationFrame. In the chain form the result is expressed in the
/// new reference orientation frame, so the position is re-expressed too (p' = R_A p).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<Composition<PoseSemantics>>
ChangeRefOrientationFrame(const PoseSemantics& X, const OrientationSemantics& A) noexcept;
/// Checks: O.orientation = X.[r], O.[r] in {O.orientation, O.ref_orientation}.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> ChangeCoordinateFrame(
    const PoseSemantics& X, const OrientationSemantics& O) noexcept;
/// The parts of a pose.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT PositionSemantics
PositionOf(const PoseSemantics& X) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT OrientationSemantics
OrientationOf(const PoseSemantics& X) noexcept;
/// Pose(P, O). Checks: P.body = O.body, P.ref_body = O.ref_body, P.[r] = O.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> Combine(
    const PositionSemantics& P, const OrientationSemantics& O) noexcept;

// ---------------------------------------------------------------- Linear / angular velocity
/// (e|C, D, [r]) -> (e|D, C, [r]); value -v.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT LinearVelocitySemantics
Inverse(const LinearVelocitySemantics& X) noexcept;
/// Checks: X.point = Y.point, X.ref_body = Y.body, X.[r] = Y.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<LinearVelocitySemantics> Compose(
    const LinearVelocitySemantics& X, const LinearVelocitySemantics& Y) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<LinearVelocitySemantics> ChangeCoordinateFrame(
    const LinearVelocitySemantics& X, const OrientationSemantics& O) noexcept;

[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT AngularVelocitySemantics
Inverse(const AngularVelocitySemantics& X) noexcept;
/// Checks: X.ref_body = Y.body, X.[r] = Y.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AngularVelocitySemantics> Compose(
    const AngularVelocitySemantics& X, const AngularVelocitySemantics& Y) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<AngularVelocitySemantics> ChangeCoordinateFrame(
    const AngularVelocitySemantics& X, const OrientationSemantics& O) noexcept;

// ---------------------------------------------------------------- Twist
/// (e|C, D, [r]) -> (e|D, C, [r]); value (-v, -w).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT TwistSemantics Inverse(const TwistSemantics& X) noexcept;
/// Checks: X.point = Y.point, X.ref_body = Y.body, X.[r] = Y.[r]. Result (e|X.body, Y.ref_body,
/// [r]).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> Compose(
    const TwistSemantics& X, const TwistSemantics& Y) noexcept;
/// Change of velocity reference point. A = Position(old point e wrt new point f, [r]).
/// Checks: A.point = X.point, A.[r] = X.[r]. Result point f (a point of X.body coinciding with
/// f). A's bodies are not checked: the vector between two points at an instant does not depend
/// on which bodies they are fixed to (docs/semantics.md, decision D3).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> ChangePoint(
    const TwistSemantics& X, const PositionSemantics& A) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> ChangeCoordinateFrame(
    const TwistSemantics& X, const OrientationSemantics& O) noexcept;
/// Screw transform by a pose P = Pose((e,[a]), (f,[b]), [b]) (KDL Frame*Twist).
/// Checks: X.point = P.point, X.[r] = P.orientation, P.[r] = P.ref_orientation.
/// Result (f|X.body, X.ref_body, [b]); value w' = R w, v' = R v + p(e/f) x w'.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> ScrewTransform(
    const TwistSemantics& X, const PoseSemantics& P) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT LinearVelocitySemantics
LinearOf(const TwistSemantics& X) noexcept;
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT AngularVelocitySemantics
AngularOf(const TwistSemantics& X) noexcept;
/// Twist(L, W). Checks: L.body = W.body, L.ref_body = W.ref_body, L.[r] = W.[r].
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> Combine(
    const LinearVelocitySemantics& L, const AngularVelocitySemantics& W) noexcept;

}  // namespace semgraph::semantics
