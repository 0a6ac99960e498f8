// File: semgraph/semantics/mismatch.h
//
// Mismatch: why a semantic operation was refused, as a small trivially copyable value (no
// strings: it is produced on query paths). It names the operation, the two fields that had to
// match, and their names (and bodies); Describe() in describe.h turns it into
//   "compose: reference point f|D of the first does not match point g|D of the second".
// Cost: 32 bytes, O(1) to build and copy.
#pragma once

#include <cstdint>

#include "semgraph/base/error_code.h"
#include "semgraph/semantics/names.h"

namespace semgraph::semantics {

enum class Operation : std::uint8_t {
  kCompose,
  kInverseInNewRef,
  kChangePoint,
  kChangeRefPoint,
  kChangeOrientationFrame,
  kChangeRefOrientationFrame,
  kChangeCoordinateFrame,
  kScrewTransform,
  kCombine,  // Pose(Position, Orientation) or Twist(LinearVelocity, AngularVelocity)
  // Time (time_operations.h): integration, differentiation, interpolation of an edge's motion.
  kIntegrate,
  kDifferentiate,
  kInterpolate,
  // Dynamics (dynamics_operations.h): accelerations and wrenches.
  kInverse,   // an acceleration's inverse relation (needs the twist: not a plain negation)
  kReaction,  // the wrench on D by C from the one on C by D
  kSum,       // wrenches on one body at one point in one frame
  kPower,     // a wrench with a twist
};

enum class RelationKind : std::uint8_t {
  kPosition,
  kOrientation,
  kPose,
  kLinearVelocity,
  kAngularVelocity,
  kTwist,
  kAcceleration,
  kWrench,
};

/// The fields of every relation. A wrench reuses kBody for the body it acts on and kRefBody for
/// the body that exerts it (Describe says "on body" and "by body" for a wrench).
enum class Field : std::uint8_t {
  kPoint,
  kOrientation,
  kBody,
  kRefPoint,
  kRefOrientation,
  kRefBody,
  kCoordinateFrame,
};

/// Which operand a field belongs to: the first/second operand of a compose or combine, or the
/// subject / argument of a change operation (X.ChangePoint(A): X is the subject, A the argument).
enum class Operand : std::uint8_t { kFirst, kSecond, kSubject, kArgument };

struct MismatchSide {
  Operand operand = Operand::kFirst;
  RelationKind relation = RelationKind::kPose;
  Field field = Field::kPoint;
  NameId name;  ///< the point / orientation frame / body / coordinate frame named by `field`
  NameId body;  ///< body the point or orientation frame is fixed to (invalid when not applicable)
};

struct Mismatch {
  ErrorCode code = ErrorCode::kSemanticMismatch;
  Operation operation = Operation::kCompose;
  MismatchSide lhs;  ///< "<lhs> does not match <rhs>"
  MismatchSide rhs;
  /// For pose/orientation compose: neither the same coordinate frame nor the matrix chain form.
  bool coordinate_forms = false;
};

}  // namespace semgraph::semantics
