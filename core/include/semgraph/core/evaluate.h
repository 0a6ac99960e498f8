// File: semgraph/core/evaluate.h
//
// The one evaluator of the paper's Algorithms 1-3 over a query plan (query_plan.h). Every
// answer of the scene graph is computed here: one-shot queries, compiled queries, and the
// edge-form conversion of AddPose / AddTwist (the plan run backwards: ToEdgeForm).
//
// The evaluator is generic over a chain source, which says how to compose X_AF for one chain:
//   ForestSource  walks parent pointers from F up to A (one-shot queries, conversions). Debug and
//                 SEMGRAPH_EXPENSIVE_CHECKS builds replay each chain through the checked
//                 coord::Compose and demand the same semantics, verifying the shortcut below.
//   FlatSource    composes a compiled query's flattened edge list, checking each edge's epoch
//                 through its sequence lock (a removed edge fails the evaluation).
// Time (timed_read.h): given a TimeContext, both sources read each edge at the policy's time
// (interpolated, extrapolated, differentiated) through the same functions; without one they
// read each edge's current value, as before time existed. The composition is the same.
// An extrapolated pose edge's integration twist (ExtrapolationTwist) is planned where the
// context says (IntegrationTwistPlan): on the topology (PlanTwist), or a compiled query's plan
// made at compile time (IntegrationTwistPlans; the compiled queries with covariance).
// Why no semantic checks here: a plan is made only after every semantic check passed, and each
// composition along a chain is valid by the forest invariant (the edge into g stores
// PoseCoord({g}|G, {p}|P, [p]) and the next edge up starts at p). So only numbers remain, with
// coord's kernels; the result carries the plan's semantics.
//
// Costs: O(edges on the plan's chains) backend compositions; noexcept, allocation-free,
// lock-free, string-free. Thread safety: reads values through sequence locks only.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/base/demand.h"
#include "semgraph/coord/dynamics_operations.h"
#include "semgraph/coord/homogeneous_backend.h"
#include "semgraph/coord/operations.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/query_plan.h"
#include "semgraph/core/timed_read.h"

namespace semgraph::core::internal {

/// What a pose evaluation delivers: the whole pose, or only its translation or rotation (the
/// position and orientation queries skip the other half's arithmetic).
enum class Part { kPose, kTranslation, kRotation };

#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
/// The topology's change count when this thread's current optimistic read began (set by
/// ReadValidated, optimistic_read.h), or kNoPlanCount outside one (the writer's own calls).
/// Only the checked replay of debug builds reads it.
inline constexpr std::uint64_t kNoPlanCount = ~std::uint64_t{0};
inline std::uint64_t& ReplayPlanCount() noexcept {
  thread_local std::uint64_t count = kNoPlanCount;
  return count;
}
#endif

/// Composes one-shot chains by walking the pose forest.
template <coord::Backend B>
class ForestSource {
 public:
  using Chain = ForestChain;
  using PoseCoords = typename B::PoseCoords;

  ForestSource(const topology::SceneTopology& t, const EdgeValues<B>& v,
               TimeContext* time = nullptr) noexcept
      : t_(t), v_(v), time_(time) {}

  /// X_AF, A = c.to above F = c.from; identity when F == A. Composed bottom-up (each parent's
  /// edge is prepended: acc = X_PG acc), straight from the locked words for quaternions.
  /// False when the walk leaves the forest or takes more steps than there are frames: only a
  /// reader racing a topology change (its answer is then thrown away, optimistic_read.h).
  bool EvalChain(const ForestChain& c, PoseCoords& X_AF, bool& identity) const noexcept {
    identity = c.from == c.to;
    if (identity) return true;
#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
    const std::uint64_t headers = ChainHeaders(c);
    if (!Compose(c, X_AF)) return false;
    ReplayChecked(c, X_AF, headers);
    return true;
#else
    return Compose(c, X_AF);
#endif
  }
  bool LoadTwist(const TwistStep<ForestChain>& s, TwistNumbers& V) const noexcept {
    if (s.pose_edge.is_valid()) {
      TimeContext latest;  // a derivative without a context: of the newest segment
      latest.histories = &v_.history;
      DerivePoseAt<B>(v_, s.pose_edge.value(), time_ ? *time_ : latest, V);
    } else if (time_) {
      ReadTwistAt<B>(v_, s.edge.value(), *time_, V);
    } else {
      V = v_.V_DH[s.edge.value()].Load();
    }
    return true;
  }
  /// The acceleration record of a step's twist edge, at the current values or the policy's time
  /// (present = 0: the edge carries none; a pose edge's derivative never has one).
  bool LoadAcceleration(const TwistStep<ForestChain>& s, TwistAndAcceleration& r) const noexcept {
    if (s.pose_edge.is_valid()) {
      r.present = 0.0;
    } else if (time_) {
      ReadTwistAt<B, false, true>(v_, s.edge.value(), *time_, r.V, nullptr, &r);
    } else {
      r = v_.A_DH[s.edge.value()].Load();
    }
    return true;
  }

 private:
  // EvalChain's composition (c.from != c.to).
  [[gnu::always_inline]] bool Compose(const ForestChain& c, PoseCoords& X_AF) const noexcept {
    const std::size_t n = t_.num_frames();
    std::size_t steps = 0;
    // The next frame up, or invalid when the walk went astray.
    const auto up = [&](FrameIndex g) noexcept {
      const FrameIndex p = t_.pose_parent(g);
      return ++steps < n ? p : FrameIndex();
    };
    FrameIndex g = up(c.from);
    if (!g.is_valid()) return false;  // c.from has no edge: no value to read
    if (time_) {                      // each edge at the policy's time (timed_read.h)
      X_AF = Edge(c.from);
      for (; g != c.to; g = up(g)) {
        if (!g.is_valid()) return false;
        X_AF = B::ComposeChain(X_AF, Edge(g));
      }
    } else if constexpr (std::is_same_v<B, coord::QuaternionBackend>) {
      typename PoseValue<B>::Word w[PoseValue<B>::kWords];
      v_.X_PF[c.from.value()].LoadWords(w);
      Eigen::Quaterniond q(w[3], w[0], w[1], w[2]);
      Eigen::Vector3d p(w[4], w[5], w[6]);
      for (; g != c.to; g = up(g)) {
        if (!g.is_valid()) return false;
        v_.X_PF[g.value()].LoadWords(w);
        const Eigen::Quaterniond q_g(w[3], w[0], w[1], w[2]);
        p = B::Rotate(q_g, p) + Eigen::Vector3d(w[4], w[5], w[6]);
        q = q_g * q;
      }
      X_AF = PoseCoords{q, p};
    } else {
      X_AF = v_.X_PF[c.from.value()].Load();
      for (; g != c.to; g = up(g)) {
        if (!g.is_valid()) return false;
        X_AF = B::ComposeChain(X_AF, v_.X_PF[g.value()].Load());
      }
    }
    return true;
  }
  PoseCoords Edge(FrameIndex g) const noexcept {
    if (!time_) return v_.X_PF[g.value()].Load();
    PoseCoords X;
    ReadPoseAt<B>(v_, g.value(), *time_, X);
    return X;
  }
#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
  // A frame index the replay may read: a reader racing a change can meet any index.
  bool Known(FrameIndex g) const noexcept { return g.is_valid() && g.value() < t_.num_frames(); }
  // X_PF of `child` (Known) with its semantics; false when its parent is not Known.
  bool EdgePose(FrameIndex child, coord::Pose<B>& X) const noexcept {
    const FrameIndex parent = t_.pose_parent(child);
    if (!Known(parent)) return false;
    X = coord::Pose<B>{semantics::PoseSemantics::OfFrame(t_.FrameSem(child), t_.BodyOfSem(child),
                                                         t_.FrameSem(parent), t_.BodyOfSem(parent),
                                                         t_.FrameSem(parent).axes()),
                       v_.X_PF[child.value()].Load()};
    return true;
  }
  // The sum of the chain's sequence-lock headers, 0 when the walk went astray: unchanged across
  // two reads means no write to the chain's values began or ended between them (each header
  // only grows).
  std::uint64_t ChainHeaders(const ForestChain& c) const noexcept {
    std::uint64_t sum = 0;
    std::size_t steps = 0;
    for (FrameIndex g = c.from; g != c.to; g = t_.pose_parent(g)) {
      if (!Known(g) || ++steps > t_.num_frames()) return 0;
      sum += v_.X_PF[g.value()].header();
    }
    return sum;
  }
  // The chain again through the checked coord::Compose: the same semantics as the shortcut,
  // and the same numbers up to rounding.
  // Checked only when the topology is the one the plan was made on: no change since this
  // thread's optimistic read began (ReplayPlanCount) and none during the replay. A reader on
  // another thread may hold a plan of a torn forest; its answer is thrown away anyway.
  void ReplayChecked(const ForestChain& c, const PoseCoords& X_AF,
                     std::uint64_t headers) const noexcept {
    const std::uint64_t before = t_.change_count();
    if ((before & 1) != 0) return;
    if (ReplayPlanCount() != kNoPlanCount && ReplayPlanCount() != before) return;
    if (!Known(c.from) || !Known(c.to)) return;
    coord::Pose<B> checked;
    if (!EdgePose(c.from, checked)) return;
    bool composed = true;
    std::size_t steps = 0;
    for (FrameIndex g = t_.pose_parent(c.from); g != c.to; g = t_.pose_parent(g)) {
      coord::Pose<B> X_PG;
      if (!Known(g) || ++steps > t_.num_frames() || !EdgePose(g, X_PG)) return;
      auto next = coord::Compose(checked, X_PG);
      composed = composed && next.has_value();
      if (next) checked = *next;
    }
    const bool same_semantics =
        checked.semantics == semantics::PoseSemantics::OfFrame(
                                 t_.FrameSem(c.from), t_.BodyOfSem(c.from), t_.FrameSem(c.to),
                                 t_.BodyOfSem(c.to), t_.FrameSem(c.to).axes());
    const double scale = 1.0 + B::TranslationOf(X_AF).norm();
    // The replay composes the current values: comparable unless a timed read used others, or
    // another thread wrote a value of the chain since the shortcut read it.
    const bool same_numbers =
        time_ || headers == 0 || ChainHeaders(c) != headers ||
        (B::TranslationOf(checked.value) - B::TranslationOf(X_AF)).norm() <= 1e-9 * scale;
    if (t_.change_count() != before) return;
    SEMGRAPH_DEMAND(composed && same_semantics && same_numbers);
  }
#endif
  const topology::SceneTopology& t_;
  const EdgeValues<B>& v_;
  TimeContext* time_;
};

/// A compiled query's edge: the frame whose parent edge is read, the address of that edge's
/// value (a PoseValue<B> of the graph's EdgeValues: stable while the graph lives, so the hot
/// loop needs no index arithmetic and the writer may add edges meanwhile), and the sequence-lock
/// header it must carry (its epoch when compiled, no write in progress).
struct EdgeRef {
  std::uint64_t expected_header;
  const void* value;
  std::uint32_t child;
  [[nodiscard]] std::uint32_t epoch() const noexcept {
    return static_cast<std::uint32_t>(expected_header >> 32);
  }
};
/// X_AF of a compiled query: edges [begin, end) of its list, from F upward.
struct FlatChain {
  std::uint32_t begin = 0, end = 0;
};

/// Composes a compiled query's flattened chains; fails when an edge's epoch changed.
template <coord::Backend B>
class FlatSource {
 public:
  using Chain = FlatChain;
  using PoseCoords = typename B::PoseCoords;

  FlatSource(const EdgeValues<B>& v, const EdgeRef* edges, TimeContext* time = nullptr) noexcept
      : v_(v), edges_(edges), time_(time) {}
  /// Whether edges are read at a policy's time (else: at their current values).
  [[nodiscard]] bool timed() const noexcept { return time_ != nullptr; }

  // The edges are stored from F upward and composed top-down, acc = acc * X_i, as a
  // hand-written chain would (p += q p_i; q = q q_i for quaternions), so the loop-carried
  // dependency is one rotation product. Flattened: GCC 12 stops inlining Eigen's products
  // (here the 3x3 one of HomogeneousBackend::ComposeChain) once the translation unit has grown
  // (--param inline-unit-growth), and a call per edge costs 1.3x the loop (bench/icount.sh).
  [[gnu::flatten]] bool EvalChain(const FlatChain& c, PoseCoords& X_AF,
                                  bool& identity) const noexcept {
    identity = c.begin == c.end;
    if (identity) return true;
    const EdgeRef* first = edges_ + c.begin;
    const EdgeRef* e = edges_ + c.end - 1;
    if (time_) return EvalChainAt(first, e, X_AF);
    if constexpr (std::is_same_v<B, coord::QuaternionBackend>) {
      // The hot case: rebuild each edge's quaternion and vector straight from the locked words
      // (x y z w, then p), so nothing round-trips through the stack.
      // The words in lane pairs (x y, z w, p.x p.y, p.z p.z), which Eigen's quaternion product
      // loads as pairs: built from single words they went through the stack as two 8-byte
      // stores read back as one 16-byte load, which the store buffer cannot forward (a stall
      // of about a dozen cycles per edge).
      const auto load = [&](const EdgeRef& r, Eigen::Quaterniond& q, Eigen::Vector3d& p) {
        typename PoseValue<B>::WordPair w[4];
        if (!Value(r).LoadWordPairs(w, std::index_sequence<0, 2, 4, 6>{},
                                    std::index_sequence<1, 3, 5, 6>{}, r.expected_header)) {
          return false;
        }
        static_assert(sizeof(Eigen::Quaterniond) == sizeof(w[0]) * 2);
        std::memcpy(static_cast<void*>(q.coeffs().data()), static_cast<const void*>(w),
                    sizeof(Eigen::Quaterniond));  // x y z w, as the words
        std::memcpy(static_cast<void*>(p.data()), static_cast<const void*>(&w[2]), sizeof(w[2]));
        p.z() = w[3][0];
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
        p += B::Rotate(q, p_i);
        q = q * q_i;
      }
      X_AF = PoseCoords{q, p};
      return true;
    } else {
      PoseCoords acc;
      if (!Value(*e).Load(acc, e->epoch())) return false;
      while (e != first) {
        --e;
        PoseCoords X_i;
        if (!Value(*e).Load(X_i, e->epoch())) return false;
        acc = B::ComposeChain(X_i, acc);
      }
      X_AF = acc;
      return true;
    }
  }
  // An edge read from its history is bracketed by two epoch checks: the first skips a removed
  // edge early, the second is what makes reading a retired or reused history safe (HistoryTable,
  // edge_history.h: the removal bumps the epoch before it retires the history, so a reader
  // that read anything written after the removal sees the new epoch here).
  bool LoadTwist(const TwistStep<FlatChain>& s, TwistNumbers& V) const noexcept {
    if (s.pose_edge.is_valid()) {
      const PoseValue<B>& value = v_.X_PF[s.pose_edge.value()];
      if (value.epoch() != s.epoch) return false;
      TimeContext latest;
      latest.histories = &v_.history;
      DerivePoseAt<B>(v_, s.pose_edge.value(), time_ ? *time_ : latest, V);
      return value.epoch() == s.epoch;
    }
    if (!time_) return v_.V_DH[s.edge.value()].Load(V, s.epoch);
    const TwistValue& value = v_.V_DH[s.edge.value()];
    if (value.epoch() != s.epoch) return false;
    ReadTwistAt<B>(v_, s.edge.value(), *time_, V);
    return value.epoch() == s.epoch;
  }
  /// A compiled acceleration step's record (s.epoch: the record's epoch when compiled), at the
  /// current values or the policy's time (two epoch checks: see LoadTwist). False when the edge
  /// was removed since.
  bool LoadAcceleration(const TwistStep<FlatChain>& s, TwistAndAcceleration& r) const noexcept {
    if (s.pose_edge.is_valid()) {
      r.present = 0.0;
      return true;
    }
    return LoadAcceleration(v_.A_DH[s.edge.value()], s, r);
  }
  /// The same for a twist edge's record resolved when compiling (value: v.A_DH[s.edge], which
  /// never moves while the graph lives), so that the hot loop does no index lookup.
  bool LoadAcceleration(const AccelerationValue& value, const TwistStep<FlatChain>& s,
                        TwistAndAcceleration& r) const noexcept {
    // At the current values: one consistent read. (The compiled acceleration query's hot loop
    // reads records straight into lane pairs instead: motion_pairs.h, LoadEdgeMotion.)
    if (!time_) return value.Load(r, s.epoch);
    if (value.epoch() != s.epoch) return false;
    ReadTwistAt<B, false, true>(v_, s.edge.value(), *time_, r.V, nullptr, &r);
    return value.epoch() == s.epoch;
  }

 private:
  // Each edge at the policy's time, after its epoch check; composed top-down. Out of line so
  // that the untimed loop above stays small enough for the compiler to keep inlining its
  // arithmetic (with this branch inline, GCC 12 called Eigen's quaternion-vector product out of
  // line: 1.39x the raw chain's instructions at d = 8 instead of 1.15x).
  [[gnu::noinline]] bool EvalChainAt(const EdgeRef* first, const EdgeRef* e,
                                     PoseCoords& X_AF) const noexcept {
    const auto load = [&](const EdgeRef& r, PoseCoords& X) {  // two epoch checks: see LoadTwist
      if (Value(r).epoch() != r.epoch()) return false;
      ReadPoseAt<B>(v_, r.child, *time_, X);
      return Value(r).epoch() == r.epoch();
    };
    PoseCoords acc;
    if (!load(*e, acc)) return false;
    while (e != first) {
      --e;
      PoseCoords X_i;
      if (!load(*e, X_i)) return false;
      acc = B::ComposeChain(X_i, acc);
    }
    X_AF = acc;
    return true;
  }
  static const PoseValue<B>& Value(const EdgeRef& r) noexcept {
    return *static_cast<const PoseValue<B>*>(r.value);
  }
  const EdgeValues<B>& v_;
  const EdgeRef* edges_;
  TimeContext* time_;
};

}  // namespace semgraph::core::internal

namespace semgraph::core {
template <coord::Backend B>
struct PoseCache;
}  // namespace semgraph::core

namespace semgraph::core::internal {

/// Composes a compiled query's chains through a caller-owned memo of partial products
/// (PoseCache, compiled_query.h): reads every edge's header, reloads only the edges that
/// changed, recomposes only the tree nodes above them. Same answers as FlatSource, up to the
/// association of the products (rounding).
template <coord::Backend B>
class CachedSource {
 public:
  using Chain = FlatChain;
  using PoseCoords = typename B::PoseCoords;

  CachedSource(const EdgeValues<B>& v, const EdgeRef* edges, PoseCache<B>& cache) noexcept
      : v_(v), edges_(edges), cache_(&cache) {}

  bool EvalChain(const FlatChain& c, PoseCoords& X_AF, bool& identity) const noexcept;

 private:
  const EdgeValues<B>& v_;
  const EdgeRef* edges_;
  PoseCache<B>* cache_;
};

/// Algorithm 2: X_BA = X_CA X_CB^-1, with no composition with an identity.
template <coord::Backend B, class Source>
bool EvalBasic(const Source& src, const BasicPath<typename Source::Chain>& path,
               typename B::PoseCoords& X_BA) noexcept {
  typename B::PoseCoords X_CA, X_CB;
  bool a_identity, b_identity;
  if (!src.EvalChain(path.up_a, X_CA, a_identity) || !src.EvalChain(path.up_b, X_CB, b_identity)) {
    return false;
  }
  if (b_identity) {
    X_BA = a_identity ? B::Identity() : X_CA;
  } else if (a_identity) {
    X_BA = B::InvertChain(X_CB);
  } else {
    X_BA = B::ComposeChain(X_CA, B::InvertChain(X_CB));
  }
  return true;
}

/// Algorithm 1 on numbers: X_BA in [b], then reference point, point, coordinate frame.
/// Writes R (orientation operator in [r]) unless P == kTranslation, p (position in [r]) unless
/// P == kRotation. False when a compiled edge changed epoch.
template <coord::Backend B, Part P, class Source>
bool EvaluatePose(const Source& src, const PoseSteps<typename Source::Chain>& s,
                  typename B::Rotation& R, Eigen::Vector3d& p) noexcept {
  typename B::PoseCoords X_BA;
  if (!EvalBasic<B>(src, s.ab, X_BA)) return false;
  R = B::RotationOf(X_BA);
  if constexpr (P != Part::kRotation) {
    p = B::TranslationOf(X_BA);
    if (s.change_ref_point) {  // p_FE = p_BE - p_BF
      typename B::PoseCoords X_BF;
      if (!EvalBasic<B>(src, s.fb, X_BF)) return false;
      p -= B::TranslationOf(X_BF);
    }
    if (s.change_point) {  // p_BE = p_BA + R_BA p_AE_A
      typename B::PoseCoords X_AE;
      if (!EvalBasic<B>(src, s.ea, X_AE)) return false;
      p += B::Rotate(R, B::TranslationOf(X_AE));
    }
  }
  if (s.change_frame) {  // [b] -> [r]: p' = R_RB p, R' = R_RB R R_RB^T
    typename B::PoseCoords X_RB;
    if (!EvalBasic<B>(src, s.br, X_RB)) return false;
    const typename B::Rotation R_RB = B::RotationOf(X_RB);
    if constexpr (P == Part::kPose) {
      const auto X = coord::kernels::Reexpress<B>(B::MakePose(R, p), R_RB);
      R = B::RotationOf(X);
      p = B::TranslationOf(X);
    } else if constexpr (P == Part::kTranslation) {
      p = B::Rotate(R_RB, p);
    } else {
      R = B::Multiply(B::Multiply(R_RB, R), B::Transpose(R_RB));  // Reexpress, rotation only
    }
  }
  return true;
}

/// Part P of a pose answer, by type: the bare value the evaluator writes (Value), the relation
/// value a query returns (Result, with Semantics), the plan it is evaluated from (Plan), and a
/// value to start from (Initial).
template <coord::Backend B, Part P>
struct PartTraits;
template <coord::Backend B>
struct PartTraits<B, Part::kPose> {
  using Value = typename B::PoseCoords;
  using Result = coord::Pose<B>;
  using Semantics = semantics::PoseSemantics;
  using Plan = PosePlan;
  static Value Initial() noexcept { return B::Identity(); }
};
template <coord::Backend B>
struct PartTraits<B, Part::kTranslation> {
  using Value = Eigen::Vector3d;
  using Result = coord::Position;
  using Semantics = semantics::PositionSemantics;
  using Plan = PositionPlan;
  static Value Initial() noexcept { return Eigen::Vector3d::Zero(); }
};
template <coord::Backend B>
struct PartTraits<B, Part::kRotation> {
  using Value = typename B::Rotation;
  using Result = coord::Orientation<B>;
  using Semantics = semantics::OrientationSemantics;
  using Plan = OrientationPlan;
  static Value Initial() noexcept { return B::RotationOf(B::Identity()); }
};
/// The part a plan asks for.
template <class Plan>
inline constexpr Part kPartOf = Part::kPose;
template <>
inline constexpr Part kPartOf<PositionPlan> = Part::kTranslation;
template <>
inline constexpr Part kPartOf<OrientationPlan> = Part::kRotation;

/// Part P of a pose answer into `out` (unchanged when false: a compiled edge changed epoch).
/// The one evaluation behind every pose, position and orientation query, one-shot or compiled.
template <coord::Backend B, Part P, class Source>
bool EvaluatePart(const Source& src, const PoseSteps<typename Source::Chain>& s,
                  typename PartTraits<B, P>::Value& out) noexcept {
  typename B::Rotation R;
  Eigen::Vector3d p;  // written by EvaluatePose before any use (it returns early otherwise)
  if (!EvaluatePose<B, P>(src, s, R, p)) return false;
  if constexpr (P == Part::kPose) {
    out = B::MakePose(R, p);
  } else if constexpr (P == Part::kTranslation) {
    out = p;
  } else {
    out = R;
  }
  return true;
}

/// Algorithm 1 backwards: the edge form X_BA (a wrt b in [b]) of a pose given as
/// (e,[a]) wrt (f,[b]) in [r], with the plan of that pose. The steps are undone in reverse:
/// [r] -> [b], then the reference point f -> b (p += p_BF) and the point e -> a
/// (p -= R_BA p_AE_A). The plan's basic pose ab is not read (it is the unknown).
/// Over any chain source: false when a compiled edge changed epoch (X_BA then unspecified).
/// Converting handles (converting_handles.h) run it over their flattened chains.
template <coord::Backend B, class Source>
bool ToEdgeForm(const Source& src, const PoseSteps<typename Source::Chain>& s,
                const typename B::PoseCoords& X_given, typename B::PoseCoords& X_BA) noexcept {
  typename B::PoseCoords X = X_given;
  if (s.change_frame) {
    typename B::PoseCoords X_RB;
    if (!EvalBasic<B>(src, s.br, X_RB)) return false;
    X = coord::kernels::Reexpress<B>(X, B::Transpose(B::RotationOf(X_RB)));
  }
  typename B::Rotation R_BA = B::RotationOf(X);
  Eigen::Vector3d p_BA = B::TranslationOf(X);
  if (s.change_ref_point) {
    typename B::PoseCoords X_BF;
    if (!EvalBasic<B>(src, s.fb, X_BF)) return false;
    p_BA += B::TranslationOf(X_BF);
  }
  if (s.change_point) {
    typename B::PoseCoords X_AE;
    if (!EvalBasic<B>(src, s.ea, X_AE)) return false;
    p_BA -= B::Rotate(R_BA, B::TranslationOf(X_AE));
  }
  X_BA = B::MakePose(R_BA, p_BA);
  return true;
}
/// The one-shot form (AddPose): the forest's chains cannot fail.
template <coord::Backend B>
typename B::PoseCoords ToEdgeForm(const ForestSource<B>& src, const PoseSteps<ForestChain>& s,
                                  const typename B::PoseCoords& X_given) noexcept {
  typename B::PoseCoords X_BA = X_given;
  ToEdgeForm<B>(src, s, X_given, X_BA);
  return X_BA;
}

/// Algorithm 3, one twist edge: its screw twist, inverted if traversed against its direction,
/// moved to point e and re-expressed in [r], added to (v, w). False when a compiled edge
/// changed epoch.
template <coord::Backend B, class Source>
bool AccumulateTwistStep(const Source& src, const TwistStep<typename Source::Chain>& s,
                         Eigen::Vector3d& v, Eigen::Vector3d& w) noexcept {
  TwistNumbers V;  // TwistCoord(h|H, D, [h])
  if (!src.LoadTwist(s, V)) return false;
  Eigen::Vector3d v_i = s.invert ? Eigen::Vector3d(-V.v_DHo_H) : V.v_DHo_H;
  Eigen::Vector3d w_i = s.invert ? Eigen::Vector3d(-V.w_DH_H) : V.w_DH_H;
  if (s.move_point) {  // v_e = v_h + p_EH x w, with p_EH = -p_HE (both in [h])
    typename B::PoseCoords X_HE;
    if (!EvalBasic<B>(src, s.eh, X_HE)) return false;
    v_i = coord::kernels::ShiftLinear(v_i, w_i, -B::TranslationOf(X_HE));
  }
  if (s.change_frame) {
    typename B::PoseCoords X_RH;
    if (!EvalBasic<B>(src, s.hr, X_RH)) return false;
    const typename B::Rotation R_RH = B::RotationOf(X_RH);
    v_i = B::Rotate(R_RH, v_i);
    w_i = B::Rotate(R_RH, w_i);
  }
  v += v_i;
  w += w_i;
  return true;
}

/// The motion of one relation at point e in [r]: twist (v, w) and acceleration (a, alpha).
struct Motion {
  Eigen::Vector3d v, w, a, alpha;
  static Motion Zero() noexcept {
    const Eigen::Vector3d z = Eigen::Vector3d::Zero();
    return Motion{z, z, z, z};
  }
};
/// The relation X (M rel B) followed by Y (B rel C) at one point, in one frame: M rel C
/// (alpha = alpha_X + alpha_Y + w_X x w_Y, a = a_X + a_Y + 2 w_X x v_Y; twists summed).
inline Motion ComposeMotion(const Motion& X, const Motion& Y) noexcept {
  const auto A = coord::kernels::ComposeAccelerations(Y.a, Y.alpha, X.a, X.alpha, Y.v, Y.w, X.w);
  return Motion{X.v + Y.v, X.w + Y.w, A.linear, A.angular};
}

/// Algorithm 3 for accelerations, one twist edge: its twist and acceleration (edge form),
/// inverted if traversed against its direction (alpha' = -alpha, a' = -a + 2 w x v), moved to
/// point e (a_e = a_h + alpha x p_HE + w x (w x p_HE)) and re-expressed in [r]. `present`
/// false: the edge carries no acceleration (m then unspecified). False when a compiled edge
/// changed epoch, the step's pose chains included even when the edge carries no acceleration
/// (a removed edge is reported as such, not as a missing acceleration).
/// A twist edge's record as the motion of the step's relation at h in [h]: the edge's own, or
/// its inverse when traversed against its direction (alpha' = -alpha, a' = -a + 2 w x v).
inline Motion EdgeMotion(const TwistAndAcceleration& r, bool invert) noexcept {
  Motion m{r.V.v_DHo_H, r.V.w_DH_H, r.A.a_DHo_H, r.A.alpha_DH_H};
  if (invert) {
    const auto inv = coord::kernels::InvertAcceleration(m.a, m.alpha, m.v, m.w);
    m = Motion{-m.v, -m.w, inv.linear, inv.angular};
  }
  return m;
}
/// The motion at another point of the same relation: p = old point - new point, in m's frame
/// (v' = v + p x w, a' = a + p x alpha - w x (w x p)).
inline void ShiftMotion(Motion& m, const Eigen::Vector3d& p) noexcept {
  m.a = coord::kernels::ShiftAcceleration(m.a, m.alpha, m.w, p);
  m.v = coord::kernels::ShiftLinear(m.v, m.w, p);
}
/// The motion re-expressed with rotation R (R_new_old), in place: one 3x3 matrix for the four
/// vectors (a quaternion's four rotations cost twice as much). The products are written out per
/// row (the sums in Eigen's order): GCC 12 called Eigen's 3x3-by-vector assignment out of line
/// from the compiled acceleration query's loop, about 25 instructions per product plus the call.
template <coord::Backend B>
[[gnu::always_inline]] inline void RotateMotion(const typename B::Rotation& R, Motion& m) noexcept {
  const Eigen::Matrix3d M = B::ToMatrix(R);
  const auto rotate = [&M](const Eigen::Vector3d& x) noexcept {
    return Eigen::Vector3d(M(0, 0) * x.x() + M(0, 1) * x.y() + M(0, 2) * x.z(),
                           M(1, 0) * x.x() + M(1, 1) * x.y() + M(1, 2) * x.z(),
                           M(2, 0) * x.x() + M(2, 1) * x.y() + M(2, 2) * x.z());
  };
  m.v = rotate(m.v);
  m.w = rotate(m.w);
  m.a = rotate(m.a);
  m.alpha = rotate(m.alpha);
}

template <coord::Backend B, class Source>
bool AccelerationStep(const Source& src, const TwistStep<typename Source::Chain>& s, Motion& m,
                      bool& present) noexcept {
  TwistAndAcceleration r;
  if (!src.LoadAcceleration(s, r)) return false;
  present = r.present != 0.0;
  if (!present) {  // only the chains' validity
    typename B::PoseCoords X;
    return (!s.move_point || EvalBasic<B>(src, s.eh, X)) &&
           (!s.change_frame || EvalBasic<B>(src, s.hr, X));
  }
  m = EdgeMotion(r, s.invert);
  if (s.move_point) {  // p = old point - new point = h - e = -p_HE
    typename B::PoseCoords X_HE;
    if (!EvalBasic<B>(src, s.eh, X_HE)) return false;
    ShiftMotion(m, -B::TranslationOf(X_HE));
  }
  if (s.change_frame) {
    typename B::PoseCoords X_RH;
    if (!EvalBasic<B>(src, s.hr, X_RH)) return false;
    RotateMotion<B>(B::RotationOf(X_RH), m);
  }
  return true;
}

/// The composition of a twist plan's steps (ForEachTwistStep's order: C's side from C up to the
/// common ancestor X, then D's side from D up to X): C's side prepended (X rel ... rel C), D's
/// side appended (D rel ... rel X), then D rel X followed by X rel C.
/// In place (no Motion copied per edge): d_side = ComposeMotion(d_side, m), c_side =
/// ComposeMotion(m, c_side), written out.
struct AccelerationComposer {
  Motion c_side = Motion::Zero(), d_side = Motion::Zero();
  template <class Chain>
  void Add(const TwistStep<Chain>& s, const Motion& m) noexcept {
    Add(s.ref_side, m);
  }
  void Add(bool ref_side, const Motion& m) noexcept {
    if (ref_side) {  // X = d_side, Y = m
      Motion& X = d_side;
      X.a += m.a + 2.0 * X.w.cross(m.v);
      X.alpha += m.alpha + X.w.cross(m.w);
      X.v += m.v;
      X.w += m.w;
    } else {  // X = m, Y = c_side
      Motion& Y = c_side;
      Y.a += m.a + 2.0 * m.w.cross(Y.v);
      Y.alpha += m.alpha + m.w.cross(Y.w);
      Y.v += m.v;
      Y.w += m.w;
    }
  }
  [[nodiscard]] Motion Result() const noexcept { return ComposeMotion(d_side, c_side); }
};

/// The plan of the integration twist TwistCoord(h|H, T, [h]) of the pose edge {t}|T -> {h}|H
/// into h (the screw twist an extrapolated edge is integrated with); none when h has no pose
/// parent or there is no twist path. noexcept; O(depth of the twist forest).
inline std::optional<TwistPlan> PlanIntegrationTwist(const topology::SceneTopology& t,
                                                     FrameIndex h) noexcept {
  const FrameIndex tail = t.pose_parent(h);
  if (!tail.is_valid()) return std::nullopt;
  const semantics::TwistSemantics q{t.FrameSem(h).origin(), t.BodyOfSem(h), t.BodyOfSem(tail),
                                    t.FrameSem(h).axes()};
  auto plan = PlanTwist(t, q);
  if (!plan) return std::nullopt;
  return *plan;
}

/// A compiled query's integration twist plans (PlanIntegrationTwist of each pose edge it reads,
/// made at compile time: Add allocates), by frame, sorted. Find: O(log edges), noexcept,
/// allocation-free. Invariant: the plans are those of the topology at compile time (a twist
/// path changed since is not seen: recompile, as for any topology change).
struct IntegrationTwistPlans {
  std::vector<std::pair<std::uint32_t, std::optional<TwistPlan>>> plans;
  void Add(const topology::SceneTopology& t, FrameIndex h) {
    const auto it = std::lower_bound(plans.begin(), plans.end(), h.value(),
                                     [](const auto& e, std::uint32_t f) { return e.first < f; });
    if (it != plans.end() && it->first == h.value()) return;
    plans.insert(it, {h.value(), PlanIntegrationTwist(t, h)});
  }
  /// The plan of the edge into `frame`; nullptr when not compiled or without a twist path.
  [[nodiscard]] const TwistPlan* Find(std::uint32_t frame) const noexcept {
    const auto it = std::lower_bound(plans.begin(), plans.end(), frame,
                                     [](const auto& e, std::uint32_t f) { return e.first < f; });
    if (it == plans.end() || it->first != frame || !it->second) return nullptr;
    return &*it->second;
  }
};

/// The integration twist plan of the pose edge into `frame` for an evaluation in context tc:
/// the compiled query's (tc.twist_plans), else planned now on tc.topology (the one-shot path).
/// The one place an extrapolation's twist plan comes from (ExtrapolationTwist, and
/// timed_covariance.h ExtrapolationCovariance / KeyedSink).
inline std::optional<TwistPlan> IntegrationTwistPlan(const TimeContext& tc,
                                                     std::uint32_t frame) noexcept {
  if (tc.twist_plans != nullptr) {
    const TwistPlan* p = tc.twist_plans->Find(frame);
    if (p == nullptr) return std::nullopt;
    return *p;
  }
  if (tc.topology == nullptr) return std::nullopt;
  return PlanIntegrationTwist(*tc.topology, FrameIndex(frame));
}

/// The screw twist TwistCoord(h|H, T, [h]) of the pose edge {t}|T -> {h}|H into `frame`, at
/// stamp s, from the twist edges (a twist query planned and evaluated here, at s, without
/// extrapolation). The samples it reads count in the parent's oldest / newest; its edges are
/// not "used" (no not_before, no latest common, not recorded). False: no twist path, or a twist
/// edge on it has no data at s.
template <coord::Backend B>
bool ExtrapolationTwist(const EdgeValues<B>& v, std::uint32_t frame, std::int64_t s,
                        TimeContext& parent, Eigen::Vector3d& v_out,
                        Eigen::Vector3d& w_out) noexcept {
  if (parent.topology == nullptr) return false;
  const topology::SceneTopology& t = *parent.topology;
  const std::optional<TwistPlan> plan = IntegrationTwistPlan(parent, frame);
  if (!plan) return false;
  TimeContext nested;
  nested.at = true;
  nested.t = s;
  nested.nested = true;
  nested.histories = parent.histories;
  nested.topology = parent.topology;
  const ForestSource<B> src(t, v, &nested);
  v_out.setZero();
  w_out.setZero();
  ForEachTwistStep(t, *plan, [&](const TwistStep<ForestChain>& step) {
    AccumulateTwistStep<B>(src, step, v_out, w_out);
  });
  if (nested.extrapolation.code != base::ErrorCode::kOk) return false;
  if (nested.read_any) {
    parent.Read(nested.oldest);
    parent.Read(nested.newest);
  }
  return true;
}

}  // namespace semgraph::core::internal
