// Compiled pose queries with covariance: the edge list (compile), then one evaluation pass
// top-down and one Jacobian per uncertain edge. Contract: compiled_covariance.h.
#include "semgraph/core/compiled_covariance.h"

#include <algorithm>

#include "semgraph/core/covariance_lanes.h"
#include "semgraph/core/timed_covariance.h"

namespace semgraph::core {

namespace jac = coord::jacobians;

namespace internal {

std::vector<FrameIndex> ChainUnionTopDown(const topology::SceneTopology& t,
                                          std::span<const FrameIndex> ends, FrameIndex z) {
  std::vector<FrameIndex> edges;
  for (const FrameIndex k : ends) {
    for (FrameIndex g = k; g != z; g = t.pose_parent(g)) {
      if (std::find(edges.begin(), edges.end(), g) != edges.end()) break;  // an earlier chain's
      edges.push_back(g);
    }
  }
  const topology::PoseForest& forest = t.forest();
  std::stable_sort(edges.begin(), edges.end(),
                   [&](FrameIndex x, FrameIndex y) { return forest.depth(x) < forest.depth(y); });
  return edges;
}

std::int32_t EntryOf(const std::vector<FrameIndex>& edges, FrameIndex g) {
  const auto it = std::find(edges.begin(), edges.end(), g);
  return it == edges.end() ? -1 : static_cast<std::int32_t>(it - edges.begin());
}

}  // namespace internal

template <coord::Backend B>
CompiledPoseWithCovariance<B>::CompiledPoseWithCovariance(const topology::SceneTopology& t,
                                                          const EdgeValues<B>& values,
                                                          const semantics::PoseSemantics& s,
                                                          const FrameIndex (&k)[5])
    : semantics_(s), values_(&values), topology_(&t) {
  const topology::PoseForest& forest = t.forest();
  FrameIndex z = k[0];
  for (int i = 1; i < 5; ++i) z = forest.CommonAncestor(z, k[i]);
  const std::vector<FrameIndex> heads = internal::ChainUnionTopDown(t, k, z);
  edges_.reserve(heads.size());
  for (const FrameIndex g : heads) {
    Edge e{};
    e.frame = g.value();
    e.epoch = values.X_PF[g.value()].epoch();
    e.parent = internal::EntryOf(heads, t.pose_parent(g));
    e.value = &values.X_PF[g.value()];
    e.moves = {forest.IsAncestor(g, k[0]), forest.IsAncestor(g, k[2]), forest.IsAncestor(g, k[1]),
               forest.IsAncestor(g, k[3]), forest.IsAncestor(g, k[4])};
    // EdgeOnPoseFactors: lever = m_e (g - e) - m_f (g - f) + m_r (e - f) = s g + alpha e + beta f.
    const auto flag = [](bool b) { return b ? 1.0 : 0.0; };
    e.s = flag(e.moves.e) - flag(e.moves.f);
    e.c = flag(e.moves.a) - flag(e.moves.r);
    e.d = flag(e.moves.r) - flag(e.moves.b);
    e.alpha = flag(e.moves.r) - flag(e.moves.e);
    e.beta = flag(e.moves.f) - flag(e.moves.r);
    with_o_ = with_o_ || e.d != 0.0;
    edges_.push_back(e);
    plans_.Add(t, g);
  }
  for (int i = 0; i < 5; ++i) frame_entry_[i] = internal::EntryOf(heads, k[i]);
  scratch_.resize(edges_.size());
  lanes_.assign(internal::LaneDoubles(static_cast<int>(edges_.size())), 0.0);
}

template <coord::Backend B>
ErrorCode CompiledPoseWithCovariance<B>::Evaluate(PoseCoords& X, Covariance6& S,
                                                  CovarianceOrder order) noexcept {
  // Each edge's value, and its head's pose in Z (top-down); an uncertain edge's covariance
  // straight into the next lane, with the edge's rotation R_ZP and Jacobian factors.
  using Row = internal::LaneRow;
  static_assert(internal::LaneIndex(1, 5) - internal::LaneIndex(0, 5) == 4);
  const Eigen::Matrix3d identity =
      Eigen::Matrix3d::Identity();  // R_ZP below Z (no static: no guard)
  const std::size_t n = edges_.size();
  double* const x = lanes_.data();
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Edge& e = edges_[i];
    const InZ* up = e.parent < 0 ? nullptr : &scratch_[static_cast<std::size_t>(e.parent)];
    const PoseValue<B>& value = *e.value;
    if (value.epoch() != e.epoch) return ErrorCode::kQueryInvalidated;
    PoseCoords X_PG;
    double* const lane = x + internal::LaneIndex(0, count);  // row r at lane[4 r]
    const bool uncertain = values_->LoadPoseIntoLanes(       // value and covariance of one write
        e.frame, X_PG, lane + 4 * Row::kS11);
    if (value.epoch() != e.epoch) return ErrorCode::kQueryInvalidated;  // removed meanwhile
    InZ& out = scratch_[i];
    internal::ComposePoseEdgeInZ<B>(X_PG, up, out);
    if (!uncertain) continue;
    internal::SetLaneFactors(lane, up ? up->R_ZG : identity, e.s * out.p_ZG, e.alpha, e.beta, e.s,
                             e.c, e.d);
    ++count;
  }
  FinishLanes(X, S, order, count);
  return ErrorCode::kOk;
}

template <coord::Backend B>
bool CompiledPoseWithCovariance<B>::LoadAt(internal::TimeContext& tc) noexcept {
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    const Edge& e = edges_[i];
    const InZ* up = e.parent < 0 ? nullptr : &scratch_[static_cast<std::size_t>(e.parent)];
    if (!internal::LoadPoseEdgeInZAt<B>(*values_, e.frame, e.epoch, tc, up, scratch_[i])) {
      return false;
    }
  }
  return true;
}

// As the one-shot query (time_uncertainty.cc KeyedPoseCovariance): an extrapolated answer's
// Jacobians are keyed, formed in the evaluation's context (latest common: its second pass).
template <coord::Backend B>
ErrorCode CompiledPoseWithCovariance<B>::Evaluate(PoseCoords& X, Covariance6& S,
                                                  const TimePolicy& policy, TimeReport& report,
                                                  CovarianceOrder order) noexcept {
  PoseCoords X_keyed;
  Covariance6 S_keyed;
  bool keyed = false;
  const ErrorCode code = internal::RunWithCovariance(
      policy, values_->history, topology_, plans_,
      [&](internal::TimeContext& tc) {
        if (!LoadAt(tc)) return ErrorCode::kQueryInvalidated;
        keyed = tc.extrapolated && tc.error() == ErrorCode::kOk;
        if (keyed) {
          internal::SharedPerturbations acc;  // on the stack
          Finish(X_keyed, S_keyed, order, internal::KeyedSink<B>{values_, &tc, &acc});
        }
        return ErrorCode::kOk;
      },
      report);
  if (code != ErrorCode::kOk) return code;
  if (keyed) {
    X = X_keyed;
    S = S_keyed;
  } else {
    Finish(X, S, order, internal::DirectSink{});
  }
  return ErrorCode::kOk;
}

template <coord::Backend B>
void CompiledPoseWithCovariance<B>::AnswerInZ(PoseCoords& X, jac::PoseInZ& q) const noexcept {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();  // Z in Z (no static: no guard)
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d* R_Z[5];  // in scratch_, not copied
  const Eigen::Vector3d* p_Z[5];
  for (int i = 0; i < 5; ++i) {
    const bool z = frame_entry_[i] < 0;
    const InZ* g = z ? nullptr : &scratch_[static_cast<std::size_t>(frame_entry_[i])];
    R_Z[i] = z ? &identity : &g->R_ZG;
    p_Z[i] = z ? &zero : &g->p_ZG;
  }
  // Products by a frame that is Z (the identity) skipped: known at compile time, often the case
  // ("of e relative to f", [b] = [r] = [f] = Z).
  q.R_RZ = R_Z[4]->transpose();
  q.p_ZoEo_Z = *p_Z[0];
  q.p_ZoFo_Z = *p_Z[2];
  if (frame_entry_[3] < 0) {
    q.O_Z = *R_Z[1];
  } else {
    q.O_Z.noalias() = *R_Z[1] * R_Z[3]->transpose();
  }
  if (frame_entry_[4] < 0) {
    X = B::MakePose(B::FromMatrix(q.O_Z), q.p_ZoEo_Z - q.p_ZoFo_Z);
  } else {
    const Eigen::Matrix3d M = q.R_RZ * q.O_Z * *R_Z[4];
    X = B::MakePose(B::FromMatrix(M), q.R_RZ * (q.p_ZoEo_Z - q.p_ZoFo_Z));
  }
}

// The frames in Z, the answer, then each uncertain edge's J S J^T.
template <coord::Backend B>
template <class Sink>
void CompiledPoseWithCovariance<B>::Finish(PoseCoords& X, Covariance6& S, CovarianceOrder order,
                                           Sink&& sink) const noexcept {
  const std::size_t n = edges_.size();
  jac::PoseInZ q;
  AnswerInZ(X, q);
  // Rows in Z: rotated into [r] once, at the end.
  for (std::size_t i = 0; i < n; ++i) {
    const InZ& g = scratch_[i];
    if (g.exact) continue;
    const Edge& e = edges_[i];
    const Eigen::Matrix3d R_ZP = e.parent < 0 ? Eigen::Matrix3d::Identity()
                                              : scratch_[static_cast<std::size_t>(e.parent)].R_ZG;
    sink.AddPoseEdge({internal::PerturbedEdge::Kind::kPose, e.frame}, q, {R_ZP, g.p_ZG}, e.moves,
                     g.S);
  }
  Covariance6 S_Z;
  sink.Finish(S_Z);
  S = jac::RotateRows(q.R_RZ, S_Z);
  if (order != CovarianceOrder::kLinearAngular) S = coord::SwapHalves(S);
}

template <coord::Backend B>
void CompiledPoseWithCovariance<B>::FinishLanes(PoseCoords& X, Covariance6& S,
                                                CovarianceOrder order, int count) noexcept {
  jac::PoseInZ q;
  AnswerInZ(X, q);
  internal::PadLanes(lanes_.data(), count);
  internal::PoseCovarianceSums sums;
  internal::SumPoseEdgeLanes(lanes_.data(), count, q.p_ZoEo_Z, q.p_ZoFo_Z,
                             with_o_ ? &q.O_Z : nullptr, sums);
  // Rows in Z, rotated into [r] once (not at all when [r] is Z).
  if (frame_entry_[4] < 0) {
    S.setZero();
    sums.AddTo(S);
  } else {
    Covariance6 S_Z = Covariance6::Zero();
    sums.AddTo(S_Z);
    S = jac::RotateRows(q.R_RZ, S_Z);
  }
  if (order != CovarianceOrder::kLinearAngular) S = coord::SwapHalves(S);
}

template class CompiledPoseWithCovariance<coord::QuaternionBackend>;
template class CompiledPoseWithCovariance<coord::HomogeneousBackend>;

}  // namespace semgraph::core
