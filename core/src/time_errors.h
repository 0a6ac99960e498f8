// Private to core/src: the errors of timed queries and their one driver, shared by the timed
// queries (time_query.cc) and the timed queries with covariance (time_uncertainty.cc).
//   FromFailure         a TimeFailure (which edge, its samples, the time asked) as a QueryError
//   PlanOrPolicyError   invalid_name -> invalid_number (the policy's horizon) -> the plan's
//   RepresentationError the backend's check of an answer's value
//   SceneGraph::RunTimed  eval(TimeContext&) under a policy (internal::RunPolicy)
// noexcept where the queries are; QueryError carries no allocation.
#pragma once

#include <optional>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core {
namespace internal {

using semantics::Field;

inline QueryError FromFailure(const topology::SceneTopology& t, const TimeFailure& f) {
  QueryError e;
  e.code = f.code;
  e.time.twist_edge = f.twist_edge;
  e.time.single_sample = f.single_sample;
  e.time.first = f.first;
  e.time.last = f.last;
  e.time.asked = f.asked;
  if (f.twist_edge) {
    const auto& edge = t.twist_edge(TwistEdgeIndex(f.index));
    e.name = t.frame_name_id(edge.head);
    e.other = t.body_name_id(edge.tail);
  } else {
    const FrameIndex h(f.index);
    e.name = t.frame_name_id(h);
    e.other = t.frame_name_id(t.pose_parent(h));
  }
  return e;
}

inline QueryError InvalidHorizon() {
  QueryError e;
  e.code = ErrorCode::kInvalidNumber;
  return e;
}

// invalid_name -> invalid_number (the policy) -> the plan's other errors.
template <class Plan>
std::optional<QueryError> PlanOrPolicyError(const Expected<Plan, QueryError>& plan,
                                            bool policy_valid) {
  if (!plan && plan.error().code == ErrorCode::kInvalidName) return plan.error();
  if (!policy_valid) return InvalidHorizon();
  if (!plan) return plan.error();
  return std::nullopt;
}

// The backend's check of a query's value (not of a position's), as the query's error.
template <coord::Backend B, class Semantics>
std::optional<QueryError> RepresentationError(const Semantics& q) noexcept {
  auto ok = coord::CheckRepresentation<B>(q);
  if (ok) return std::nullopt;
  QueryError e;
  e.code = ok.error().code;
  e.detail = ok.error();
  return e;
}

}  // namespace internal

// The one driver of every timed one-shot query: eval(TimeContext&) runs the evaluator.
template <coord::Backend B>
template <class Eval>
std::optional<QueryError> SceneGraph<B>::RunTimed(const TimePolicy& policy, TimeReport& report,
                                                  internal::EdgeRecorder* recorder,
                                                  Eval&& eval) const noexcept {
  internal::TimeContext base;
  base.histories = &values_.history;
  base.topology = &topology_;
  base.recorder = recorder;
  internal::TimeFailure failure;
  const ErrorCode code = internal::RunPolicy(
      internal::PartsOf(policy), base,
      [&](internal::TimeContext& tc) {
        eval(tc);
        return ErrorCode::kOk;
      },
      report, &failure);
  if (code != ErrorCode::kOk) return internal::FromFailure(topology_, failure);
  return std::nullopt;
}

}  // namespace semgraph::core
