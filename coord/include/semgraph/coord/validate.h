// File: semgraph/coord/validate.h
//
// Input validation and the checked constructors (Make*) of relation values. This is the only
// way numbers enter semgraph: every later operation trusts the invariants established here.
//
// Checks, in the spec's order: invalid_number (NaN/Inf anywhere, including inside a quaternion
// or matrix) -> invalid_rotation (| |q| - 1 | > 1e-6; max |M^T M - I| > 1e-6 or det <= 0; a 4x4
// whose bottom row is not [0 0 0 1]) -> representation_constraint (the backend's Constraints).
// Within tolerance, rotations are normalized: q -> q/|q|, M -> its nearest rotation (polar
// decomposition via SVD); a rotation already unit / orthonormal to rounding (kUnitRounding,
// kOrthonormalRounding) is kept exactly as given. Normalizing is therefore idempotent: a value
// read back from a graph (pose_value, GetPose, a scene written by semgraph::script::WriteScene)
// and added again is stored bit for bit as it was.
// Cost: O(1); a matrix input costs one 3x3 SVD. No allocation. Build-time, not hot path.
#pragma once

#include "semgraph/base/expected.h"
#include "semgraph/coord/error.h"
#include "semgraph/coord/export.h"
#include "semgraph/coord/values.h"

namespace semgraph::coord {

using base::Expected;
using base::Ok;
using base::Unexpected;

/// Rotations unit or orthonormal to rounding are kept as given: a quaternion with
/// | |q| - 1 | <= kUnitRounding, a matrix with max |M^T M - I| <= kOrthonormalRounding. What
/// normalizing gives is within them (q / |q| within 1.5 ulp of unit, a polar decomposition
/// within about 25 ulp of orthonormal: measured on 10^7 quaternions and 10^6 matrices), so
/// normalizing is idempotent, and the stored values stay as close to unit as normalizing
/// every time would keep them.
inline constexpr double kUnitRounding = 4 * 2.220446049250313e-16;           // 4 ulp of 1
inline constexpr double kOrthonormalRounding = 128 * 2.220446049250313e-16;  // 128 ulp of 1

[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Eigen::Vector3d, Error> ValidateVector(
    const Eigen::Vector3d& v, ValueRole role) noexcept;
/// Returns q / |q| (q itself when | |q| - 1 | <= kUnitRounding).
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Eigen::Quaterniond, Error> ValidateQuaternion(
    const Eigen::Quaterniond& q) noexcept;
/// Returns the nearest proper rotation (R itself when max |R^T R - I| <= kOrthonormalRounding).
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Eigen::Matrix3d, Error> ValidateRotationMatrix(
    const Eigen::Matrix3d& R) noexcept;

/// Whether backend B can hold these semantics; the error names B and the two names it requires
/// to be equal.
template <Backend B>
[[nodiscard]] Expected<Ok, Error> CheckRepresentation(const PoseSemantics& s) noexcept;
template <Backend B>
[[nodiscard]] Expected<Ok, Error> CheckRepresentation(const OrientationSemantics& s) noexcept;

[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Position, Error> MakePosition(
    const PositionSemantics& s, const Eigen::Vector3d& p) noexcept;
template <Backend B>
[[nodiscard]] Expected<Orientation<B>, Error> MakeOrientation(const OrientationSemantics& s,
                                                              const Eigen::Quaterniond& q) noexcept;
template <Backend B>
[[nodiscard]] Expected<Orientation<B>, Error> MakeOrientation(const OrientationSemantics& s,
                                                              const Eigen::Matrix3d& R) noexcept;
template <Backend B>
[[nodiscard]] Expected<Pose<B>, Error> MakePose(const PoseSemantics& s, const Eigen::Quaterniond& q,
                                                const Eigen::Vector3d& p) noexcept;
template <Backend B>
[[nodiscard]] Expected<Pose<B>, Error> MakePose(const PoseSemantics& s, const Eigen::Matrix3d& R,
                                                const Eigen::Vector3d& p) noexcept;
/// From a 4x4 homogeneous matrix [R p; 0 0 0 1].
template <Backend B>
[[nodiscard]] Expected<Pose<B>, Error> MakePose(const PoseSemantics& s,
                                                const Eigen::Matrix4d& T) noexcept;
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<LinearVelocity, Error> MakeLinearVelocity(
    const LinearVelocitySemantics& s, const Eigen::Vector3d& v) noexcept;
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<AngularVelocity, Error> MakeAngularVelocity(
    const AngularVelocitySemantics& s, const Eigen::Vector3d& w) noexcept;
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Twist, Error> MakeTwist(
    const TwistSemantics& s, const Eigen::Vector3d& v, const Eigen::Vector3d& w) noexcept;
/// Linear (classical) acceleration a, angular acceleration alpha.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Acceleration, Error> MakeAcceleration(
    const AccelerationSemantics& s, const Eigen::Vector3d& a,
    const Eigen::Vector3d& alpha) noexcept;
/// Force f, moment m (about the semantics' point).
[[nodiscard]] SEMGRAPH_COORD_EXPORT Expected<Wrench, Error> MakeWrench(
    const WrenchSemantics& s, const Eigen::Vector3d& f, const Eigen::Vector3d& m) noexcept;

// ------------------------------------------------------------------ implementation

namespace internal {
SEMGRAPH_COORD_EXPORT Error RepresentationError(const char* representation,
                                                semantics::MismatchSide lhs,
                                                semantics::MismatchSide rhs) noexcept;
SEMGRAPH_COORD_EXPORT Expected<Ok, Error> CheckPoseConstraints(const Constraints& c,
                                                               const char* name,
                                                               const PoseSemantics& s) noexcept;
SEMGRAPH_COORD_EXPORT Expected<Ok, Error> CheckOrientationConstraints(
    const Constraints& c, const char* name, const OrientationSemantics& s) noexcept;
}  // namespace internal

template <Backend B>
Expected<Ok, Error> CheckRepresentation(const PoseSemantics& s) noexcept {
  return internal::CheckPoseConstraints(B::kConstraints, B::kName, s);
}
template <Backend B>
Expected<Ok, Error> CheckRepresentation(const OrientationSemantics& s) noexcept {
  return internal::CheckOrientationConstraints(B::kConstraints, B::kName, s);
}

template <Backend B>
Expected<Orientation<B>, Error> MakeOrientation(const OrientationSemantics& s,
                                                const Eigen::Quaterniond& q) noexcept {
  auto q_valid = ValidateQuaternion(q);
  if (!q_valid) return Unexpected{q_valid.error()};
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s, B::FromQuaternion(*q_valid)};
}

template <Backend B>
Expected<Orientation<B>, Error> MakeOrientation(const OrientationSemantics& s,
                                                const Eigen::Matrix3d& R) noexcept {
  auto R_valid = ValidateRotationMatrix(R);
  if (!R_valid) return Unexpected{R_valid.error()};
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Orientation<B>{s, B::FromMatrix(*R_valid)};
}

template <Backend B>
Expected<Pose<B>, Error> MakePose(const PoseSemantics& s, const Eigen::Quaterniond& q,
                                  const Eigen::Vector3d& p) noexcept {
  // Numbers first (all of them), then rotation, then representation: the spec's order.
  auto p_valid = ValidateVector(p, ValueRole::kPosition);
  if (!p_valid) return Unexpected{p_valid.error()};
  auto q_valid = ValidateQuaternion(q);
  if (!q_valid) return Unexpected{q_valid.error()};
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Pose<B>{s, B::MakePose(B::FromQuaternion(*q_valid), *p_valid)};
}

template <Backend B>
Expected<Pose<B>, Error> MakePose(const PoseSemantics& s, const Eigen::Matrix3d& R,
                                  const Eigen::Vector3d& p) noexcept {
  auto p_valid = ValidateVector(p, ValueRole::kPosition);
  if (!p_valid) return Unexpected{p_valid.error()};
  auto R_valid = ValidateRotationMatrix(R);
  if (!R_valid) return Unexpected{R_valid.error()};
  if (auto ok = CheckRepresentation<B>(s); !ok) return Unexpected{ok.error()};
  return Pose<B>{s, B::MakePose(B::FromMatrix(*R_valid), *p_valid)};
}

namespace internal {
SEMGRAPH_COORD_EXPORT Expected<Ok, Error> ValidateHomogeneousShape(
    const Eigen::Matrix4d& T) noexcept;
}  // namespace internal

template <Backend B>
Expected<Pose<B>, Error> Pose<B>::FromIsometry(const PoseSemantics& s,
                                               const Eigen::Isometry3d& X) noexcept {
  return MakePose<B>(s, Eigen::Matrix3d(X.linear()), Eigen::Vector3d(X.translation()));
}

template <Backend B>
Expected<Pose<B>, Error> MakePose(const PoseSemantics& s, const Eigen::Matrix4d& T) noexcept {
  if (auto ok = internal::ValidateHomogeneousShape(T); !ok) return Unexpected{ok.error()};
  return MakePose<B>(s, Eigen::Matrix3d(T.topLeftCorner<3, 3>()),
                     Eigen::Vector3d(T.topRightCorner<3, 1>()));
}

}  // namespace semgraph::coord
