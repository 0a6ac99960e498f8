// File: semgraph/coord/covariance.h
//
// Covariances of poses and twists (docs/uncertainty.md): the 6x6 matrix type, the checks every
// covariance passes before it is stored, and the conversions between the named conventions and
// semgraph's edge form.
//
// Meaning. A pose's covariance is the covariance of the perturbation of its coordinates,
// delta = (dp, dtheta): p_true = p + dp, R_true = Exp(dtheta) R (dtheta a rotation vector in the
// pose's coordinate frame). A twist's is that of (dv, dw) = (v_true - v, w_true - w). Rows and
// columns are linear first (CovarianceOrder::kLinearAngular), as ROS orders them; GTSAM puts
// the rotation first (kAngularLinear). For an edge-form pose X = (R, p) = (R[t<-h], p(h/t) in
// [t]) the other accepted convention is kBody: X_true = X Exp(xi), xi = (rho, phi) at point h in
// [h] (GTSAM's Pose3, manif's SE3), to first order delta = (R rho, R phi), so
//   Sigma_coordinates = diag(R, R) Sigma_body diag(R, R)^T.
//
// Checks, on the matrix as given (before any reordering or conversion), in this order:
//   invalid_number      an entry not finite or with |x| > kMaxMagnitude (the first in
//                       row-major order)
//   invalid_covariance  not symmetric: |S(i,j) - S(j,i)| > tol (the first such i < j), else an
//                       eigenvalue of (S + S^T)/2 below -tol (the smallest);
//                       tol = kCovarianceTolerance * max(1, max |S(i,j)|)
// An accepted covariance is stored symmetrized, (S + S^T)/2.
//
// Invariants: every function here is noexcept and allocation-free (fixed-size Eigen types), so
// it may run on the real-time path (a value update with its covariance).
// Cost: CheckCovariance is O(36) plus one 6x6 symmetric eigen-decomposition (a few
// microseconds); the conversions are a few 6x6 products.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "semgraph/base/expected.h"
#include "semgraph/coord/error.h"
#include "semgraph/coord/export.h"

namespace semgraph::coord {

/// A pose or twist covariance; rows and columns (dp, dtheta) or (dv, dw) unless an order says
/// otherwise.
using Covariance6 = Eigen::Matrix<double, 6, 6>;

/// Which half comes first in a 6x6 covariance's rows and columns.
enum class CovarianceOrder : std::uint8_t {
  kLinearAngular,  ///< (dp, dtheta) / (dv, dw): semgraph's and ROS's order
  kAngularLinear,  ///< (dtheta, dp) / (dw, dv): GTSAM's order
};

/// How a pose's perturbation is applied (docs/uncertainty.md, "Conventions").
enum class PoseCovarianceConvention : std::uint8_t {
  kCoordinates,  ///< p_true = p + dp, R_true = Exp(dtheta) R: semgraph's edge form, ROS's
  kBody,         ///< X_true = X Exp(xi), xi = (rho, phi) at the head's origin in [head]
};

/// Relative tolerance of the symmetry and eigenvalue checks (times max(1, max |S(i,j)|)).
inline constexpr double kCovarianceTolerance = 1e-9;

/// What is wrong with a covariance: the first problem found, in the checks' order.
enum class CovarianceProblem : std::uint8_t {
  kNone,
  kNotFinite,     ///< invalid_number: an entry is NaN or infinite
  kTooLarge,      ///< invalid_number: |entry| > kMaxMagnitude
  kNotSymmetric,  ///< invalid_covariance: |S(i,j) - S(j,i)| > tol
  kNotPositive,   ///< invalid_covariance: an eigenvalue of (S + S^T)/2 below -tol
};

/// The verdict of CheckCovariance: small, trivially copyable, no strings. Describe formats it.
struct CovarianceCheck {
  CovarianceProblem problem = CovarianceProblem::kNone;
  /// The entry (row, col) as given (kNotFinite, kTooLarge, kNotSymmetric: the upper one, i < j);
  /// 0, 0 for kNotPositive.
  int row = 0;
  int col = 0;
  double value = 0.0;  ///< the entry S(row, col), or the smallest eigenvalue (kNotPositive)
  double other = 0.0;  ///< kNotSymmetric: S(col, row)
  double limit = 0.0;  ///< the bound broken: kMaxMagnitude, tol, or -tol (kNotPositive)

  [[nodiscard]] bool ok() const noexcept { return problem == CovarianceProblem::kNone; }
  [[nodiscard]] bool is_number_problem() const noexcept {
    return problem == CovarianceProblem::kNotFinite || problem == CovarianceProblem::kTooLarge;
  }
  /// kOk, kInvalidNumber or kInvalidCovariance.
  [[nodiscard]] SEMGRAPH_COORD_EXPORT ErrorCode code() const noexcept;
  /// As a coord::Error (role kCovariance, component 6 * row + col, problem kNotFinite,
  /// kTooLarge, kNotSymmetric or kNegativeEigenvalue, magnitude: the entry, the asymmetry
  /// |S(row,col) - S(col,row)|, or the eigenvalue), for callers that carry one.
  [[nodiscard]] SEMGRAPH_COORD_EXPORT Error error() const noexcept;
};

/// The checks above, on `sigma` as given. No allocation.
[[nodiscard]] SEMGRAPH_COORD_EXPORT CovarianceCheck
CheckCovariance(const Covariance6& sigma) noexcept;

/// (S + S^T) / 2.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6 Symmetrized(const Covariance6& sigma) noexcept;

/// `sigma` with its linear and angular halves swapped: an involution, so the same call converts
/// either way between kLinearAngular and kAngularLinear.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6 SwapHalves(const Covariance6& sigma) noexcept;
/// `sigma` given in `order`, as kLinearAngular; or, the same swap, a kLinearAngular `sigma`
/// written in `order`.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6 Reorder(const Covariance6& sigma,
                                                        CovarianceOrder order) noexcept;

/// kBody -> kCoordinates for an edge-form pose with rotation R_TH (= R[t<-h]), linear-angular
/// order: diag(R, R) S diag(R, R)^T.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6
BodyToCoordinates(const Eigen::Matrix3d& R_TH, const Covariance6& sigma_body) noexcept;
/// kCoordinates -> kBody, the inverse: diag(R, R)^T S diag(R, R).
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6
CoordinatesToBody(const Eigen::Matrix3d& R_TH, const Covariance6& sigma_coordinates) noexcept;

/// The input path of an edge-form pose's covariance: check `sigma` as given, then reorder to
/// linear-angular, convert to kCoordinates (R_TH: the pose's rotation, used by kBody only), and
/// symmetrize. The error is the check's verdict.
[[nodiscard]] SEMGRAPH_COORD_EXPORT base::Expected<Covariance6, CovarianceCheck>
PoseCovarianceToEdgeForm(const Covariance6& sigma, CovarianceOrder order,
                         PoseCovarianceConvention convention, const Eigen::Matrix3d& R_TH) noexcept;
/// The output path: an edge-form (coordinates, linear-angular) covariance in `convention` and
/// `order`.
[[nodiscard]] SEMGRAPH_COORD_EXPORT Covariance6 PoseCovarianceFromEdgeForm(
    const Covariance6& sigma_edge, CovarianceOrder order, PoseCovarianceConvention convention,
    const Eigen::Matrix3d& R_TH) noexcept;

/// A twist's covariance: check as given, reorder to linear-angular, symmetrize.
[[nodiscard]] SEMGRAPH_COORD_EXPORT base::Expected<Covariance6, CovarianceCheck>
TwistCovarianceToEdgeForm(const Covariance6& sigma, CovarianceOrder order) noexcept;

/// One line naming what is wrong, e.g. "covariance entry (0, 1) = 0.5 differs from entry
/// (1, 0) = 0.25 by 0.25 (more than 1e-09)", "covariance has eigenvalue -0.5 (below -1e-09)",
/// "covariance entry (2, 3) is nan (must be finite)". "ok" when ok. Allocates.
[[nodiscard]] SEMGRAPH_COORD_EXPORT std::string Describe(const CovarianceCheck& check);

}  // namespace semgraph::coord
