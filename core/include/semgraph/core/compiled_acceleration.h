// File: semgraph/core/compiled_acceleration.h
//
// CompiledAcceleration: AccelerationCoord(e|C, D, [r]) compiled (SceneGraph::CompileAcceleration,
// build time, allocates): the twist plan's steps flattened as CompiledTwist's, each with the
// epoch of its edge's acceleration record, evaluated any number of times by the one evaluator
// (evaluate.h: AccelerationStep, AccelerationComposer over FlatSource).
//
// Under a time policy each edge is read as the timed one-shot query reads it (timed_read.h).
// Invariants: as every compiled query (compiled_query.h): a removed edge of the path makes
// Evaluate return kQueryInvalidated, never a wrong number. An edge of the path that carries no
// acceleration when evaluated (never given, or cleared by a twist given without one):
// kNoAcceleration. Costs: Evaluate O(edges on the path and on their pose paths); noexcept,
// allocation-free, lock-free, string-free. Thread safety: as CompiledTwist (one writer, any number
// of readers); each edge's acceleration and twist are read together, untorn.
#pragma once

#include <vector>

#include "semgraph/core/compiled_query.h"

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
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& a_DCe_R,
                                   Eigen::Vector3d& alpha_DC_R) const noexcept;
  /// At the policy's time (as CompiledTwist's): also kInvalidNumber (a negative horizon),
  /// kExtrapolation, kStale; the outputs are written on kOk only.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& a_DCe_R, Eigen::Vector3d& alpha_DC_R,
                                   const TimePolicy& policy, TimeReport& report) const noexcept;
  /// In GetAcceleration's result type (without the name of a missing edge).
  [[nodiscard]] QueryResult<coord::Acceleration> Evaluate() const noexcept {
    coord::Acceleration A{semantics_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    return internal::Answer(Evaluate(A.linear, A.angular), A);
  }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return steps_.size(); }

 private:
  ErrorCode Compose(const internal::FlatSource<B>& src, internal::Motion& out) const noexcept;

  semantics::AccelerationSemantics semantics_;
  std::vector<TwistStep<typename CompiledQuery<B>::Chain>> steps_;
};

extern template class CompiledAcceleration<coord::QuaternionBackend>;
extern template class CompiledAcceleration<coord::HomogeneousBackend>;

}  // namespace semgraph::core
