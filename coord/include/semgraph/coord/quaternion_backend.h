// File: semgraph/coord/quaternion_backend.h
//
// QuaternionBackend (the default): unit quaternion (Hamilton, w x y z) + 3-vector. Imposes no
// constraint: any point, reference point and coordinate frame. An orientation expressed in [r]
// is the operator M = R[r<-b] R[b<-a] R[b<-r] as a quaternion; a pose is (q, p) with p the
// position of the point wrt the reference point in [r].
// Invariant: quaternions are unit (inputs are validated and normalized once; products of unit
// quaternions stay unit up to rounding, renormalized only where documented).
// Cost: ComposeChain 2 quaternion products worth of flops (~60), no allocation.
#pragma once

#include "semgraph/coord/backend.h"
#include "semgraph/coord/export.h"

namespace semgraph::coord {

struct SEMGRAPH_COORD_EXPORT QuaternionBackend {
  static constexpr const char* kName = "quaternion";
  static constexpr Constraints kConstraints{};

  using Rotation = Eigen::Quaterniond;
  struct PoseCoords {
    Eigen::Quaterniond rotation;
    Eigen::Vector3d translation;
  };
  /// Bytes of PoseCoords that hold data (the rest is alignment padding): stores copy only these.
  static constexpr std::size_t kPosePayloadBytes = sizeof(Eigen::Quaterniond) + sizeof(Eigen::Vector3d);

  static Rotation FromMatrix(const Eigen::Matrix3d& R) noexcept { return Rotation(R).normalized(); }
  static Rotation FromQuaternion(const Eigen::Quaterniond& q) noexcept { return q; }
  static Eigen::Matrix3d ToMatrix(const Rotation& M) noexcept { return M.toRotationMatrix(); }
  static Eigen::Quaterniond ToQuaternion(const Rotation& M) noexcept { return M; }
  static Rotation Multiply(const Rotation& A, const Rotation& B) noexcept { return A * B; }
  static Rotation Transpose(const Rotation& M) noexcept { return M.conjugate(); }
  static Eigen::Vector3d Rotate(const Rotation& M, const Eigen::Vector3d& v) noexcept {
    return M * v;
  }
  static PoseCoords MakePose(const Rotation& M, const Eigen::Vector3d& p) noexcept {
    return {M, p};
  }
  static Rotation RotationOf(const PoseCoords& X) noexcept { return X.rotation; }
  static Eigen::Vector3d TranslationOf(const PoseCoords& X) noexcept { return X.translation; }
  static PoseCoords ComposeChain(const PoseCoords& X, const PoseCoords& Y) noexcept {
    return {Y.rotation * X.rotation, Y.rotation * X.translation + Y.translation};
  }
  static PoseCoords InvertChain(const PoseCoords& X) noexcept {
    const Eigen::Quaterniond R_inv = X.rotation.conjugate();
    return {R_inv, -(R_inv * X.translation)};
  }
};

static_assert(Backend<QuaternionBackend>);
static_assert(sizeof(Eigen::Quaterniond) == 32 && sizeof(QuaternionBackend::PoseCoords) == 64,
              "kPosePayloadBytes assumes the rotation at offset 0 and the translation at 32");

}  // namespace semgraph::coord
