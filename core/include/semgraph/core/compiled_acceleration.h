// File: semgraph/core/compiled_acceleration.h
//
// CompiledAcceleration: AccelerationCoord(e|C, D, [r]) compiled (SceneGraph::CompileAcceleration,
// build time, allocates), evaluated in one pass (docs/performance.md, "Accelerations"):
//   - compile: the twist plan's steps (edge, direction, side), the frames they need (e, [r] and
//     every step's head h), their youngest common ancestor Z, and the union of those frames'
//     pose chains up to Z, each pose edge once, top-down (compiled_covariance.h,
//     ChainUnionTopDown);
//   - evaluate: every union edge read once and composed with the one above it (its head's pose
//     in Z, kept in the object's scratch: one composition per edge); every step's twist and
//     acceleration rotated into [Z] and moved to Z's origin with that pose, then appended to
//     one running product with the Coriolis terms (D's steps in the plan's order, C's reversed),
//     in one fused step on lane pairs (motion_pairs.h: MovedEdgeMotion, ThenPairs, the math of
//     evaluate.h's EdgeMotion, RotateMotion, ShiftMotion and AccelerationComposer); the result
//     moved to e
//     and rotated into [r] once (neither when e, or [r], is Z). Each edge is read through the
//     one evaluator's source (FlatSource: the current values, or the policy's time), so the
//     reads are those of every compiled query; at the current values each record's words go
//     straight from its sequence lock into the motion (one header test per read).
// Invariants: as every compiled query (compiled_query.h): a removed edge makes Evaluate return
// kQueryInvalidated, never a wrong number (reported before kNoAcceleration). An edge of the path
// that carries no acceleration when evaluated (never given, cleared by a twist given without
// one, a stamped sample without one): kNoAcceleration. Under a time policy each edge is read as
// the timed one-shot query reads it (timed_read.h).
// Costs: Evaluate O(pose edges in the union + twist edges): one composition per pose edge, four
// rotations, one shift and one composition per twist edge (the one-shot query moves each edge
// through its own chains: O(twist edges x chain length)); on the bench chain about 1.05x the
// instructions and 1.15-1.2x the CPU time of a hand-written Eigen chain (docs/performance.md,
// "Accelerations"); noexcept, allocation-free, lock-free, string-free.
// Thread safety: Evaluate uses the object's own scratch: one evaluating thread per object (a
// copy is independent), concurrently with one writer; each edge's acceleration and twist are
// read together, untorn.
#pragma once

#include <vector>

#include "semgraph/core/compiled_query.h"
#include "semgraph/core/motion_pairs.h"

namespace semgraph::core {

template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledAcceleration : public CompiledQuery<B> {
 public:
  CompiledAcceleration() = default;
  CompiledAcceleration(const topology::SceneTopology& t, const EdgeValues<B>& values,
                       const TwistPlan& plan);
  [[nodiscard]] const semantics::AccelerationSemantics& semantics() const noexcept {
    return semantics_;
  }
  /// a_DCe_R (classical, of the point of C at e) and alpha_DC_R. kOk, kQueryInvalidated or
  /// kNoAcceleration (then the outputs are unchanged); kQueryInvalidated first: an edge of the
  /// path removed is reported as such even when an edge carries no acceleration.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& a_DCe_R, Eigen::Vector3d& alpha_DC_R) noexcept;
  /// At the policy's time (as CompiledTwist's): also kInvalidNumber (a negative horizon),
  /// kExtrapolation, kStale; the outputs are written on kOk only.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& a_DCe_R, Eigen::Vector3d& alpha_DC_R,
                                   const TimePolicy& policy, TimeReport& report) noexcept;
  /// In GetAcceleration's result type (without the name of a missing edge).
  [[nodiscard]] QueryResult<coord::Acceleration> Evaluate() noexcept {
    coord::Acceleration A{semantics_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    return internal::Answer(Evaluate(A.linear, A.angular), A);
  }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return steps_.size(); }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return parent_.size(); }

 private:
  /// A twist step: the record it reads (step.epoch: the acceleration record's; record: its
  /// value, resolved once) and the scratch entry of its head's pose in Z.
  struct Step {
    TwistStep<typename CompiledQuery<B>::Chain> step;
    const AccelerationValue* record = nullptr;
    std::int32_t head = -1;
  };
  [[gnu::flatten]] ErrorCode Compose(const internal::FlatSource<B>& src,
                                     internal::Motion& out) noexcept;

  semantics::AccelerationSemantics semantics_;
  std::vector<std::int32_t> parent_;  ///< per union edge (edges_ entry i): the entry above, -1: Z
  std::vector<Step> steps_;           ///< D's side in the plan's order, then C's reversed
  std::int32_t e_entry_ = 0, r_entry_ = 0;  ///< scratch entries of e's and [r]'s poses in Z
  /// Per union edge: its head's pose in Z; then Z's own (the identity: the entry of e, [r] or
  /// a head that is Z). Empty when there is no step.
  std::vector<typename B::PoseCoords> scratch_;
};

extern template class CompiledAcceleration<coord::QuaternionBackend>;
extern template class CompiledAcceleration<coord::HomogeneousBackend>;

}  // namespace semgraph::core
