// File: semgraph/core/wrenches.h
//
// Wrenches in the scene graph (docs/dynamics.md, "Wrenches in the graph"): the words of the API
// (WrenchSpec, WrenchHandle), the store of wrench values (internal::WrenchStore, a member of
// SceneGraph) and the compiled wrench query (CompiledWrench).
//
// What is stored: at most one wrench per ordered pair (on C, by D) of bodies, as
// WrenchCoord(s|C, D, [s]) with s a frame of C (the dual of the screw form of twist edges):
// force f_S and moment m_So_S about s's origin, both in [s]. The storage frame s is chosen once,
// when the pair is first given: the op's point if it is a frame of C, else the op's coordinate
// frame if it is a frame of C, else the frame of C made last (SceneTopology keeps a body's
// frames newest first) in the pose tree of the op's point. An update of the pair keeps s.
// A value given at another point or in another frame is converted with the pose graph at the
// current values by the one evaluator (evaluate.h): the pose of the given point and frame
// relative to (s, [s]), Algorithm 1.
//
// Stamped pairs (docs/dynamics.md, "Stamped wrenches"): a pair whose first value had a stamp
// keeps its samples (f_S, m_So_S) in a WrenchHistory (edge_history.h SampleHistory<6>, the
// graph's TimeOptions, allocated by the add), in WrenchStore::history by slot; its value is its
// newest sample. A stamped value given at another point or frame is converted with the poses at
// its stamp. Read at a time as a twist edge is (timed_read.h ReadLinearAt: linear in the stored
// form, a nearest sample held within the horizon), through the query's TimeContext, which also
// reads the poses moving it.
//
// Moving a stored wrench to point e and frame [r] (queries): with X = pose of (s,[s]) wrt
// (e,[r]) in [r] (R_RS, p_EoSo_R): f_R = R_RS f_S, m_Re = R_RS m_S + p_EoSo_R x f_R (KDL
// Frame*Wrench). The reaction of a stored wrench (the wrench on D by C) is its negation.
//
// Invariants: a live slot names two different bodies and a frame of its `on` body; no two live
// slots name the same unordered pair of bodies; a live slot is stamped (history.of(slot) not
// null, >= 1 sample, the value = its newest sample) or timeless for its whole life; a free
// slot has no history. Removing a slot bumps its value's epoch, then retires its history (reused
// by the next stamped pair, HistoryTable), so handles and compiled queries that used it are
// refused / invalidated, never wrong.
// Costs: AddWrench O(W + log n + d) (W stored wrenches: the pair is found by a scan; a stamped
// value also O(log samples) per stamped pose edge converting it, plus a shift when out of
// order); RemoveWrench O(W); one-shot queries O(W + terms * (log n + d)), at a policy also
// O(log samples) per stamped wrench and edge read (twice for latest common); SetWrench O(1)
// (stamped: in order O(1), out of order a shift), noexcept, allocation-free;
// CompiledWrench::Evaluate O(terms * edges on their pose paths) (+ O(log samples) each at a
// policy), noexcept, allocation-free. Memory: a stamped pair's history, capacity x 56 bytes.
// Thread safety: as pose and twist edges: one writer may call SetWrench while other threads
// evaluate compiled wrench queries (each value behind a sequence lock, each history behind its
// own; values and histories never move: stable_array.h, edge_history.h). Adds, removals and
// one-shot queries: the writer thread.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "semgraph/coord/values.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/edge_history.h"
#include "semgraph/core/seqlock_value.h"
#include "semgraph/core/specs.h"
#include "semgraph/core/stable_array.h"
#include "semgraph/core/timed_read.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core {

/// The names of a wrench: on body C, by body D (empty in a query: the net wrench on C), about
/// point e (a frame's origin), in [r].
///   WrenchSpec::On("C").By("D").At("e").ExpressedIn("r")
/// At(p) sets the point and the coordinate frame; ExpressedIn then overrides the frame.
struct WrenchSpec {
  std::string_view on, by, point, coordinate_frame;

  static WrenchSpec On(std::string_view body) {
    WrenchSpec s;
    s.on = body;
    return s;
  }
  WrenchSpec& By(std::string_view body) {
    by = body;
    return *this;
  }
  WrenchSpec& At(std::string_view frame) {
    point = coordinate_frame = frame;
    return *this;
  }
  WrenchSpec& ExpressedIn(std::string_view frame) {
    coordinate_frame = frame;
    return *this;
  }
};

/// A stored wrench: force and moment about the storage frame's origin, both in that frame.
struct WrenchNumbers {
  Eigen::Vector3d f_S;
  Eigen::Vector3d m_So_S;
};
using WrenchValue = SeqLockValue<WrenchNumbers>;
/// The samples of a stamped wrench: f_S, then m_So_S (6 words, as a twist edge's).
using WrenchHistory = SampleHistory<6>;

/// A stored wrench, for O(1) value updates from a control loop (SceneGraph::SetWrench). Made by
/// FindWrench; refused by SetWrench when made by another graph, forged, or its wrench removed.
struct WrenchHandle {
  std::uint32_t slot = 0;
  std::uint32_t epoch = 0;
  std::uint32_t graph = 0;     ///< GraphId of the graph that made it (0: none)
  topology::FrameIndex frame;  ///< the storage frame s: SetWrench takes f_S, m_So_S in [s]
  friend bool operator==(const WrenchHandle&, const WrenchHandle&) = default;
};

namespace internal {

/// One stored wrench's bookkeeping (writer side).
struct WrenchSlot {
  topology::BodyIndex on, by;
  topology::FrameIndex frame;  ///< s, a frame of `on`
  bool live = false;
};

/// The graph's wrenches: slots (reused after removal), their seqlocked values (a stamped pair's:
/// its newest sample) and the histories of the stamped pairs (null: timeless).
struct WrenchStore {
  std::vector<WrenchSlot> slots;
  StableArray<WrenchValue> values;      ///< by slot; never move (compiled queries point at them)
  HistoryTable<WrenchHistory> history;  ///< by slot, as the twist edges' (edge_history.h)
  std::size_t num_live = 0;

  /// The live slot of (on, by), or -1. O(W).
  [[nodiscard]] int Find(topology::BodyIndex on, topology::BodyIndex by) const noexcept {
    for (std::size_t i = 0; i < slots.size(); ++i) {
      const WrenchSlot& s = slots[i];
      if (s.live && s.on == on && s.by == by) return static_cast<int>(i);
    }
    return -1;
  }
  /// A free slot (a removed one, or a new one: allocates). Build time.
  [[nodiscard]] std::uint32_t NewSlot() {
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (!slots[i].live) return static_cast<std::uint32_t>(i);
    }
    values.Reserve(slots.size() + 1);
    history.Reserve(slots.size() + 1);
    slots.reserve(slots.size() + 1);
    values.EmplaceBack();
    history.Grow(slots.size() + 1);  // reserved: no allocation
    slots.emplace_back();
    return static_cast<std::uint32_t>(slots.size() - 1);
  }
};

inline void WordsFromWrench(const WrenchNumbers& W, double (&w)[6]) noexcept {
  for (int k = 0; k < 3; ++k) {
    w[k] = W.f_S[k];
    w[3 + k] = W.m_So_S[k];
  }
}
inline WrenchNumbers WrenchFromWords(const double (&w)[6]) noexcept {
  return {Eigen::Vector3d(w[0], w[1], w[2]), Eigen::Vector3d(w[3], w[4], w[5])};
}

/// The stored wrench of `slot` at the context's time: its value when timeless (or tc null: the
/// newest sample of a stamped one), else its samples read as a twist edge's (ReadLinearAt: linear
/// in the stored form, a nearest sample held within the horizon); a failure of its samples is
/// marked as the wrench's (TimeFailure::wrench). O(log samples), noexcept, allocation-free.
inline void ReadWrenchAt(const WrenchValue& value, const WrenchHistory* h, std::uint32_t slot,
                         TimeContext* tc, WrenchNumbers& W) noexcept {
  if (tc == nullptr || h == nullptr) {
    W = value.Load();
    return;
  }
  const bool failed = tc->extrapolation.code != base::ErrorCode::kOk,
             stale = tc->stale.code != base::ErrorCode::kOk;
  EdgeRead rec;  // not an edge: never recorded
  double w[6];
  (void)ReadLinearAt(*h, true, slot, *tc, rec, w);
  W = WrenchFromWords(w);
  if (!failed && tc->extrapolation.code != base::ErrorCode::kOk) tc->extrapolation.wrench = true;
  if (!stale && tc->stale.code != base::ErrorCode::kOk) tc->stale.wrench = true;
}

/// One term of a wrench answer: a stored wrench (or its reaction, sign -1) moved with the plan
/// of the pose of (s,[s]) wrt (e,[r]) in [r].
template <class Chain>
struct WrenchTerm {
  PoseSteps<Chain> steps;
  const WrenchValue* value = nullptr;
  const HistoryTable<WrenchHistory>* histories = nullptr;  ///< the store's (its samples, if any)
  std::uint32_t slot = 0;
  std::uint32_t epoch = 0;
  double sign = 1.0;
};

/// The one wrench move (queries, compiled queries, the conversion of an add): the stored
/// (f, m) about s in [s], times sign, moved to e in [r] by the pose X of (s,[s]) wrt (e,[r]),
/// added to (f_acc, m_acc). False when a compiled edge changed epoch.
template <coord::Backend B, class Source>
bool AccumulateWrench(const Source& src, const PoseSteps<typename Source::Chain>& steps,
                      const WrenchNumbers& W, double sign, Eigen::Vector3d& f_acc,
                      Eigen::Vector3d& m_acc) noexcept {
  typename B::Rotation R;
  Eigen::Vector3d p;
  if (!EvaluatePose<B, Part::kPose>(src, steps, R, p)) return false;
  const Eigen::Vector3d f = sign * B::Rotate(R, W.f_S);
  f_acc += f;
  m_acc += sign * B::Rotate(R, W.m_So_S) + p.cross(f);
  return true;
}

}  // namespace internal

/// WrenchCoord(e|C, D or several, [r]) compiled: the terms (stored wrenches on C, reactions of
/// the wrenches by C; only the one pair's with a `by`) and their pose paths, fixed when
/// compiled. A wrench of the pair(s) removed since: kQueryInvalidated; a wrench added since is
/// not part of it (recompile). Evaluate: noexcept, allocation-free, lock-free.
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT CompiledWrench : public CompiledQuery<B> {
 public:
  using Term = internal::WrenchTerm<typename CompiledQuery<B>::Chain>;
  CompiledWrench() = default;
  /// Made by SceneGraph::CompileWrench: `terms` of one-shot plans, flattened here.
  CompiledWrench(const topology::SceneTopology& t, const EdgeValues<B>& values,
                 const semantics::WrenchSemantics& semantics,
                 const std::vector<internal::WrenchTerm<ForestChain>>& terms);
  [[nodiscard]] const semantics::WrenchSemantics& semantics() const noexcept { return semantics_; }
  /// f_R and m_Re. kOk or kQueryInvalidated (then the outputs are unspecified).
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& f_R, Eigen::Vector3d& m_Re) const noexcept;
  /// At the policy's time (compiled_query.h, Time): the stored wrenches and the poses moving
  /// them read at one time; `f_R`, `m_Re` written on kOk only. Codes: kOk, kQueryInvalidated,
  /// kInvalidNumber (a negative horizon), kExtrapolation, kStale.
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& f_R, Eigen::Vector3d& m_Re,
                                   const TimePolicy& policy, TimeReport& report) const noexcept;
  /// In GetWrench's result type.
  [[nodiscard]] QueryResult<coord::Wrench> Evaluate() const noexcept {
    coord::Wrench W{semantics_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    return internal::Answer(Evaluate(W.force, W.moment), W);
  }
  [[nodiscard]] std::size_t num_terms() const noexcept { return terms_.size(); }

 private:
  /// One evaluation (tc null: the current values); false when a term was removed since.
  bool Accumulate(internal::TimeContext* tc, Eigen::Vector3d& f, Eigen::Vector3d& m) const noexcept;
  semantics::WrenchSemantics semantics_;
  std::vector<Term> terms_;
};

extern template class CompiledWrench<coord::QuaternionBackend>;
extern template class CompiledWrench<coord::HomogeneousBackend>;

}  // namespace semgraph::core
