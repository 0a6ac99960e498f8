// File: semgraph/coord/covariance.h
//
// The 6x6 covariance of a pose or twist value (docs/uncertainty.md): rows and columns
// (dp, dtheta) for a pose, (dv, dw) for a twist, linear first unless an order says otherwise.
// The checks of a covariance given as input (invalid_number, invalid_covariance), and the
// reordering between linear_angular and angular_linear.
// Costs: O(1); CheckCovariance runs one 6x6 self-adjoint eigen decomposition. noexcept,
// allocation-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace semgraph::coord {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

/// The order of a covariance's rows and columns: linear then angular (semgraph's twist order,
/// ROS's) or angular then linear (GTSAM's).
enum class CovarianceOrder : std::uint8_t { kLinearAngular, kAngularLinear };
/// What a pose covariance perturbs: the coordinates (p + dp, Exp(dtheta) R, at the pose's
/// point in its [r]) or the body (X Exp(xi), xi at the point in the pose's own axes).
enum class PoseCovarianceConvention : std::uint8_t { kCoordinates, kBody };

/// What is wrong with a covariance, the first problem found (entries in row-major order).
enum class CovarianceProblem : std::uint8_t {
  kNone,
  kNotFinite,      ///< invalid_number: an entry is NaN or infinite
  kTooLarge,       ///< invalid_number: |entry| > 1e12
  kNotSymmetric,   ///< invalid_covariance: |S(i,j) - S(j,i)| > 1e-9 max(1, max|S|)
  kNotPositive,    ///< invalid_covariance: an eigenvalue below -1e-9 max(1, max|S|)
};
struct CovarianceCheck {
  CovarianceProblem problem = CovarianceProblem::kNone;
  int row = 0, col = 0;  ///< the offending entry (kNotFinite, kTooLarge, kNotSymmetric)
  double value = 0.0;    ///< that entry, or the offending eigenvalue (kNotPositive)
  [[nodiscard]] bool ok() const noexcept { return problem == CovarianceProblem::kNone; }
  [[nodiscard]] bool is_number_problem() const noexcept {
    return problem == CovarianceProblem::kNotFinite || problem == CovarianceProblem::kTooLarge;
  }
};

/// The checks of docs/uncertainty.md on a covariance as given (before any reordering).
[[nodiscard]] inline CovarianceCheck CheckCovariance(const Covariance6& S) noexcept {
  CovarianceCheck c;
  double max_abs = 0.0;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      const double x = S(i, j);
      if (!std::isfinite(x)) return {CovarianceProblem::kNotFinite, i, j, x};
      if (std::abs(x) > 1e12) return {CovarianceProblem::kTooLarge, i, j, x};
      max_abs = std::max(max_abs, std::abs(x));
    }
  }
  const double tol = 1e-9 * std::max(1.0, max_abs);
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      if (std::abs(S(i, j) - S(j, i)) > tol) return {CovarianceProblem::kNotSymmetric, i, j, S(i, j)};
    }
  }
  const Covariance6 sym = 0.5 * (S + S.transpose());
  const Eigen::SelfAdjointEigenSolver<Covariance6> eig(sym, Eigen::EigenvaluesOnly);
  const double lowest = eig.eigenvalues()(0);
  if (lowest < -tol) {
    c.problem = CovarianceProblem::kNotPositive;
    c.value = lowest;
  }
  return c;
}

/// S with its linear and angular halves swapped (an involution: the same call converts either
/// way between kLinearAngular and kAngularLinear).
[[nodiscard]] inline Covariance6 SwapHalves(const Covariance6& S) noexcept {
  Covariance6 out;
  out.topLeftCorner<3, 3>() = S.bottomRightCorner<3, 3>();
  out.bottomRightCorner<3, 3>() = S.topLeftCorner<3, 3>();
  out.topRightCorner<3, 3>() = S.bottomLeftCorner<3, 3>();
  out.bottomLeftCorner<3, 3>() = S.topRightCorner<3, 3>();
  return out;
}
/// S given in `order`, as linear_angular (or back: the same swap).
[[nodiscard]] inline Covariance6 Reorder(const Covariance6& S, CovarianceOrder order) noexcept {
  return order == CovarianceOrder::kLinearAngular ? S : SwapHalves(S);
}

}  // namespace semgraph::coord
