// File: semgraph/core/jacobian.h
//
// Semantic Jacobians (docs/kinematics.md): Jacobian(e|C, D, [r]) is the 6 x n matrix J with
//   TwistCoord(e|C, D, [r]) = J qdot + (the twists of the non-joint twist edges on the path).
// Columns: the independent movable joints driving twist edges on the TG path between C and D,
// in path order from D to C; a mimic adds multiplier x its column to its master's column (placed
// where the first of the master and its mimics stands on the path). Rows: v (3) then w (3).
//
// How it is computed: on the twist query's plan (query_plan.h, PlanTwist and ForEachTwistStep:
// the same path, the same inversions), keeping the joints' steps; every pose comes from the one
// evaluator's EvalBasic (evaluate.h) over the query's chain source, so one-shot and compiled
// Jacobians compose exactly as twist queries do. A column is the joint's unit twist re-expressed
// in [r] and moved to e with positions in [r] (EvaluateJacobian below): one basic pose per
// column instead of the twist step's two.
//
// Costs: planning as a twist query plus O(k) for the column assignment (k twist edges on the
// path); evaluation O(sum over the joint steps of the chain h -> r) + one chain e -> r. CompiledJacobian::Evaluate is noexcept, allocation-free, lock-free (it reads
// the edge values through their sequence locks, and fails with kQueryInvalidated when an edge
// it reads, or a joint's twist edge, was removed). GetJacobian (one-shot) allocates its result.
// Thread safety: as compiled queries (compiled_query.h).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "semgraph/core/compiled_query.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/joints.h"
#include "semgraph/core/query_plan.h"

namespace semgraph::core {

/// A 6 x n Jacobian: rows v_x v_y v_z w_x w_y w_z (v: velocity of the point, w: angular
/// velocity, both in [r]); column i belongs to joints[i].
using JacobianMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// A one-shot Jacobian with its semantics: J maps the columns' joint velocities to
/// TwistCoord(e|C, D, [r]) (less the non-joint twist edges' contribution).
struct Jacobian {
  semantics::TwistSemantics semantics;
  std::vector<JointHandle> joints;
  JacobianMatrix J;
};

namespace internal {

/// A twist step of a joint's edge with the joint's twist at unit velocity (times the mimic
/// multiplier) and the column it adds to.
template <class Chain>
struct JacobianStep {
  TwistStep<Chain> step;
  TwistNumbers unit;  ///< in [c], the joint's child frame
  std::uint32_t column = 0;
};

struct JacobianPlan {
  TwistPlan twist;
  std::vector<JointHandle> columns;
  std::vector<JacobianStep<ForestChain>> steps;  ///< their `hr` (h wrt r) only; no `eh`
  bool change_point = false;                     ///< e != r: X_RE is needed
  BasicPath<ForestChain> er;                     ///< X_RE: e wrt r, in [r]
};

/// Fills J (6 x columns, zeroed first) from the steps; false when a compiled edge changed.
/// Each column is the joint's unit twist (negated when the path crosses the joint from child
/// to parent), re-expressed in [r] by X_RH and moved from h to e with the positions of both in
/// [r]: v_e = v_h + w x (p_RE - p_RH). All poses come from the evaluator's EvalBasic, so the
/// cost per column is one basic pose (h wrt r), plus X_RE once: about n^2 / 2 compositions for
/// a serial chain of n joints expressed at its base.
template <coord::Backend B, class Source, class Steps>
bool EvaluateJacobian(const Source& src, bool change_point, const BasicPath<typename Source::Chain>& er,
                      const Steps& steps, Eigen::Ref<JacobianMatrix> J) noexcept {
  J.setZero();
  Eigen::Vector3d p_RE = Eigen::Vector3d::Zero();
  if (change_point) {
    typename B::PoseCoords X_RE;
    if (!EvalBasic<B>(src, er, X_RE)) return false;
    p_RE = B::TranslationOf(X_RE);
  }
  for (const auto& s : steps) {
    TwistNumbers unused;
    if (!src.LoadTwist(s.step, unused)) return false;  // the joint's twist edge still exists
    Eigen::Vector3d v = s.step.invert ? Eigen::Vector3d(-s.unit.v_DHo_H) : s.unit.v_DHo_H;
    Eigen::Vector3d w = s.step.invert ? Eigen::Vector3d(-s.unit.w_DH_H) : s.unit.w_DH_H;
    Eigen::Vector3d p_RH = Eigen::Vector3d::Zero();
    if (s.step.change_frame) {
      typename B::PoseCoords X_RH;
      if (!EvalBasic<B>(src, s.step.hr, X_RH)) return false;
      const typename B::Rotation R_RH = B::RotationOf(X_RH);
      v = B::Rotate(R_RH, v);
      w = B::Rotate(R_RH, w);
      p_RH = B::TranslationOf(X_RH);
    }
    v = coord::kernels::ShiftLinear(v, w, p_RH - p_RE);  // v + (p_RH - p_RE) x w = v + w x (p_RE - p_RH)
    J.col(s.column).template head<3>() += v;
    J.col(s.column).template tail<3>() += w;
  }
  return true;
}

}  // namespace internal

/// A compiled Jacobian (SceneGraph::CompileJacobian): evaluate into caller storage.
template <coord::Backend B>
class CompiledJacobian : public CompiledQuery<B> {
 public:
  CompiledJacobian() = default;
  CompiledJacobian(const topology::SceneTopology& t, const EdgeValues<B>& values,
                   const internal::JacobianPlan& plan);
  [[nodiscard]] const semantics::TwistSemantics& semantics() const noexcept { return semantics_; }
  /// The columns' joints, in column order.
  [[nodiscard]] const std::vector<JointHandle>& joints() const noexcept { return joints_; }
  [[nodiscard]] std::size_t num_columns() const noexcept { return joints_.size(); }
  /// Writes the 6 x num_columns() Jacobian (J.cols() must equal num_columns(); checked).
  /// kOk or kQueryInvalidated.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Ref<JacobianMatrix> J) const noexcept;

 private:
  semantics::TwistSemantics semantics_;
  std::vector<JointHandle> joints_;
  std::vector<internal::JacobianStep<typename CompiledQuery<B>::Chain>> steps_;
  bool change_point_ = false;
  BasicPath<typename CompiledQuery<B>::Chain> er_;
};

extern template class CompiledJacobian<coord::QuaternionBackend>;
extern template class CompiledJacobian<coord::HomogeneousBackend>;

}  // namespace semgraph::core
