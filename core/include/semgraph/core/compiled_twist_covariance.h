// File: semgraph/core/compiled_twist_covariance.h
//
// CompiledTwistWithCovariance<B>: a compiled twist query that gives the first-order covariance
// of its answer too (docs/uncertainty.md §3), on the real-time path. Made by
// SceneGraph::CompileTwistWithCovariance (build time, allocates): the twist edges of Algorithm
// 3's path (each with its head h and sign), the point e and [r], their youngest common ancestor
// Z, and the union of the pose chains of e, [r] and every h up to Z as one edge list in top-down
// order (each edge after its parent's), each with the frames it moves: e, [r], and a bit per
// twist edge (its head). No twist edge (C = D): no pose edge either (the answer is zero).
// Evaluate reads each edge once, value and covariance together (EdgeValues::LoadPose /
// LoadTwist: consistent under a concurrent writer), composes every pose edge's pose in Z (one
// composition per edge), sums the twist edges' contributions in Z (a_Z + w_Z x (e - h), w_Z),
// then adds each uncertain twist edge's J S J^T and each uncertain pose edge's (the Jacobians of
// coord/jacobians.h: TwistEdgeOnTwist, PoseEdgeOnTwistSum, the formulas one-shot queries use
// through core/propagate.h).
// Invariants: each edge's epoch at compile time is kept; a removed edge turns an evaluation into
// kQueryInvalidated (nothing written). At a time (Evaluate with a TimePolicy): each edge read
// with its covariance by the one-shot timed query's readers (timed_read.h), extrapolating as the
// one-shot query within the policy's max_extrapolation (a twist edge holds its nearest sample, a
// pose edge is integrated with its integration twist, planned at compile time:
// IntegrationTwistPlans, one per pose edge; recompile after a topology change), with keyed
// Jacobians when the answer was extrapolated (timed_covariance.h KeyedSink).
// Twist source `poses` (the PoseTwistPlan constructor): each step is an inter-body pose edge's
// derivative at the time (its head h, its two samples' covariances) in place of a twist edge,
// never extrapolated (as the one-shot GetTwistWithCovariance(spec, policy, order, kPoses)).
// Costs: Evaluate O(n + k + u k) for n pose edges, k twist edges and u uncertain pose edges:
// one composition per pose edge, one Jacobian per uncertain edge; noexcept, allocation-free,
// lock-free, string-free.
// Thread safety: Evaluate uses the object's own scratch (one evaluating thread per object; a
// copy is independent), concurrently with one writer (SetPose, SetTwist, Add*, Remove*), except
// an evaluation that extrapolates: it walks the twist forests of its integration twists, which a
// topology change rewrites (docs/realtime.md, "Which evaluations").
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/jacobians.h"
#include "semgraph/coord/operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/core/compiled_covariance.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/export.h"
#include "semgraph/core/query_plan.h"
#include "semgraph/core/time_plan.h"
#include "semgraph/core/uncertainty.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core {

template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledTwistWithCovariance {
 public:
  CompiledTwistWithCovariance() = default;
  /// From a checked twist plan (PlanTwist).
  CompiledTwistWithCovariance(const topology::SceneTopology& t, const EdgeValues<B>& values,
                              const TwistPlan& plan);
  /// Twist source `poses` (PlanPoseTwist, time_plan.h): each step is an inter-body pose edge's
  /// derivative at the time (timed_read.h DerivePoseAt with its covariance), in place of a twist
  /// edge (same sums and Jacobians, as propagate.h PoseTwistCovariance); every edge is read with
  /// no horizon (never extrapolates, as the one-shot query: WithoutExtrapolation). The untimed
  /// Evaluate reads the derivatives under Latest (as CompiledTwist from poses).
  CompiledTwistWithCovariance(const topology::SceneTopology& t, const EdgeValues<B>& values,
                              const PoseTwistPlan& plan);
  [[nodiscard]] const semantics::TwistSemantics& semantics() const noexcept { return semantics_; }
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return pose_edges_.size(); }
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return steps_.size(); }

  /// The answer (v_DCe_R, w_DC_R) (as CompiledTwist::Evaluate writes it, up to rounding) and its
  /// covariance S (rows (dv, dw) in [r], in `order`). kOk or kQueryInvalidated (nothing
  /// written); from poses: the timed Evaluate under Latest (its codes too).
  [[nodiscard]] ErrorCode Evaluate(
      Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R, Covariance6& S,
      CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept;
  /// At the policy's time: each pose and twist edge's value and covariance read as the one-shot
  /// GetTwistWithCovariance(spec, policy) reads them (timed_read.h ReadPoseAt / ReadTwistAt with
  /// their covariance), then the same sums and Jacobians as above, and the report of what was
  /// read. Extrapolates as the one-shot query (CompiledPoseWithCovariance's timed Evaluate:
  /// within max_extrapolation a twist edge holds its nearest sample, a pose edge is integrated
  /// with its integration twist; keyed Jacobians when the answer was extrapolated), so answer,
  /// covariance and report are the one-shot's (up to rounding). Codes: kOk, kQueryInvalidated,
  /// kInvalidNumber, kExtrapolation, kStale; the answer and S are written on kOk only. Extra
  /// cost when extrapolated: as CompiledPoseWithCovariance's (about 20 KB of stack).
  [[nodiscard]] ErrorCode Evaluate(
      Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R, Covariance6& S, const TimePolicy& policy,
      TimeReport& report, CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept;
  /// In GetTwistWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::Twist, 6>> Evaluate(
      CovarianceOrder order = CovarianceOrder::kLinearAngular) noexcept {
    WithCovariance<coord::Twist, 6> r{
        {semantics_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, Covariance6::Zero()};
    return internal::Answer(Evaluate(r.value.linear, r.value.angular, r.covariance, order), r);
  }

 private:
  struct PoseEdge {
    std::uint32_t frame;  ///< the edge's head (its value and covariance records)
    std::uint32_t epoch;
    std::int32_t parent;  ///< the entry of the edge above (its tail's edge), -1: Z
    bool moves_e, moves_r;
  };
  struct TwistEdge {
    std::uint32_t slot;  ///< the twist edge's slot; from poses: the pose edge's head frame
    std::uint32_t epoch;
    std::int32_t head_entry;  ///< the pose edge entry of its head h, -1: h is Z
    double sign;              ///< -1: traversed against its direction
  };
  using InZ = internal::PoseEdgeInZ;  // scratch of one evaluation, per pose edge
  struct StepScratch {                // per twist edge
    coord::jacobians::TwistStepInZ st;
    Eigen::Matrix3d R_ZH;
    Covariance6 S;
  };
  // The pose chains of e, r and the steps' heads up to their common ancestor (constructors).
  void AddPoseEdges(const topology::SceneTopology& t, FrameIndex e, FrameIndex r,
                    const std::vector<FrameIndex>& heads);
  // Every edge into the scratch, at the context's time when tc is given; false when one was
  // removed.
  bool LoadPoseEdges(internal::TimeContext* tc) noexcept;
  bool LoadTwistEdges(internal::TimeContext* tc) noexcept;
  // The answer and its covariance from the scratch, each uncertain edge's Jacobian into `sink`
  // (propagate.h DirectSink, or a KeyedSink).
  template <class Sink>
  void Finish(Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R, Covariance6& S,
              CovarianceOrder order, Sink&& sink) const noexcept;

  semantics::TwistSemantics semantics_;
  const EdgeValues<B>* values_ = nullptr;
  const topology::SceneTopology* topology_ = nullptr;  ///< extrapolation's twist forests
  internal::IntegrationTwistPlans plans_;              ///< each pose edge's integration twist
  bool from_poses_ = false;  ///< twist source `poses`: steps are derivatives, no extrapolation
  std::vector<PoseEdge> pose_edges_;
  std::vector<TwistEdge> steps_;
  std::vector<std::uint8_t> moves_h_;  ///< [pose edge * steps + step]: the edge moves that head
  std::int32_t e_entry_ = -1, r_entry_ = -1;
  std::vector<InZ> scratch_;
  std::vector<StepScratch> step_scratch_;
};

/// CompiledLinearVelocityWithCovariance<B> / CompiledAngularVelocityWithCovariance<B>: the twist
/// query above answering one part and its 3x3 block: what GetLinearVelocityWithCovariance and
/// GetAngularVelocityWithCovariance answer. Made by SceneGraph::CompileLinearVelocityWith-
/// Covariance / CompileAngularVelocityWithCovariance (the angular one on the twist at [r]'s
/// origin, whose angular part does not depend on the point). Invariants, costs and thread
/// safety: the twist query's.
template <coord::Backend B>
class CompiledLinearVelocityWithCovariance {
 public:
  CompiledLinearVelocityWithCovariance() = default;
  explicit CompiledLinearVelocityWithCovariance(CompiledTwistWithCovariance<B> twist)
      : twist_(std::move(twist)) {}
  /// v_DCe_R and its covariance. kOk or kQueryInvalidated (nothing written).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& v_DCe_R, Eigen::Matrix3d& S) noexcept {
    Eigen::Vector3d v, w;
    Covariance6 S6;
    const ErrorCode code = twist_.Evaluate(v, w, S6);
    if (code != ErrorCode::kOk) return code;
    v_DCe_R = v;
    S = S6.template topLeftCorner<3, 3>();
    return code;
  }
  /// At the policy's time (CompiledTwistWithCovariance's timed Evaluate: codes, report).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& v_DCe_R, Eigen::Matrix3d& S,
                                   const TimePolicy& policy, TimeReport& report) noexcept {
    Eigen::Vector3d v, w;
    Covariance6 S6;
    const ErrorCode code = twist_.Evaluate(v, w, S6, policy, report);
    if (code != ErrorCode::kOk) return code;
    v_DCe_R = v;
    S = S6.template topLeftCorner<3, 3>();
    return code;
  }
  /// In GetLinearVelocityWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::LinearVelocity, 3>> Evaluate() noexcept {
    WithCovariance<coord::LinearVelocity, 3> r{
        coord::LinearOf(
            coord::Twist{twist_.semantics(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}),
        Eigen::Matrix3d::Zero()};
    return internal::Answer(Evaluate(r.value.value, r.covariance), r);
  }

 private:
  CompiledTwistWithCovariance<B> twist_;
};

template <coord::Backend B>
class CompiledAngularVelocityWithCovariance {
 public:
  CompiledAngularVelocityWithCovariance() = default;
  explicit CompiledAngularVelocityWithCovariance(CompiledTwistWithCovariance<B> twist)
      : twist_(std::move(twist)) {}
  /// w_DC_R and its covariance. kOk or kQueryInvalidated (nothing written).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& w_DC_R, Eigen::Matrix3d& S) noexcept {
    Eigen::Vector3d v, w;
    Covariance6 S6;
    const ErrorCode code = twist_.Evaluate(v, w, S6);
    if (code != ErrorCode::kOk) return code;
    w_DC_R = w;
    S = S6.template bottomRightCorner<3, 3>();
    return code;
  }
  /// At the policy's time (CompiledTwistWithCovariance's timed Evaluate: codes, report).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& w_DC_R, Eigen::Matrix3d& S,
                                   const TimePolicy& policy, TimeReport& report) noexcept {
    Eigen::Vector3d v, w;
    Covariance6 S6;
    const ErrorCode code = twist_.Evaluate(v, w, S6, policy, report);
    if (code != ErrorCode::kOk) return code;
    w_DC_R = w;
    S = S6.template bottomRightCorner<3, 3>();
    return code;
  }
  /// In GetAngularVelocityWithCovariance's result type.
  [[nodiscard]] QueryResult<WithCovariance<coord::AngularVelocity, 3>> Evaluate() noexcept {
    WithCovariance<coord::AngularVelocity, 3> r{
        coord::AngularOf(
            coord::Twist{twist_.semantics(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}),
        Eigen::Matrix3d::Zero()};
    return internal::Answer(Evaluate(r.value.value, r.covariance), r);
  }

 private:
  CompiledTwistWithCovariance<B> twist_;
};

extern template class CompiledTwistWithCovariance<coord::QuaternionBackend>;
extern template class CompiledTwistWithCovariance<coord::HomogeneousBackend>;

}  // namespace semgraph::core
