// Semantic Jacobians (contract: jacobian.h): planned on the twist plan, keeping the joints'
// steps, and evaluated by the one evaluator (EvaluateJacobian over a chain source), one-shot
// or compiled.
#include "semgraph/core/jacobian.h"

#include <algorithm>
#include <vector>

#include "semgraph/base/demand.h"
#include "semgraph/core/scene_graph.h"

namespace semgraph::core {

using base::Unexpected;

template <coord::Backend B>
Expected<internal::JacobianPlan, QueryError> SceneGraph<B>::PlanJacobian(
    const TwistSpec& spec) const {
  auto twist = PlanTwist(topology_, spec);
  if (!twist) return Unexpected{twist.error()};
  internal::JacobianPlan plan;
  plan.twist = *twist;
  // The steps in path order from D to C: D's side as walked (D up to the ancestor), then C's
  // side reversed (the ancestor down to C).
  std::vector<TwistStep<ForestChain>> c_side, d_side;
  std::size_t c_count = 0;
  {
    // Count C's side first: ForEachTwistStep walks C's side, then D's side.
    BodyIndex body = plan.twist.body;
    if (plan.twist.tg) {
      for (; body != plan.twist.ancestor; body = plan.twist.tg->parent(body)) ++c_count;
    }
  }
  std::size_t seen = 0;
  ForEachTwistStep(topology_, plan.twist, [&](const TwistStep<ForestChain>& s) {
    (seen++ < c_count ? c_side : d_side).push_back(s);
  });
  std::vector<TwistStep<ForestChain>> path = d_side;
  path.insert(path.end(), c_side.rbegin(), c_side.rend());
  for (const TwistStep<ForestChain>& s : path) {
    const internal::JointRecord* j = joints_.OfChild(topology_.twist_edge(s.edge).head);
    if (!j || !j->movable()) continue;
    const JointHandle column_joint =
        j->is_mimic() ? joints_.HandleOf(joints_[j->master]) : joints_.HandleOf(*j);
    const double scale = j->is_mimic() ? j->multiplier : 1.0;
    auto it = std::find(plan.columns.begin(), plan.columns.end(), column_joint);
    if (it == plan.columns.end()) it = plan.columns.insert(plan.columns.end(), column_joint);
    internal::JacobianStep<ForestChain> step;
    step.step = s;
    step.step.move_point = false;  // moved with positions in [r] (EvaluateJacobian)
    step.step.eh = {};
    j->TwistAt(scale, step.unit.v_DHo_H, step.unit.w_DH_H);
    step.column = static_cast<std::uint32_t>(it - plan.columns.begin());
    plan.steps.push_back(step);
  }
  if ((plan.change_point = plan.twist.point != plan.twist.frame && !plan.steps.empty())) {
    plan.er = PlanBasic(topology_, plan.twist.point, plan.twist.frame);
  }
  // Chain each step's h -> ancestor composition on the previous one's where it continues it:
  // same ancestor c and reference chain, and the previous h on the way from this h up to c.
  const auto continues = [&](const BasicPath<ForestChain>& prev,
                             const BasicPath<ForestChain>& next) {
    if (prev.up_a.to != next.up_a.to || prev.up_b.from != next.up_b.from ||
        prev.up_b.to != next.up_b.to)
      return false;
    for (FrameIndex g = next.up_a.from; g.is_valid(); g = topology_.pose_parent(g)) {
      if (g == prev.up_a.from) return true;
      if (g == next.up_a.to) return false;
    }
    return false;
  };
  const internal::JacobianStep<ForestChain>* prev = nullptr;
  for (internal::JacobianStep<ForestChain>& s : plan.steps) {
    if (!s.step.change_frame) {
      prev = nullptr;  // h == r: the running composition is not updated
      continue;
    }
    if (prev && continues(prev->step.hr, s.step.hr)) {
      s.chained = true;
      s.rest = ForestChain{s.step.hr.up_a.from, prev->step.hr.up_a.from};
    }
    prev = &s;
  }
  if (plan.change_point && prev && &plan.steps.back() == prev &&
      continues(prev->step.hr, plan.er)) {
    plan.e_chained = true;
    plan.e_rest = ForestChain{plan.er.up_a.from, prev->step.hr.up_a.from};
  }
  return plan;
}

template <coord::Backend B>
Expected<Jacobian, QueryError> SceneGraph<B>::GetJacobian(const TwistSpec& spec) const {
  auto plan = PlanJacobian(spec);
  if (!plan) return Unexpected{plan.error()};
  Jacobian out;
  out.semantics = plan->twist.semantics;
  out.joints = plan->columns;
  out.J.setZero(6, static_cast<Eigen::Index>(plan->columns.size()));
  internal::EvaluateJacobian<B>(source(), plan->change_point, plan->er, plan->e_chained,
                                plan->e_rest, plan->steps, out.J);
  return out;
}

template <coord::Backend B>
Expected<CompiledJacobian<B>, QueryError> SceneGraph<B>::CompileJacobian(
    const TwistSpec& spec) const {
  auto plan = PlanJacobian(spec);
  if (!plan) return Unexpected{plan.error()};
  return CompiledJacobian<B>(topology_, values_, *plan);
}

template <coord::Backend B>
CompiledJacobian<B>::CompiledJacobian(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                      const internal::JacobianPlan& plan)
    : CompiledQuery<B>(t, values), semantics_(plan.twist.semantics), joints_(plan.columns) {
  if ((change_point_ = plan.change_point)) er_ = this->Flatten(t, plan.er);
  if ((e_chained_ = plan.e_chained)) e_rest_ = this->Flatten(t, plan.e_rest);
  steps_.reserve(plan.steps.size());
  for (const internal::JacobianStep<ForestChain>& s : plan.steps) {
    internal::JacobianStep<typename CompiledQuery<B>::Chain> flat;
    flat.step.edge = s.step.edge;
    flat.step.epoch = values.V_DH[s.step.edge.value()].epoch();
    flat.step.invert = s.step.invert;
    if ((flat.step.change_frame = s.step.change_frame)) flat.step.hr = this->Flatten(t, s.step.hr);
    flat.unit = s.unit;
    flat.column = s.column;
    if ((flat.chained = s.chained)) flat.rest = this->Flatten(t, s.rest);
    steps_.push_back(flat);
  }
}

template <coord::Backend B>
ErrorCode CompiledJacobian<B>::Evaluate(Eigen::Ref<JacobianMatrix> J) const noexcept {
  SEMGRAPH_DEMAND(static_cast<std::size_t>(J.cols()) == joints_.size());
  return internal::EvaluateJacobian<B>(this->source(), change_point_, er_, e_chained_, e_rest_,
                                       steps_, J)
             ? ErrorCode::kOk
             : ErrorCode::kQueryInvalidated;
}

#define SEMGRAPH_INSTANTIATE_JACOBIAN(B)                                                      \
  template Expected<internal::JacobianPlan, QueryError> SceneGraph<B>::PlanJacobian(          \
      const TwistSpec&) const;                                                                \
  template Expected<Jacobian, QueryError> SceneGraph<B>::GetJacobian(const TwistSpec&) const; \
  template Expected<CompiledJacobian<B>, QueryError> SceneGraph<B>::CompileJacobian(          \
      const TwistSpec&) const;                                                                \
  template class CompiledJacobian<B>;
SEMGRAPH_INSTANTIATE_JACOBIAN(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_JACOBIAN(coord::HomogeneousBackend)

}  // namespace semgraph::core
