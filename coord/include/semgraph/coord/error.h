// File: semgraph/coord/error.h
//
// coord::Error: why a checked coordinate operation or a value construction failed. Small and
// trivially copyable (no strings): it is returned on query paths. Describe() formats it.
//
//   kSemanticMismatch          the names do not fit (mismatch says which fields)
//   kRepresentationConstraint  the backend cannot express the semantics (representation names
//                              the backend; mismatch.lhs/rhs name the two names it requires equal)
//   kInvalidNumber             NaN or +-Inf in an input, or a position/velocity/acceleration/
//                              force/moment component beyond
//                              kMaxMagnitude (value says where); subnormal inputs are accepted
//                              and flushed to zero (they carry no physical meaning and would
//                              slow down every later product)
//   kInvalidRotation           quaternion norm or matrix orthonormality off by more than
//                              kRotationTolerance, or a reflection
//   kInvalidCovariance         a covariance not symmetric or not positive semi-definite
//                              (coord/covariance.h; value says which entry or eigenvalue)
// Cost: O(1), 56 bytes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "semgraph/base/error_code.h"
#include "semgraph/coord/export.h"
#include "semgraph/semantics/mismatch.h"
#include "semgraph/semantics/names.h"

namespace semgraph::coord {

using base::ErrorCode;

/// Spec tolerance for rotations: | |q| - 1 | <= 1e-6; max |M^T M - I| <= 1e-6.
inline constexpr double kRotationTolerance = 1e-6;

/// Largest accepted magnitude of a position (m), velocity (m/s, rad/s), acceleration (m/s^2,
/// rad/s^2), force (N) or moment (N m) component: beyond it, sums along long paths lose all
/// precision (and 1e12 m is seven times Earth–Sun).
inline constexpr double kMaxMagnitude = 1e12;

/// What is wrong with an input number.
enum class ValueProblem : std::uint8_t {
  kNone,
  kNotFinite,           ///< NaN or +-Inf; `component` is its index within `what`
  kTooLarge,            ///< |x| > kMaxMagnitude; `magnitude` is the value
  kQuaternionNorm,      ///< `magnitude` = | |q| - 1 |
  kNotOrthonormal,      ///< `magnitude` = max |M^T M - I|
  kReflection,          ///< det(M) <= 0
  kNotRigidTransform,   ///< bottom row of a 4x4 homogeneous matrix is not [0 0 0 1]
  kOutsideLimits,       ///< a joint position beyond [lower, upper]; `magnitude` is the value
  kNotSymmetric,        ///< a covariance: `magnitude` = |S(i,j) - S(j,i)| (coord/covariance.h)
  kNegativeEigenvalue,  ///< a covariance: `magnitude` is the eigenvalue (coord/covariance.h)
};

/// Which input a ValueProblem is about.
enum class ValueRole : std::uint8_t {
  kPosition,
  kQuaternion,
  kRotationMatrix,
  kHomogeneousMatrix,
  kLinearVelocity,
  kAngularVelocity,
  kJointPosition,
  kJointVelocity,
  kJointAcceleration,
  kLinearAcceleration,
  kAngularAcceleration,
  kForce,
  kMoment,
  kCovariance,  ///< a 6x6 covariance; component = 6 * row + col (an eigenvalue: its index)
};

struct ValueDetail {
  ValueProblem problem = ValueProblem::kNone;
  ValueRole role = ValueRole::kPosition;
  std::uint8_t component = 0;
  double magnitude = 0.0;
};

/// The bound a problem is about: kMaxMagnitude (kTooLarge), kRotationTolerance (a quaternion's
/// norm, a matrix's orthonormality, a 4x4's bottom row); 0 when the rule has no number of its own
/// (not finite; a reflection: det <= 0; a joint's limits, which are the joint's).
[[nodiscard]] constexpr double LimitOf(ValueProblem problem) noexcept {
  switch (problem) {
    case ValueProblem::kTooLarge:
      return kMaxMagnitude;
    case ValueProblem::kQuaternionNorm:
    case ValueProblem::kNotOrthonormal:
    case ValueProblem::kNotRigidTransform:
      return kRotationTolerance;
    default:
      return 0.0;
  }
}

struct Error {
  ErrorCode code = ErrorCode::kOk;
  semantics::Mismatch mismatch;          ///< kSemanticMismatch, kRepresentationConstraint
  const char* representation = nullptr;  ///< backend name for kRepresentationConstraint
  ValueDetail value;                     ///< kInvalidNumber, kInvalidRotation, kInvalidCovariance
};

/// x in the fewest digits that read back as exactly x (std::to_chars, shortest round trip):
/// "0.1", "1000000000000.5", "1e+12", "-0", "nan", "-inf". Every number in a message is written
/// so, so that a message never shows a rounded value that would not be the offending one
/// (1000000000000.5 is not "1e+12").
[[nodiscard]] SEMGRAPH_COORD_EXPORT std::string FormatNumber(double x);

/// One line naming what is wrong, e.g.
/// "homogeneous representation: point e|C of the pose must be the origin of orientation frame
/// [a]|C of the pose", or "quaternion norm differs from 1 by 0.2 (more than 1e-06)".
[[nodiscard]] SEMGRAPH_COORD_EXPORT std::string Describe(const Error& error,
                                                         const semantics::NameTable& names);

}  // namespace semgraph::coord
