// Compiled queries: evaluation of resolved paths. Contract: compiled_query.h. The arithmetic is
// the same as the checked operations of semgraph::coord (see their comments), without the
// semantic checks, which were done once when compiling.
#include "semgraph/core/compiled_query.h"

#include <type_traits>

namespace semgraph::core {

template <coord::Backend B>
bool CompiledQuery<B>::is_valid() const noexcept {
  for (const EdgeRef& e : edges_) {
    if (graph_->X_PF_[e.child].epoch() != e.epoch()) return false;
  }
  return true;
}

template <coord::Backend B>
auto CompiledQuery<B>::AddBasic(FrameIndex a, FrameIndex b) -> Basic {
  const PoseForest& forest = graph_->forest_;
  const FrameIndex anc = forest.CommonAncestor(a, b);
  SEMGRAPH_DEMAND(anc.is_valid());
  const auto chain = [&](FrameIndex f) {
    Chain c;
    c.begin = static_cast<std::uint32_t>(edges_.size());
    for (FrameIndex g = f; g != anc; g = forest.parent(g)) {
      edges_.push_back(
          EdgeRef{PoseValue<B>::ExpectedHeader(graph_->X_PF_[g.value()].epoch()), g.value()});
    }
    c.end = static_cast<std::uint32_t>(edges_.size());
    return c;
  };
  Basic basic;
  basic.up_a = chain(a);
  basic.up_b = chain(b);
  return basic;
}

// X_AF = X_A.. * ... * X_PF. The edges are stored from F upward; they are composed top-down,
// acc = acc * X_i, as a hand-written chain would (p += q p_i; q = q q_i for quaternions), so the
// loop-carried dependency is one rotation product.
template <coord::Backend B>
bool CompiledQuery<B>::EvalChain(Chain c, PoseCoords& X_AF, bool& identity) const noexcept {
  identity = c.begin == c.end;
  if (identity) return true;
  const auto* values = graph_->X_PF_.data();
  const EdgeRef* first = edges_.data() + c.begin;
  const EdgeRef* e = edges_.data() + c.end - 1;
  if constexpr (std::is_same_v<B, coord::QuaternionBackend>) {
    // The hot case: rebuild each edge's quaternion and vector straight from the locked words
    // (x y z w, then p), so nothing round-trips through the stack.
    using Words = typename PoseValue<B>::Word[PoseValue<B>::kWords];
    const auto load = [&](const EdgeRef& r, Eigen::Quaterniond& q, Eigen::Vector3d& p) {
      Words w;
      if (!values[r.child].LoadWords(w, r.expected_header)) return false;
      const auto d = [&w](int i) { return w[i]; };
      q = Eigen::Quaterniond(d(3), d(0), d(1), d(2));
      p = Eigen::Vector3d(d(4), d(5), d(6));
      return true;
    };
    Eigen::Quaterniond q;
    Eigen::Vector3d p;
    if (!load(*e, q, p)) return false;
    while (e != first) {
      --e;
      Eigen::Quaterniond q_i;
      Eigen::Vector3d p_i;
      if (!load(*e, q_i, p_i)) return false;
      p += q * p_i;
      q = q * q_i;
    }
    X_AF = PoseCoords{q, p};
    return true;
  }
  PoseCoords acc;
  if (!values[e->child].Load(acc, e->epoch())) return false;
  while (e != first) {
    --e;
    PoseCoords X_i;
    if (!values[e->child].Load(X_i, e->epoch())) return false;
    acc = B::ComposeChain(X_i, acc);
  }
  X_AF = acc;
  return true;
}

template <coord::Backend B>
bool CompiledQuery<B>::EvalBasic(const Basic& basic, PoseCoords& X_BA) const noexcept {
  PoseCoords X_CA, X_CB;
  bool a_identity, b_identity;
  if (!EvalChain(basic.up_a, X_CA, a_identity) || !EvalChain(basic.up_b, X_CB, b_identity)) {
    return false;
  }
  if (b_identity) {
    X_BA = a_identity ? B::MakePose(B::FromQuaternion(Eigen::Quaterniond::Identity()),
                                    Eigen::Vector3d::Zero())
                      : X_CA;
  } else if (a_identity) {
    X_BA = B::InvertChain(X_CB);
  } else {
    X_BA = B::ComposeChain(X_CA, B::InvertChain(X_CB));
  }
  return true;
}

template <coord::Backend B>
bool CompiledQuery<B>::LoadTwistEdge(std::uint32_t slot, std::uint32_t epoch, Eigen::Vector3d& v,
                                     Eigen::Vector3d& w) const noexcept {
  typename SceneGraph<B>::TwistNumbers n;
  if (!graph_->twist_edges_[slot].value.Load(n, epoch)) return false;
  v = n.v;
  w = n.w;
  return true;
}

template <coord::Backend B>
ErrorCode CompiledPose<B>::Evaluate(typename B::PoseCoords& X) const noexcept {
  // Algorithm 1 on numbers: X_BA in [b], then reference point, point, coordinate frame.
  typename B::PoseCoords X_BA;
  if (!this->EvalBasic(ab_, X_BA)) return ErrorCode::kQueryInvalidated;
  typename B::Rotation M = B::RotationOf(X_BA);
  Eigen::Vector3d p = B::TranslationOf(X_BA);
  if (change_ref_point_) {  // p_FE = p_BE - p_BF
    typename B::PoseCoords X_BF;
    if (!this->EvalBasic(fb_, X_BF)) return ErrorCode::kQueryInvalidated;
    p -= B::TranslationOf(X_BF);
  }
  if (change_point_) {  // p += R_BA p_AE_A
    typename B::PoseCoords X_AE;
    if (!this->EvalBasic(ea_, X_AE)) return ErrorCode::kQueryInvalidated;
    p += B::Rotate(M, B::TranslationOf(X_AE));
  }
  if (change_frame_) {  // p' = R_RB p, M' = R_RB M R_RB^T
    typename B::PoseCoords X_RB;
    if (!this->EvalBasic(br_, X_RB)) return ErrorCode::kQueryInvalidated;
    const typename B::Rotation R_RB = B::RotationOf(X_RB);
    p = B::Rotate(R_RB, p);
    M = B::Multiply(B::Multiply(R_RB, M), B::Transpose(R_RB));
  }
  X = B::MakePose(M, p);
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledPosition<B>::Evaluate(Eigen::Vector3d& p) const noexcept {
  typename B::PoseCoords X_FE;
  if (!this->EvalBasic(ef_, X_FE)) return ErrorCode::kQueryInvalidated;
  p = B::TranslationOf(X_FE);
  if (change_frame_) {
    typename B::PoseCoords X_RF;
    if (!this->EvalBasic(fr_, X_RF)) return ErrorCode::kQueryInvalidated;
    p = B::Rotate(B::RotationOf(X_RF), p);
  }
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledOrientation<B>::Evaluate(typename B::Rotation& M) const noexcept {
  typename B::PoseCoords X_BA;
  if (!this->EvalBasic(ab_, X_BA)) return ErrorCode::kQueryInvalidated;
  M = B::RotationOf(X_BA);
  if (change_frame_) {
    typename B::PoseCoords X_RB;
    if (!this->EvalBasic(br_, X_RB)) return ErrorCode::kQueryInvalidated;
    const typename B::Rotation R_RB = B::RotationOf(X_RB);
    M = B::Multiply(B::Multiply(R_RB, M), B::Transpose(R_RB));
  }
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledTwist<B>::Evaluate(Eigen::Vector3d& v, Eigen::Vector3d& w) const noexcept {
  v.setZero();
  w.setZero();
  for (const Step& s : steps_) {
    Eigen::Vector3d v_i, w_i;  // TwistCoord(h|B_{i-1}, B_i, [h])
    if (!this->LoadTwistEdge(s.slot, s.epoch, v_i, w_i)) return ErrorCode::kQueryInvalidated;
    if (s.invert) {
      v_i = -v_i;
      w_i = -w_i;
    }
    if (s.move_point) {  // A = p(h wrt e) in [h] = -p(e wrt h): v' = v + A x w
      typename B::PoseCoords X_HE;
      if (!this->EvalBasic(s.eh, X_HE)) return ErrorCode::kQueryInvalidated;
      v_i -= B::TranslationOf(X_HE).cross(w_i);
    }
    if (s.change_frame) {
      typename B::PoseCoords X_RH;
      if (!this->EvalBasic(s.hr, X_RH)) return ErrorCode::kQueryInvalidated;
      const typename B::Rotation R_RH = B::RotationOf(X_RH);
      v_i = B::Rotate(R_RH, v_i);
      w_i = B::Rotate(R_RH, w_i);
    }
    v += v_i;
    w += w_i;
  }
  return ErrorCode::kOk;
}

template class CompiledQuery<coord::QuaternionBackend>;
template class CompiledQuery<coord::HomogeneousBackend>;
template class CompiledPose<coord::QuaternionBackend>;
template class CompiledPose<coord::HomogeneousBackend>;
template class CompiledPosition<coord::QuaternionBackend>;
template class CompiledPosition<coord::HomogeneousBackend>;
template class CompiledOrientation<coord::QuaternionBackend>;
template class CompiledOrientation<coord::HomogeneousBackend>;
template class CompiledTwist<coord::QuaternionBackend>;
template class CompiledTwist<coord::HomogeneousBackend>;

}  // namespace semgraph::core
