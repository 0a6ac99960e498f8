// Compiled twist queries with covariance: the edge lists (compile), then one evaluation pass
// top-down over the pose edges, one over the twist edges, and one Jacobian per uncertain edge.
// Contract: compiled_twist_covariance.h.
#include "semgraph/core/compiled_twist_covariance.h"

#include "semgraph/core/timed_covariance.h"

namespace semgraph::core {

namespace jac = coord::jacobians;

template <coord::Backend B>
CompiledTwistWithCovariance<B>::CompiledTwistWithCovariance(const topology::SceneTopology& t,
                                                            const EdgeValues<B>& values,
                                                            const TwistPlan& plan)
    : semantics_(plan.semantics), values_(&values), topology_(&t) {
  std::vector<FrameIndex> heads;
  ForEachTwistStep(t, plan, [&](const TwistStep<ForestChain>& s) {
    heads.push_back(t.twist_edge(s.edge).head);
    steps_.push_back(
        {s.edge.value(), values.V_DH[s.edge.value()].epoch(), -1, s.invert ? -1.0 : 1.0});
  });
  AddPoseEdges(t, plan.point, plan.frame, heads);
  for (const PoseEdge& g : pose_edges_) plans_.Add(t, FrameIndex(g.frame));
}

template <coord::Backend B>
CompiledTwistWithCovariance<B>::CompiledTwistWithCovariance(const topology::SceneTopology& t,
                                                            const EdgeValues<B>& values,
                                                            const PoseTwistPlan& plan)
    : semantics_(plan.semantics), values_(&values), topology_(&t), from_poses_(true) {
  std::vector<FrameIndex> heads;
  ForEachPoseDerivativeStep(t, plan, [&](const TwistStep<ForestChain>& s) {
    heads.push_back(s.pose_edge);  // a derivative's twist is at the edge's head, in [h]
    steps_.push_back(
        {s.pose_edge.value(), values.X_PF[s.pose_edge.value()].epoch(), -1, s.invert ? -1.0 : 1.0});
  });
  AddPoseEdges(t, plan.point, plan.frame, heads);
}

template <coord::Backend B>
void CompiledTwistWithCovariance<B>::AddPoseEdges(const topology::SceneTopology& t, FrameIndex e,
                                                  FrameIndex r,
                                                  const std::vector<FrameIndex>& heads) {
  // No step (C = D): the answer is exactly zero and reads no pose edge, as the one-shot query
  // (so a timed evaluation reports nothing read, as it does).
  if (steps_.empty()) return;
  const topology::PoseForest& forest = t.forest();
  FrameIndex z = forest.CommonAncestor(e, r);
  for (const FrameIndex h : heads) z = forest.CommonAncestor(z, h);
  std::vector<FrameIndex> chain_ends{e, r};
  chain_ends.insert(chain_ends.end(), heads.begin(), heads.end());
  const std::vector<FrameIndex> edges = internal::ChainUnionTopDown(t, chain_ends, z);
  pose_edges_.reserve(edges.size());
  moves_h_.reserve(edges.size() * heads.size());
  for (const FrameIndex g : edges) {
    pose_edges_.push_back({g.value(), values_->X_PF[g.value()].epoch(),
                           internal::EntryOf(edges, t.pose_parent(g)), forest.IsAncestor(g, e),
                           forest.IsAncestor(g, r)});
    for (const FrameIndex h : heads) moves_h_.push_back(forest.IsAncestor(g, h) ? 1 : 0);
  }
  e_entry_ = internal::EntryOf(edges, e);
  r_entry_ = internal::EntryOf(edges, r);
  for (std::size_t j = 0; j < steps_.size(); ++j) {
    steps_[j].head_entry = internal::EntryOf(edges, heads[j]);
  }
  scratch_.resize(pose_edges_.size());
  step_scratch_.resize(steps_.size());
}

// Each pose edge's value and covariance, and its head's pose in Z (top-down).
template <coord::Backend B>
bool CompiledTwistWithCovariance<B>::LoadPoseEdges(internal::TimeContext* tc) noexcept {
  for (std::size_t i = 0; i < pose_edges_.size(); ++i) {
    const PoseEdge& e = pose_edges_[i];
    const InZ* up = e.parent < 0 ? nullptr : &scratch_[static_cast<std::size_t>(e.parent)];
    const bool ok =
        tc ? internal::LoadPoseEdgeInZAt<B>(*values_, e.frame, e.epoch, *tc, up, scratch_[i])
           : internal::LoadPoseEdgeInZ<B>(*values_, e.frame, e.epoch, up, scratch_[i]);
    if (!ok) return false;
  }
  return true;
}

// Each twist edge's value and covariance, signed and rotated into Z at its head.
template <coord::Backend B>
bool CompiledTwistWithCovariance<B>::LoadTwistEdges(internal::TimeContext* tc) noexcept {
  for (std::size_t j = 0; j < steps_.size(); ++j) {
    const TwistEdge& s = steps_[j];
    const auto epoch = [&] {
      return from_poses_ ? values_->X_PF[s.slot].epoch() : values_->V_DH[s.slot].epoch();
    };
    StepScratch& out = step_scratch_[j];
    TwistNumbers V;
    if (epoch() != s.epoch) return false;
    if (from_poses_) {  // always at a time (the untimed Evaluate runs Latest)
      internal::DerivePoseAt<B, true>(*values_, s.slot, *tc, V, &out.S);
    } else if (tc) {
      internal::ReadTwistAt<B, true>(*values_, s.slot, *tc, V, &out.S);
    } else {
      values_->LoadTwist(s.slot, V, out.S);
    }
    if (epoch() != s.epoch) return false;
    Eigen::Vector3d p_ZH = Eigen::Vector3d::Zero();
    out.R_ZH.setIdentity();
    if (s.head_entry >= 0) {
      const InZ& h = scratch_[static_cast<std::size_t>(s.head_entry)];
      out.R_ZH = h.R_ZG;
      p_ZH = h.p_ZG;
    }
    out.st = {s.sign * (out.R_ZH * V.v_DHo_H), s.sign * (out.R_ZH * V.w_DH_H), p_ZH, false};
  }
  return true;
}

template <coord::Backend B>
ErrorCode CompiledTwistWithCovariance<B>::Evaluate(Eigen::Vector3d& v_DCe_R,
                                                   Eigen::Vector3d& w_DC_R, Covariance6& S,
                                                   CovarianceOrder order) noexcept {
  if (from_poses_) {
    TimeReport report;
    return Evaluate(v_DCe_R, w_DC_R, S, Latest{}, report, order);
  }
  if (!LoadPoseEdges(nullptr) || !LoadTwistEdges(nullptr)) return ErrorCode::kQueryInvalidated;
  Finish(v_DCe_R, w_DC_R, S, order, internal::DirectSink{});
  return ErrorCode::kOk;
}

// As the one-shot query (time_uncertainty.cc GetTwistWithCovariance): an extrapolated answer's
// Jacobians are keyed, formed in the evaluation's context (latest common: its second pass).
template <coord::Backend B>
ErrorCode CompiledTwistWithCovariance<B>::Evaluate(Eigen::Vector3d& v_DCe_R,
                                                   Eigen::Vector3d& w_DC_R, Covariance6& S,
                                                   const TimePolicy& policy, TimeReport& report,
                                                   CovarianceOrder order) noexcept {
  Eigen::Vector3d v_keyed, w_keyed;
  Covariance6 S_keyed;
  bool keyed = false;
  // Twist source `poses`: no horizon (as the one-shot query: WithoutExtrapolation).
  const ErrorCode code = internal::RunWithCovariance(
      from_poses_ ? internal::WithoutExtrapolation(policy) : policy, values_->history, topology_,
      plans_,
      [&](internal::TimeContext& tc) {
        if (!LoadPoseEdges(&tc) || !LoadTwistEdges(&tc)) return ErrorCode::kQueryInvalidated;
        keyed = tc.extrapolated && tc.error() == ErrorCode::kOk;
        if (keyed) {
          internal::SharedPerturbations acc;  // on the stack
          Finish(v_keyed, w_keyed, S_keyed, order, internal::KeyedSink<B>{values_, &tc, &acc});
        }
        return ErrorCode::kOk;
      },
      report);
  if (code != ErrorCode::kOk) return code;
  if (keyed) {
    v_DCe_R = v_keyed;
    w_DC_R = w_keyed;
    S = S_keyed;
  } else {
    Finish(v_DCe_R, w_DC_R, S, order, internal::DirectSink{});
  }
  return ErrorCode::kOk;
}

// The answer in Z, then each uncertain edge's J S J^T.
template <coord::Backend B>
template <class Sink>
void CompiledTwistWithCovariance<B>::Finish(Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R,
                                            Covariance6& S, CovarianceOrder order,
                                            Sink&& sink) const noexcept {
  const auto pose_in_z = [&](std::int32_t entry, Eigen::Matrix3d& R, Eigen::Vector3d& p) {
    if (entry < 0) {
      R.setIdentity();
      p.setZero();
    } else {
      R = scratch_[static_cast<std::size_t>(entry)].R_ZG;
      p = scratch_[static_cast<std::size_t>(entry)].p_ZG;
    }
  };
  Eigen::Matrix3d R_ZE, R_ZR;
  Eigen::Vector3d p_ZoEo_Z, p_ZoRo_Z;
  pose_in_z(e_entry_, R_ZE, p_ZoEo_Z);
  pose_in_z(r_entry_, R_ZR, p_ZoRo_Z);
  const Eigen::Matrix3d R_RZ = R_ZR.transpose();
  // The answer in Z, and each uncertain twist edge's J S J^T (rows already in [r]).
  Eigen::Vector3d v_Z = Eigen::Vector3d::Zero(), w_Z = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < steps_.size(); ++j) {
    const StepScratch& s = step_scratch_[j];
    v_Z += s.st.a_Z + s.st.w_Z.cross(p_ZoEo_Z - s.st.p_ZoHo_Z);
    w_Z += s.st.w_Z;
    if (s.S.isZero(0.0)) continue;
    sink.Add({from_poses_ ? internal::PerturbedEdge::Kind::kDerivative
                          : internal::PerturbedEdge::Kind::kTwist,
              steps_[j].slot},
             jac::TwistEdgeOnTwist(R_RZ, s.R_ZH, s.st.p_ZoHo_Z, p_ZoEo_Z, steps_[j].sign), s.S);
  }
  // Each uncertain pose edge: its Jacobian sums over the twist edges whose head it moves.
  const std::size_t k = steps_.size();
  for (std::size_t i = 0; i < pose_edges_.size(); ++i) {
    const InZ& g = scratch_[i];
    if (g.exact) continue;
    const PoseEdge& e = pose_edges_[i];
    const Eigen::Matrix3d R_ZP = e.parent < 0 ? Eigen::Matrix3d::Identity()
                                              : scratch_[static_cast<std::size_t>(e.parent)].R_ZG;
    const jac::EdgeInZ edge{R_ZP, g.p_ZG};
    jac::PoseEdgeOnTwistSum sum;
    for (std::size_t j = 0; j < k; ++j) {
      jac::TwistStepInZ st = step_scratch_[j].st;
      st.moves = moves_h_[i * k + j] != 0;
      sum.Add(st, p_ZoEo_Z, edge, e.moves_e);
    }
    sink.Add({internal::PerturbedEdge::Kind::kPose, e.frame},
             sum.Finish(R_RZ, v_Z, w_Z, edge, e.moves_r), g.S);
  }
  Covariance6 S_R;
  sink.Finish(S_R);
  v_DCe_R = R_RZ * v_Z;
  w_DC_R = R_RZ * w_Z;
  S = order == CovarianceOrder::kLinearAngular ? S_R : coord::SwapHalves(S_R);
}

template class CompiledTwistWithCovariance<coord::QuaternionBackend>;
template class CompiledTwistWithCovariance<coord::HomogeneousBackend>;

}  // namespace semgraph::core
