// SceneGraph queries, one-shot and compiled: plan (query_plan.cc), then the backend's only
// check (representation_constraint), then the one evaluator (evaluate.h). Adds: add.cc;
// real-time updates: realtime.cc; text: describe.cc; Dump and checks: scene_graph_debug.cc.
#include "semgraph/core/scene_graph.h"

#include "angular_velocity.h"
#include "optimistic_read.h"

namespace semgraph::core {

using base::Unexpected;
using internal::Part;

namespace {
QueryError QError(const coord::Error& detail) {
  QueryError e;
  e.code = detail.code;
  e.detail = detail;
  return e;
}

// Answers a planned pose, position or orientation query: the backend's check where the query
// has one (not a position: it has no orientation to represent), then the evaluator. Each
// one-shot query is planned exactly once, by names or by ids.
// Inlined into the attempt of ReadValidated, as it was into the query before: the one-shot
// path's cost (docs/performance.md).
template <coord::Backend B, class Plan>
[[gnu::always_inline]] inline auto Answer(const internal::ForestSource<B>& src,
                                          const Expected<Plan, QueryError>& plan) noexcept
    -> QueryResult<typename internal::PartTraits<B, internal::kPartOf<Plan>>::Result> {
  using Traits = internal::PartTraits<B, internal::kPartOf<Plan>>;
  if (!plan) return Unexpected{plan.error()};
  if constexpr (internal::kPartOf<Plan> != Part::kTranslation) {
    auto ok = coord::CheckRepresentation<B>(plan->semantics);
    if (!ok) return Unexpected{QError(ok.error())};
  }
  typename Traits::Result answer{plan->semantics, Traits::Initial()};
  internal::EvaluatePart<B, internal::kPartOf<Plan>>(src, plan->steps, answer.value);
  return answer;
}

template <coord::Backend B>
QueryResult<coord::Twist> Answer(const topology::SceneTopology& t,
                                 const internal::ForestSource<B>& src,
                                 const Expected<TwistPlan, QueryError>& plan) noexcept {
  if (!plan) return Unexpected{plan.error()};
  Eigen::Vector3d v_DCe_R = Eigen::Vector3d::Zero(), w_DC_R = Eigen::Vector3d::Zero();
  ForEachTwistStep(t, *plan, [&](const TwistStep<ForestChain>& step) {
    internal::AccumulateTwistStep<B>(src, step, v_DCe_R, w_DC_R);
  });
  return coord::Twist{plan->semantics, v_DCe_R, w_DC_R};
}
}  // namespace

// ====================================================================== one-shot

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Pose> SceneGraph<B>::GetPose(
    const semantics::PoseSemantics& q) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return Answer(source(), PlanPose(topology_, q)); });
}
template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Pose> SceneGraph<B>::GetPose(
    const PoseSpec& spec) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return Answer(source(), PlanPose(topology_, spec)); });
}

template <coord::Backend B>
QueryResult<coord::Position> SceneGraph<B>::GetPosition(
    const semantics::PositionSemantics& q) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return Answer(source(), PlanPosition(topology_, q)); });
}
template <coord::Backend B>
QueryResult<coord::Position> SceneGraph<B>::GetPosition(const PoseSpec& spec) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return Answer(source(), PlanPosition(topology_, spec)); });
}

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Orientation> SceneGraph<B>::GetOrientation(
    const semantics::OrientationSemantics& q) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return Answer(source(), PlanOrientation(topology_, q)); });
}
template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Orientation> SceneGraph<B>::GetOrientation(
    const PoseSpec& spec) const noexcept {
  return internal::ReadValidated(
      topology_, [&] { return Answer(source(), PlanOrientation(topology_, spec)); });
}

template <coord::Backend B>
QueryResult<coord::Twist> SceneGraph<B>::GetTwist(
    const semantics::TwistSemantics& q) const noexcept {
  return internal::ReadValidated(
      topology_, [&] { return Answer(topology_, source(), PlanTwist(topology_, q)); });
}
template <coord::Backend B>
QueryResult<coord::Twist> SceneGraph<B>::GetTwist(const TwistSpec& spec) const noexcept {
  return internal::ReadValidated(
      topology_, [&] { return Answer(topology_, source(), PlanTwist(topology_, spec)); });
}

template <coord::Backend B>
QueryResult<coord::LinearVelocity> SceneGraph<B>::GetLinearVelocity(
    const TwistSpec& spec) const noexcept {
  auto tw = GetTwist(spec);
  if (!tw) return Unexpected{tw.error()};
  return coord::LinearOf(*tw);
}

template <coord::Backend B>
QueryResult<coord::AngularVelocity> SceneGraph<B>::GetAngularVelocity(
    const TwistSpec& spec) const noexcept {
  auto tw =
      internal::TwistOfAngularVelocity(spec, [this](const TwistSpec& s) { return GetTwist(s); });
  if (!tw) return Unexpected{tw.error()};
  return coord::AngularOf(*tw);
}

// ====================================================================== compiled

// Compile* plan and flatten on a validated snapshot of the topology (optimistic_read.h), so
// that a reader thread may compile while the writer changes the topology.
template <coord::Backend B>
Expected<CompiledPose<B>, QueryError> SceneGraph<B>::CompilePose(const PoseSpec& spec) const {
  return internal::ReadValidated(topology_, [&]() -> Expected<CompiledPose<B>, QueryError> {
    auto plan = PlanPose(topology_, spec);
    if (!plan) return Unexpected{plan.error()};
    if (auto ok = coord::CheckRepresentation<B>(plan->semantics); !ok)
      return Unexpected{QError(ok.error())};
    return CompiledPose<B>(topology_, values_, *plan);
  });
}

template <coord::Backend B>
Expected<CompiledPosition<B>, QueryError> SceneGraph<B>::CompilePosition(
    const PoseSpec& spec) const {
  return internal::ReadValidated(topology_, [&]() -> Expected<CompiledPosition<B>, QueryError> {
    auto plan = PlanPosition(topology_, spec);
    if (!plan) return Unexpected{plan.error()};
    return CompiledPosition<B>(topology_, values_, *plan);
  });
}

template <coord::Backend B>
Expected<CompiledOrientation<B>, QueryError> SceneGraph<B>::CompileOrientation(
    const PoseSpec& spec) const {
  return internal::ReadValidated(topology_, [&]() -> Expected<CompiledOrientation<B>, QueryError> {
    auto plan = PlanOrientation(topology_, spec);
    if (!plan) return Unexpected{plan.error()};
    if (auto ok = coord::CheckRepresentation<B>(plan->semantics); !ok)
      return Unexpected{QError(ok.error())};
    return CompiledOrientation<B>(topology_, values_, *plan);
  });
}

// The point is required, as for GetTwist (an angular velocity is the angular part of any
// point's twist: pass the coordinate frame as the point).
template <coord::Backend B>
Expected<CompiledTwist<B>, QueryError> SceneGraph<B>::CompileTwist(const TwistSpec& spec) const {
  return internal::ReadValidated(topology_, [&]() -> Expected<CompiledTwist<B>, QueryError> {
    auto plan = PlanTwist(topology_, spec);
    if (!plan) return Unexpected{plan.error()};
    return CompiledTwist<B>(topology_, values_, *plan);
  });
}

template class SceneGraph<coord::QuaternionBackend>;
template class SceneGraph<coord::HomogeneousBackend>;

}  // namespace semgraph::core
