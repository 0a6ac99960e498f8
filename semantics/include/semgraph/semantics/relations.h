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
//
// Field roles: the unprefixed fields describe what the relation is *of* (point, orientation,
// body), the ref_ fields what it is *relative to*, and coordinate_frame what it is *expressed
// in*. In velocity relations, e|C is the point of C that coincides with e at this instant.
//
// Invariants: none beyond valid ids; any combination of names is a well-formed semantics (an
// identity relation such as a position of e wrt e is legal).
// Cost: plain aggregates of 3..7 ids, trivially copyable, compared field by field.
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

}  // namespace semgraph::semantics
