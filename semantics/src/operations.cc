// Semantic operations: precondition checks and result semantics. See operations.h for the
// contract and docs/semantics.md for the math and the decisions.
#include "semgraph/semantics/operations.h"

#include "checks.h"

namespace semgraph::semantics {
namespace {

using namespace checks;  // NOLINT(google-build-using-namespace): this file's vocabulary

// The coordinate form of an orientation composition of X (a wrt b, in rX) with Y (b wrt c, in
// rY). Chain first: it is the edge form, and when both forms apply they agree.
template <class S>
Checked<CoordinateForm> CompositionForm(Operation op, Operand x_role, RK x_kind, const S& X,
                                        Operand y_role, RK y_kind, const S& Y) noexcept {
  if (X.coordinate_frame == X.ref_orientation && Y.coordinate_frame == Y.ref_orientation) {
    return CoordinateForm::kChain;
  }
  if (X.coordinate_frame == Y.coordinate_frame) return CoordinateForm::kSameFrame;
  return Fail(op, CoordSide(x_role, x_kind, X), CoordSide(y_role, y_kind, Y),
              /*coordinate_forms=*/true);
}

// Result coordinate frame of a composition in the given form: Y's frame in both forms.
template <class S>
constexpr OrientationFrame ComposedFrame(const S& /*X*/, const S& Y) noexcept {
  return Y.coordinate_frame;
}

}  // namespace

// ============================================================== Position

PositionSemantics Inverse(const PositionSemantics& X) noexcept {
  return {X.ref_point, X.ref_body, X.point, X.body, X.coordinate_frame};
}

namespace {
Checked<PositionSemantics> ComposePositions(Operation op, Operand x_role,
                                            const PositionSemantics& X, Operand y_role,
                                            const PositionSemantics& Y) noexcept {
  constexpr RK k = RK::kPosition;
  if (!(X.ref_point == Y.point))
    return Fail(op, RefPointSide(x_role, k, X), PointSide(y_role, k, Y));
  if (!(X.ref_body == Y.body)) return Fail(op, RefBodySide(x_role, k, X), BodySide(y_role, k, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame)) {
    return Fail(op, CoordSide(x_role, k, X), CoordSide(y_role, k, Y));
  }
  return PositionSemantics{X.point, X.body, Y.ref_point, Y.ref_body, X.coordinate_frame};
}

// Shared by Position and Pose: A relates the new point to the old point on X's body.
template <class S>
Checked<Ok> CheckChangePoint(const S& X, RK kind, const PositionSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangePoint;
  constexpr RK a = RK::kPosition;
  if (!(A.ref_point == X.point))
    return Fail(op, RefPointSide(kArgument, a, A), PointSide(kSubject, kind, X));
  if (!(A.ref_body == X.body))
    return Fail(op, RefBodySide(kArgument, a, A), BodySide(kSubject, kind, X));
  if (!(A.body == X.body)) return Fail(op, BodySide(kArgument, a, A), BodySide(kSubject, kind, X));
  if (!(A.coordinate_frame == X.coordinate_frame)) {
    return Fail(op, CoordSide(kArgument, a, A), CoordSide(kSubject, kind, X));
  }
  return Ok{};
}

template <class S>
Checked<Ok> CheckChangeRefPoint(const S& X, RK kind, const PositionSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangeRefPoint;
  constexpr RK a = RK::kPosition;
  if (!(A.point == X.ref_point))
    return Fail(op, PointSide(kArgument, a, A), RefPointSide(kSubject, kind, X));
  if (!(A.body == X.ref_body))
    return Fail(op, BodySide(kArgument, a, A), RefBodySide(kSubject, kind, X));
  if (!(A.ref_body == X.ref_body))
    return Fail(op, RefBodySide(kArgument, a, A), RefBodySide(kSubject, kind, X));
  if (!(A.coordinate_frame == X.coordinate_frame)) {
    return Fail(op, CoordSide(kArgument, a, A), CoordSide(kSubject, kind, X));
  }
  return Ok{};
}
}  // namespace

Checked<PositionSemantics> Compose(const PositionSemantics& X,
                                   const PositionSemantics& Y) noexcept {
  return ComposePositions(Operation::kCompose, kFirst, X, kSecond, Y);
}

Checked<PositionSemantics> ChangePoint(const PositionSemantics& X,
                                       const PositionSemantics& A) noexcept {
  if (auto ok = CheckChangePoint(X, RK::kPosition, A); !ok) return Unexpected{ok.error()};
  PositionSemantics r = X;
  r.point = A.point;
  return r;
}

Checked<PositionSemantics> ChangeRefPoint(const PositionSemantics& X,
                                          const PositionSemantics& A) noexcept {
  if (auto ok = CheckChangeRefPoint(X, RK::kPosition, A); !ok) return Unexpected{ok.error()};
  PositionSemantics r = X;
  r.ref_point = A.ref_point;
  return r;
}

Checked<PositionSemantics> ChangeCoordinateFrame(const PositionSemantics& X,
                                                 const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kPosition, O);
  if (!r_new) return Unexpected{r_new.error()};
  PositionSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

// ============================================================== Orientation

OrientationSemantics Inverse(const OrientationSemantics& X) noexcept {
  return {X.ref_orientation, X.ref_body, X.orientation, X.body, X.coordinate_frame};
}

Checked<OrientationSemantics> InverseInNewRef(const OrientationSemantics& X) noexcept {
  constexpr RK k = RK::kOrientation;
  if (!(X.coordinate_frame == X.ref_orientation)) {
    return Fail(Operation::kInverseInNewRef, CoordSide(kSubject, k, X),
                RefOrientationSide(kSubject, k, X));
  }
  return OrientationSemantics{X.ref_orientation, X.ref_body, X.orientation, X.body, X.orientation};
}

namespace {
Checked<Composition<OrientationSemantics>> ComposeOrientations(
    Operation op, Operand x_role, RK x_kind, const OrientationSemantics& X, Operand y_role,
    RK y_kind, const OrientationSemantics& Y) noexcept {
  if (!(X.ref_orientation == Y.orientation)) {
    return Fail(op, RefOrientationSide(x_role, x_kind, X), OrientationSide(y_role, y_kind, Y));
  }
  if (!(X.ref_body == Y.body))
    return Fail(op, RefBodySide(x_role, x_kind, X), BodySide(y_role, y_kind, Y));
  auto form = CompositionForm(op, x_role, x_kind, X, y_role, y_kind, Y);
  if (!form) return Unexpected{form.error()};
  return Composition<OrientationSemantics>{
      {X.orientation, X.body, Y.ref_orientation, Y.ref_body, ComposedFrame(X, Y)}, *form};
}
}  // namespace

Checked<Composition<OrientationSemantics>> Compose(const OrientationSemantics& X,
                                                   const OrientationSemantics& Y) noexcept {
  constexpr RK k = RK::kOrientation;
  return ComposeOrientations(Operation::kCompose, kFirst, k, X, kSecond, k, Y);
}

namespace {
// A = [a'] wrt [a] on X's body: the composition Compose(A, X).
template <class S>
Checked<Ok> CheckChangeOrientationFrame(const S& X, RK kind,
                                        const OrientationSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangeOrientationFrame;
  constexpr RK a = RK::kOrientation;
  if (!(A.ref_orientation == X.orientation)) {
    return Fail(op, RefOrientationSide(kArgument, a, A), OrientationSide(kSubject, kind, X));
  }
  if (!(A.ref_body == X.body))
    return Fail(op, RefBodySide(kArgument, a, A), BodySide(kSubject, kind, X));
  if (!(A.body == X.body)) return Fail(op, BodySide(kArgument, a, A), BodySide(kSubject, kind, X));
  return Ok{};
}
// A = [b] wrt [b'] on X's reference body: the composition Compose(X, A).
template <class S>
Checked<Ok> CheckChangeRefOrientationFrame(const S& X, RK kind,
                                           const OrientationSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangeRefOrientationFrame;
  constexpr RK a = RK::kOrientation;
  if (!(A.orientation == X.ref_orientation)) {
    return Fail(op, OrientationSide(kArgument, a, A), RefOrientationSide(kSubject, kind, X));
  }
  if (!(A.body == X.ref_body))
    return Fail(op, BodySide(kArgument, a, A), RefBodySide(kSubject, kind, X));
  if (!(A.ref_body == X.ref_body)) {
    return Fail(op, RefBodySide(kArgument, a, A), RefBodySide(kSubject, kind, X));
  }
  return Ok{};
}
}  // namespace

Checked<Composition<OrientationSemantics>> ChangeOrientationFrame(
    const OrientationSemantics& X, const OrientationSemantics& A) noexcept {
  constexpr RK k = RK::kOrientation;
  if (auto ok = CheckChangeOrientationFrame(X, k, A); !ok) return Unexpected{ok.error()};
  return ComposeOrientations(Operation::kChangeOrientationFrame, kArgument, k, A, kSubject, k, X);
}

Checked<Composition<OrientationSemantics>> ChangeRefOrientationFrame(
    const OrientationSemantics& X, const OrientationSemantics& A) noexcept {
  constexpr RK k = RK::kOrientation;
  if (auto ok = CheckChangeRefOrientationFrame(X, k, A); !ok) return Unexpected{ok.error()};
  return ComposeOrientations(Operation::kChangeRefOrientationFrame, kSubject, k, X, kArgument, k,
                             A);
}

Checked<OrientationSemantics> ChangeCoordinateFrame(const OrientationSemantics& X,
                                                    const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kOrientation, O);
  if (!r_new) return Unexpected{r_new.error()};
  OrientationSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

// ============================================================== Pose

PoseSemantics Inverse(const PoseSemantics& X) noexcept {
  return {X.ref_point, X.ref_orientation, X.ref_body, X.point, X.orientation,
          X.body,      X.coordinate_frame};
}

Checked<PoseSemantics> InverseInNewRef(const PoseSemantics& X) noexcept {
  constexpr RK k = RK::kPose;
  if (!(X.coordinate_frame == X.ref_orientation)) {
    return Fail(Operation::kInverseInNewRef, CoordSide(kSubject, k, X),
                RefOrientationSide(kSubject, k, X));
  }
  return PoseSemantics{X.ref_point, X.ref_orientation, X.ref_body, X.point, X.orientation,
                       X.body,      X.orientation};
}

Checked<Composition<PoseSemantics>> Compose(const PoseSemantics& X,
                                            const PoseSemantics& Y) noexcept {
  constexpr Operation op = Operation::kCompose;
  constexpr RK k = RK::kPose;
  if (!(X.ref_point == Y.point))
    return Fail(op, RefPointSide(kFirst, k, X), PointSide(kSecond, k, Y));
  if (!(X.ref_orientation == Y.orientation)) {
    return Fail(op, RefOrientationSide(kFirst, k, X), OrientationSide(kSecond, k, Y));
  }
  if (!(X.ref_body == Y.body)) return Fail(op, RefBodySide(kFirst, k, X), BodySide(kSecond, k, Y));
  auto form = CompositionForm(op, kFirst, k, X, kSecond, k, Y);
  if (!form) return Unexpected{form.error()};
  return Composition<PoseSemantics>{{X.point, X.orientation, X.body, Y.ref_point, Y.ref_orientation,
                                     Y.ref_body, ComposedFrame(X, Y)},
                                    *form};
}

Checked<PoseSemantics> ChangePoint(const PoseSemantics& X, const PositionSemantics& A) noexcept {
  if (auto ok = CheckChangePoint(X, RK::kPose, A); !ok) return Unexpected{ok.error()};
  PoseSemantics r = X;
  r.point = A.point;
  return r;
}

Checked<PoseSemantics> ChangeRefPoint(const PoseSemantics& X, const PositionSemantics& A) noexcept {
  if (auto ok = CheckChangeRefPoint(X, RK::kPose, A); !ok) return Unexpected{ok.error()};
  PoseSemantics r = X;
  r.ref_point = A.ref_point;
  return r;
}

Checked<Composition<PoseSemantics>> ChangeOrientationFrame(const PoseSemantics& X,
                                                           const OrientationSemantics& A) noexcept {
  constexpr RK k = RK::kPose;
  if (auto ok = CheckChangeOrientationFrame(X, k, A); !ok) return Unexpected{ok.error()};
  auto c = ComposeOrientations(Operation::kChangeOrientationFrame, kArgument, RK::kOrientation, A,
                               kSubject, k, OrientationOf(X));
  if (!c) return Unexpected{c.error()};
  PoseSemantics r = X;
  r.orientation = A.orientation;
  r.coordinate_frame = c->result.coordinate_frame;  // X's frame in both forms
  return Composition<PoseSemantics>{r, c->form};
}

Checked<Composition<PoseSemantics>> ChangeRefOrientationFrame(
    const PoseSemantics& X, const OrientationSemantics& A) noexcept {
  constexpr RK k = RK::kPose;
  if (auto ok = CheckChangeRefOrientationFrame(X, k, A); !ok) return Unexpected{ok.error()};
  auto c = ComposeOrientations(Operation::kChangeRefOrientationFrame, kSubject, k, OrientationOf(X),
                               kArgument, RK::kOrientation, A);
  if (!c) return Unexpected{c.error()};
  PoseSemantics r = X;
  r.ref_orientation = A.ref_orientation;
  r.coordinate_frame = c->result.coordinate_frame;  // [b'] in the chain form
  return Composition<PoseSemantics>{r, c->form};
}

Checked<PoseSemantics> ChangeCoordinateFrame(const PoseSemantics& X,
                                             const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kPose, O);
  if (!r_new) return Unexpected{r_new.error()};
  PoseSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

PositionSemantics PositionOf(const PoseSemantics& X) noexcept {
  return {X.point, X.body, X.ref_point, X.ref_body, X.coordinate_frame};
}

OrientationSemantics OrientationOf(const PoseSemantics& X) noexcept {
  return {X.orientation, X.body, X.ref_orientation, X.ref_body, X.coordinate_frame};
}

Checked<PoseSemantics> Combine(const PositionSemantics& P, const OrientationSemantics& O) noexcept {
  constexpr Operation op = Operation::kCombine;
  if (!(P.body == O.body)) {
    return Fail(op, BodySide(kFirst, RK::kPosition, P), BodySide(kSecond, RK::kOrientation, O));
  }
  if (!(P.ref_body == O.ref_body)) {
    return Fail(op, RefBodySide(kFirst, RK::kPosition, P),
                RefBodySide(kSecond, RK::kOrientation, O));
  }
  if (!(P.coordinate_frame == O.coordinate_frame)) {
    return Fail(op, CoordSide(kFirst, RK::kPosition, P), CoordSide(kSecond, RK::kOrientation, O));
  }
  return PoseSemantics{P.point,    O.orientation,     P.body, P.ref_point, O.ref_orientation,
                       P.ref_body, P.coordinate_frame};
}

// ============================================================== Velocities

LinearVelocitySemantics Inverse(const LinearVelocitySemantics& X) noexcept {
  return {X.point, X.ref_body, X.body, X.coordinate_frame};
}

Checked<LinearVelocitySemantics> Compose(const LinearVelocitySemantics& X,
                                         const LinearVelocitySemantics& Y) noexcept {
  constexpr Operation op = Operation::kCompose;
  constexpr RK k = RK::kLinearVelocity;
  if (!(X.point == Y.point)) return Fail(op, PointSide(kFirst, k, X), PointSide(kSecond, k, Y));
  if (!(X.ref_body == Y.body)) return Fail(op, RefBodySide(kFirst, k, X), BodySide(kSecond, k, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame)) {
    return Fail(op, CoordSide(kFirst, k, X), CoordSide(kSecond, k, Y));
  }
  return LinearVelocitySemantics{X.point, X.body, Y.ref_body, X.coordinate_frame};
}

Checked<LinearVelocitySemantics> ChangeCoordinateFrame(const LinearVelocitySemantics& X,
                                                       const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kLinearVelocity, O);
  if (!r_new) return Unexpected{r_new.error()};
  LinearVelocitySemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

AngularVelocitySemantics Inverse(const AngularVelocitySemantics& X) noexcept {
  return {X.ref_body, X.body, X.coordinate_frame};
}

Checked<AngularVelocitySemantics> Compose(const AngularVelocitySemantics& X,
                                          const AngularVelocitySemantics& Y) noexcept {
  constexpr Operation op = Operation::kCompose;
  constexpr RK k = RK::kAngularVelocity;
  if (!(X.ref_body == Y.body)) return Fail(op, RefBodySide(kFirst, k, X), BodySide(kSecond, k, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame)) {
    return Fail(op, CoordSide(kFirst, k, X), CoordSide(kSecond, k, Y));
  }
  return AngularVelocitySemantics{X.body, Y.ref_body, X.coordinate_frame};
}

Checked<AngularVelocitySemantics> ChangeCoordinateFrame(const AngularVelocitySemantics& X,
                                                        const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kAngularVelocity, O);
  if (!r_new) return Unexpected{r_new.error()};
  AngularVelocitySemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

// ============================================================== Twist

TwistSemantics Inverse(const TwistSemantics& X) noexcept {
  return {X.point, X.ref_body, X.body, X.coordinate_frame};
}

Checked<TwistSemantics> Compose(const TwistSemantics& X, const TwistSemantics& Y) noexcept {
  constexpr Operation op = Operation::kCompose;
  constexpr RK k = RK::kTwist;
  if (!(X.point == Y.point)) return Fail(op, PointSide(kFirst, k, X), PointSide(kSecond, k, Y));
  if (!(X.ref_body == Y.body)) return Fail(op, RefBodySide(kFirst, k, X), BodySide(kSecond, k, Y));
  if (!(X.coordinate_frame == Y.coordinate_frame)) {
    return Fail(op, CoordSide(kFirst, k, X), CoordSide(kSecond, k, Y));
  }
  return TwistSemantics{X.point, X.body, Y.ref_body, X.coordinate_frame};
}

Checked<TwistSemantics> ChangePoint(const TwistSemantics& X, const PositionSemantics& A) noexcept {
  constexpr Operation op = Operation::kChangePoint;
  if (!(A.point == X.point)) {
    return Fail(op, Side(kArgument, RK::kPosition, Field::kPoint, A.point.id(), A.body.id()),
                Side(kSubject, RK::kTwist, Field::kPoint, X.point.id(), X.body.id()));
  }
  if (!(A.coordinate_frame == X.coordinate_frame)) {
    return Fail(op, CoordSide(kArgument, RK::kPosition, A), CoordSide(kSubject, RK::kTwist, X));
  }
  TwistSemantics r = X;
  r.point = A.ref_point;
  return r;
}

Checked<TwistSemantics> ChangeCoordinateFrame(const TwistSemantics& X,
                                              const OrientationSemantics& O) noexcept {
  auto r_new = CheckCoordinateChange(X, RK::kTwist, O);
  if (!r_new) return Unexpected{r_new.error()};
  TwistSemantics r = X;
  r.coordinate_frame = *r_new;
  return r;
}

Checked<TwistSemantics> ScrewTransform(const TwistSemantics& X, const PoseSemantics& P) noexcept {
  constexpr Operation op = Operation::kScrewTransform;
  if (!(P.point == X.point)) {
    return Fail(op, PointSide(kArgument, RK::kPose, P),
                Side(kSubject, RK::kTwist, Field::kPoint, X.point.id(), X.body.id()));
  }
  if (!(P.orientation == X.coordinate_frame)) {
    return Fail(op, OrientationSide(kArgument, RK::kPose, P), CoordSide(kSubject, RK::kTwist, X));
  }
  if (!(P.coordinate_frame == P.ref_orientation)) {
    return Fail(op, CoordSide(kArgument, RK::kPose, P),
                RefOrientationSide(kArgument, RK::kPose, P));
  }
  return TwistSemantics{P.ref_point, X.body, X.ref_body, P.ref_orientation};
}

LinearVelocitySemantics LinearOf(const TwistSemantics& X) noexcept {
  return {X.point, X.body, X.ref_body, X.coordinate_frame};
}

AngularVelocitySemantics AngularOf(const TwistSemantics& X) noexcept {
  return {X.body, X.ref_body, X.coordinate_frame};
}

Checked<TwistSemantics> Combine(const LinearVelocitySemantics& L,
                                const AngularVelocitySemantics& W) noexcept {
  constexpr Operation op = Operation::kCombine;
  if (!(L.body == W.body)) {
    return Fail(op, BodySide(kFirst, RK::kLinearVelocity, L),
                BodySide(kSecond, RK::kAngularVelocity, W));
  }
  if (!(L.ref_body == W.ref_body)) {
    return Fail(op, RefBodySide(kFirst, RK::kLinearVelocity, L),
                RefBodySide(kSecond, RK::kAngularVelocity, W));
  }
  if (!(L.coordinate_frame == W.coordinate_frame)) {
    return Fail(op, CoordSide(kFirst, RK::kLinearVelocity, L),
                CoordSide(kSecond, RK::kAngularVelocity, W));
  }
  return TwistSemantics{L.point, L.body, L.ref_body, L.coordinate_frame};
}

}  // namespace semgraph::semantics
