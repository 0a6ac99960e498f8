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
// path); evaluation O(sum over the joint steps of the chain h -> r) + one chain e -> r.
// CompiledJacobian::Evaluate is noexcept, allocation-free, lock-free (it reads the edge values
// through their sequence locks, and fails with kQueryInvalidated when an edge it reads, or a
// joint's twist edge, was removed). GetJacobian (one-shot) allocates its result. Thread safety: as
// compiled queries (compiled_query.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "semgraph/core/compiled_query.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/export.h"
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
  /// The previous step's chain up_a (its h up to the common ancestor with r) is the top of
  /// this one's: compose only the edges from this h up to the previous h (`rest`). Serial
  /// chains expressed at their base then cost O(n) compositions, not O(n^2).
  bool chained = false;
  Chain rest;
};

struct JacobianPlan {
  TwistPlan twist;
  std::vector<JointHandle> columns;
  std::vector<JacobianStep<ForestChain>> steps;  ///< their `hr` (h wrt r) only; no `eh`
  bool change_point = false;                     ///< e != r: X_RE is needed
  BasicPath<ForestChain> er;                     ///< X_RE: e wrt r, in [r]
  bool e_chained = false;                        ///< er.up_a continues the last step's up_a
  ForestChain e_rest;                            ///< then: e up to the last step's h
};

/// X_BA of a basic path whose chain up_a is X_CA, already composed (EvalBasic's second half).
template <coord::Backend B, class Source>
bool FinishBasic(const Source& src, const BasicPath<typename Source::Chain>& path,
                 const typename B::PoseCoords& X_CA, typename B::PoseCoords& X_BA) noexcept {
  typename B::PoseCoords X_CB;
  bool b_identity;
  if (!src.EvalChain(path.up_b, X_CB, b_identity)) return false;
  X_BA = b_identity ? X_CA : B::ComposeChain(X_CA, B::InvertChain(X_CB));
  return true;
}

/// X_CA of up_a: composed from scratch, or as `rest` on top of the previous X_CA.
template <coord::Backend B, class Source>
bool UpA(const Source& src, bool chained, const typename Source::Chain& rest,
         const typename Source::Chain& up_a, typename B::PoseCoords& X_CA) noexcept {
  typename B::PoseCoords X;
  bool identity;
  if (!src.EvalChain(chained ? rest : up_a, X, identity)) return false;
  if (chained) {
    if (!identity) X_CA = B::ComposeChain(X, X_CA);
  } else {
    X_CA = identity ? B::Identity() : X;
  }
  return true;
}

/// Fills J (6 x columns, zeroed first) from the steps; false when a compiled edge changed.
/// Each column is the joint's unit twist (negated when the path crosses the joint from child
/// to parent), re-expressed in [r] by X_RH and moved from h to e with the positions of both in
/// [r]: v_e = v_h + w x (p_RE - p_RH) (first to r's origin, then all columns to e). Every chain
/// is composed by the chain source (the one composition loop); a step whose chain continues the
/// previous step's composes only its own edges, so a serial chain costs O(n) compositions.
template <coord::Backend B, class Source, class Steps, class EChain>
bool EvaluateJacobian(const Source& src, bool change_point,
                      const BasicPath<typename Source::Chain>& er, bool e_chained,
                      const EChain& e_rest, const Steps& steps,
                      Eigen::Ref<JacobianMatrix> J) noexcept {
  J.setZero();
  typename B::PoseCoords X_CA = B::Identity();
  for (const auto& s : steps) {
    TwistNumbers unused;
    if (!src.LoadTwist(s.step, unused)) return false;  // the joint's twist edge still exists
    Eigen::Vector3d v = s.step.invert ? Eigen::Vector3d(-s.unit.v_DHo_H) : s.unit.v_DHo_H;
    Eigen::Vector3d w = s.step.invert ? Eigen::Vector3d(-s.unit.w_DH_H) : s.unit.w_DH_H;
    if (s.step.change_frame) {
      typename B::PoseCoords X_RH;
      if (!UpA<B>(src, s.chained, s.rest, s.step.hr.up_a, X_CA) ||
          !FinishBasic<B>(src, s.step.hr, X_CA, X_RH)) {
        return false;
      }
      const typename B::Rotation R_RH = B::RotationOf(X_RH);
      v = B::Rotate(R_RH, v);
      w = B::Rotate(R_RH, w);
      v = coord::kernels::ShiftLinear(v, w, B::TranslationOf(X_RH));  // to r's origin
    }
    J.col(s.column).template head<3>() += v;
    J.col(s.column).template tail<3>() += w;
  }
  if (change_point) {  // all columns from r's origin to e: v += (-p_RE) x w
    typename B::PoseCoords X_RE;
    if (!UpA<B>(src, e_chained, e_rest, er.up_a, X_CA) || !FinishBasic<B>(src, er, X_CA, X_RE))
      return false;
    const Eigen::Vector3d p_ER = -B::TranslationOf(X_RE);
    for (Eigen::Index c = 0; c < J.cols(); ++c) {
      const Eigen::Vector3d w = J.col(c).template tail<3>();
      J.col(c).template head<3>() =
          coord::kernels::ShiftLinear(J.col(c).template head<3>(), w, p_ER);
    }
  }
  return true;
}

}  // namespace internal

/// A compiled Jacobian (SceneGraph::CompileJacobian): evaluate into caller storage.
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledJacobian : public CompiledQuery<B> {
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
  bool e_chained_ = false;
  typename CompiledQuery<B>::Chain e_rest_;
};

extern template class CompiledJacobian<coord::QuaternionBackend>;
extern template class CompiledJacobian<coord::HomogeneousBackend>;

}  // namespace semgraph::core
