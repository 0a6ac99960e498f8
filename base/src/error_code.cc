#include "semgraph/base/error_code.h"

#include <array>
#include <cstdio>
#include <cstdlib>

#include "semgraph/base/demand.h"

namespace semgraph::base {
namespace {
constexpr std::array<std::string_view, kNumErrorCodes> kNames = {
    "ok",
    "semantic_mismatch",
    "invalid_name",
    "invalid_number",
    "invalid_rotation",
    "duplicate_body",
    "duplicate_frame",
    "unknown_body",
    "unknown_frame",
    "frame_without_body",
    "frame_body_mismatch",
    "self_edge",
    "representation_constraint",
    "pose_not_convertible",
    "constant_pose_change",
    "multiple_pose_parents",
    "pose_cycle",
    "duplicate_pose_path",
    "twist_merge_conflict",
    "twist_same_body",
    "twist_not_convertible",
    "multiple_twist_parents",
    "duplicate_twist_path",
    "no_such_edge",
    "no_pose_path",
    "no_twist_path",
    "query_invalidated",
    "stamp_mismatch",
    "stamp_too_old",
    "duplicate_stamp",
    "extrapolation",
    "stale",
    "invalid_model",
    "duplicate_joint",
    "unknown_joint",
    "joint_limit",
    "mimic_joint",
    "joint_edge",
    "invalid_covariance",
    "self_wrench",
    "wrench_not_convertible",
    "duplicate_wrench",
    "no_wrench",
    "no_acceleration",
    "acceleration_not_convertible",
};
}  // namespace

std::string_view ToString(ErrorCode code) noexcept {
  const auto i = static_cast<std::size_t>(code);
  return i < kNames.size() ? kNames[i] : std::string_view("unknown_error");
}

std::optional<ErrorCode> ErrorCodeFromString(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<ErrorCode>(i);
  }
  return std::nullopt;
}

void DemandFailed(const char* condition, const char* file, int line) noexcept {
  std::fprintf(stderr, "semgraph: internal check failed: %s at %s:%d\n", condition, file, line);
  std::abort();
}

}  // namespace semgraph::base
