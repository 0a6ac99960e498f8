// Compiled acceleration queries (contract: compiled_acceleration.h): the twist plan's steps
// flattened (as CompiledTwist's), evaluated by the one evaluator (evaluate.h).
#include "semgraph/core/compiled_acceleration.h"

namespace semgraph::core {

template <coord::Backend B>
CompiledAcceleration<B>::CompiledAcceleration(const topology::SceneTopology& t,
                                              const EdgeValues<B>& values, const TwistPlan& plan)
    : CompiledQuery<B>(t, values),
      semantics_{plan.semantics.point, plan.semantics.body, plan.semantics.ref_body,
                 plan.semantics.coordinate_frame} {
  ForEachTwistStep(t, plan, [&](const TwistStep<ForestChain>& step) {
    TwistStep<typename CompiledQuery<B>::Chain> flat;
    flat.edge = step.edge;
    flat.epoch = values.A_DH[step.edge.value()].epoch();
    flat.invert = step.invert;
    flat.ref_side = step.ref_side;
    if ((flat.move_point = step.move_point)) flat.eh = this->Flatten(t, step.eh);
    if ((flat.change_frame = step.change_frame)) flat.hr = this->Flatten(t, step.hr);
    steps_.push_back(flat);
  });
}

// Every step read (a removed edge is reported as such even after an edge without an
// acceleration), then kNoAcceleration or the composition into m.
template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Compose(const internal::FlatSource<B>& src,
                                           internal::Motion& out) const noexcept {
  internal::AccelerationComposer composer;
  bool missing = false;
  for (const auto& step : steps_) {
    internal::Motion m;
    bool present = false;
    if (!internal::AccelerationStep<B>(src, step, m, present)) return ErrorCode::kQueryInvalidated;
    missing = missing || !present;
    if (!missing) composer.Add(step.ref_side, m);
  }
  if (missing) return ErrorCode::kNoAcceleration;
  out = composer.Result();
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Evaluate(Eigen::Vector3d& a_DCe_R,
                                            Eigen::Vector3d& alpha_DC_R) const noexcept {
  internal::Motion m;
  const ErrorCode code = Compose(this->source(), m);
  if (code != ErrorCode::kOk) return code;
  a_DCe_R = m.a;
  alpha_DC_R = m.alpha;
  return ErrorCode::kOk;
}

// RunTimed knows only invalidation; a missing acceleration is carried beside it.
template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Evaluate(Eigen::Vector3d& a_DCe_R, Eigen::Vector3d& alpha_DC_R,
                                            const TimePolicy& policy,
                                            TimeReport& report) const noexcept {
  internal::Motion m;
  ErrorCode composed = ErrorCode::kOk;
  const ErrorCode code = this->RunTimed(policy, report, [&](const internal::FlatSource<B>& src) {
    composed = Compose(src, m);
    return composed != ErrorCode::kQueryInvalidated;
  });
  if (code != ErrorCode::kOk) return code;
  if (composed != ErrorCode::kOk) return composed;
  a_DCe_R = m.a;
  alpha_DC_R = m.alpha;
  return ErrorCode::kOk;
}

template class CompiledAcceleration<coord::QuaternionBackend>;
template class CompiledAcceleration<coord::HomogeneousBackend>;

}  // namespace semgraph::core
