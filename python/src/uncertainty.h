// File: python/src/uncertainty.h
//
// The covariance keywords of add_pose / add_twist (docs/uncertainty.md): covariance= (a 6x6
// list, tuple or numpy array), covariance_order= ('linear_angular' default, 'angular_linear'),
// convention= ('coordinates' default, 'body'; poses only). Read before the writer lock; the
// numbers themselves are the core's to judge (invalid_number, invalid_covariance).
#pragma once

#include <utility>

#include "common.h"
#include "semgraph/core/uncertainty.h"

namespace semgraph::python {

/// The covariance keywords as read; Input() points into this object (keep it alive).
struct CovarianceArgs {
  bool given = false;
  coord::Covariance6 S = coord::Covariance6::Zero();
  core::CovarianceOrder order = core::CovarianceOrder::kLinearAngular;
  core::PoseCovarianceConvention convention = core::PoseCovarianceConvention::kCoordinates;
  [[nodiscard]] core::CovarianceInput Input() const {
    return {given ? &S : nullptr, order, convention};
  }
};

/// covariance None: none given (then order / convention must be None too: ValueError).
/// A shape other than (6, 6): ValueError; an order or convention not one of the names:
/// ValueError. `convention` is py::none() for a twist.
CovarianceArgs ReadCovarianceArgs(py::handle covariance, py::handle order, py::handle convention,
                                  const char* function);

/// 'linear_angular' (None too) or 'angular_linear'; ValueError otherwise.
core::CovarianceOrder CovarianceOrderArg(py::handle order, const char* function,
                                         const char* argument);

/// (result, covariance): what the queries with covariance return, the covariance a numpy (N, N)
/// array (a copy).
template <int N>
py::tuple WithCovariance(py::object result, const Eigen::Matrix<double, N, N>& S) {
  const Eigen::Matrix<double, N, N, Eigen::RowMajor> rows = S;
  return py::make_tuple(std::move(result), Array(rows.data(), {N, N}));
}

/// SceneGraph.pose_with_covariance ... angular_velocity_with_covariance (uncertainty.cc).
void BindUncertainty(GraphClass& graph);

}  // namespace semgraph::python
