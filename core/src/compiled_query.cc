// Compiled queries: a plan flattened into an edge list, evaluated by the one evaluator
// (evaluate.h, FlatSource). Contract: compiled_query.h.
#include "semgraph/core/compiled_query.h"

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"

namespace semgraph::core {

template <coord::Backend B>
bool CompiledQuery<B>::is_valid() const noexcept {
  for (const internal::EdgeRef& e : edges_) {
    if (values_->X_PF[e.child].epoch() != e.epoch()) return false;
  }
  return true;
}

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const ForestChain& c) -> Chain {
  Chain flat;
  flat.begin = static_cast<std::uint32_t>(edges_.size());
  for (FrameIndex g = c.from; g != c.to; g = t.pose_parent(g)) {
    edges_.push_back(internal::EdgeRef{PoseValue<B>::ExpectedHeader(values_->X_PF[g.value()].epoch()), g.value()});
  }
  flat.end = static_cast<std::uint32_t>(edges_.size());
  return flat;
}

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const BasicPath<ForestChain>& path)
    -> BasicPath<Chain> {
  BasicPath<Chain> flat;
  flat.up_a = Flatten(t, path.up_a);
  flat.up_b = Flatten(t, path.up_b);
  return flat;
}

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const PoseSteps<ForestChain>& s)
    -> PoseSteps<Chain> {
  PoseSteps<Chain> flat;
  flat.ab = Flatten(t, s.ab);
  if ((flat.change_ref_point = s.change_ref_point)) flat.fb = Flatten(t, s.fb);
  if ((flat.change_point = s.change_point)) flat.ea = Flatten(t, s.ea);
  if ((flat.change_frame = s.change_frame)) flat.br = Flatten(t, s.br);
  return flat;
}

template <coord::Backend B>
CompiledPose<B>::CompiledPose(const topology::SceneTopology& t, const EdgeValues<B>& values, const PosePlan& plan)
    : CompiledQuery<B>(values), semantics_(plan.semantics), steps_(this->Flatten(t, plan.steps)) {}

template <coord::Backend B>
ErrorCode CompiledPose<B>::Evaluate(typename B::PoseCoords& X) const noexcept {
  typename B::Rotation R;
  Eigen::Vector3d p;  // written by the evaluator before any use (Evaluate returns early otherwise)
  if (!internal::EvaluatePose<B, internal::Part::kPose>(this->source(), steps_, R, p)) {
    return ErrorCode::kQueryInvalidated;
  }
  X = B::MakePose(R, p);
  return ErrorCode::kOk;
}

template <coord::Backend B>
CompiledPosition<B>::CompiledPosition(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                      const PositionPlan& plan)
    : CompiledQuery<B>(values), semantics_(plan.semantics), steps_(this->Flatten(t, plan.steps)) {}

template <coord::Backend B>
ErrorCode CompiledPosition<B>::Evaluate(Eigen::Vector3d& p_FE_R) const noexcept {
  typename B::Rotation R;  // the rotation half, unused by a position
  return internal::EvaluatePose<B, internal::Part::kTranslation>(this->source(), steps_, R, p_FE_R)
             ? ErrorCode::kOk
             : ErrorCode::kQueryInvalidated;
}

template <coord::Backend B>
CompiledOrientation<B>::CompiledOrientation(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                            const OrientationPlan& plan)
    : CompiledQuery<B>(values), semantics_(plan.semantics), steps_(this->Flatten(t, plan.steps)) {}

template <coord::Backend B>
ErrorCode CompiledOrientation<B>::Evaluate(typename B::Rotation& R_BA_R) const noexcept {
  Eigen::Vector3d p;  // the translation half, unused by an orientation
  return internal::EvaluatePose<B, internal::Part::kRotation>(this->source(), steps_, R_BA_R, p)
             ? ErrorCode::kOk
             : ErrorCode::kQueryInvalidated;
}

template <coord::Backend B>
CompiledTwist<B>::CompiledTwist(const topology::SceneTopology& t, const EdgeValues<B>& values, const TwistPlan& plan)
    : CompiledQuery<B>(values), semantics_(plan.semantics) {
  ForEachTwistStep(t, plan, [&](const TwistStep<ForestChain>& step) {
    TwistStep<typename CompiledQuery<B>::Chain> flat;
    flat.edge = step.edge;
    flat.epoch = values.V_DH[step.edge.value()].epoch();
    flat.invert = step.invert;
    if ((flat.move_point = step.move_point)) flat.eh = this->Flatten(t, step.eh);
    if ((flat.change_frame = step.change_frame)) flat.hr = this->Flatten(t, step.hr);
    steps_.push_back(flat);
  });
}

template <coord::Backend B>
ErrorCode CompiledTwist<B>::Evaluate(Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R) const noexcept {
  v_DCe_R.setZero();
  w_DC_R.setZero();
  const internal::FlatSource<B> src = this->source();
  for (const auto& step : steps_) {
    if (!internal::AccumulateTwistStep<B>(src, step, v_DCe_R, w_DC_R)) return ErrorCode::kQueryInvalidated;
  }
  return ErrorCode::kOk;
}

template class CompiledQuery<coord::QuaternionBackend>;
template class CompiledQuery<coord::HomogeneousBackend>;
template class CompiledPose<coord::QuaternionBackend>;
template class CompiledPose<coord::HomogeneousBackend>;
template class CompiledPosition<coord::QuaternionBackend>;
template class CompiledPosition<coord::HomogeneousBackend>;
template class CompiledOrientation<coord::QuaternionBackend>;
template class CompiledOrientation<coord::HomogeneousBackend>;
template class CompiledTwist<coord::QuaternionBackend>;
template class CompiledTwist<coord::HomogeneousBackend>;

}  // namespace semgraph::core
