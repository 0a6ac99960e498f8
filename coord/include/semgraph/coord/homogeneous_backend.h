// File: semgraph/coord/homogeneous_backend.h
//
// HomogeneousBackend: a 4x4 homogeneous transform (Eigen::Isometry3d), orientations as 3x3
// rotation matrices. Imposes (paper §IV-D): point = origin of [a], reference point = origin of
// [b], and [r] = [b] on poses; [r] = [b] on orientations. Positions and twists are 3-vectors and
// unconstrained. Operations whose result breaks a constraint fail with
// representation_constraint naming "homogeneous".
// Cost: ComposeChain one 3x3*3x3 and one 3x3*3 product (~63 flops), no allocation.
#pragma once

#include "semgraph/coord/backend.h"
#include "semgraph/coord/export.h"

namespace semgraph::coord {

struct SEMGRAPH_COORD_EXPORT HomogeneousBackend {
  static constexpr const char* kName = "homogeneous";
  static constexpr Constraints kConstraints{true, true, true};

  using Rotation = Eigen::Matrix3d;
  using PoseCoords = Eigen::Isometry3d;

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
    PoseCoords X = PoseCoords::Identity();
    X.linear() = M;
    X.translation() = p;
    return X;
  }
  static PoseCoords Identity() noexcept { return PoseCoords::Identity(); }
  static Rotation RotationOf(const PoseCoords& X) noexcept { return X.linear(); }
  static Eigen::Vector3d TranslationOf(const PoseCoords& X) noexcept { return X.translation(); }
  /// Y X for rigid transforms: R_Y R_X, R_Y p_X + p_Y, bottom row [0 0 0 1]. Written as the two
  /// products and always inlined, for the reason given at QuaternionBackend::Rotate: GCC 12 in
  /// a large translation unit calls Eigen's general transform product out of line.
  [[gnu::always_inline]] static PoseCoords ComposeChain(const PoseCoords& X,
                                                        const PoseCoords& Y) noexcept {
    PoseCoords Z;
    Z.linear().noalias() = Y.linear() * X.linear();
    Z.translation().noalias() = Y.linear() * X.translation();
    Z.translation() += Y.translation();
    Z.makeAffine();
    return Z;
  }
  static PoseCoords InvertChain(const PoseCoords& X) noexcept { return X.inverse(Eigen::Isometry); }
};

static_assert(Backend<HomogeneousBackend>);

}  // namespace semgraph::coord
