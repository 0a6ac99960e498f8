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

/// The checks of §2; `pose_edge_form`: the value is a pose in edge form (the only form the
/// body convention applies to); `twist`: a twist (no convention at all).
[[nodiscard]] inline std::optional<CovarianceRejection> CheckCovarianceInput(
    const CovarianceInput& c, bool pose_edge_form, bool twist) {
  const coord::CovarianceCheck check = coord::CheckCovariance(*c.matrix);
  const auto entry = [&] {
    return "covariance entry (" + std::to_string(check.row) + ", " + std::to_string(check.col) +
           ") = " + std::to_string(check.value);
  };
  switch (check.problem) {
    case coord::CovarianceProblem::kNone:
      break;
    case coord::CovarianceProblem::kNotFinite:
      return CovarianceRejection{ErrorCode::kInvalidNumber, entry() + " is not finite"};
    case coord::CovarianceProblem::kTooLarge:
      return CovarianceRejection{ErrorCode::kInvalidNumber, entry() + " is above 1e12"};
    case coord::CovarianceProblem::kNotSymmetric:
      return CovarianceRejection{ErrorCode::kInvalidCovariance,
                                 entry() + " differs from its transpose by more than 1e-9 "
                                           "max(1, max|S|): the matrix is not symmetric"};
    case coord::CovarianceProblem::kNotPositive:
      return CovarianceRejection{ErrorCode::kInvalidCovariance,
                                 "covariance eigenvalue " + std::to_string(check.value) +
                                     " is below -1e-9 max(1, max|S|): not positive "
                                     "semidefinite"};
  }
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
  Covariance6 S = coord::Reorder(*c.matrix, c.order);
  S = 0.5 * (S + S.transpose()).eval();
  if (c.convention == PoseCovarianceConvention::kBody) S = coord::jacobians::BodyToCoordinates(R, S);
  return S;
}

/// True when a restated value's covariance (null: none) equals the stored one (zero: none):
/// every entry within 1e-9 max(1, max|S_stored|) (§2).
[[nodiscard]] inline bool SameCovariance(const Covariance6& stored,
                                         const Covariance6* given) noexcept {
  const double tol = 1e-9 * std::max(1.0, stored.cwiseAbs().maxCoeff());
  if (given == nullptr) return stored.cwiseAbs().maxCoeff() <= tol && stored.isZero(0.0);
  return (stored - *given).cwiseAbs().maxCoeff() <= tol;
}

}  // namespace semgraph::core::internal
