// File: semgraph/core/compiled_query.h
//
// Compiled queries: a query plan (query_plan.h: semantics checked, path resolved once, by
// SceneGraph::Compile*, build time, allocates) with its chains flattened into an edge list,
// then evaluated any number of times on the real-time path by the one evaluator (evaluate.h,
// FlatSource). For a frame-to-frame pose that is one composition per edge, as a hand-written
// chain would do. A compiled query reads the graph's EdgeValues only; it needs no access to the
// graph's topology after compiling.
//
// Invariants: a compiled query holds, for every edge it reads, the edge's epoch at compile time;
// removing an edge bumps its epoch, so Evaluate() of an affected query returns
// kQueryInvalidated (never a wrong number). Adding edges never changes an existing path (pose
// trees and TG(P) stay forests), so it invalidates nothing. Recompile to recover.
// One result type: Evaluate() returns the answer as the one-shot query does (QueryResult<Pose>
// like GetPose, with the semantics), the Evaluate(out) forms write bare coordinates.
// Costs: Evaluate O(edges on the path), noexcept, no allocation, no lock, no string.
// Thread safety: Evaluate is const and may run on any number of threads concurrently with one
// writer calling SceneGraph::SetPose/SetTwist. Each edge value is read untorn (sequence lock);
// different edges of one path may come from different writer updates (there is no cross-edge
// snapshot). The writer may also change the topology (add/remove) meanwhile: each edge is read
// through the address of its value, taken at compile time (values never move: stable_array.h),
// and its epoch check turns a removal into kQueryInvalidated, so an untimed Evaluate answers for
// the graph it was compiled on or is invalidated. The timed forms and twists from pose
// derivatives too: they read sample histories, which a removal retires but never frees
// (edge_history.h HistoryTable), between two epoch checks of each edge (evaluate.h FlatSource).
// Not under concurrent topology changes: an At evaluation that extrapolates
// (max_extrapolation > 0, a time outside an edge's samples), which plans a twist from the
// topology (docs/realtime.md).
// Time (docs/time.md): Evaluate(..., policy, report) reads every edge at the policy's time
// through the same evaluator and reports what it read; also noexcept and allocation-free
// (extrapolation plans its twist from the graph's topology, which is why a compiled query keeps
// a pointer to it). Codes: kOk, kQueryInvalidated, kInvalidNumber (a negative horizon),
// kExtrapolation, kStale.
#pragma once

#include <cstdint>
#include <vector>

#include "semgraph/core/edge_values.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/export.h"
#include "semgraph/core/query_plan.h"
#include "semgraph/core/time.h"
#include "semgraph/core/time_plan.h"

namespace semgraph::core {

/// A caller-owned memo of a compiled pose, position or orientation query: per chain of the
/// query, a balanced tree of partial products over its edges, with the sequence-lock header
/// each edge value was read under. Made by MakeCache() (allocates); used by Evaluate(out, cache)
/// (no allocation). Opaque to callers.
///
/// Why: in a control loop most edges of a path are constant (mountings, calibrations) or change
/// less often than the query runs. An evaluation reads every edge's header (a load and a
/// compare), reloads only the edges whose header changed, and recomposes only the tree nodes
/// above them: O(n + k log n) for k changed edges of n, instead of n compositions. When most
/// edges changed it rebuilds the tree and composes the next few evaluations directly, as the
/// uncached query does, then looks again (compiled_query.cc: the policy).
/// Invariants: a cached leaf is the value its edge had under the cached header (so it is never
/// torn: it was read under the sequence lock); an internal node is the product of its children
/// whenever `built`. Cost: 2 * next_pow2(n) pose values + n headers per chain (bytes()).
/// Thread safety: one cache per evaluating thread; the compiled query itself stays shareable.
template <coord::Backend B>
struct PoseCache {
  struct Tree {
    std::uint32_t leaves = 0;       // power of two >= the chain's edges
    std::uint32_t node_offset = 0;  // nodes_[node_offset + k], k = 1 .. 2 * leaves - 1
    std::uint32_t skip = 0;         // evaluations left that compose directly (busy chain)
    std::uint32_t unscanned = 0;    // evaluations composed directly since the last scan
    bool built = false;             // internal nodes are the products of their children
    bool scanned = false;           // every leaf has been loaded once
  };
  std::uint64_t query_id = 0;                 // the compiled query (and its copies) it serves
  std::vector<Tree> trees;                    // one per chain
  std::vector<std::uint32_t> tree_of_begin;   // by edge index: the tree of the chain starting there
  std::vector<std::uint64_t> headers;         // by edge index: header of the cached leaf value
  std::vector<typename B::PoseCoords> nodes;  // every tree's nodes
  std::vector<std::uint32_t> changed;         // scratch: changed leaves of one chain
  [[nodiscard]] std::size_t bytes() const noexcept {
    return trees.capacity() * sizeof(Tree) + tree_of_begin.capacity() * 4 + headers.capacity() * 8 +
           nodes.capacity() * sizeof(typename B::PoseCoords) + changed.capacity() * 4;
  }
};

/// Shared machinery of the compiled queries: the flattened edges and the values they read.
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledQuery {
 public:
  using PoseCoords = typename B::PoseCoords;

  /// True while every edge the query reads still exists (O(edges)).
  [[nodiscard]] bool is_valid() const noexcept;
  /// Number of pose edges read per evaluation (the path length).
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return edges_.size(); }
  /// A memo for Evaluate(out, cache) (build time, allocates; PoseCache).
  [[nodiscard]] PoseCache<B> MakeCache() const;

 protected:
  using Chain = internal::FlatChain;
  CompiledQuery() = default;
  CompiledQuery(const topology::SceneTopology& t, const EdgeValues<B>& values);

  /// Appends the edges of a one-shot chain to the list; returns their range.
  Chain Flatten(const topology::SceneTopology& t, const ForestChain& c);
  BasicPath<Chain> Flatten(const topology::SceneTopology& t, const BasicPath<ForestChain>& path);
  PoseSteps<Chain> Flatten(const topology::SceneTopology& t, const PoseSteps<ForestChain>& s);
  [[nodiscard]] internal::FlatSource<B> source() const noexcept {
    return {*values_, edges_.data()};
  }
  [[nodiscard]] internal::FlatSource<B> source(internal::TimeContext& tc) const noexcept {
    return {*values_, edges_.data(), &tc};
  }
  /// Runs eval(const FlatSource<B>&) -> bool (false: invalidated) under the policy.
  template <class Eval>
  ErrorCode RunTimed(const TimePolicy& policy, TimeReport& report, Eval&& eval) const noexcept;
  [[nodiscard]] internal::CachedSource<B> source(PoseCache<B>& cache) const noexcept;

  const topology::SceneTopology* topology_ = nullptr;
  const EdgeValues<B>* values_ = nullptr;
  std::vector<internal::EdgeRef> edges_;
  std::vector<Chain> chains_;  // every flattened chain, for MakeCache
  std::uint64_t id_ = 0;       // shared by copies (same edges): identifies the caches it made
};

// Defined here (not in compiled_query.cc) so that every compiled query's file can run it.
template <coord::Backend B>
template <class Eval>
ErrorCode CompiledQuery<B>::RunTimed(const TimePolicy& policy, TimeReport& report,
                                     Eval&& eval) const noexcept {
  const internal::PolicyParts parts = internal::PartsOf(policy);
  if (!parts.valid()) return ErrorCode::kInvalidNumber;
  internal::TimeContext base;
  base.histories = &values_->history;
  base.topology = topology_;
  return internal::RunPolicy(
      parts, base,
      [&](internal::TimeContext& tc) {
        return eval(this->source(tc)) ? ErrorCode::kOk : ErrorCode::kQueryInvalidated;
      },
      report);
}

namespace internal {
/// A compiled query's answer as the one-shot queries give it: the value, or a QueryError with
/// only the code (kQueryInvalidated: the query says nothing more).
template <class T>
QueryResult<T> Answer(ErrorCode code, const T& value) noexcept {
  if (code == ErrorCode::kOk) return value;
  QueryError e;
  e.code = code;
  return base::Unexpected{e};
}
}  // namespace internal

/// A compiled pose, position or orientation query: part P of PoseCoord((e,[a])|C, (f,[b])|D,
/// [r]) (internal::PartTraits: the value Evaluate writes, the result type, the plan). One
/// implementation for the three parts; use them by their names below.
template <coord::Backend B, internal::Part P>
class SEMGRAPH_CORE_EXPORT CompiledPoseQuery : public CompiledQuery<B> {
 public:
  using Traits = internal::PartTraits<B, P>;
  using Value = typename Traits::Value;    ///< what Evaluate(out) writes
  using Result = typename Traits::Result;  ///< what Evaluate() returns, with the semantics

  CompiledPoseQuery() = default;
  /// Made by SceneGraph::Compile* from a checked plan of that graph.
  CompiledPoseQuery(const topology::SceneTopology& t, const EdgeValues<B>& values,
                    const typename Traits::Plan& plan);
  [[nodiscard]] const typename Traits::Semantics& semantics() const noexcept { return semantics_; }
  /// Writes the answer. kOk or kQueryInvalidated (then `out` is unchanged).
  [[nodiscard]] ErrorCode Evaluate(Value& out) const noexcept;
  /// At the policy's time (compiled_query.h, Time); `out` is written on kOk only.
  [[nodiscard]] ErrorCode Evaluate(Value& out, const TimePolicy& policy,
                                   TimeReport& report) const noexcept;
  /// The same answer through a memo of partial products (PoseCache, from MakeCache() of this
  /// query): far fewer compositions when few edges changed since the last evaluation.
  [[nodiscard]] ErrorCode Evaluate(Value& out, PoseCache<B>& cache) const noexcept;
  /// The answer in the one-shot query's result type (GetPose, GetPosition, GetOrientation):
  /// the value with its semantics, or the error (kQueryInvalidated). The numbers of
  /// Evaluate(out).
  [[nodiscard]] QueryResult<Result> Evaluate() const noexcept {
    Result r{semantics_, Traits::Initial()};
    return internal::Answer(Evaluate(r.value), r);
  }
  [[nodiscard]] QueryResult<Result> Evaluate(PoseCache<B>& cache) const noexcept {
    Result r{semantics_, Traits::Initial()};
    return internal::Answer(Evaluate(r.value, cache), r);
  }

 private:
  typename Traits::Semantics semantics_;
  PoseSteps<typename CompiledQuery<B>::Chain> steps_;
};

/// PoseCoord((e,[a])|C, (f,[b])|D, [r]): Evaluate(X) writes the pose X (orientation operator
/// and position, in [r]).
template <coord::Backend B>
class CompiledPose : public CompiledPoseQuery<B, internal::Part::kPose> {
 public:
  using CompiledPoseQuery<B, internal::Part::kPose>::CompiledPoseQuery;
};

/// PositionCoord(e|C, f|D, [r]): Evaluate(p_FE_R) writes the position of e wrt f in [r].
template <coord::Backend B>
class CompiledPosition : public CompiledPoseQuery<B, internal::Part::kTranslation> {
 public:
  using CompiledPoseQuery<B, internal::Part::kTranslation>::CompiledPoseQuery;
};

/// OrientationCoord([a]|C, [b]|D, [r]): Evaluate(R_BA_R) writes the orientation operator of [a]
/// wrt [b] in [r].
template <coord::Backend B>
class CompiledOrientation : public CompiledPoseQuery<B, internal::Part::kRotation> {
 public:
  using CompiledPoseQuery<B, internal::Part::kRotation>::CompiledPoseQuery;
};

/// TwistCoord(e|C, D, [r]); linear and angular velocity are its parts.
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledTwist : public CompiledQuery<B> {
 public:
  CompiledTwist() = default;
  CompiledTwist(const topology::SceneTopology& t, const EdgeValues<B>& values,
                const TwistPlan& plan);
  /// Twist source `poses`: the pose edges' derivatives (time_plan.h); an Evaluate with a policy
  /// ignores its horizon (nothing is extrapolated from poses).
  CompiledTwist(const topology::SceneTopology& t, const EdgeValues<B>& values,
                const PoseTwistPlan& plan);
  [[nodiscard]] const semantics::TwistSemantics& semantics() const noexcept { return semantics_; }
  /// v_DCe_R: velocity of the point of C at e relative to D; w_DC_R: angular velocity; in [r].
  /// From poses: the timed Evaluate under Latest, with its codes (a used edge with one sample
  /// has no derivative: kExtrapolation); the outputs are written on kOk only.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& v_DCe_R,
                                   Eigen::Vector3d& w_DC_R) const noexcept;
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R,
                                   const TimePolicy& policy, TimeReport& report) const noexcept;
  /// In GetTwist's result type (see CompiledPoseQuery::Evaluate()).
  [[nodiscard]] QueryResult<coord::Twist> Evaluate() const noexcept {
    coord::Twist V{semantics_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    return internal::Answer(Evaluate(V.linear, V.angular), V);
  }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return steps_.size(); }

 private:
  void AddStep(const topology::SceneTopology& t, const EdgeValues<B>& values,
               const TwistStep<ForestChain>& step);
  template <class Source>
  bool Accumulate(const Source& src, Eigen::Vector3d& v, Eigen::Vector3d& w) const noexcept;

  semantics::TwistSemantics semantics_;
  std::vector<TwistStep<typename CompiledQuery<B>::Chain>> steps_;
  bool from_poses_ = false;  ///< twist source `poses`: never extrapolates (the horizon is ignored)
};

extern template class CompiledQuery<coord::QuaternionBackend>;
extern template class CompiledQuery<coord::HomogeneousBackend>;
extern template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kPose>;
extern template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kPose>;
extern template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kTranslation>;
extern template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kTranslation>;
extern template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kRotation>;
extern template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kRotation>;
extern template class CompiledTwist<coord::QuaternionBackend>;
extern template class CompiledTwist<coord::HomogeneousBackend>;

}  // namespace semgraph::core
