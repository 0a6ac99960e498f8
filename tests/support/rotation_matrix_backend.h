// File: tests/support/rotation_matrix_backend.h
//
// A third, test-only backend: rotation matrix + vector (KDL's composite Pose<Vector, Rotation>).
// It imposes only [r] = [b] on orientations and poses (the rotation-matrix convention), so the
// point and the reference point are free. It exists to show that adding a backend touches no
// semantic check: it declares its constraints and implements the arithmetic, nothing else, and
// passes the same typed test suite as the shipped backends.
#pragma once

#include "semgraph/coord/backend.h"

namespace semgraph::testing {

struct RotationMatrixBackend {
  static constexpr const char* kName = "rotation_matrix";
  static constexpr coord::Constraints kConstraints{false, false, true};

  using Rotation = Eigen::Matrix3d;
  struct PoseCoords {
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
  };

  static Rotation FromMatrix(const Eigen::Matrix3d& R) noexcept { return R; }
  static Rotation FromQuaternion(const Eigen::Quaterniond& q) noexcept {
    return q.toRotationMatrix();
  }
  static Eigen::Matrix3d ToMatrix(const Rotation& M) noexcept { return M; }
  static Eigen::Quaterniond ToQuaternion(const Rotation& M) noexcept {
    return Eigen::Quaterniond(M).normalized();
  }
  static Rotation Multiply(const Rotation& A, const Rotation& B) noexcept { return A * B; }
  static Rotation Transpose(const Rotation& M) noexcept { return M.transpose(); }
  static Eigen::Vector3d Rotate(const Rotation& M, const Eigen::Vector3d& v) noexcept {
    return M * v;
  }
  static PoseCoords MakePose(const Rotation& M, const Eigen::Vector3d& p) noexcept {
    return {M, p};
  }
  static PoseCoords Identity() noexcept {
    return {Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
  }
  static Rotation RotationOf(const PoseCoords& X) noexcept { return X.rotation; }
  static Eigen::Vector3d TranslationOf(const PoseCoords& X) noexcept { return X.translation; }
  static PoseCoords ComposeChain(const PoseCoords& X, const PoseCoords& Y) noexcept {
    return {Y.rotation * X.rotation, Y.rotation * X.translation + Y.translation};
  }
  static PoseCoords InvertChain(const PoseCoords& X) noexcept {
    const Eigen::Matrix3d R_inv = X.rotation.transpose();
    return {R_inv, -(R_inv * X.translation)};
  }
};

static_assert(coord::Backend<RotationMatrixBackend>);

}  // namespace semgraph::testing
