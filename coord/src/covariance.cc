// Covariance checks and convention conversions (coord/covariance.h).
#include "semgraph/coord/covariance.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

namespace semgraph::coord {
namespace {

CovarianceCheck Refuse(CovarianceProblem problem, int row, int col, double value, double other,
                       double limit) noexcept {
  return CovarianceCheck{problem, row, col, value, other, limit};
}

// diag(R, R) as a 6x6 (the same rotation on both halves).
Covariance6 BlockDiagonal(const Eigen::Matrix3d& R) noexcept {
  Covariance6 D = Covariance6::Zero();
  D.topLeftCorner<3, 3>() = R;
  D.bottomRightCorner<3, 3>() = R;
  return D;
}

}  // namespace

ErrorCode CovarianceCheck::code() const noexcept {
  if (ok()) return ErrorCode::kOk;
  return is_number_problem() ? ErrorCode::kInvalidNumber : ErrorCode::kInvalidCovariance;
}

Error CovarianceCheck::error() const noexcept {
  Error e;
  e.code = code();
  ValueProblem p = ValueProblem::kNone;
  double magnitude = value;
  switch (problem) {
    case CovarianceProblem::kNone:
      break;
    case CovarianceProblem::kNotFinite:
      p = ValueProblem::kNotFinite;
      break;
    case CovarianceProblem::kTooLarge:
      p = ValueProblem::kTooLarge;
      break;
    case CovarianceProblem::kNotSymmetric:
      p = ValueProblem::kNotSymmetric;
      magnitude = std::abs(value - other);
      break;
    case CovarianceProblem::kNotPositive:
      p = ValueProblem::kNegativeEigenvalue;
      break;
  }
  e.value =
      ValueDetail{p, ValueRole::kCovariance, static_cast<std::uint8_t>(6 * row + col), magnitude};
  return e;
}

CovarianceCheck CheckCovariance(const Covariance6& sigma) noexcept {
  // Numbers first, in row-major order (the order the user writes the matrix).
  double largest = 0.0;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      const double x = sigma(r, c);
      if (!std::isfinite(x)) {
        return Refuse(CovarianceProblem::kNotFinite, r, c, x, 0.0, 0.0);
      }
      if (std::abs(x) > kMaxMagnitude) {
        return Refuse(CovarianceProblem::kTooLarge, r, c, x, 0.0, kMaxMagnitude);
      }
      largest = std::max(largest, std::abs(x));
    }
  }
  const double tol = kCovarianceTolerance * std::max(1.0, largest);
  for (int r = 0; r < 6; ++r) {
    for (int c = r + 1; c < 6; ++c) {
      if (std::abs(sigma(r, c) - sigma(c, r)) > tol) {
        return Refuse(CovarianceProblem::kNotSymmetric, r, c, sigma(r, c), sigma(c, r), tol);
      }
    }
  }
  // Symmetric within tol: the eigenvalues of the symmetrized matrix (the one that is stored).
  const Eigen::SelfAdjointEigenSolver<Covariance6> eigen(Symmetrized(sigma),
                                                         Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()[0];  // ascending
  if (!(smallest >= -tol)) {
    return Refuse(CovarianceProblem::kNotPositive, 0, 0, smallest, 0.0, -tol);
  }
  return CovarianceCheck{};
}

Covariance6 Symmetrized(const Covariance6& sigma) noexcept {
  return 0.5 * (sigma + sigma.transpose());
}

Covariance6 SwapHalves(const Covariance6& sigma) noexcept {
  Covariance6 out;
  out.topLeftCorner<3, 3>() = sigma.bottomRightCorner<3, 3>();
  out.bottomRightCorner<3, 3>() = sigma.topLeftCorner<3, 3>();
  out.topRightCorner<3, 3>() = sigma.bottomLeftCorner<3, 3>();
  out.bottomLeftCorner<3, 3>() = sigma.topRightCorner<3, 3>();
  return out;
}

Covariance6 Reorder(const Covariance6& sigma, CovarianceOrder order) noexcept {
  return order == CovarianceOrder::kLinearAngular ? sigma : SwapHalves(sigma);
}

Covariance6 BodyToCoordinates(const Eigen::Matrix3d& R_TH, const Covariance6& sigma_body) noexcept {
  // X Exp(xi) = (R Exp(phi), p + R V(phi) rho) = (Exp(R phi) R, p + R rho + O(|xi|^2)).
  const Covariance6 D = BlockDiagonal(R_TH);
  return D * sigma_body * D.transpose();
}

Covariance6 CoordinatesToBody(const Eigen::Matrix3d& R_TH,
                              const Covariance6& sigma_coordinates) noexcept {
  const Covariance6 D = BlockDiagonal(R_TH);
  return D.transpose() * sigma_coordinates * D;
}

base::Expected<Covariance6, CovarianceCheck> PoseCovarianceToEdgeForm(
    const Covariance6& sigma, CovarianceOrder order, PoseCovarianceConvention convention,
    const Eigen::Matrix3d& R_TH) noexcept {
  const CovarianceCheck check = CheckCovariance(sigma);
  if (!check.ok()) return base::Unexpected{check};
  Covariance6 out = Reorder(sigma, order);
  if (convention == PoseCovarianceConvention::kBody) out = BodyToCoordinates(R_TH, out);
  return Symmetrized(out);
}

Covariance6 PoseCovarianceFromEdgeForm(const Covariance6& sigma_edge, CovarianceOrder order,
                                       PoseCovarianceConvention convention,
                                       const Eigen::Matrix3d& R_TH) noexcept {
  Covariance6 out = sigma_edge;
  if (convention == PoseCovarianceConvention::kBody) out = CoordinatesToBody(R_TH, out);
  return Symmetrized(Reorder(out, order));
}

base::Expected<Covariance6, CovarianceCheck> TwistCovarianceToEdgeForm(
    const Covariance6& sigma, CovarianceOrder order) noexcept {
  const CovarianceCheck check = CheckCovariance(sigma);
  if (!check.ok()) return base::Unexpected{check};
  return Symmetrized(Reorder(sigma, order));
}

std::string Describe(const CovarianceCheck& check) {
  const auto entry = [](int r, int c) {
    return "(" + std::to_string(r) + ", " + std::to_string(c) + ")";
  };
  const std::string at = "covariance entry " + entry(check.row, check.col);
  switch (check.problem) {
    case CovarianceProblem::kNone:
      return "ok";
    case CovarianceProblem::kNotFinite:
      return at + " is " + FormatNumber(check.value) + " (must be finite)";
    case CovarianceProblem::kTooLarge:
      return at + " is " + FormatNumber(check.value) + " (magnitude above " +
             FormatNumber(kMaxMagnitude) + ")";
    case CovarianceProblem::kNotSymmetric:
      return at + " = " + FormatNumber(check.value) + " differs from entry " +
             entry(check.col, check.row) + " = " + FormatNumber(check.other) + " by " +
             FormatNumber(std::abs(check.value - check.other)) + " (more than " +
             FormatNumber(check.limit) + ": not symmetric)";
    case CovarianceProblem::kNotPositive:
      return "covariance has eigenvalue " + FormatNumber(check.value) + " (below " +
             FormatNumber(check.limit) + ": not positive semi-definite)";
  }
  return "ok";
}

}  // namespace semgraph::coord
