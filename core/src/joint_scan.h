// Private to core/src: the one check of a joint group's values before a set, shared by the
// unstamped and the stamped group setters (SetGroup: joints.cc; SetGroupStamped:
// joint_time.cc). One pass that keeps flags only, so the accepted case stays cheap; the joint
// that breaks a rule is found by a second pass (RefuseJoints) only on refusal.
// Real-time path: noexcept, allocation-free.
#pragma once

#include <cmath>
#include <cstddef>

#include "semgraph/base/error_code.h"
#include "semgraph/core/joints.h"

namespace semgraph::core::internal {

/// The tolerance of a joint limit check (all joint setters).
inline constexpr double kLimitSlack = 1e-9;

/// The first failing rule over the whole group in the rules' order invalid_number ->
/// unknown_joint -> mimic_joint -> joint_limit (kOk: none). q / qdot / qddot may be null (not
/// set); only positions are limited.
/// `extra(i, j)` is called for each known movable joint j at position i, for the caller's own
/// checks (reported after these). O(group size).
template <class Extra>
[[nodiscard]] base::ErrorCode ScanJointGroup(const JointTable& joints, const JointGroup& group,
                                             const double* q, const double* qdot,
                                             const double* qddot, Extra&& extra) noexcept {
  bool bad_number = false, unknown = false, mimic = false, limit = false;
  for (std::size_t i = 0; i < group.joints.size(); ++i) {
    bad_number |= (q && !std::isfinite(q[i])) || (qdot && !std::isfinite(qdot[i])) ||
                  (qddot && !std::isfinite(qddot[i]));
    const JointRecord* j = joints.Get(group.joints[i]);
    if (!j || !j->movable()) {
      unknown = true;
      continue;
    }
    mimic |= j->is_mimic();
    limit |=
        q && j->limited() && !(q[i] >= j->lower - kLimitSlack && q[i] <= j->upper + kLimitSlack);
    extra(i, *j);
  }
  if (bad_number) return base::ErrorCode::kInvalidNumber;
  if (unknown) return base::ErrorCode::kUnknownJoint;
  if (mimic) return base::ErrorCode::kMimicJoint;
  if (limit) return base::ErrorCode::kJointLimit;
  return base::ErrorCode::kOk;
}

}  // namespace semgraph::core::internal
