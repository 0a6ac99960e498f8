// File: tests/support/tolerance.h
//
// Approximate comparison of Eigen vectors, matrices and quaternions for GoogleTest.
//
//   ExpectNear(a, b)            max_i |a_i - b_i| <= kTolerance (absolute, 1e-9)
//   ExpectNear(a, b, tol)       max_i |a_i - b_i| <= tol
//   ExpectNear(q1, q2, tol)     quaternions: q and -q are the same rotation, so
//                               min(max|q1 - q2|, max|q1 + q2|) <= tol (over w x y z)
//   Near(...)                   the same, as a ::testing::AssertionResult for
//   EXPECT_TRUE/ASSERT_TRUE
//
// The epsilon is absolute: every quantity in the test scenes is O(1..10) (unit rotations,
// translations in [-2,2]^3, velocities in [-1,1]^3 per body), so double rounding through a
// handful of products stays below 1e-13 and 1e-9 leaves four orders of margin while still
// catching any wrong sign, transpose, frame or lever arm (errors of order 1e-1 and up).
// A failure message states the epsilon used, the largest difference and both operands, and
// points at the caller's line (__builtin_FILE/__builtin_LINE as default arguments are evaluated
// at the call site; std::source_location is not usable with clang 14 + libstdc++ 12).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <sstream>
#include <string>

namespace semgraph::testing {

/// Default absolute epsilon of ExpectNear (see the file comment).
inline constexpr double kTolerance = 1e-9;

namespace internal {
template <class Derived>
std::string Format(const Eigen::MatrixBase<Derived>& m) {
  const Eigen::IOFormat fmt(17, 0, ", ", "; ", "", "", "[", "]");
  std::ostringstream out;
  out << m.format(fmt);
  return out.str();
}
inline std::string Format(const Eigen::Quaterniond& q) {
  std::ostringstream out;
  out.precision(17);
  out << "(w " << q.w() << ", x " << q.x() << ", y " << q.y() << ", z " << q.z() << ")";
  return out.str();
}
}  // namespace internal

template <class DA, class DB>
::testing::AssertionResult Near(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b,
                                double tol = kTolerance) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "shapes differ: " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  const double diff = (a.template cast<double>() - b.template cast<double>()).cwiseAbs().maxCoeff();
  if (diff <= tol) return ::testing::AssertionSuccess();  // NaN fails
  return ::testing::AssertionFailure()
         << "max |a - b| = " << diff << " exceeds epsilon " << tol
         << "\n  a = " << internal::Format(a) << "\n  b = " << internal::Format(b);
}

inline ::testing::AssertionResult Near(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b,
                                       double tol = kTolerance) {
  const double same = (a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff();
  const double opposite = (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff();
  const double diff = std::min(same, opposite);
  if (diff <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "quaternions differ (q and -q equal): min(max|a - b|, max|a + b|) = " << diff
         << " exceeds epsilon " << tol << "\n  a = " << internal::Format(a)
         << "\n  b = " << internal::Format(b);
}

template <class DA, class DB>
void ExpectNear(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b,
                double tol = kTolerance, const char* file = __builtin_FILE(),
                int line = __builtin_LINE()) {
  if (auto r = Near(a, b, tol); !r) {
    ADD_FAILURE_AT(file, line) << r.message();
  }
}

inline void ExpectNear(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b,
                       double tol = kTolerance, const char* file = __builtin_FILE(),
                       int line = __builtin_LINE()) {
  if (auto r = Near(a, b, tol); !r) {
    ADD_FAILURE_AT(file, line) << r.message();
  }
}

}  // namespace semgraph::testing
