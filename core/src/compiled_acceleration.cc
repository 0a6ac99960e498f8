// Compiled acceleration queries (contract: compiled_acceleration.h): the union of the pose chains
// the steps need, flattened top-down (compile); one pass over it, then one over the steps
// (evaluate).
#include "semgraph/core/compiled_acceleration.h"

#include <algorithm>

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
  // Z itself (-1 in the list) is the scratch's last entry, the identity: no test per step.
  const auto entry = [&](FrameIndex f) {
    const std::int32_t i = internal::EntryOf(edges, f);
    return i < 0 ? static_cast<std::int32_t>(edges.size()) : i;
  };
  e_entry_ = entry(e);
  r_entry_ = entry(r);
  for (std::size_t j = 0; j < steps_.size(); ++j) steps_[j].head = entry(ends[2 + j]);
  // One running product (ThenPairs): D's side in the plan's order, then C's reversed (C's side
  // is prepended step by step; the composition is associative).
  const auto c_side = std::stable_partition(steps_.begin(), steps_.end(),
                                            [](const Step& s) { return s.step.ref_side; });
  std::reverse(c_side, steps_.end());
  scratch_.assign(edges.size() + 1, B::Identity());
}

template <coord::Backend B>
ErrorCode CompiledAcceleration<B>::Compose(const internal::FlatSource<B>& src,
                                           internal::Motion& out) noexcept {
  if (steps_.empty()) {  // C == D (or a default-constructed query): zero, nothing read
    out = internal::Motion::Zero();
    return ErrorCode::kOk;
  }
  // Every union edge's head in Z, top-down (each after the edge above it). Through local
  // pointers: the stores to the scratch would otherwise reload the vectors' bounds each edge.
  using Pose = typename B::PoseCoords;
  Pose* const in_z = scratch_.data();
  const std::int32_t* const parent = parent_.data();
  const auto n = static_cast<std::uint32_t>(parent_.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    Pose X_PG;
    bool identity = false;
    if (!src.EvalChain(internal::FlatChain{i, i + 1}, X_PG, identity)) {
      return ErrorCode::kQueryInvalidated;
    }
    in_z[i] = parent[i] < 0 ? X_PG : B::ComposeChain(X_PG, in_z[parent[i]]);
  }
  // Every step at Z's origin in [Z], composed in steps_'s order (D's, then C's reversed); every
  // record read even after a missing one.
  internal::MotionPairs m = internal::MotionPairs::Zero();
  bool missing = false;
  for (const Step& s : steps_) {
    internal::MotionPairs edge;
    double present = 0.0;
    if (!internal::LoadEdgeMotion(src, *s.record, s.step, edge, present)) {
      return ErrorCode::kQueryInvalidated;
    }
    missing = missing || present == 0.0;
    if (missing) continue;
    const Pose& X_ZH = in_z[s.head];  // h to Z's origin (p = h - Zo), into [Z]
    internal::ThenPairs(m, internal::MovedEdgeMotion(edge, s.step.invert,
                                                     internal::RotationPairs(B::RotationOf(X_ZH)),
                                                     B::TranslationOf(X_ZH)));
  }
  if (missing) return ErrorCode::kNoAcceleration;
  // To e, then into [r]; neither move when e or [r] is Z (its entry: the last, past the edges).
  // In pairs to the end: through Eigen's vectors the tail went through the stack (8-byte stores
  // read back as 16-byte loads, which the store buffer cannot forward).
  const auto z = static_cast<std::int32_t>(n);
  if (e_entry_ != z) internal::ShiftPairs(-B::TranslationOf(in_z[e_entry_]), m);  // p = Zo - e
  if (r_entry_ != z) {                                                            // R_rZ = R_Zr^T
    m = internal::RotatePairs(internal::RotationPairs(B::Transpose(B::RotationOf(in_z[r_entry_]))),
                              m);
  }
  out = m.ToMotion();
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
