// File: tests/support/random_covariance.h
//
// Random draws for the covariance tests at a time: stamps in milliseconds, rotations from a
// rotation vector, covariances 1e-6 L L^T (L with standard normal entries: positive
// semidefinite, almost surely definite) and standard normal vectors. Deterministic given rng.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <random>

#include "semgraph/coord/covariance.h"
#include "semgraph/core/time.h"

namespace semgraph::testing {

inline core::Stamp Ms(std::int64_t ms) { return core::Stamp::Nanoseconds(ms * 1000000); }

inline Eigen::Matrix3d ExpR(const Eigen::Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(Eigen::AngleAxisd(th, w / th));
}
inline coord::Covariance6 RandomCovariance(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> L;
  for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
  return 1e-6 * L * L.transpose();
}
inline Eigen::Vector3d RandomVector(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng));
}

}  // namespace semgraph::testing
