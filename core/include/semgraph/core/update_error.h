// File: semgraph/core/update_error.h
//
// UpdateError: why a real-time update (SceneGraph::SetPose, SetTwist, SetJointPositions /
// Velocities / State, by plain or converting handle, stamped or not) was refused, in numbers:
// the code, which input and which of its numbers, the number, and the limit it broke. Each
// setter fills it through its optional last argument `why`, so that a caller that must say more
// than the code (the Python bindings, the DDS mirror) reads the setter's own verdict instead of
// checking the values again with copied limits.
//
// Invariants: after a setter returns, why->code is the code it returned; the other fields are
// meaningful for kInvalidNumber, kInvalidRotation and kJointLimit only (zero otherwise).
// Cost: trivially copyable, no string (40 bytes); filling it is O(1), noexcept, allocation-free,
// so it is part of the real-time path. Describe() formats it, off the hot path.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>

#include "semgraph/base/error_code.h"
#include "semgraph/coord/error.h"
#include "semgraph/core/export.h"

namespace semgraph::core {

struct UpdateError {
  base::ErrorCode code = base::ErrorCode::kOk;
  /// kInvalidNumber / kInvalidRotation / kJointLimit: the problem, the input it is in (role:
  /// position, quaternion, rotation matrix, linear or angular velocity, joint position or
  /// velocity), which of the input's numbers (component, in coord::Error's order), and the
  /// number itself or, for a rotation, its measured deviation (magnitude).
  coord::ValueDetail value;
  /// The bound `value.magnitude` broke: coord::kMaxMagnitude, coord::kRotationTolerance, or
  /// the joint's lower or upper limit (kJointLimit); 0 when the rule has no number (not
  /// finite, a reflection).
  double limit = 0.0;
  /// Joint setters: the position in the group (the span's index) of the joint it is about.
  std::uint32_t joint = 0;

  /// As a coord::Error (code and value), for coord::Describe and the callers that take one.
  [[nodiscard]] coord::Error error() const noexcept {
    coord::Error e;
    e.code = code;
    e.value = value;
    return e;
  }
};

static_assert(std::is_trivially_copyable_v<UpdateError> && sizeof(UpdateError) <= 40);

/// One line saying what was wrong and which limit it broke, e.g. "position component 1 is
/// 2e+12 (magnitude above 1e+12)", "quaternion norm differs from 1 by 0.2 (more than 1e-06)",
/// "joint position 3 of the group is 2.5, above the joint's upper limit 2"; the code's name
/// for the other codes. Allocates (off the real-time path).
[[nodiscard]] SEMGRAPH_CORE_EXPORT std::string Describe(const UpdateError& error);

namespace internal {
/// The setters' reports: fill *why (when given) and return the code.
inline base::ErrorCode Report(UpdateError* why, base::ErrorCode code) noexcept {
  if (why != nullptr) *why = UpdateError{code, {}, 0.0, 0};
  return code;
}
inline base::ErrorCode Report(UpdateError* why, const coord::Error& e) noexcept {
  if (why != nullptr) *why = UpdateError{e.code, e.value, coord::LimitOf(e.value.problem), 0};
  return e.code;
}
}  // namespace internal

}  // namespace semgraph::core
