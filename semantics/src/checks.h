// Private to the semantics layer: the helpers every checked operation builds its Mismatch with
// (operations.cc, dynamics_operations.cc), so that a field is reported the same way everywhere.
// Cost: O(1), constexpr where possible, noexcept.
#pragma once

#include "semgraph/semantics/operations.h"

namespace semgraph::semantics::checks {

using RK = RelationKind;

constexpr MismatchSide Side(Operand operand, RK relation, Field field, NameId name,
                            NameId body = NameId()) noexcept {
  return {operand, relation, field, name, body};
}

constexpr Unexpected<Mismatch> Fail(Operation op, MismatchSide lhs, MismatchSide rhs,
                                    bool coordinate_forms = false) noexcept {
  return Unexpected{Mismatch{ErrorCode::kSemanticMismatch, op, lhs, rhs, coordinate_forms}};
}

// Field accessors that also know the body a field's point/orientation frame is fixed to, so that
// a message can say "f|D" rather than "f".
template <class S>
constexpr MismatchSide PointSide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kPoint, s.point.id(), s.body.id());
}
template <class S>
constexpr MismatchSide RefPointSide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kRefPoint, s.ref_point.id(), s.ref_body.id());
}
template <class S>
constexpr MismatchSide OrientationSide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kOrientation, s.orientation.id(), s.body.id());
}
template <class S>
constexpr MismatchSide RefOrientationSide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kRefOrientation, s.ref_orientation.id(), s.ref_body.id());
}
template <class S>
constexpr MismatchSide BodySide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kBody, s.body.id());
}
template <class S>
constexpr MismatchSide RefBodySide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kRefBody, s.ref_body.id());
}
template <class S>
constexpr MismatchSide CoordSide(Operand o, RK k, const S& s) noexcept {
  return Side(o, k, Field::kCoordinateFrame, s.coordinate_frame.id());
}

constexpr Operand kFirst = Operand::kFirst;
constexpr Operand kSecond = Operand::kSecond;
constexpr Operand kSubject = Operand::kSubject;
constexpr Operand kArgument = Operand::kArgument;

// The coordinate-frame argument of every ChangeCoordinateFrame: O = Orientation([old r] wrt
// [new r]) expressed in [old r] or [new r]. Returns the new coordinate frame.
template <class S>
Checked<OrientationFrame> CheckCoordinateChange(const S& X, RK kind,
                                                const OrientationSemantics& O) noexcept {
  if (!(O.orientation == X.coordinate_frame)) {
    return Fail(Operation::kChangeCoordinateFrame, OrientationSide(kArgument, RK::kOrientation, O),
                CoordSide(kSubject, kind, X));
  }
  if (!(O.coordinate_frame == O.orientation) && !(O.coordinate_frame == O.ref_orientation)) {
    return Fail(Operation::kChangeCoordinateFrame, CoordSide(kArgument, RK::kOrientation, O),
                RefOrientationSide(kArgument, RK::kOrientation, O));
  }
  return O.ref_orientation;
}

}  // namespace semgraph::semantics::checks
