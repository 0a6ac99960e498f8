#include "semgraph/semantics/describe.h"

#include <array>
#include <string>

namespace semgraph::semantics {
namespace {

std::string Str(const NameTable& names, NameId id) { return std::string(names.name(id)); }
std::string Pt(const NameTable& n, Point e, Body C) {
  return Str(n, e.id()) + "|" + Str(n, C.id());
}
std::string Of(const NameTable& n, OrientationFrame a) { return "[" + Str(n, a.id()) + "]"; }
std::string OfB(const NameTable& n, OrientationFrame a, Body C) {
  return Of(n, a) + "|" + Str(n, C.id());
}

}  // namespace

std::string_view FieldName(Field f) noexcept {
  switch (f) {
    case Field::kPoint:
      return "point";
    case Field::kOrientation:
      return "orientation frame";
    case Field::kBody:
      return "body";
    case Field::kRefPoint:
      return "reference point";
    case Field::kRefOrientation:
      return "reference orientation frame";
    case Field::kRefBody:
      return "reference body";
    case Field::kCoordinateFrame:
      return "coordinate frame";
  }
  return "field";
}

namespace {

std::string_view RelationName(RelationKind k) noexcept {
  switch (k) {
    case RelationKind::kPosition:
      return "position";
    case RelationKind::kOrientation:
      return "orientation";
    case RelationKind::kPose:
      return "pose";
    case RelationKind::kLinearVelocity:
      return "linear velocity";
    case RelationKind::kAngularVelocity:
      return "angular velocity";
    case RelationKind::kTwist:
      return "twist";
    case RelationKind::kAcceleration:
      return "acceleration";
    case RelationKind::kWrench:
      return "wrench";
  }
  return "relation";
}

}  // namespace

namespace {
// A wrench names its bodies by their roles in the interaction: on C, by D.
std::string_view SideFieldName(const MismatchSide& s) noexcept {
  if (s.relation == RelationKind::kWrench && s.field == Field::kBody) return "on body";
  if (s.relation == RelationKind::kWrench && s.field == Field::kRefBody) return "by body";
  return FieldName(s.field);
}
}  // namespace

std::string Describe(const MismatchSide& s, const NameTable& names) {
  std::string value;
  switch (s.field) {
    case Field::kPoint:
    case Field::kRefPoint:
      value = Str(names, s.name);
      break;
    case Field::kOrientation:
    case Field::kRefOrientation:
    case Field::kCoordinateFrame:
      value = "[" + Str(names, s.name) + "]";
      break;
    case Field::kBody:
    case Field::kRefBody:
      // A wrench by several bodies (a sum) has no by body: the one body field that may be empty.
      value = s.relation == RelationKind::kWrench && !s.name.is_valid()
                  ? std::string("(several bodies)")
                  : Str(names, s.name);
      break;
  }
  if (s.body.is_valid()) value += "|" + Str(names, s.body);
  std::string owner;
  switch (s.operand) {
    case Operand::kFirst:
      owner = "the first";
      break;
    case Operand::kSecond:
      owner = "the second";
      break;
    case Operand::kSubject:
      owner = "the " + std::string(RelationName(s.relation));
      break;
    case Operand::kArgument:
      owner = "the argument " + std::string(RelationName(s.relation));
      break;
  }
  return std::string(SideFieldName(s)) + " " + value + " of " + owner;
}

std::string_view ToString(Operation op) noexcept {
  switch (op) {
    case Operation::kCompose:
      return "compose";
    case Operation::kInverseInNewRef:
      return "inverse_in_new_ref";
    case Operation::kChangePoint:
      return "change_point";
    case Operation::kChangeRefPoint:
      return "change_ref_point";
    case Operation::kChangeOrientationFrame:
      return "change_orientation_frame";
    case Operation::kChangeRefOrientationFrame:
      return "change_ref_orientation_frame";
    case Operation::kChangeCoordinateFrame:
      return "change_coordinate_frame";
    case Operation::kScrewTransform:
      return "screw_transform";
    case Operation::kCombine:
      return "combine";
    case Operation::kIntegrate:
      return "integrate";
    case Operation::kDifferentiate:
      return "differentiate";
    case Operation::kInterpolate:
      return "interpolate";
    case Operation::kInverse:
      return "inverse";
    case Operation::kReaction:
      return "reaction";
    case Operation::kSum:
      return "sum";
    case Operation::kPower:
      return "power";
  }
  return "operation";
}

std::string Describe(const Mismatch& m, const NameTable& names) {
  if (m.operation == Operation::kReaction) {  // its one refusal: no single body to act on
    return "reaction: the wrench on " + Str(names, m.rhs.name) +
           " is a sum of wrenches by several bodies, which has no single reaction";
  }
  std::string text = std::string(ToString(m.operation)) + ": " + Describe(m.lhs, names) +
                     " does not match " + Describe(m.rhs, names);
  if (m.coordinate_forms) {
    text += ", and the two are not each expressed in their own reference orientation frame";
  }
  return text;
}

std::string Describe(const PositionSemantics& s, const NameTable& n) {
  return "PositionCoord(" + Pt(n, s.point, s.body) + ", " + Pt(n, s.ref_point, s.ref_body) + ", " +
         Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const OrientationSemantics& s, const NameTable& n) {
  return "OrientationCoord(" + OfB(n, s.orientation, s.body) + ", " +
         OfB(n, s.ref_orientation, s.ref_body) + ", " + Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const PoseSemantics& s, const NameTable& n) {
  auto part = [&](Point e, OrientationFrame a, Body C) {
    if (IsOriginOf(e, a)) return "{" + Str(n, e.id()) + "}|" + Str(n, C.id());
    return "(" + Str(n, e.id()) + "," + Of(n, a) + ")|" + Str(n, C.id());
  };
  return "PoseCoord(" + part(s.point, s.orientation, s.body) + ", " +
         part(s.ref_point, s.ref_orientation, s.ref_body) + ", " + Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const LinearVelocitySemantics& s, const NameTable& n) {
  return "LinearVelocityCoord(" + Pt(n, s.point, s.body) + ", " + Str(n, s.ref_body.id()) + ", " +
         Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const AngularVelocitySemantics& s, const NameTable& n) {
  return "AngularVelocityCoord(" + Str(n, s.body.id()) + ", " + Str(n, s.ref_body.id()) + ", " +
         Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const TwistSemantics& s, const NameTable& n) {
  return "TwistCoord(" + Pt(n, s.point, s.body) + ", " + Str(n, s.ref_body.id()) + ", " +
         Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const AccelerationSemantics& s, const NameTable& n) {
  return "AccelerationCoord(" + Pt(n, s.point, s.body) + ", " + Str(n, s.ref_body.id()) + ", " +
         Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const WrenchSemantics& s, const NameTable& n) {
  const std::string by = s.by_several ? std::string("several") : Str(n, s.by.id());
  return "WrenchCoord(" + Pt(n, s.point, s.on) + ", " + by + ", " + Of(n, s.coordinate_frame) + ")";
}

std::string Describe(const PowerSemantics& s, const NameTable& n) {
  return "Power(" + Str(n, s.on.id()) + ", " + Str(n, s.by.id()) + ")";
}

}  // namespace semgraph::semantics
