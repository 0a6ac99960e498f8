// Input validation, representation constraints, and error text for the coord layer.
#include "semgraph/coord/validate.h"

#include <Eigen/SVD>
#include <charconv>
#include <cmath>
#include <string>

#include "semgraph/semantics/describe.h"

namespace semgraph::coord {
namespace {

Error ValueError(ErrorCode code, ValueProblem problem, ValueRole role, int component = 0,
                 double magnitude = 0.0) noexcept {
  Error e;
  e.code = code;
  e.value = ValueDetail{problem, role, static_cast<std::uint8_t>(component), magnitude};
  return e;
}

template <class M>
Expected<Ok, Error> CheckFinite(const M& m, ValueRole role) noexcept {
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    if (!std::isfinite(m.data()[i])) {
      return Unexpected{ValueError(ErrorCode::kInvalidNumber, ValueProblem::kNotFinite, role,
                                   static_cast<int>(i), m.data()[i])};
    }
  }
  return Ok{};
}

// Subnormals become zero: physically meaningless, and slow in every later product.
double FlushSubnormal(double x) noexcept { return std::fpclassify(x) == FP_SUBNORMAL ? 0.0 : x; }

}  // namespace

Expected<Eigen::Vector3d, Error> ValidateVector(const Eigen::Vector3d& v, ValueRole role) noexcept {
  if (auto ok = CheckFinite(v, role); !ok) return Unexpected{ok.error()};
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(v[i]) > kMaxMagnitude) {
      return Unexpected{
          ValueError(ErrorCode::kInvalidNumber, ValueProblem::kTooLarge, role, i, v[i])};
    }
    out[i] = FlushSubnormal(v[i]);
  }
  return out;
}

Expected<Eigen::Quaterniond, Error> ValidateQuaternion(const Eigen::Quaterniond& q) noexcept {
  // Component order in messages is w x y z (Hamilton, as in the scene-script format).
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(wxyz[i])) {
      return Unexpected{ValueError(ErrorCode::kInvalidNumber, ValueProblem::kNotFinite,
                                   ValueRole::kQuaternion, i, wxyz[i])};
    }
  }
  const double norm = q.norm();
  const double off = std::abs(norm - 1.0);
  if (!(off <= kRotationTolerance)) {
    return Unexpected{ValueError(ErrorCode::kInvalidRotation, ValueProblem::kQuaternionNorm,
                                 ValueRole::kQuaternion, 0, off)};
  }
  // Unit to rounding (kUnitRounding): kept as given, so that normalizing is idempotent.
  Eigen::Quaterniond out = off <= kUnitRounding ? q : Eigen::Quaterniond(q.coeffs() / norm);
  for (int i = 0; i < 4; ++i) out.coeffs()[i] = FlushSubnormal(out.coeffs()[i]);
  return out;
}

Expected<Eigen::Matrix3d, Error> ValidateRotationMatrix(const Eigen::Matrix3d& R) noexcept {
  // Row-major component index in messages, as the user writes the matrix.
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(R(r, c))) {
        return Unexpected{ValueError(ErrorCode::kInvalidNumber, ValueProblem::kNotFinite,
                                     ValueRole::kRotationMatrix, 3 * r + c, R(r, c))};
      }
    }
  }
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kRotationTolerance)) {
    return Unexpected{ValueError(ErrorCode::kInvalidRotation, ValueProblem::kNotOrthonormal,
                                 ValueRole::kRotationMatrix, 0, off)};
  }
  const double det = R.determinant();
  if (!(det > 0.0)) {
    return Unexpected{ValueError(ErrorCode::kInvalidRotation, ValueProblem::kReflection,
                                 ValueRole::kRotationMatrix, 0, det)};
  }
  // Orthonormal to rounding (kOrthonormalRounding): kept as given, so that normalizing is
  // idempotent. Otherwise the polar decomposition: the nearest rotation is U V^T (det > 0 and
  // near-orthonormal, so the singular values are all close to 1 and no sign fix is needed).
  Eigen::Matrix3d out = R;
  if (!(off <= kOrthonormalRounding)) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    out = svd.matrixU() * svd.matrixV().transpose();
  }
  for (int i = 0; i < 9; ++i) out.data()[i] = FlushSubnormal(out.data()[i]);
  return out;
}

Expected<Position, Error> MakePosition(const PositionSemantics& s,
                                       const Eigen::Vector3d& p) noexcept {
  auto ok = ValidateVector(p, ValueRole::kPosition);
  if (!ok) return Unexpected{ok.error()};
  return Position{s, *ok};
}

Expected<LinearVelocity, Error> MakeLinearVelocity(const LinearVelocitySemantics& s,
                                                   const Eigen::Vector3d& v) noexcept {
  auto ok = ValidateVector(v, ValueRole::kLinearVelocity);
  if (!ok) return Unexpected{ok.error()};
  return LinearVelocity{s, *ok};
}

Expected<AngularVelocity, Error> MakeAngularVelocity(const AngularVelocitySemantics& s,
                                                     const Eigen::Vector3d& w) noexcept {
  auto ok = ValidateVector(w, ValueRole::kAngularVelocity);
  if (!ok) return Unexpected{ok.error()};
  return AngularVelocity{s, *ok};
}

Expected<Twist, Error> MakeTwist(const TwistSemantics& s, const Eigen::Vector3d& v,
                                 const Eigen::Vector3d& w) noexcept {
  auto v_ok = ValidateVector(v, ValueRole::kLinearVelocity);
  if (!v_ok) return Unexpected{v_ok.error()};
  auto w_ok = ValidateVector(w, ValueRole::kAngularVelocity);
  if (!w_ok) return Unexpected{w_ok.error()};
  return Twist{s, *v_ok, *w_ok};
}

Expected<Acceleration, Error> MakeAcceleration(const AccelerationSemantics& s,
                                               const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& alpha) noexcept {
  auto a_ok = ValidateVector(a, ValueRole::kLinearAcceleration);
  if (!a_ok) return Unexpected{a_ok.error()};
  auto alpha_ok = ValidateVector(alpha, ValueRole::kAngularAcceleration);
  if (!alpha_ok) return Unexpected{alpha_ok.error()};
  return Acceleration{s, *a_ok, *alpha_ok};
}

Expected<Wrench, Error> MakeWrench(const WrenchSemantics& s, const Eigen::Vector3d& f,
                                   const Eigen::Vector3d& m) noexcept {
  auto f_ok = ValidateVector(f, ValueRole::kForce);
  if (!f_ok) return Unexpected{f_ok.error()};
  auto m_ok = ValidateVector(m, ValueRole::kMoment);
  if (!m_ok) return Unexpected{m_ok.error()};
  return Wrench{s, *f_ok, *m_ok};
}

namespace internal {

Error RepresentationError(const char* representation, semantics::MismatchSide lhs,
                          semantics::MismatchSide rhs) noexcept {
  Error e;
  e.code = ErrorCode::kRepresentationConstraint;
  e.representation = representation;
  e.mismatch.code = ErrorCode::kRepresentationConstraint;
  e.mismatch.lhs = lhs;
  e.mismatch.rhs = rhs;
  return e;
}

Expected<Ok, Error> CheckPoseConstraints(const Constraints& c, const char* name,
                                         const PoseSemantics& s) noexcept {
  using semantics::Field;
  using semantics::MismatchSide;
  using semantics::Operand;
  using semantics::RelationKind;
  constexpr Operand o = Operand::kSubject;
  constexpr RelationKind k = RelationKind::kPose;
  if (c.pose_point_is_origin && !semantics::IsOriginOf(s.point, s.orientation)) {
    return Unexpected{RepresentationError(
        name, MismatchSide{o, k, Field::kPoint, s.point.id(), s.body.id()},
        MismatchSide{o, k, Field::kOrientation, s.orientation.id(), s.body.id()})};
  }
  if (c.pose_ref_point_is_origin && !semantics::IsOriginOf(s.ref_point, s.ref_orientation)) {
    return Unexpected{RepresentationError(
        name, MismatchSide{o, k, Field::kRefPoint, s.ref_point.id(), s.ref_body.id()},
        MismatchSide{o, k, Field::kRefOrientation, s.ref_orientation.id(), s.ref_body.id()})};
  }
  if (c.coordinate_frame_is_ref_orientation && !(s.coordinate_frame == s.ref_orientation)) {
    return Unexpected{RepresentationError(
        name, MismatchSide{o, k, Field::kCoordinateFrame, s.coordinate_frame.id(), {}},
        MismatchSide{o, k, Field::kRefOrientation, s.ref_orientation.id(), s.ref_body.id()})};
  }
  return Ok{};
}

Expected<Ok, Error> CheckOrientationConstraints(const Constraints& c, const char* name,
                                                const OrientationSemantics& s) noexcept {
  using semantics::Field;
  using semantics::MismatchSide;
  constexpr auto o = semantics::Operand::kSubject;
  constexpr auto k = semantics::RelationKind::kOrientation;
  if (c.coordinate_frame_is_ref_orientation && !(s.coordinate_frame == s.ref_orientation)) {
    return Unexpected{RepresentationError(
        name, MismatchSide{o, k, Field::kCoordinateFrame, s.coordinate_frame.id(), {}},
        MismatchSide{o, k, Field::kRefOrientation, s.ref_orientation.id(), s.ref_body.id()})};
  }
  return Ok{};
}

Expected<Ok, Error> ValidateHomogeneousShape(const Eigen::Matrix4d& T) noexcept {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(T(r, c))) {
        return Unexpected{ValueError(ErrorCode::kInvalidNumber, ValueProblem::kNotFinite,
                                     ValueRole::kHomogeneousMatrix, 4 * r + c, T(r, c))};
      }
    }
  }
  const Eigen::RowVector4d bottom = T.row(3);
  const double off = (bottom - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  if (!(off <= kRotationTolerance)) {
    return Unexpected{ValueError(ErrorCode::kInvalidRotation, ValueProblem::kNotRigidTransform,
                                 ValueRole::kHomogeneousMatrix, 0, off)};
  }
  return Ok{};
}

}  // namespace internal

namespace {
const char* RoleName(ValueRole role) noexcept {
  switch (role) {
    case ValueRole::kPosition:
      return "position";
    case ValueRole::kQuaternion:
      return "quaternion";
    case ValueRole::kRotationMatrix:
      return "rotation matrix";
    case ValueRole::kHomogeneousMatrix:
      return "homogeneous matrix";
    case ValueRole::kLinearVelocity:
      return "linear velocity";
    case ValueRole::kAngularVelocity:
      return "angular velocity";
    case ValueRole::kJointPosition:
      return "joint position";
    case ValueRole::kJointVelocity:
      return "joint velocity";
    case ValueRole::kJointAcceleration:
      return "joint acceleration";
    case ValueRole::kLinearAcceleration:
      return "linear acceleration";
    case ValueRole::kAngularAcceleration:
      return "angular acceleration";
    case ValueRole::kForce:
      return "force";
    case ValueRole::kMoment:
      return "moment";
    case ValueRole::kCovariance:
      return "covariance";
  }
  return "value";
}
}  // namespace

namespace {
// "(row, col)" of a covariance entry given as 6 * row + col.
std::string CovarianceEntry(int component) {
  return "(" + std::to_string(component / 6) + ", " + std::to_string(component % 6) + ")";
}
}  // namespace

std::string FormatNumber(double x) {
  if (std::isnan(x)) return "nan";  // whatever its sign bit: one non-number to the user
  char buf[64];  // the shortest round-trip form of a double needs at most 24 characters
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, r.ptr);
}

std::string Describe(const Error& error, const semantics::NameTable& names) {
  // Plain string concatenation, not a stream: a stream swallows std::bad_alloc (it sets badbit
  // and yields a cut text), while every build operation lets it through unchanged.
  const std::string magnitude = FormatNumber(error.value.magnitude);
  const std::string tolerance = FormatNumber(kRotationTolerance);
  switch (error.code) {
    case ErrorCode::kSemanticMismatch:
      return semantics::Describe(error.mismatch, names);
    case ErrorCode::kRepresentationConstraint: {
      const bool origin = error.mismatch.lhs.field == semantics::Field::kPoint ||
                          error.mismatch.lhs.field == semantics::Field::kRefPoint;
      return std::string("the ") + (error.representation ? error.representation : "chosen") +
             " representation requires " + semantics::Describe(error.mismatch.lhs, names) +
             (origin ? " to be the origin of " : " to be ") +
             semantics::Describe(error.mismatch.rhs, names);
    }
    case ErrorCode::kInvalidNumber:
      if (error.value.role == ValueRole::kCovariance) {
        return "covariance entry " + CovarianceEntry(error.value.component) + " is " + magnitude +
               (error.value.problem == ValueProblem::kTooLarge
                    ? " (magnitude above " + FormatNumber(kMaxMagnitude) + ")"
                    : std::string(" (must be finite)"));
      }
      return std::string(RoleName(error.value.role)) + " component " +
             std::to_string(int(error.value.component)) + " is " + magnitude +
             (error.value.problem == ValueProblem::kTooLarge
                  ? " (magnitude above " + FormatNumber(kMaxMagnitude) + ")"
                  : std::string(" (must be finite)"));
    case ErrorCode::kInvalidRotation:
      switch (error.value.problem) {
        case ValueProblem::kQuaternionNorm:
          return "quaternion norm differs from 1 by " + magnitude + " (more than " + tolerance +
                 ")";
        case ValueProblem::kNotOrthonormal:
          return "rotation matrix is not orthonormal: max |M^T M - I| = " + magnitude +
                 " (more than " + tolerance + ")";
        case ValueProblem::kReflection:
          return "rotation matrix has determinant " + magnitude + " (a reflection, not a rotation)";
        case ValueProblem::kNotRigidTransform:
          return "homogeneous matrix bottom row is not [0 0 0 1] (off by " + magnitude + ")";
        default:
          return "invalid rotation";
      }
    case ErrorCode::kInvalidCovariance:
      // The tolerance scales with the matrix, which this Error does not carry: the rule in
      // words (coord::Describe(CovarianceCheck) gives the number).
      if (error.value.problem == ValueProblem::kNegativeEigenvalue) {
        return "covariance has eigenvalue " + magnitude +
               " (below -1e-09 * max(1, max |entry|): not positive semi-definite)";
      }
      return "covariance entry " + CovarianceEntry(error.value.component) +
             " differs from its transpose by " + magnitude +
             " (more than 1e-09 * max(1, max |entry|): not symmetric)";
    default:
      return std::string(base::ToString(error.code));
  }
}

}  // namespace semgraph::coord
