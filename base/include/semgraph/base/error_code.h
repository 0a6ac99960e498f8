// File: semgraph/base/error_code.h
//
// The stable error codes of docs/rules.md (snake_case names on the wire), plus
// `semantic_mismatch` for a failed precondition of a semantic operation. One enum for every
// layer, so that a code crosses layers unchanged.
// Cost: ToString is a table lookup; it returns a static string (no allocation).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "semgraph/base/export.h"

namespace semgraph::base {

enum class ErrorCode : std::uint8_t {
  kOk = 0,
  // Semantic operations (this layer).
  kSemanticMismatch,
  // Input validation.
  kInvalidName,
  kInvalidNumber,
  kInvalidRotation,
  // Nodes.
  kDuplicateBody,
  kDuplicateFrame,
  kUnknownBody,
  kUnknownFrame,
  kFrameWithoutBody,
  kFrameBodyMismatch,
  // Pose edges.
  kSelfEdge,
  kRepresentationConstraint,
  kPoseNotConvertible,
  kConstantPoseChange,
  kMultiplePoseParents,
  kPoseCycle,
  kDuplicatePosePath,
  kTwistMergeConflict,
  // Twist edges.
  kTwistSameBody,
  kTwistNotConvertible,
  kMultipleTwistParents,
  kDuplicateTwistPath,
  // Removal.
  kNoSuchEdge,
  // Queries.
  kNoPosePath,
  kNoTwistPath,
  kQueryInvalidated,
  // Time (docs/time.md): adds and updates of stamped values, then queries.
  kStampMismatch,
  kStampTooOld,
  kDuplicateStamp,
  kExtrapolation,
  kStale,
  // Joints and robot models (docs/kinematics.md).
  kInvalidModel,
  kDuplicateJoint,
  kUnknownJoint,
  kJointLimit,
  kMimicJoint,
  kJointEdge,
  // Uncertainty (docs/uncertainty.md): checked right after invalid_rotation; appended here so
  // that the other codes keep their values.
  kInvalidCovariance,
  // Wrenches (docs/dynamics.md).
  kSelfWrench,
  kWrenchNotConvertible,
  kDuplicateWrench,
  kNoWrench,
  // Accelerations on twist edges (docs/dynamics.md).
  kNoAcceleration,
  kAccelerationNotConvertible,
};

inline constexpr int kNumErrorCodes = static_cast<int>(ErrorCode::kAccelerationNotConvertible) + 1;

/// The spec's snake_case name, e.g. "multiple_pose_parents"; "ok" for kOk.
[[nodiscard]] SEMGRAPH_BASE_EXPORT std::string_view ToString(ErrorCode code) noexcept;

/// Inverse of ToString; nullopt for an unknown name.
[[nodiscard]] SEMGRAPH_BASE_EXPORT std::optional<ErrorCode> ErrorCodeFromString(
    std::string_view name) noexcept;

}  // namespace semgraph::base
