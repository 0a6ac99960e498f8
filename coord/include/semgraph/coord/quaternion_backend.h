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
  static constexpr std::size_t kPosePayloadBytes =
      sizeof(Eigen::Quaterniond) + sizeof(Eigen::Vector3d);

  static Rotation FromMatrix(const Eigen::Matrix3d& R) noexcept { return Rotation(R).normalized(); }
  static Rotation FromQuaternion(const Eigen::Quaterniond& q) noexcept { return q; }
  static Eigen::Matrix3d ToMatrix(const Rotation& M) noexcept { return M.toRotationMatrix(); }
  static Eigen::Quaterniond ToQuaternion(const Rotation& M) noexcept { return M; }
  static Rotation Multiply(const Rotation& A, const Rotation& B) noexcept { return A * B; }
  static Rotation Transpose(const Rotation& M) noexcept { return M.conjugate(); }
  /// q v q*, by Eigen's formula (t = 2 q_v x v; v + w t + q_v x t, the same operations in the
  /// same order, so the same bits), written out and always inlined: in a large translation unit
  /// GCC 12 stops inlining Eigen's `q * v` (--param inline-unit-growth), and the compiled-query
  /// loop then spills each edge to the stack around a call (1.38x the raw chain's instructions
  /// instead of 1.15x; bench/icount.sh). Every rotation of a vector by a quaternion goes here.
  [[gnu::always_inline]] static Eigen::Vector3d Rotate(const Rotation& q,
                                                       const Eigen::Vector3d& v) noexcept {
    const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
    double tx = y * v.z() - z * v.y(), ty = z * v.x() - x * v.z(), tz = x * v.y() - y * v.x();
    tx += tx;
    ty += ty;
    tz += tz;
    return Eigen::Vector3d(v.x() + w * tx + (y * tz - z * ty), v.y() + w * ty + (z * tx - x * tz),
                           v.z() + w * tz + (x * ty - y * tx));
  }
  static PoseCoords MakePose(const Rotation& M, const Eigen::Vector3d& p) noexcept {
    return {M, p};
  }
  static PoseCoords Identity() noexcept {
    return {Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()};
  }
  static Rotation RotationOf(const PoseCoords& X) noexcept { return X.rotation; }
  static Eigen::Vector3d TranslationOf(const PoseCoords& X) noexcept { return X.translation; }
  static PoseCoords ComposeChain(const PoseCoords& X, const PoseCoords& Y) noexcept {
    return {Y.rotation * X.rotation, Rotate(Y.rotation, X.translation) + Y.translation};
  }
  static PoseCoords InvertChain(const PoseCoords& X) noexcept {
    const Eigen::Quaterniond R_inv = X.rotation.conjugate();
    return {R_inv, -Rotate(R_inv, X.translation)};
  }
};

static_assert(Backend<QuaternionBackend>);
static_assert(sizeof(Eigen::Quaterniond) == 32 && sizeof(QuaternionBackend::PoseCoords) == 64,
              "kPosePayloadBytes assumes the rotation at offset 0 and the translation at 32");

}  // namespace semgraph::coord
