// Accelerations' and wrenches' preconditions. Contract: dynamics_operations.h.
#include "semgraph/semantics/dynamics_operations.h"

#include "checks.h"

namespace semgraph::semantics {
namespace {

using namespace checks;  // NOLINT(google-build-using-namespace): this file's vocabulary

constexpr RK kAcc = RK::kAcceleration;
constexpr RK kWr = RK::kWrench;

// The velocity an acceleration operation is given must be of the acceleration's own relation:
// V against X's point, body, ref body and coordinate frame (X plays `role`).
Checked<Ok> CheckTwistOf(Operation op, Operand role, const AccelerationSemantics& X,
                         const TwistSemantics& V) noexcept {
  constexpr RK t = RK::kTwist;
  if (!(V.point == X.point)) return Fail(op, PointSide(kArgument, t, V), PointSide(role, kAcc, X));
  if (!(V.body == X.body)) return Fail(op, BodySide(kArgument, t, V), BodySide(role, kAcc, X));
  if (!(V.ref_body == X.ref_body))
    return Fail(op, RefBodySide(kArgument, t, V), RefBodySide(role, kAcc, X));
  if (!(V.coordinate_frame == X.coordinate_frame))
    return Fail(op, CoordSide(kArgument, t, V), CoordSide(role, kAcc, X));
  return Ok{};
}

// The angular velocity of X's relation: body, ref body, coordinate frame.
Checked<Ok> CheckAngularOf(Operation op, Operand role, const AccelerationSemantics& X,
                           const AngularVelocitySemantics& W) noexcept {
  constexpr RK w = RK::kAngularVelocity;
  if (!(W.body == X.body)) return Fail(op, BodySide(kArgument, w, W), BodySide(role, kAcc, X));
  if (!(W.ref_body == X.ref_body))
    return Fail(op, RefBodySide(kArgument, w, W), RefBodySide(role, kAcc, X));
  if (!(W.coordinate_frame == X.coordinate_frame))
    return Fail(op, CoordSide(kArgument, w, W), CoordSide(role, kAcc, X));
  return Ok{};
}

// A wrench's fields as mismatch sides: its point is reported with the body it acts on (e|C);
// `by` is the ref-body field, with no name when the wrench is by several bodies.
constexpr MismatchSide WrenchPoint(Operand o, const WrenchSemantics& X) noexcept {
  return Side(o, kWr, Field::kPoint, X.point.id(), X.on.id());
}
constexpr MismatchSide WrenchOn(Operand o, const WrenchSemantics& X) noexcept {
  return Side(o, kWr, Field::kBody, X.on.id());
}
constexpr MismatchSide WrenchBy(Operand o, const WrenchSemantics& X) noexcept {
  return Side(o, kWr, Field::kRefBody, X.by_several ? NameId() : X.by.id());
}

}  // namespace

// ============================================================== Acceleration

Checked<AccelerationSemantics> Inverse(const AccelerationSemantics& X,
                                       const TwistSemantics& V) noexcept {
  if (auto ok = CheckTwistOf(Operation::kInverse, kSubject, X, V); !ok)
    return Unexpected{ok.error()};
  return AccelerationSemantics{X.point, X.ref_body, X.body, X.coordinate_frame};
}

Checked<AccelerationSemantics> Compose(const AccelerationSemantics& X,
                                       const AccelerationSemantics& Y, const TwistSemantics& V_X,
                                       const AngularVelocitySemantics& W_Y) noexcept {
  constexpr Operation op = Operation::kCompose;
  if (!(X.point == Y.point))
    return Fail(op, PointSide(kFirst, kAcc, X), PointSide(kSecond, kAcc, Y));
  if (!(X.ref_body == Y.body))
    return Fail(op, RefBodySide(kFirst, kAcc, X), BodySide(kSecond, kAcc, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame))
    return Fail(op, CoordSide(kFirst, kAcc, X), CoordSide(kSecond, kAcc, Y));
  if (auto ok = CheckTwistOf(op, kFirst, X, V_X); !ok) return Unexpected{ok.error()};
  if (auto ok = CheckAngularOf(op, kSecond, Y, W_Y); !ok) return Unexpected{ok.error()};
  return AccelerationSemantics{X.point, X.body, Y.ref_body, X.coordinate_frame};
}

Checked<AccelerationSemantics> ChangePoint(const AccelerationSemantics& X,
                                           const PositionSemantics& A,
                                           const AngularVelocitySemantics& W) noexcept {
  constexpr Operation op = Operation::kChangePoint;
  if (!(A.point == X.point))
    return Fail(op, PointSide(kArgument, RK::kPosition, A), PointSide(kSubject, kAcc, X));
  if (!(A.coordinate_frame == X.coordinate_frame))
    return Fail(op, CoordSide(kArgument, RK::kPosition, A), CoordSide(kSubject, kAcc, X));
  if (auto ok = CheckAngularOf(op, kSubject, X, W); !ok) return Unexpected{ok.error()};
  AccelerationSemantics r = X;
  r.point = A.ref_point;
  return r;
}

Checked<AccelerationSemantics> ChangeCoordinateFrame(const AccelerationSemantics& X,
                                                     const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, kAcc, O);
  if (!r_new) return Unexpected{r_new.error()};
  AccelerationSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

// ============================================================== Wrench

Checked<WrenchSemantics> ChangePoint(const WrenchSemantics& X,
                                     const PositionSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangePoint;
  if (!(A.point == X.point))
    return Fail(op, PointSide(kArgument, RK::kPosition, A), WrenchPoint(kSubject, X));
  if (!(A.coordinate_frame == X.coordinate_frame))
    return Fail(op, CoordSide(kArgument, RK::kPosition, A), CoordSide(kSubject, kWr, X));
  WrenchSemantics r = X;
  r.point = A.ref_point;
  return r;
}

Checked<WrenchSemantics> ChangeCoordinateFrame(const WrenchSemantics& X,
                                               const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, kWr, O);
  if (!r_new) return Unexpected{r_new.error()};
  WrenchSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

Checked<WrenchSemantics> ScrewTransform(const WrenchSemantics& X, const PoseSemantics& P) noexcept {
  constexpr Operation op = Operation::kScrewTransform;
  if (!(P.point == X.point))
    return Fail(op, PointSide(kArgument, RK::kPose, P), WrenchPoint(kSubject, X));
  if (!(P.orientation == X.coordinate_frame))
    return Fail(op, OrientationSide(kArgument, RK::kPose, P), CoordSide(kSubject, kWr, X));
  if (!(P.coordinate_frame == P.ref_orientation)) {
    return Fail(op, CoordSide(kArgument, RK::kPose, P),
                RefOrientationSide(kArgument, RK::kPose, P));
  }
  WrenchSemantics r = X;
  r.point = P.ref_point;
  r.coordinate_frame = P.ref_orientation;
  return r;
}

Checked<WrenchSemantics> Reaction(const WrenchSemantics& X) noexcept {
  if (X.by_several) return Fail(Operation::kReaction, WrenchBy(kSubject, X), WrenchOn(kSubject, X));
  return WrenchSemantics{X.point, X.by, X.on, X.coordinate_frame, false};
}

Checked<WrenchSemantics> Sum(const WrenchSemantics& X, const WrenchSemantics& Y) noexcept {
  constexpr Operation op = Operation::kSum;
  if (!(X.on == Y.on)) return Fail(op, WrenchOn(kFirst, X), WrenchOn(kSecond, Y));
  if (!(X.point == Y.point)) return Fail(op, WrenchPoint(kFirst, X), WrenchPoint(kSecond, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame))
    return Fail(op, CoordSide(kFirst, kWr, X), CoordSide(kSecond, kWr, Y));
  const bool one = !X.by_several && !Y.by_several && X.by == Y.by;
  return WrenchSemantics{X.point, X.on, one ? X.by : Body(), X.coordinate_frame, !one};
}

Checked<PowerSemantics> PowerOf(const WrenchSemantics& W, const TwistSemantics& V) noexcept {
  constexpr Operation op = Operation::kPower;
  constexpr RK t = RK::kTwist;
  if (!(V.point == W.point)) return Fail(op, PointSide(kArgument, t, V), WrenchPoint(kSubject, W));
  if (!(V.body == W.on)) return Fail(op, BodySide(kArgument, t, V), WrenchOn(kSubject, W));
  if (W.by_several || !(V.ref_body == W.by))
    return Fail(op, RefBodySide(kArgument, t, V), WrenchBy(kSubject, W));
  if (!(V.coordinate_frame == W.coordinate_frame))
    return Fail(op, CoordSide(kArgument, t, V), CoordSide(kSubject, kWr, W));
  return PowerSemantics{W.on, W.by};
}

}  // namespace semgraph::semantics
