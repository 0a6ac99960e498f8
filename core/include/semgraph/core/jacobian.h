// File: semgraph/core/jacobian.h
//
// Semantic Jacobians (docs/kinematics.md): Jacobian(e|C, D, [r]) is the 6 x n matrix J with
//   TwistCoord(e|C, D, [r]) = J qdot + (the twists of the non-joint twist edges on the path).
// Columns: the independent movable joints driving twist edges on the TG path between C and D,
// in path order from D to C; a mimic adds multiplier x its column to its master's column (placed
// where the first of the master and its mimics stands on the path). Rows: v (3) then w (3).
//
// How it is computed: a Jacobian is the twist query's plan (query_plan.h, ForEachTwistStep)
// where each joint's step is evaluated by the one evaluator's AccumulateTwistStep (evaluate.h)
// with the joint's twist at unit velocity in place of the stored value (UnitTwistSource), so the
// point change, the re-expression and the inversion of a column are the twist query's own
// arithmetic; non-joint steps are skipped.
//
// Costs: planning as a twist query plus O(k) for the column assignment (k twist edges on the
// path); evaluation O(sum over joint steps of their two basic poses), i.e. what the twist query
// costs, per column. CompiledJacobian::Evaluate is noexcept, allocation-free, lock-free (it reads
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
  std::vector<JacobianStep<ForestChain>> steps;
};

/// A chain source that composes poses as `Inner` does and yields the unit twist in place of a
/// stored twist value (after Inner's epoch check of the edge, so a removed joint's twist edge
/// still invalidates a compiled Jacobian).
template <class Inner>
class UnitTwistSource {
 public:
  using Chain = typename Inner::Chain;
  using PoseCoords = typename Inner::PoseCoords;
  UnitTwistSource(const Inner& inner, const TwistNumbers& unit) noexcept : inner_(inner), unit_(unit) {}
  bool EvalChain(const Chain& c, PoseCoords& X, bool& identity) const noexcept {
    return inner_.EvalChain(c, X, identity);
  }
  bool LoadTwist(const TwistStep<Chain>& s, TwistNumbers& V) const noexcept {
    if (!inner_.LoadTwist(s, V)) return false;
    V = unit_;
    return true;
  }

 private:
  const Inner& inner_;
  const TwistNumbers& unit_;
};

/// Fills J (6 x columns, zeroed first) from the steps; false when a compiled edge changed.
template <coord::Backend B, class Source, class Steps>
bool EvaluateJacobian(const Source& src, const Steps& steps, Eigen::Ref<JacobianMatrix> J) noexcept {
  J.setZero();
  for (const auto& s : steps) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    if (!AccumulateTwistStep<B>(UnitTwistSource<Source>(src, s.unit), s.step, v, w)) return false;
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
};

extern template class CompiledJacobian<coord::QuaternionBackend>;
extern template class CompiledJacobian<coord::HomogeneousBackend>;

}  // namespace semgraph::core
