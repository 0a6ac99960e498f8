// File: semgraph/core/compiled_covariance.h
//
// CompiledPoseWithCovariance<B>: a compiled pose query that gives the first-order covariance of
// its answer too (docs/uncertainty.md §3), on the real-time path. Made by
// SceneGraph::CompilePoseWithCovariance (build time, allocates): the query's frames e, [a], f,
// [b], [r], their youngest common ancestor Z, and the union of their chains up to Z as one
// edge list in top-down order (each edge after its parent's), each with the frames it moves.
// Evaluate reads each edge once, value and covariance together (one record,
// EdgeValues::LoadPoseIntoLanes, so they are consistent under a concurrent writer), composes
// every edge's pose in Z (one composition per edge, as the plain query), puts each uncertain
// edge's covariance, rotation and Jacobian factors in a SIMD lane, computes the answer from the
// frames' poses in Z, then sums each uncertain edge's J S J^T (covariance_lanes.h, the kernel of
// one-shot queries too, checked against coord/jacobians.h EdgeOnPoseInZ).
// At a time (Evaluate with a TimePolicy): each edge read with its covariance by the one-shot
// timed query's reader (timed_read.h ReadPoseAt, between two epoch checks as evaluate.h
// FlatSource), then the same composition and propagation (through propagate.h DirectSink);
// within the policy's max_extrapolation an edge outside its samples is extrapolated as the
// one-shot query does (its integration twist planned at compile time: IntegrationTwistPlans, one
// per edge), and an extrapolated answer's Jacobians are keyed (timed_covariance.h KeyedSink).
// Invariants: the edge list holds each edge's epoch and value record at compile time (records
// never move); a removed edge turns an evaluation into kQueryInvalidated (nothing written). The
// integration twist plans are those of the topology at compile time (recompile after a topology
// change).
// Costs: Evaluate O(edges) (latest common: two passes over the edges): one composition per edge,
// plus one J S J^T per edge that carries a covariance, with the edges in SIMD lanes (about 4.2x /
// 4.5x the query without covariance on the bench chain at d = 64 / 8 with AVX2,
// docs/performance.md "Covariances"); noexcept, allocation-free (the lanes are sized at compile
// time), lock-free, string-free. Thread safety: Evaluate uses the object's own scratch
// (one evaluating thread per object; a copy is independent), concurrently with one writer (SetPose,
// Add*, Remove*), except an evaluation that extrapolates: it walks the twist forests of its
// integration twists, which a topology change rewrites (docs/realtime.md, "Which evaluations").
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/jacobians.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/export.h"
#include "semgraph/core/specs.h"
#include "semgraph/core/uncertainty.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core {

using topology::FrameIndex;

namespace internal {

/// The pose edges a compiled query with covariance reads: the union of the chains of `ends` up
/// to their youngest common ancestor `z`, each edge once (named by its head frame), top-down
/// (each after the edge above it). Build time (allocates); O(n^2) for n edges.
[[nodiscard]] std::vector<FrameIndex> ChainUnionTopDown(const topology::SceneTopology& t,
                                                        std::span<const FrameIndex> ends,
                                                        FrameIndex z);
/// The index of g in `edges`, -1 when absent (z itself). Build time.
[[nodiscard]] std::int32_t EntryOf(const std::vector<FrameIndex>& edges, FrameIndex g);

/// One edge of such a list at evaluation: its head's pose in Z and its covariance.
struct PoseEdgeInZ {
  Eigen::Matrix3d R_ZG;
  Eigen::Vector3d p_ZG;
  Covariance6 S;
  bool exact;
};
/// Sets out's pose in Z from the edge's value X_PG and `up` (the edge above, nullptr: below Z).
/// noexcept, allocation-free.
template <coord::Backend B>
[[gnu::always_inline]] inline void ComposePoseEdgeInZ(const typename B::PoseCoords& X_PG,
                                                      const PoseEdgeInZ* up,
                                                      PoseEdgeInZ& out) noexcept {
  const Eigen::Matrix3d R_PG = B::ToMatrix(B::RotationOf(X_PG));
  const Eigen::Vector3d p_PG = B::TranslationOf(X_PG);
  if (up == nullptr) {
    out.R_ZG = R_PG;
    out.p_ZG = p_PG;
  } else {
    out.R_ZG.noalias() = up->R_ZG * R_PG;
    out.p_ZG.noalias() = up->R_ZG * p_PG;
    out.p_ZG += up->p_ZG;
  }
}

/// Reads the pose edge into `frame` (value and covariance of one write, between two checks of
/// its epoch) and composes it with `up` (the edge above, nullptr: below Z). False when the edge
/// was removed since `epoch`. noexcept, allocation-free.
template <coord::Backend B>
bool LoadPoseEdgeInZ(const EdgeValues<B>& values, std::uint32_t frame, std::uint32_t epoch,
                     const PoseEdgeInZ* up, PoseEdgeInZ& out) noexcept {
  const PoseValue<B>& value = values.X_PF[frame];
  typename B::PoseCoords X_PG;
  if (value.epoch() != epoch) return false;
  values.LoadPose(frame, X_PG, out.S);       // value and covariance of one write
  if (value.epoch() != epoch) return false;  // removed meanwhile
  out.exact = out.S.isZero(0.0);
  ComposePoseEdgeInZ<B>(X_PG, up, out);
  return true;
}

/// LoadPoseEdgeInZ at the context's time: the value and covariance ReadPoseAt<B, true> gives
/// (timed_read.h; the one-shot timed query's reader), between two checks of the epoch (as
/// evaluate.h FlatSource). The caller includes timed_covariance.h (ReadPoseAt's extrapolation).
template <coord::Backend B>
bool LoadPoseEdgeInZAt(const EdgeValues<B>& values, std::uint32_t frame, std::uint32_t epoch,
                       TimeContext& tc, const PoseEdgeInZ* up, PoseEdgeInZ& out) noexcept {
  const PoseValue<B>& value = values.X_PF[frame];
  typename B::PoseCoords X_PG;
  if (value.epoch() != epoch) return false;
  ReadPoseAt<B, true>(values, frame, tc, X_PG, &out.S);
  if (value.epoch() != epoch) return false;
  out.exact = out.S.isZero(0.0);
  ComposePoseEdgeInZ<B>(X_PG, up, out);
  return true;
}

/// Runs eval(TimeContext&) (kOk, or kQueryInvalidated: an edge was removed) under the policy
/// for a compiled query with covariance, as the one-shot timed queries run theirs (RunPolicy):
/// within the policy's horizon a pose edge is extrapolated with its integration twist, whose
/// plan is the query's `plans` (made at compile time, IntegrationTwistPlans), and a twist edge
/// holds its nearest sample. kOk, kInvalidNumber (a negative horizon), kExtrapolation, kStale
/// or kQueryInvalidated; fills the report. noexcept, allocation-free.
template <class Eval>
[[nodiscard]] ErrorCode RunWithCovariance(const TimePolicy& policy, const EdgeHistories& histories,
                                          const topology::SceneTopology* topology,
                                          const IntegrationTwistPlans& plans, Eval&& eval,
                                          TimeReport& report) noexcept {
  const PolicyParts parts = PartsOf(policy);
  if (!parts.valid()) return ErrorCode::kInvalidNumber;
  TimeContext base;
  base.histories = &histories;
  base.topology = topology;
  base.twist_plans = &plans;
  return RunPolicy(parts, base, eval, report);
}

}  // namespace internal

template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledPoseWithCovariance {
 public:
  using PoseCoords = typename B::PoseCoords;

  CompiledPoseWithCovariance() = default;
  /// From the frames {e, a, f, b, r} of a checked pose plan (all of one pose tree).
  CompiledPoseWithCovariance(const topology::SceneTopology& t, const EdgeValues<B>& values,
                             const semantics::PoseSemantics& semantics, const FrameIndex (&k)[5]);
  [[nodiscard]] const semantics::PoseSemantics& semantics() const noexcept { return semantics_; }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return edges_.size(); }

  /// The answer X (as CompiledPose::Evaluate writes it, up to rounding) and its covariance S
  /// (rows (dp, dth) in [r], in `order`). kOk or kQueryInvalidated (nothing written).
  [[nodiscard]] ErrorCode Evaluate(
      PoseCoords& X, Covariance6& S,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept;
  /// In GetPoseWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::Pose<B>, 6>> Evaluate(
      CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept {
    WithCovariance<coord::Pose<B>, 6> r{{semantics_, B::Identity()}, Covariance6::Zero()};
    return internal::Answer(Evaluate(r.value.value, r.covariance, order), r);
  }
  /// At the policy's time (docs/time.md): each edge's value and covariance read as the one-shot
  /// GetPoseWithCovariance(spec, policy) reads them (timed_read.h ReadPoseAt: a sample's, or the
  /// interpolation of two at the time; latest: the newest; latest common: at the minimum of the
  /// newest stamps; outside an edge's samples, within the policy's max_extrapolation, the edge
  /// integrated with its integration twist, whose plan was made at compile time), the same
  /// composition and propagation as above, and the report of what was read. When the answer was
  /// extrapolated, the Jacobians go through the one-shot query's keyed sink (timed_covariance.h
  /// KeyedSink: an edge shared by an integration twist and the query is perturbed once), so the
  /// answer, covariance and report are the one-shot query's (up to rounding). Codes: kOk,
  /// kQueryInvalidated, kInvalidNumber (a negative horizon), kExtrapolation (beyond
  /// max_extrapolation, or no integration twist), kStale; X and S are written on kOk only,
  /// report as the plain compiled queries fill it (reset first, complete on kOk). Extra cost
  /// when extrapolated: per extrapolated edge its integration twist evaluated twice and
  /// propagated twice over its path (the edge's covariance as read, then keyed: as the one-shot
  /// query), a plan lookup O(log edges), the keyed sum's linear search over at most 32 keys per
  /// Jacobian, and SharedPerturbations on the stack (about 20 KB); still noexcept and
  /// allocation-free. Not under concurrent topology changes when it extrapolates (the
  /// integration twists walk the twist forest, as plain compiled queries: compiled_query.h).
  [[nodiscard]] ErrorCode Evaluate(
      PoseCoords& X, Covariance6& S, const TimePolicy& policy, TimeReport& report,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept;

 private:
  struct Edge {
    std::uint32_t frame;  ///< the edge's head (its value and covariance records)
    std::uint32_t epoch;
    std::int32_t parent;  ///< the entry of the edge above (its tail's edge), -1: Z
    coord::jacobians::PoseMoves moves;
    /// The edge's Jacobian factors (EdgeOnPoseFactors) as covariance_lanes.h takes them:
    /// s, c, d, and the lever arm s g + alpha e + beta f.
    double s, c, d, alpha, beta;
    const PoseValue<B>* value;  ///< its value record (records never move: stable_array.h)
  };
  using InZ = internal::PoseEdgeInZ;  // scratch of one evaluation, per edge
  // The answer from the frames' poses in Z (scratch_), and the Jacobians' common parts.
  void AnswerInZ(PoseCoords& X, coord::jacobians::PoseInZ& q) const noexcept;
  // The answer and its covariance from the edges in scratch_ (loaded by either Evaluate), each
  // uncertain edge's Jacobian into `sink` (propagate.h DirectSink, or a KeyedSink).
  template <class Sink>
  void Finish(PoseCoords& X, Covariance6& S, CovarianceOrder order, Sink&& sink) const noexcept;
  // The same from the `count` edges Evaluate put in lanes_.
  void FinishLanes(PoseCoords& X, Covariance6& S, CovarianceOrder order, int count) noexcept;
  // Every edge at the context's time into scratch_; false when one was removed.
  bool LoadAt(internal::TimeContext& tc) noexcept;
  semantics::PoseSemantics semantics_;
  const EdgeValues<B>* values_ = nullptr;
  const topology::SceneTopology* topology_ = nullptr;  ///< extrapolation's twist forests
  std::vector<Edge> edges_;
  internal::IntegrationTwistPlans plans_;  ///< each edge's integration twist (extrapolation)
  std::int32_t frame_entry_[5] = {-1, -1, -1, -1, -1};  ///< the entry of each frame's edge
  std::vector<InZ> scratch_;
  /// The uncertain edges' inputs to the covariance kernel (covariance_lanes.h LaneIndex), one
  /// lane per uncertain edge in evaluation order.
  std::vector<double> lanes_;
  bool with_o_ = false;  ///< some edge has d != 0
};

/// CompiledPositionWithCovariance<B> and CompiledOrientationWithCovariance<B>: the pose query
/// above on the frames {e, e, f, f, r} (the position of e wrt f in [r]) or {a, a, b, b, r} (the
/// orientation of [a] wrt [b] in [r]), answering its translation or rotation and the linear or
/// angular 3x3 block of its covariance: what GetPositionWithCovariance and
/// GetOrientationWithCovariance answer. Made by SceneGraph::CompilePositionWithCovariance /
/// CompileOrientationWithCovariance. Invariants, costs and thread safety: the pose query's.
template <coord::Backend B>
class CompiledPositionWithCovariance {
 public:
  CompiledPositionWithCovariance() = default;
  CompiledPositionWithCovariance(const semantics::PositionSemantics& s,
                                 CompiledPoseWithCovariance<B> pose)
      : semantics_(s), pose_(std::move(pose)) {}
  [[nodiscard]] const semantics::PositionSemantics& semantics() const noexcept {
    return semantics_;
  }
  /// p_FoEo_R and its covariance. kOk or kQueryInvalidated (nothing written).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& p_FoEo_R, Eigen::Matrix3d& S) noexcept {
    typename B::PoseCoords X;
    Covariance6 S6;
    const ErrorCode code = pose_.Evaluate(X, S6);
    if (code != ErrorCode::kOk) return code;
    p_FoEo_R = B::TranslationOf(X);
    S = S6.template topLeftCorner<3, 3>();
    return code;
  }
  /// At the policy's time (CompiledPoseWithCovariance's timed Evaluate: codes, report).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& p_FoEo_R, Eigen::Matrix3d& S,
                                   const TimePolicy& policy, TimeReport& report) noexcept {
    typename B::PoseCoords X;
    Covariance6 S6;
    const ErrorCode code = pose_.Evaluate(X, S6, policy, report);
    if (code != ErrorCode::kOk) return code;
    p_FoEo_R = B::TranslationOf(X);
    S = S6.template topLeftCorner<3, 3>();
    return code;
  }
  /// In GetPositionWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::Position, 3>> Evaluate() noexcept {
    WithCovariance<coord::Position, 3> r{{semantics_, Eigen::Vector3d::Zero()},
                                         Eigen::Matrix3d::Zero()};
    return internal::Answer(Evaluate(r.value.value, r.covariance), r);
  }

 private:
  semantics::PositionSemantics semantics_;
  CompiledPoseWithCovariance<B> pose_;
};

template <coord::Backend B>
class CompiledOrientationWithCovariance {
 public:
  CompiledOrientationWithCovariance() = default;
  CompiledOrientationWithCovariance(const semantics::OrientationSemantics& s,
                                    CompiledPoseWithCovariance<B> pose)
      : semantics_(s), pose_(std::move(pose)) {}
  [[nodiscard]] const semantics::OrientationSemantics& semantics() const noexcept {
    return semantics_;
  }
  /// R_BA_R (in B's rotation form) and its covariance. kOk or kQueryInvalidated (nothing
  /// written).
  [[nodiscard]] ErrorCode Evaluate(typename B::Rotation& R_BA_R, Eigen::Matrix3d& S) noexcept {
    typename B::PoseCoords X;
    Covariance6 S6;
    const ErrorCode code = pose_.Evaluate(X, S6);
    if (code != ErrorCode::kOk) return code;
    R_BA_R = B::RotationOf(X);
    S = S6.template bottomRightCorner<3, 3>();
    return code;
  }
  /// At the policy's time (CompiledPoseWithCovariance's timed Evaluate: codes, report).
  [[nodiscard]] ErrorCode Evaluate(typename B::Rotation& R_BA_R, Eigen::Matrix3d& S,
                                   const TimePolicy& policy, TimeReport& report) noexcept {
    typename B::PoseCoords X;
    Covariance6 S6;
    const ErrorCode code = pose_.Evaluate(X, S6, policy, report);
    if (code != ErrorCode::kOk) return code;
    R_BA_R = B::RotationOf(X);
    S = S6.template bottomRightCorner<3, 3>();
    return code;
  }
  /// In GetOrientationWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::Orientation<B>, 3>> Evaluate() noexcept {
    WithCovariance<coord::Orientation<B>, 3> r{{semantics_, B::RotationOf(B::Identity())},
                                               Eigen::Matrix3d::Zero()};
    return internal::Answer(Evaluate(r.value.value, r.covariance), r);
  }

 private:
  semantics::OrientationSemantics semantics_;
  CompiledPoseWithCovariance<B> pose_;
};

extern template class CompiledPoseWithCovariance<coord::QuaternionBackend>;
extern template class CompiledPoseWithCovariance<coord::HomogeneousBackend>;

}  // namespace semgraph::core
