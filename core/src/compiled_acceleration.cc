// Compiled acceleration queries (contract: compiled_acceleration.h): the union of the pose chains
// the steps need, flattened top-down (compile); one pass over it, then one over the steps
// (evaluate).
#include "semgraph/core/compiled_acceleration.h"

#include "semgraph/core/compiled_covariance.h"

namespace semgraph::core {

template <coord::Backend B>
CompiledAcceleration<B>::CompiledAcceleration(const topology::SceneTopology& t,
                                              const EdgeValues<B>& values, const TwistPlan& plan)
    : CompiledQuery<B>(t, values),
      semantics_{plan.semantics.point, plan.semantics.body, plan.semantics.ref_body,
                 plan.semantics.coordinate_frame} {
  const topology::PoseForest& forest = t.forest();
  const FrameIndex e = plan.point, r = plan.frame;
  std::vector<FrameIndex> ends{e, r};
  ForEachTwistStep(t, plan, [&](const TwistStep<ForestChain>& s) {
    Step step;
    step.step.edge = s.edge;
    step.record = &values.A_DH[s.edge.value()];
    step.step.epoch = step.record->epoch();
    step.step.invert = s.invert;
    step.step.ref_side = s.ref_side;
    steps_.push_back(step);
    ends.push_back(t.twist_edge(s.edge).head);
  });
  // No step (C == D: zero): no pose edge is read (a removal never invalidates it). Else the
  // union is the smallest subtree joining e, [r] and the heads: the edges of the one-shot
  // query's chains (e to each head, each head to [r]), each once.
  if (steps_.empty()) return;
  FrameIndex z = e;
  for (const FrameIndex f : ends) z = forest.CommonAncestor(z, f);
  const std::vector<FrameIndex> edges = internal::ChainUnionTopDown(t, ends, z);
  // Each union edge as a one-edge chain of the compiled query's list (entry i = edges_[i]), so
  // that FlatSource reads it, with its epoch, at the current values or at a time.
  for (const FrameIndex g : edges) {
    (void)this->Flatten(t, ForestChain{g, t.pose_parent(g)});
    parent_.push_back(internal::EntryOf(edges, t.pose_parent(g)));
  }
  e_entry_ = internal::EntryOf(edges, e);
  r_entry_ = internal::EntryOf(edges, r);
  for (std::size_t j = 0; j < steps_.size(); ++j) {
    steps_[j].head = internal::EntryOf(edges, ends[2 + j]);
  }
  scratch_.resize(edges.size());
}

template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Compose(const internal::FlatSource<B>& src,
                                           internal::Motion& out) noexcept {
  // Every union edge's head in Z, top-down (each after the edge above it).
  for (std::size_t i = 0; i < parent_.size(); ++i) {
    typename B::PoseCoords X_PG;
    bool identity = false;
    const auto k = static_cast<std::uint32_t>(i);
    if (!src.EvalChain(internal::FlatChain{k, k + 1}, X_PG, identity)) {
      return ErrorCode::kQueryInvalidated;
    }
    if (parent_[i] < 0) {
      scratch_[i] = X_PG;
    } else {
      scratch_[i] = B::ComposeChain(X_PG, scratch_[static_cast<std::size_t>(parent_[i])]);
    }
  }
  static const typename B::PoseCoords kZ = B::Identity();
  const auto in_z = [&](std::int32_t entry) -> const typename B::PoseCoords& {
    return entry < 0 ? kZ : scratch_[static_cast<std::size_t>(entry)];
  };
  // Every step at Z's origin in [Z], composed; every record read even after a missing one.
  internal::AccelerationComposer composer;
  bool missing = false;
  for (const Step& s : steps_) {
    TwistAndAcceleration rec;
    if (!src.LoadAcceleration(*s.record, s.step, rec)) return ErrorCode::kQueryInvalidated;
    missing = missing || rec.present == 0.0;
    if (missing) continue;
    const typename B::PoseCoords& X_ZH = in_z(s.head);
    internal::Motion m = internal::EdgeMotion(rec, s.step.invert);
    internal::RotateMotion<B>(B::RotationOf(X_ZH), m);
    internal::ShiftMotion(m, B::TranslationOf(X_ZH));  // h to Z's origin: p = h - Zo
    composer.Add(s.step.ref_side, m);
  }
  if (missing) return ErrorCode::kNoAcceleration;
  // To e, then into [r].
  out = composer.Result();
  internal::ShiftMotion(out, -B::TranslationOf(in_z(e_entry_)));  // Z's origin to e: p = Zo - e
  internal::RotateMotion<B>(B::RotationOf(B::InvertChain(in_z(r_entry_))), out);
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Evaluate(Eigen::Vector3d& a_DCe_R,
                                            Eigen::Vector3d& alpha_DC_R) noexcept {
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
                                            const TimePolicy& policy, TimeReport& report) noexcept {
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
