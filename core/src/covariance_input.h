// Private to core/src: a covariance given with a value (docs/uncertainty.md §1-§2): the checks
// in the rules' order (invalid_number, then invalid_covariance, on the matrix as given), and
// the covariance of the value as given, in the coordinates convention and linear_angular order,
// symmetrized. Text is formatted only on rejection.
#pragma once

#include <optional>
#include <string>

#include "semgraph/coord/jacobians.h"
#include "semgraph/core/specs.h"
#include "semgraph/core/uncertainty.h"

namespace semgraph::core::internal {

struct CovarianceRejection {
  ErrorCode code;
  std::string message;
};

/// The checks of §2 (coord/covariance.h); `pose_edge_form`: the value is a pose in edge form
/// (the only form the body convention applies to); `twist`: a twist (no convention at all).
[[nodiscard]] inline std::optional<CovarianceRejection> CheckCovarianceInput(
    const CovarianceInput& c, bool pose_edge_form, bool twist) {
  const coord::CovarianceCheck check = coord::CheckCovariance(*c.matrix);
  if (!check.ok()) return CovarianceRejection{check.code(), coord::Describe(check)};
  if (c.convention == PoseCovarianceConvention::kBody && (twist || !pose_edge_form)) {
    return CovarianceRejection{ErrorCode::kInvalidCovariance,
                               twist ? "a twist's covariance has no convention (body is for "
                                       "poses in edge form)"
                                     : "the body convention applies to a pose given in edge "
                                       "form only (point, reference point and coordinate frame "
                                       "those of the edge)"};
  }
  return std::nullopt;
}

/// The covariance of a checked input in the coordinates convention, linear_angular,
/// symmetrized; R: the pose's rotation as given (for the body convention).
[[nodiscard]] inline Covariance6 CoordinatesCovariance(const CovarianceInput& c,
                                                       const Eigen::Matrix3d& R) noexcept {
  const Covariance6 S = coord::Symmetrized(coord::Reorder(*c.matrix, c.order));
  return c.convention == PoseCovarianceConvention::kBody ? coord::BodyToCoordinates(R, S) : S;
}

/// True when a restated value's covariance (null: none) equals the stored one (zero: none):
/// every entry within 1e-9 max(1, max|S_stored|) (§2).
[[nodiscard]] inline bool SameCovariance(const Covariance6& stored,
                                         const Covariance6* given) noexcept {
  if (given == nullptr) return stored.isZero(0.0);  // none = none
  const double tol = coord::kCovarianceTolerance * std::max(1.0, stored.cwiseAbs().maxCoeff());
  return (stored - *given).cwiseAbs().maxCoeff() <= tol;
}

}  // namespace semgraph::core::internal
