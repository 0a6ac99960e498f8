// File: semgraph/coord/backend.h
//
// The coordinate backend concept: the minimum a numeric representation must provide so that
// every checked operation in operations.h works with it (about six functions, as the original
// library promised). Semantic checks never depend on the backend; each backend only *declares*
// the constraints its representation imposes (Constraints) and implements the arithmetic.
//
// A backend B provides:
//   B::kName                       "quaternion", "homogeneous", ...
//   B::kConstraints                what poses/orientations it can express (Constraints below)
//   B::Rotation                    an orientation operator (unit quaternion, 3x3 matrix, ...)
//   B::PoseCoords                  a pose: rotation + translation in one value
//   B::FromMatrix(R), B::FromQuaternion(q)   from a validated proper rotation
//   B::ToMatrix(M), B::ToQuaternion(M)
//   B::Multiply(M1, M2)            operator product M1*M2
//   B::Transpose(M)                inverse operator
//   B::Rotate(M, v)                M*v
//   B::MakePose(M, p), B::RotationOf(X), B::TranslationOf(X)
//   B::Identity()                  the identity pose (identity rotation, zero translation)
//   B::ComposeChain(X, Y)          pose chain T_Y * T_X: R_Y R_X, R_Y p_X + p_Y (the hot path)
//   B::InvertChain(X)              T_X^-1: R^T, -R^T p
// Every function is noexcept and allocation-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <concepts>
#include <string_view>

namespace semgraph::coord {

/// Constraints a representation imposes on the semantics it can hold (semantics-research §4).
struct Constraints {
  /// Pose: point = origin of the orientation frame (e = a).
  bool pose_point_is_origin = false;
  /// Pose: reference point = origin of the reference orientation frame (f = b).
  bool pose_ref_point_is_origin = false;
  /// Pose and orientation: coordinate frame = reference orientation frame ([r] = [b]).
  bool coordinate_frame_is_ref_orientation = false;
};

template <class B>
concept Backend = requires(const typename B::Rotation& M, const typename B::PoseCoords& X,
                           const Eigen::Matrix3d& R, const Eigen::Quaterniond& q,
                           const Eigen::Vector3d& p) {
  { B::kName } -> std::convertible_to<const char*>;
  { B::kConstraints } -> std::convertible_to<Constraints>;
  { B::FromMatrix(R) }
  noexcept->std::same_as<typename B::Rotation>;
  { B::FromQuaternion(q) }
  noexcept->std::same_as<typename B::Rotation>;
  { B::ToMatrix(M) }
  noexcept->std::same_as<Eigen::Matrix3d>;
  { B::ToQuaternion(M) }
  noexcept->std::same_as<Eigen::Quaterniond>;
  { B::Multiply(M, M) }
  noexcept->std::same_as<typename B::Rotation>;
  { B::Transpose(M) }
  noexcept->std::same_as<typename B::Rotation>;
  { B::Rotate(M, p) }
  noexcept->std::same_as<Eigen::Vector3d>;
  { B::MakePose(M, p) }
  noexcept->std::same_as<typename B::PoseCoords>;
  { B::Identity() }
  noexcept->std::same_as<typename B::PoseCoords>;
  { B::RotationOf(X) }
  noexcept->std::same_as<typename B::Rotation>;
  { B::TranslationOf(X) }
  noexcept->std::same_as<Eigen::Vector3d>;
  { B::ComposeChain(X, X) }
  noexcept->std::same_as<typename B::PoseCoords>;
  { B::InvertChain(X) }
  noexcept->std::same_as<typename B::PoseCoords>;
};

}  // namespace semgraph::coord
