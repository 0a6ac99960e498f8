// File: semgraph/semantics/time_operations.h
//
// Preconditions of the time operations on one pose edge's motion (coord/se3.h does the
// numbers). A pose edge {t}|T -> {h}|H stores X = PoseCoord({h}|H, {t}|T, [t]) (the edge form);
// its body-fixed (screw) twist is xi = TwistCoord(h|H, T, [h]). The three operations are
// semantic operations like every other one:
//   Integrate(X, xi)        X * Exp(dt * xi): xi must be the screw twist of that very edge
//   Differentiate(X0, X1)   Log(X0^-1 X1) / dt: both the same edge; result xi's semantics
//   Interpolate(X0, X1)     a motion between two samples of the same edge
// Integration and differentiation need the edge form (X^-1 dX is a body-fixed twist only for a
// chain-form pose); interpolation needs only equal semantics (linear interpolation of (p, M)
// is form-independent), the screw form requires the edge form (InterpolateScrew).
// Cost: O(1) id comparisons; noexcept, allocation-free.
#pragma once

#include "semgraph/semantics/export.h"
#include "semgraph/semantics/operations.h"

namespace semgraph::semantics {

/// The screw twist semantics of an edge-form pose: TwistCoord(h|H, T, [h]). X must be in edge
/// form (not checked here; EdgeScrewTwist is used by the checked operations below).
[[nodiscard]] constexpr TwistSemantics EdgeScrewTwist(const PoseSemantics& X) noexcept {
  return TwistSemantics{X.point, X.body, X.ref_body, X.orientation};
}

/// Checks: X in edge form (point = origin of [a], ref point = origin of [b], [r] = [b]).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> RequireEdgeForm(
    Operation op, const PoseSemantics& X) noexcept;

/// Checks: X in edge form; xi = EdgeScrewTwist(X) field by field. Result: X's semantics.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> Integrate(
    const PoseSemantics& X, const TwistSemantics& xi) noexcept;

/// Checks: X0 == X1 (field by field), edge form. Result: EdgeScrewTwist(X0).
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> Differentiate(
    const PoseSemantics& X0, const PoseSemantics& X1) noexcept;

/// Checks: X0 == X1 field by field; with `screw`, also the edge form. Result: X0's semantics.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<PoseSemantics> Interpolate(const PoseSemantics& X0,
                                                                           const PoseSemantics& X1,
                                                                           bool screw) noexcept;

/// Twists of one edge interpolated componentwise: X0 == X1. Result: X0's semantics.
[[nodiscard]] SEMGRAPH_SEMANTICS_EXPORT Checked<TwistSemantics> Interpolate(
    const TwistSemantics& X0, const TwistSemantics& X1) noexcept;

}  // namespace semgraph::semantics
