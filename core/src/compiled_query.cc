// Compiled queries: a plan flattened into an edge list, evaluated by the one evaluator
// (evaluate.h, FlatSource). Contract: compiled_query.h.
#include "semgraph/core/compiled_query.h"

#include <atomic>
#include <bit>

#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/quaternion_backend.h"

namespace semgraph::core {

namespace {
std::atomic<std::uint64_t> next_query_id{1};
}  // namespace

template <coord::Backend B>
CompiledQuery<B>::CompiledQuery(const topology::SceneTopology& t, const EdgeValues<B>& values)
    : topology_(&t), values_(&values), id_(next_query_id.fetch_add(1, std::memory_order_relaxed)) {}

template <coord::Backend B>
bool CompiledQuery<B>::is_valid() const noexcept {
  for (const internal::EdgeRef& e : edges_) {
    if (static_cast<const PoseValue<B>*>(e.value)->epoch() != e.epoch()) return false;
  }
  return true;
}

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const ForestChain& c) -> Chain {
  Chain flat;
  flat.begin = static_cast<std::uint32_t>(edges_.size());
  // Bounded: a reader compiling while the writer changes the topology may walk a torn forest
  // (its plan is thrown away by the validation, optimistic_read.h).
  const std::size_t n = t.num_frames();
  std::size_t steps = 0;
  for (FrameIndex g = c.from; g != c.to && g.is_valid() && steps++ < n; g = t.pose_parent(g)) {
    const PoseValue<B>& value = values_->X_PF[g.value()];
    edges_.push_back(
        internal::EdgeRef{PoseValue<B>::ExpectedHeader(value.epoch()), &value, g.value()});
  }
  flat.end = static_cast<std::uint32_t>(edges_.size());
  if (flat.end != flat.begin) chains_.push_back(flat);
  return flat;
}

template <coord::Backend B>
PoseCache<B> CompiledQuery<B>::MakeCache() const {
  PoseCache<B> cache;
  cache.query_id = id_;
  cache.tree_of_begin.assign(edges_.size(), 0);
  cache.headers.assign(edges_.size(), ~std::uint64_t{0});  // no header is odd with epoch 2^32-1
  std::size_t nodes = 0, longest = 0;
  for (const Chain& c : chains_) {
    typename PoseCache<B>::Tree tree;
    const std::uint32_t n = c.end - c.begin;
    tree.leaves = std::bit_ceil(n);
    tree.node_offset = static_cast<std::uint32_t>(nodes);
    cache.tree_of_begin[c.begin] = static_cast<std::uint32_t>(cache.trees.size());
    cache.trees.push_back(tree);
    nodes += 2 * tree.leaves;
    longest = std::max<std::size_t>(longest, n);
  }
  // Padding leaves (and everything before the first build) are the identity.
  cache.nodes.assign(nodes, B::Identity());
  cache.changed.resize(longest);
  return cache;
}

template <coord::Backend B>
internal::CachedSource<B> CompiledQuery<B>::source(PoseCache<B>& cache) const noexcept {
  SEMGRAPH_DEMAND(cache.query_id == id_);  // a cache made by MakeCache() of this query (or a copy)
  return {*values_, edges_.data(), cache};
}

namespace internal {

// Leaves are the chain's edges top first (leaf i = edge end - 1 - i), so node k = left * right
// = ComposeChain(node 2k + 1, node 2k) composes upper with lower, as the chain does.
//
// Policy, per chain: scan every header; with k changed edges of n, recompose the k paths above
// them when the tree is built and k log n <= n, else rebuild the tree (n - 1 compositions, the
// cost of the uncached chain). When more than half the edges changed, the next kSkip
// evaluations compose the chain directly without scanning (FlatSource: the uncached cost), and
// the one after scans again: a query whose edges all change every time costs about what the
// uncached query costs, and one whose edges calm down finds its tree again.
template <coord::Backend B>
bool CachedSource<B>::EvalChain(const FlatChain& c, PoseCoords& X_AF,
                                bool& identity) const noexcept {
  constexpr std::uint32_t kSkip = 15;
  identity = c.begin == c.end;
  if (identity) return true;
  PoseCache<B>& cache = *cache_;
  typename PoseCache<B>::Tree& tree = cache.trees[cache.tree_of_begin[c.begin]];
  if (tree.skip > 0) {
    --tree.skip;
    ++tree.unscanned;
    tree.built = false;
    return FlatSource<B>(v_, edges_).EvalChain(c, X_AF, identity);
  }
  PoseCoords* const node = cache.nodes.data() + tree.node_offset;
  std::uint64_t* const headers = cache.headers.data() + c.begin;
  std::uint32_t* const changed_leaves = cache.changed.data();
  const EdgeRef* const refs = edges_ + c.begin;
  const std::uint32_t n = c.end - c.begin, leaves = tree.leaves;
  std::uint32_t changed = 0;
  for (std::uint32_t j = n; j-- > 0;) {  // edge j of the chain is leaf n - 1 - j
    const PoseValue<B>& value = *static_cast<const PoseValue<B>*>(refs[j].value);
    if (value.header() == headers[j]) continue;  // unchanged since cached
    const std::uint32_t leaf = n - 1 - j;
    if (!value.LoadWithHeader(node[leaves + leaf], refs[j].expected_header, headers[j]))
      return false;
    changed_leaves[changed++] = leaf;
  }
  const std::uint32_t height = static_cast<std::uint32_t>(std::countr_zero(leaves));
  if (tree.built && changed * height <= n) {  // recompose the paths above the changed leaves
    for (std::uint32_t i = 0; i < changed; ++i) {
      for (std::uint32_t k = (leaves + changed_leaves[i]) / 2; k >= 1; k /= 2) {
        node[k] = B::ComposeChain(node[2 * k + 1], node[2 * k]);
      }
    }
  } else {
    for (std::uint32_t k = leaves - 1; k >= 1; --k)
      node[k] = B::ComposeChain(node[2 * k + 1], node[2 * k]);
    // Busy: more than half the edges changed per evaluation since the last scan (not counting
    // the first scan, which loads everything).
    if (tree.scanned && 2 * changed > n * (tree.unscanned + 1)) tree.skip = kSkip;
    tree.built = true;
  }
  tree.scanned = true;
  tree.unscanned = 0;
  X_AF = node[1];
  return true;
}

}  // namespace internal

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const BasicPath<ForestChain>& path)
    -> BasicPath<Chain> {
  BasicPath<Chain> flat;
  flat.up_a = Flatten(t, path.up_a);
  flat.up_b = Flatten(t, path.up_b);
  return flat;
}

template <coord::Backend B>
auto CompiledQuery<B>::Flatten(const topology::SceneTopology& t, const PoseSteps<ForestChain>& s)
    -> PoseSteps<Chain> {
  PoseSteps<Chain> flat;
  flat.ab = Flatten(t, s.ab);
  if ((flat.change_ref_point = s.change_ref_point)) flat.fb = Flatten(t, s.fb);
  if ((flat.change_point = s.change_point)) flat.ea = Flatten(t, s.ea);
  if ((flat.change_frame = s.change_frame)) flat.br = Flatten(t, s.br);
  return flat;
}

// ============================================================ pose, position, orientation

template <coord::Backend B, internal::Part P>
CompiledPoseQuery<B, P>::CompiledPoseQuery(const topology::SceneTopology& t,
                                           const EdgeValues<B>& values,
                                           const typename Traits::Plan& plan)
    : CompiledQuery<B>(t, values),
      semantics_(plan.semantics),
      steps_(this->Flatten(t, plan.steps)) {}

template <coord::Backend B, internal::Part P>
ErrorCode CompiledPoseQuery<B, P>::Evaluate(Value& out) const noexcept {
  return internal::EvaluatePart<B, P>(this->source(), steps_, out) ? ErrorCode::kOk
                                                                   : ErrorCode::kQueryInvalidated;
}

template <coord::Backend B, internal::Part P>
ErrorCode CompiledPoseQuery<B, P>::Evaluate(Value& out, PoseCache<B>& cache) const noexcept {
  return internal::EvaluatePart<B, P>(this->source(cache), steps_, out)
             ? ErrorCode::kOk
             : ErrorCode::kQueryInvalidated;
}

// The policy may evaluate more than once (a retry at the latest common time) and may refuse a
// successful evaluation (kStale, kExtrapolation): the answer is kept aside until the code is kOk.
template <coord::Backend B, internal::Part P>
ErrorCode CompiledPoseQuery<B, P>::Evaluate(Value& out, const TimePolicy& policy,
                                            TimeReport& report) const noexcept {
  Value answer = Traits::Initial();
  const ErrorCode code = this->RunTimed(policy, report, [&](const internal::FlatSource<B>& src) {
    return internal::EvaluatePart<B, P>(src, steps_, answer);
  });
  if (code == ErrorCode::kOk) out = answer;
  return code;
}

// ====================================================================== twist

// A step of either twist source: a twist edge's stored twist (TwistPlan) or a pose edge's
// derivative (PoseTwistPlan), with the epoch of the edge it reads.
template <coord::Backend B>
void CompiledTwist<B>::AddStep(const topology::SceneTopology& t, const EdgeValues<B>& values,
                               const TwistStep<ForestChain>& step) {
  TwistStep<typename CompiledQuery<B>::Chain> flat;
  flat.edge = step.edge;
  flat.pose_edge = step.pose_edge;
  flat.epoch = step.pose_edge.is_valid() ? values.X_PF[step.pose_edge.value()].epoch()
                                         : values.V_DH[step.edge.value()].epoch();
  flat.invert = step.invert;
  if ((flat.move_point = step.move_point)) flat.eh = this->Flatten(t, step.eh);
  if ((flat.change_frame = step.change_frame)) flat.hr = this->Flatten(t, step.hr);
  steps_.push_back(flat);
}

template <coord::Backend B>
CompiledTwist<B>::CompiledTwist(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                const TwistPlan& plan)
    : CompiledQuery<B>(t, values), semantics_(plan.semantics) {
  ForEachTwistStep(t, plan, [&](const TwistStep<ForestChain>& s) { AddStep(t, values, s); });
}

template <coord::Backend B>
CompiledTwist<B>::CompiledTwist(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                const PoseTwistPlan& plan)
    : CompiledQuery<B>(t, values), semantics_(plan.semantics), from_poses_(true) {
  ForEachPoseDerivativeStep(t, plan,
                            [&](const TwistStep<ForestChain>& s) { AddStep(t, values, s); });
}

template <coord::Backend B>
template <class Source>
bool CompiledTwist<B>::Accumulate(const Source& src, Eigen::Vector3d& v,
                                  Eigen::Vector3d& w) const noexcept {
  v.setZero();
  w.setZero();
  for (const auto& step : steps_) {
    if (!internal::AccumulateTwistStep<B>(src, step, v, w)) return false;
  }
  return true;
}

// From poses the untimed Evaluate is the timed one under Latest (the newest samples, as the
// one-shot query and CompiledTwistWithCovariance): its codes too, so a used edge with a single
// sample (no derivative) is kExtrapolation, not a zero twist.
template <coord::Backend B>
ErrorCode CompiledTwist<B>::Evaluate(Eigen::Vector3d& v_DCe_R,
                                     Eigen::Vector3d& w_DC_R) const noexcept {
  if (from_poses_) {
    TimeReport report;
    return Evaluate(v_DCe_R, w_DC_R, Latest{}, report);
  }
  return Accumulate(this->source(), v_DCe_R, w_DC_R) ? ErrorCode::kOk
                                                     : ErrorCode::kQueryInvalidated;
}

template <coord::Backend B>
ErrorCode CompiledTwist<B>::Evaluate(Eigen::Vector3d& v_DCe_R, Eigen::Vector3d& w_DC_R,
                                     const TimePolicy& policy, TimeReport& report) const noexcept {
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  const TimePolicy used = from_poses_ ? internal::WithoutExtrapolation(policy) : policy;
  const ErrorCode code = this->RunTimed(
      used, report, [&](const internal::FlatSource<B>& src) { return Accumulate(src, v, w); });
  if (code == ErrorCode::kOk) {
    v_DCe_R = v;
    w_DC_R = w;
  }
  return code;
}

template class CompiledQuery<coord::QuaternionBackend>;
template class CompiledQuery<coord::HomogeneousBackend>;
template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kPose>;
template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kPose>;
template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kTranslation>;
template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kTranslation>;
template class CompiledPoseQuery<coord::QuaternionBackend, internal::Part::kRotation>;
template class CompiledPoseQuery<coord::HomogeneousBackend, internal::Part::kRotation>;
template class CompiledTwist<coord::QuaternionBackend>;
template class CompiledTwist<coord::HomogeneousBackend>;

}  // namespace semgraph::core
