// File: semgraph/core/uncertainty.h
//
// The public types of covariances on edges and answers (docs/uncertainty.md).
//   CovarianceInput     a covariance given with a value (AddPose, AddTwist): the 6x6 matrix
//                       (none: the value is exact), its order and, for a pose, its convention.
//   WithCovariance<T,N> an answer with the first-order covariance of its coordinates (N = 6 for
//                       a pose or twist, 3 for a position, orientation or velocity).
// Plain values; no allocation.
#pragma once

#include <Eigen/Core>

#include "semgraph/coord/covariance.h"

namespace semgraph::core {

using coord::Covariance6;
using coord::CovarianceOrder;
using coord::PoseCovarianceConvention;

/// A covariance given with a value. `matrix` null: the value is exact (an update then sets the
/// edge's covariance to zero). `convention` kBody is accepted for a pose in edge form only.
struct CovarianceInput {
  const Covariance6* matrix = nullptr;
  CovarianceOrder order = CovarianceOrder::kLinearAngular;
  PoseCovarianceConvention convention = PoseCovarianceConvention::kCoordinates;
};

/// An answer with its covariance (docs/uncertainty.md §3: of the answer's own coordinates, in
/// its point, frames and [r]).
template <class T, int N>
struct WithCovariance {
  T value;
  Eigen::Matrix<double, N, N> covariance;
};

}  // namespace semgraph::core
