// Compiled pose queries with covariance: the edge list (compile), then one evaluation pass
// top-down and one Jacobian per uncertain edge. Contract: compiled_covariance.h.
#include "semgraph/core/compiled_covariance.h"

#include <algorithm>

namespace semgraph::core {

namespace jac = coord::jacobians;

template <coord::Backend B>
CompiledPoseWithCovariance<B>::CompiledPoseWithCovariance(const topology::SceneTopology& t,
                                                          const EdgeValues<B>& values,
                                                          const semantics::PoseSemantics& s,
                                                          const FrameIndex (&k)[5])
    : semantics_(s) {
  const topology::PoseForest& forest = t.forest();
  FrameIndex z = k[0];
  for (int i = 1; i < 5; ++i) z = forest.CommonAncestor(z, k[i]);
  // The union of the five chains up to Z, each edge once (named by its head frame).
  std::vector<FrameIndex> heads;
  for (const FrameIndex f : k) {
    for (FrameIndex g = f; g != z; g = t.pose_parent(g)) {
      if (std::find(heads.begin(), heads.end(), g) != heads.end()) break;
      heads.push_back(g);
    }
  }
  // Top-down: by depth, so that each edge comes after the edge above it.
  std::stable_sort(heads.begin(), heads.end(), [&](FrameIndex x, FrameIndex y) {
    return forest.depth(x) < forest.depth(y);
  });
  const auto entry_of = [&](FrameIndex g) -> std::int32_t {
    const auto it = std::find(heads.begin(), heads.end(), g);
    return it == heads.end() ? -1 : static_cast<std::int32_t>(it - heads.begin());
  };
  edges_.reserve(heads.size());
  for (const FrameIndex g : heads) {
    const PoseValue<B>& value = values.X_PF[g.value()];
    Edge e{&value, &values.S_PF[g.value()], value.epoch(), entry_of(t.pose_parent(g)), {}};
    e.moves = {forest.IsAncestor(g, k[0]), forest.IsAncestor(g, k[2]),
               forest.IsAncestor(g, k[1]), forest.IsAncestor(g, k[3]),
               forest.IsAncestor(g, k[4])};
    edges_.push_back(e);
  }
  for (int i = 0; i < 5; ++i) frame_entry_[i] = k[i] == z ? -1 : entry_of(k[i]);
  scratch_.resize(edges_.size());
}

template <coord::Backend B>
ErrorCode CompiledPoseWithCovariance<B>::Evaluate(PoseCoords& X, Covariance6& S,
                                                  CovarianceOrder order) noexcept {
  // Each edge's value and covariance, and its head's pose in Z (top-down).
  const std::size_t n = edges_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Edge& e = edges_[i];
    InZ& out = scratch_[i];
    PoseCoords X_PG;
    if (!e.value->Load(X_PG, e.epoch)) return ErrorCode::kQueryInvalidated;
    const ValueAndCovariance<PoseCoords> record = e.covariance->Load();
    if (record.active != 0.0) X_PG = record.value;
    if (e.value->epoch() != e.epoch) return ErrorCode::kQueryInvalidated;  // removed meanwhile
    out.exact = record.active == 0.0 || record.S.isZero(0.0);
    if (!out.exact) out.S = record.S;
    const Eigen::Matrix3d R_PG = B::ToMatrix(B::RotationOf(X_PG));
    const Eigen::Vector3d p_PG = B::TranslationOf(X_PG);
    if (e.parent < 0) {
      out.R_ZG = R_PG;
      out.p_ZG = p_PG;
    } else {
      const InZ& up = scratch_[static_cast<std::size_t>(e.parent)];
      out.R_ZG.noalias() = up.R_ZG * R_PG;
      out.p_ZG.noalias() = up.R_ZG * p_PG;
      out.p_ZG += up.p_ZG;
    }
  }
  // The frames in Z, the answer, then each uncertain edge's J S J^T.
  Eigen::Matrix3d R_Z[5];
  Eigen::Vector3d p_Z[5];
  for (int i = 0; i < 5; ++i) {
    if (frame_entry_[i] < 0) {
      R_Z[i].setIdentity();
      p_Z[i].setZero();
    } else {
      R_Z[i] = scratch_[static_cast<std::size_t>(frame_entry_[i])].R_ZG;
      p_Z[i] = scratch_[static_cast<std::size_t>(frame_entry_[i])].p_ZG;
    }
  }
  jac::PoseInZ q;
  q.R_RZ = R_Z[4].transpose();
  q.p_ZoEo_Z = p_Z[0];
  q.p_ZoFo_Z = p_Z[2];
  q.O_Z.noalias() = R_Z[1] * R_Z[3].transpose();
  const Eigen::Matrix3d M = q.R_RZ * q.O_Z * R_Z[4];
  X = B::MakePose(B::FromMatrix(M), q.R_RZ * (p_Z[0] - p_Z[2]));
  Covariance6 S_Z = Covariance6::Zero();  // rows in Z: rotated into [r] once, at the end
  for (std::size_t i = 0; i < n; ++i) {
    const InZ& g = scratch_[i];
    if (g.exact) continue;
    const Edge& e = edges_[i];
    const Eigen::Matrix3d R_ZP = e.parent < 0
                                     ? Eigen::Matrix3d::Identity()
                                     : scratch_[static_cast<std::size_t>(e.parent)].R_ZG;
    jac::AddPropagated(jac::EdgeOnPoseInZ(q, {R_ZP, g.p_ZG}, e.moves), g.S, S_Z);
  }
  S = jac::RotateRows(q.R_RZ, S_Z);
  if (order != CovarianceOrder::kLinearAngular) S = coord::SwapHalves(S);
  return ErrorCode::kOk;
}

template class CompiledPoseWithCovariance<coord::QuaternionBackend>;
template class CompiledPoseWithCovariance<coord::HomogeneousBackend>;

}  // namespace semgraph::core
