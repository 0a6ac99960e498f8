// Acceleration queries (scene_graph.h "accelerations"; contract: accelerations.h). Planned as
// twist queries (PlanTwist) and evaluated by the one evaluator (evaluate.h: AccelerationStep,
// AccelerationComposer), under the optimistic read of every one-shot query. Under a time policy
// (docs/dynamics.md, "Stamped accelerations"): the same answer with every edge read at the
// policy's time (timed_read.h), through the driver of every timed query (RunTimed).
#include "angular_velocity.h"
#include "optimistic_read.h"
#include "semgraph/core/scene_graph.h"
#include "time_errors.h"

namespace semgraph::core {

using base::Unexpected;

namespace {

// The acceleration of a planned twist query: every step's acceleration composed, or
// no_acceleration naming the first edge on the path without one (its head frame in `name`,
// its tail body in `other`). Every step is read even after a missing one, so that under a time
// policy every edge counts (the latest common time, an edge without data at the time: its
// error comes first). noexcept, allocation-free.
template <coord::Backend B>
QueryResult<coord::Acceleration> AnswerAcceleration(
    const topology::SceneTopology& t, const internal::ForestSource<B>& src,
    const Expected<TwistPlan, QueryError>& plan) noexcept {
  if (!plan) return Unexpected{plan.error()};
  internal::AccelerationComposer composer;
  TwistEdgeIndex missing;
  ForEachTwistStep(t, *plan, [&](const TwistStep<ForestChain>& step) {
    internal::Motion m;
    bool present = false;
    internal::AccelerationStep<B>(src, step, m, present);
    if (!present && !missing.is_valid()) missing = step.edge;
    if (!missing.is_valid()) composer.Add(step, m);
  });
  if (missing.is_valid()) {
    QueryError e;
    e.code = ErrorCode::kNoAcceleration;
    e.field = semantics::Field::kBody;
    const auto& edge = t.twist_edge(missing);
    e.name = t.frame_name_id(edge.head);
    e.other = t.body_name_id(edge.tail);
    return Unexpected{e};
  }
  const semantics::TwistSemantics& q = plan->semantics;
  const internal::Motion m = composer.Result();
  return coord::Acceleration{
      semantics::AccelerationSemantics{q.point, q.body, q.ref_body, q.coordinate_frame}, m.a,
      m.alpha};
}

}  // namespace

template <coord::Backend B>
QueryResult<coord::Acceleration> SceneGraph<B>::GetAcceleration(
    const TwistSpec& spec) const noexcept {
  return internal::ReadValidated(topology_, [&] {
    return AnswerAcceleration(topology_, source(), PlanTwist(topology_, spec));
  });
}

template <coord::Backend B>
QueryResult<LinearAcceleration> SceneGraph<B>::GetLinearAcceleration(
    const TwistSpec& spec) const noexcept {
  auto A = GetAcceleration(spec);
  if (!A) return Unexpected{A.error()};
  return LinearAcceleration{A->semantics, A->linear};
}

template <coord::Backend B>
QueryResult<AngularAcceleration> SceneGraph<B>::GetAngularAcceleration(
    const TwistSpec& spec) const noexcept {
  auto A = internal::TwistOfAngularVelocity(
      spec, [this](const TwistSpec& s) { return GetAcceleration(s); });
  if (!A) return Unexpected{A.error()};
  return AngularAcceleration{A->semantics, A->angular};
}

// The policy's errors (an edge without data at the time, stale) come before no_acceleration:
// RunTimed reports them from the context of an evaluation that read every edge.
template <coord::Backend B>
QueryResult<Timed<coord::Acceleration>> SceneGraph<B>::GetAcceleration(
    const TwistSpec& spec, const TimePolicy& policy) const noexcept {
  return internal::ReadValidated(topology_, [&]() -> QueryResult<Timed<coord::Acceleration>> {
    const auto plan = PlanTwist(topology_, spec);
    if (auto e = internal::PlanOrPolicyError(plan, internal::PartsOf(policy).valid())) {
      return Unexpected{*e};
    }
    std::optional<QueryResult<coord::Acceleration>> answer;
    TimeReport report;
    if (auto e = RunTimed(policy, report, nullptr, [&](internal::TimeContext& tc) {
          answer = AnswerAcceleration(topology_, internal::ForestSource<B>(topology_, values_, &tc),
                                      plan);
        })) {
      return Unexpected{*e};
    }
    if (!*answer) return Unexpected{answer->error()};
    return Timed<coord::Acceleration>{**answer, report};
  });
}

template <coord::Backend B>
QueryResult<Timed<LinearAcceleration>> SceneGraph<B>::GetLinearAcceleration(
    const TwistSpec& spec, const TimePolicy& policy) const noexcept {
  auto A = GetAcceleration(spec, policy);
  if (!A) return Unexpected{A.error()};
  return Timed<LinearAcceleration>{{A->value.semantics, A->value.linear}, A->time};
}

template <coord::Backend B>
QueryResult<Timed<AngularAcceleration>> SceneGraph<B>::GetAngularAcceleration(
    const TwistSpec& spec, const TimePolicy& policy) const noexcept {
  auto A = internal::TwistOfAngularVelocity(
      spec, [&](const TwistSpec& s) { return GetAcceleration(s, policy); });
  if (!A) return Unexpected{A.error()};
  return Timed<AngularAcceleration>{{A->value.semantics, A->value.angular}, A->time};
}

// Planned and flattened on a validated snapshot of the topology, as CompileTwist.
template <coord::Backend B>
Expected<CompiledAcceleration<B>, QueryError> SceneGraph<B>::CompileAcceleration(
    const TwistSpec& spec) const {
  return internal::ReadValidated(topology_, [&]() -> Expected<CompiledAcceleration<B>, QueryError> {
    auto plan = PlanTwist(topology_, spec);
    if (!plan) return Unexpected{plan.error()};
    return CompiledAcceleration<B>(topology_, values_, *plan);
  });
}

template <coord::Backend B>
std::optional<coord::Acceleration> SceneGraph<B>::acceleration_value(FrameIndex f) const noexcept {
  if (!f.is_valid() || f.value() >= topology_.num_frames()) return std::nullopt;
  const TwistEdgeIndex e = topology_.twist_edge_of(f);
  if (!e.is_valid() || !values_.HasAcceleration(e.value())) return std::nullopt;
  const TwistAndAcceleration r = values_.A_DH[e.value()].Load();
  const auto& edge = topology_.twist_edge(e);
  return coord::Acceleration{
      semantics::AccelerationSemantics{topology_.FrameSem(f).origin(), topology_.BodyOfSem(f),
                                       topology_.BodySem(edge.tail), topology_.FrameSem(f).axes()},
      r.A.a_DHo_H, r.A.alpha_DH_H};
}

#define SEMGRAPH_INSTANTIATE_ACCELERATION_QUERIES(B)                                              \
  template QueryResult<coord::Acceleration> SceneGraph<B>::GetAcceleration(const TwistSpec&)      \
      const noexcept;                                                                             \
  template QueryResult<LinearAcceleration> SceneGraph<B>::GetLinearAcceleration(const TwistSpec&) \
      const noexcept;                                                                             \
  template QueryResult<AngularAcceleration> SceneGraph<B>::GetAngularAcceleration(                \
      const TwistSpec&) const noexcept;                                                           \
  template QueryResult<Timed<coord::Acceleration>> SceneGraph<B>::GetAcceleration(                \
      const TwistSpec&, const TimePolicy&) const noexcept;                                        \
  template QueryResult<Timed<LinearAcceleration>> SceneGraph<B>::GetLinearAcceleration(           \
      const TwistSpec&, const TimePolicy&) const noexcept;                                        \
  template QueryResult<Timed<AngularAcceleration>> SceneGraph<B>::GetAngularAcceleration(         \
      const TwistSpec&, const TimePolicy&) const noexcept;                                        \
  template std::optional<coord::Acceleration> SceneGraph<B>::acceleration_value(FrameIndex)       \
      const noexcept;                                                                             \
  template Expected<CompiledAcceleration<B>, QueryError> SceneGraph<B>::CompileAcceleration(      \
      const TwistSpec&) const;
SEMGRAPH_INSTANTIATE_ACCELERATION_QUERIES(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_ACCELERATION_QUERIES(coord::HomogeneousBackend)

}  // namespace semgraph::core
