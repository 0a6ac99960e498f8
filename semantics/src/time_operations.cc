// Time operations' preconditions. Contract: time_operations.h.
#include "semgraph/semantics/time_operations.h"

#include <optional>

namespace semgraph::semantics {
namespace {

using RK = RelationKind;

constexpr Unexpected<Mismatch> Fail(Operation op, MismatchSide lhs, MismatchSide rhs) noexcept {
  return Unexpected{Mismatch{ErrorCode::kSemanticMismatch, op, lhs, rhs, false}};
}
constexpr MismatchSide Side(Operand o, RK k, Field f, NameId name,
                            NameId body = NameId()) noexcept {
  return {o, k, f, name, body};
}

// The first field where two poses differ, as a mismatch of (first, second).
std::optional<Mismatch> FirstDifference(Operation op, const PoseSemantics& X,
                                        const PoseSemantics& Y) noexcept {
  const auto pair = [&](Field f, NameId x, NameId xb, NameId y, NameId yb) {
    return Fail(op, Side(Operand::kFirst, RK::kPose, f, x, xb),
                Side(Operand::kSecond, RK::kPose, f, y, yb))
        .error;
  };
  if (!(X.point == Y.point))
    return pair(Field::kPoint, X.point.id(), X.body.id(), Y.point.id(), Y.body.id());
  if (!(X.orientation == Y.orientation)) {
    return pair(Field::kOrientation, X.orientation.id(), X.body.id(), Y.orientation.id(),
                Y.body.id());
  }
  if (!(X.body == Y.body)) return pair(Field::kBody, X.body.id(), {}, Y.body.id(), {});
  if (!(X.ref_point == Y.ref_point)) {
    return pair(Field::kRefPoint, X.ref_point.id(), X.ref_body.id(), Y.ref_point.id(),
                Y.ref_body.id());
  }
  if (!(X.ref_orientation == Y.ref_orientation)) {
    return pair(Field::kRefOrientation, X.ref_orientation.id(), X.ref_body.id(),
                Y.ref_orientation.id(), Y.ref_body.id());
  }
  if (!(X.ref_body == Y.ref_body))
    return pair(Field::kRefBody, X.ref_body.id(), {}, Y.ref_body.id(), {});
  if (!(X.coordinate_frame == Y.coordinate_frame)) {
    return pair(Field::kCoordinateFrame, X.coordinate_frame.id(), {}, Y.coordinate_frame.id(), {});
  }
  return std::nullopt;
}

}  // namespace

Checked<PoseSemantics> RequireEdgeForm(Operation op, const PoseSemantics& X) noexcept {
  constexpr Operand s = Operand::kSubject;
  if (!IsOriginOf(X.point, X.orientation)) {
    return Fail(op, Side(s, RK::kPose, Field::kPoint, X.point.id(), X.body.id()),
                Side(s, RK::kPose, Field::kOrientation, X.orientation.id(), X.body.id()));
  }
  if (!IsOriginOf(X.ref_point, X.ref_orientation)) {
    return Fail(
        op, Side(s, RK::kPose, Field::kRefPoint, X.ref_point.id(), X.ref_body.id()),
        Side(s, RK::kPose, Field::kRefOrientation, X.ref_orientation.id(), X.ref_body.id()));
  }
  if (!(X.coordinate_frame == X.ref_orientation)) {
    return Fail(
        op, Side(s, RK::kPose, Field::kCoordinateFrame, X.coordinate_frame.id()),
        Side(s, RK::kPose, Field::kRefOrientation, X.ref_orientation.id(), X.ref_body.id()));
  }
  return X;
}

Checked<PoseSemantics> Integrate(const PoseSemantics& X, const TwistSemantics& xi) noexcept {
  constexpr Operation op = Operation::kIntegrate;
  if (auto ok = RequireEdgeForm(op, X); !ok) return ok;
  constexpr Operand s = Operand::kSubject, a = Operand::kArgument;
  if (!(xi.point == X.point)) {
    return Fail(op, Side(a, RK::kTwist, Field::kPoint, xi.point.id(), xi.body.id()),
                Side(s, RK::kPose, Field::kPoint, X.point.id(), X.body.id()));
  }
  if (!(xi.body == X.body)) {
    return Fail(op, Side(a, RK::kTwist, Field::kBody, xi.body.id()),
                Side(s, RK::kPose, Field::kBody, X.body.id()));
  }
  if (!(xi.ref_body == X.ref_body)) {
    return Fail(op, Side(a, RK::kTwist, Field::kRefBody, xi.ref_body.id()),
                Side(s, RK::kPose, Field::kRefBody, X.ref_body.id()));
  }
  if (!(xi.coordinate_frame == X.orientation)) {
    return Fail(op, Side(a, RK::kTwist, Field::kCoordinateFrame, xi.coordinate_frame.id()),
                Side(s, RK::kPose, Field::kOrientation, X.orientation.id(), X.body.id()));
  }
  return X;
}

Checked<TwistSemantics> Differentiate(const PoseSemantics& X0, const PoseSemantics& X1) noexcept {
  constexpr Operation op = Operation::kDifferentiate;
  if (auto m = FirstDifference(op, X0, X1)) return Unexpected{*m};
  if (auto ok = RequireEdgeForm(op, X0); !ok) return Unexpected{ok.error()};
  return EdgeScrewTwist(X0);
}

Checked<PoseSemantics> Interpolate(const PoseSemantics& X0, const PoseSemantics& X1,
                                   bool screw) noexcept {
  constexpr Operation op = Operation::kInterpolate;
  if (auto m = FirstDifference(op, X0, X1)) return Unexpected{*m};
  if (screw) return RequireEdgeForm(op, X0);
  return X0;
}

Checked<TwistSemantics> Interpolate(const TwistSemantics& X0, const TwistSemantics& X1) noexcept {
  constexpr Operation op = Operation::kInterpolate;
  const auto pair = [&](Field f, NameId x, NameId y) {
    return Fail(op, Side(Operand::kFirst, RK::kTwist, f, x),
                Side(Operand::kSecond, RK::kTwist, f, y));
  };
  if (!(X0.point == X1.point)) return pair(Field::kPoint, X0.point.id(), X1.point.id());
  if (!(X0.body == X1.body)) return pair(Field::kBody, X0.body.id(), X1.body.id());
  if (!(X0.ref_body == X1.ref_body))
    return pair(Field::kRefBody, X0.ref_body.id(), X1.ref_body.id());
  if (!(X0.coordinate_frame == X1.coordinate_frame)) {
    return pair(Field::kCoordinateFrame, X0.coordinate_frame.id(), X1.coordinate_frame.id());
  }
  return X0;
}

}  // namespace semgraph::semantics
