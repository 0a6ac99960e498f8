// File: semgraph/semantics/relations.h
//
// Coordinate semantics of the six relations (paper Table I; semantics-research §2): the names a
// relation carries, with the coordinate frame [r] in which its numbers are expressed. No
// numbers here: those live in semgraph::coord.
//
//   PositionSemantics        PositionCoord(e|C, f|D, [r])           vector from f to e
//   OrientationSemantics     OrientationCoord([a]|C, [b]|D, [r])    operator carrying [b] onto [a]
//   PoseSemantics            PoseCoord((e,[a])|C, (f,[b])|D, [r])   position + orientation
//   LinearVelocitySemantics  LinearVelocityCoord(e|C, D, [r])       velocity of e fixed to C, rel.
//   D AngularVelocitySemantics AngularVelocityCoord(C, D, [r])        angular velocity of C rel. D
//   TwistSemantics           TwistCoord(e|C, D, [r])                (v of e|C, omega of C), rel. D
//   AccelerationSemantics    AccelerationCoord(e|C, D, [r])         (a of e|C, alpha of C), rel. D
//   WrenchSemantics          WrenchCoord(e|C, D, [r])               (f, m about e) on C by D
//   PowerSemantics           power delivered to C by D (a scalar: no point, no frame)
//
// Field roles: the unprefixed fields describe what the relation is *of* (point, orientation,
// body), the ref_ fields what it is *relative to*, and coordinate_frame what it is *expressed
// in*. In velocity relations, e|C is the point of C that coincides with e at this instant.
// Accelerations are classical (docs/dynamics.md): a is the second time derivative, taken in D,
// of the position of the point of C at e; alpha the derivative, taken in D, of omega. A wrench
// names the body it acts on (`on`) and the body that exerts it (`by`) instead of a body and a
// reference body; its point e is the point its moment is taken about.
//
// Invariants: none beyond valid ids; any combination of names is a well-formed semantics (an
// identity relation such as a position of e wrt e is legal).
// Cost: plain aggregates of 2..7 ids, trivially copyable, compared field by field.
#pragma once

#include "semgraph/semantics/primitives.h"

namespace semgraph::semantics {

struct PositionSemantics {
  Point point;                        // e
  Body body;                          // C
  Point ref_point;                    // f
  Body ref_body;                      // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const PositionSemantics&, const PositionSemantics&) = default;
};

struct OrientationSemantics {
  OrientationFrame orientation;       // [a]
  Body body;                          // C
  OrientationFrame ref_orientation;   // [b]
  Body ref_body;                      // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const OrientationSemantics&,
                                   const OrientationSemantics&) = default;
};

struct PoseSemantics {
  Point point;                        // e
  OrientationFrame orientation;       // [a]
  Body body;                          // C
  Point ref_point;                    // f
  OrientationFrame ref_orientation;   // [b]
  Body ref_body;                      // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const PoseSemantics&, const PoseSemantics&) = default;

  /// PoseCoord({a}|C, {b}|D, [r]): the frame form.
  [[nodiscard]] static constexpr PoseSemantics OfFrame(Frame a, Body C, Frame b, Body D,
                                                       OrientationFrame r) noexcept {
    return {a.origin(), a.axes(), C, b.origin(), b.axes(), D, r};
  }
  /// True when point = origin of [a] and ref point = origin of [b].
  [[nodiscard]] constexpr bool is_frame_form() const noexcept {
    return IsOriginOf(point, orientation) && IsOriginOf(ref_point, ref_orientation);
  }
  /// True when the frame form is expressed in the reference frame: a scene-graph pose edge.
  [[nodiscard]] constexpr bool is_edge_form() const noexcept {
    return is_frame_form() && coordinate_frame == ref_orientation;
  }
};

struct LinearVelocitySemantics {
  Point point;                        // e (a point of C coinciding with e)
  Body body;                          // C
  Body ref_body;                      // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const LinearVelocitySemantics&,
                                   const LinearVelocitySemantics&) = default;
};

struct AngularVelocitySemantics {
  Body body;                          // C
  Body ref_body;                      // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const AngularVelocitySemantics&,
                                   const AngularVelocitySemantics&) = default;
};

struct TwistSemantics {
  Point point;    // e: velocity reference point (a point of C coinciding with e)
  Body body;      // C
  Body ref_body;  // D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const TwistSemantics&, const TwistSemantics&) = default;

  /// True for a screw (body-fixed) twist at frame {a}: point a, expressed in [a].
  [[nodiscard]] constexpr bool is_screw_twist() const noexcept {
    return IsOriginOf(point, coordinate_frame);
  }
};

struct AccelerationSemantics {
  Point point;    // e: the point of C coinciding with e whose acceleration is `linear`
  Body body;      // C
  Body ref_body;  // D: the derivatives are taken as seen from D
  OrientationFrame coordinate_frame;  // [r]
  friend constexpr bool operator==(const AccelerationSemantics&,
                                   const AccelerationSemantics&) = default;
};

/// The twist of the same relation (same point, bodies, coordinate frame): what the checked
/// acceleration operations need beside the acceleration (omega, and v at e).
[[nodiscard]] constexpr TwistSemantics VelocityOf(const AccelerationSemantics& A) noexcept {
  return {A.point, A.body, A.ref_body, A.coordinate_frame};
}
/// The acceleration of the same relation as a twist.
[[nodiscard]] constexpr AccelerationSemantics AccelerationOf(const TwistSemantics& V) noexcept {
  return {V.point, V.body, V.ref_body, V.coordinate_frame};
}

/// WrenchCoord(e|C, D, [r]): the wrench on C by D, moment about e. A sum of wrenches by
/// different bodies is by several bodies: `by` is then invalid and `by_several` true (such a
/// wrench has no single reaction and no power: both need the one body that exerts it).
struct WrenchSemantics {
  Point point;                        // e: moment reference point
  Body on;                            // C: the body acted on
  Body by;                            // D: the body acting (invalid when by_several)
  OrientationFrame coordinate_frame;  // [r]
  bool by_several = false;            // a sum of wrenches by more than one body
  friend constexpr bool operator==(const WrenchSemantics&, const WrenchSemantics&) = default;
};

/// The power delivered to C by D: f.v + m.omega with the wrench on C by D and the twist of C
/// relative to D at one point in one frame. A scalar: it depends on no point and no frame.
struct PowerSemantics {
  Body on;  // C
  Body by;  // D
  friend constexpr bool operator==(const PowerSemantics&, const PowerSemantics&) = default;
};

}  // namespace semgraph::semantics
