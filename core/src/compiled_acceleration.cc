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

template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Evaluate(Eigen::Vector3d& a_DCe_R,
                                            Eigen::Vector3d& alpha_DC_R) const noexcept {
  const internal::FlatSource<B> src = this->source();
  internal::AccelerationComposer composer;
  bool missing = false;  // reported only when no edge of the path was removed (every step read)
  for (const auto& step : steps_) {
    internal::Motion m;
    bool present = false;
    if (!internal::AccelerationStep<B>(src, step, m, present)) return ErrorCode::kQueryInvalidated;
    missing = missing || !present;
    if (!missing) composer.Add(step.ref_side, m);
  }
  if (missing) return ErrorCode::kNoAcceleration;
  const internal::Motion m = composer.Result();
  a_DCe_R = m.a;
  alpha_DC_R = m.alpha;
  return ErrorCode::kOk;
}

template class CompiledAcceleration<coord::QuaternionBackend>;
template class CompiledAcceleration<coord::HomogeneousBackend>;

}  // namespace semgraph::core
