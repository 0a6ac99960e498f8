// File: semgraph/core/edge_values.h
//
// EdgeValues<B>: the numbers of a scene graph, apart from its topology. One sequence-locked
// value per frame, X_PF (the pose of frame F in its pose parent P, in [P]; the identity for a
// root), and one per twist edge slot, the screw twist V_DH of the edge D -> {h}|H (velocity of
// h's origin and angular velocity of H relative to D, both in [h]), with beside it the edge's
// optional acceleration A_DH (AccelerationCoord(h|H, D, [h]), its own record and presence flag).
// Indexed by the topology's FrameIndex and TwistEdgeIndex.
//
// Invariants: X_PF.size() == number of frames; V_DH.size() == A_DH.size() == number of twist
// edge slots; an acceleration record with present = 1 holds the edge's current twist; every
// stored rotation is valid for B (validated before Store); each value's epoch is bumped when its
// edge is removed, so handles and compiled queries made before see kNoSuchEdge /
// kQueryInvalidated instead of another edge's numbers.
// Handles (PoseHandle, TwistHandle) name their graph (GraphId), kind, edge and epoch.
// The values live in StableArrays (stable_array.h): a value never moves while the graph lives,
// so a compiled query holds pointers to its edges' values, and readers may keep evaluating while
// the writer adds frames and edges (frames are never deleted; a removed edge's value stays, with
// its epoch bumped, and a twist slot reused later keeps counting its epoch).
// Costs: AddFrame / AddTwistSlot O(1) amortized (they allocate a block at most doubling the
// capacity); by-index access a bit scan and a directory load; Load/Store O(1), noexcept,
// lock-free, allocation-free (seqlock_value.h).
// Thread safety: one writer (Store, BumpEpoch, AddFrame, AddTwistSlot, Reserve*) with any number
// of concurrent readers of values that existed when the reader learned of them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/coord/backend.h"
#include "semgraph/coord/covariance.h"
#include "semgraph/coord/quaternion_backend.h"
#include "semgraph/core/covariance_lanes.h"
#include "semgraph/core/edge_history.h"
#include "semgraph/core/export.h"
#include "semgraph/core/seqlock_value.h"
#include "semgraph/core/stable_array.h"
#include "semgraph/topology/ids.h"

namespace semgraph::core {

/// Bytes of B::PoseCoords that carry data (B::kPosePayloadBytes when the backend declares it).
template <coord::Backend B>
constexpr std::size_t PosePayloadBytes() noexcept {
  if constexpr (requires { B::kPosePayloadBytes; }) {
    return B::kPosePayloadBytes;
  } else {
    return sizeof(typename B::PoseCoords);
  }
}
template <coord::Backend B>
using PoseValue = SeqLockValue<typename B::PoseCoords, PosePayloadBytes<B>()>;

/// The stored screw twist V_DH of a twist edge D -> {h}|H, both vectors in [h].
struct TwistNumbers {
  Eigen::Vector3d v_DHo_H;  ///< velocity of h's origin, as a point of H, relative to D
  Eigen::Vector3d w_DH_H;   ///< angular velocity of H relative to D
};
using TwistValue = SeqLockValue<TwistNumbers>;

/// The acceleration a twist edge D -> {h}|H may carry, in the edge form
/// AccelerationCoord(h|H, D, [h]) (docs/dynamics.md §7): the classical acceleration of h's
/// origin as a point of H relative to D, and the angular acceleration of H relative to D, in [h].
struct AccelerationNumbers {
  Eigen::Vector3d a_DHo_H;
  Eigen::Vector3d alpha_DH_H;
};
/// A twist edge's acceleration record, kept apart from the hot value V_DH (one cache line) and
/// seqlocked with a copy of the twist it goes with, so that a reader gets an acceleration and the
/// twist of that very instant (the composition needs both). `present` (0 or 1): the edge carries
/// an acceleration; a twist stored without one stores the record with present = 0 first (never
/// a stale acceleration beside a new twist).
struct TwistAndAcceleration {
  TwistNumbers V;
  AccelerationNumbers A;
  double present;
};
using AccelerationValue = SeqLockValue<TwistAndAcceleration>;

/// An edge value with its covariance (docs/uncertainty.md: the edge form, linear first), kept
/// apart from the hot value (X_PF / V_DH stay one cache line) and seqlocked together, so that a
/// reader gets a value and the covariance of that very value. `active` (0 or 1): the edge has
/// carried a covariance; the record then follows every store of the value (the writer stores
/// it first), else the value is read from X_PF / V_DH with a zero covariance.
template <class T>
struct ValueAndCovariance {
  T value;
  coord::Covariance6 S;
  double active;
};
template <coord::Backend B>
using PoseCovarianceValue = SeqLockValue<ValueAndCovariance<typename B::PoseCoords>>;
using TwistCovarianceValue = SeqLockValue<ValueAndCovariance<TwistNumbers>>;

/// Which graph made a handle: a process-wide unique id per SceneGraph object, drawn from one
/// global atomic counter (0 is never drawn: it means "no graph"). A move hands the id to the
/// new object and draws a fresh one for the moved-from object, so handles follow the graph's
/// contents and never apply to whatever is built later in the emptied object. After 2^32 - 1
/// graphs in one process the counter wraps and ids may repeat.
/// Cost: one relaxed atomic increment per construction or move.
class SEMGRAPH_CORE_EXPORT GraphId {
 public:
  GraphId() noexcept : value_(Next()) {}
  GraphId(GraphId&& other) noexcept : value_(other.value_) { other.value_ = Next(); }
  GraphId& operator=(GraphId&& other) noexcept {
    if (this != &other) {
      value_ = other.value_;
      other.value_ = Next();
    }
    return *this;
  }
  GraphId(const GraphId&) = delete;
  GraphId& operator=(const GraphId&) = delete;
  [[nodiscard]] std::uint32_t value() const noexcept { return value_; }

 private:
  static std::uint32_t Next() noexcept;  // realtime.cc: one counter for the whole process
  std::uint32_t value_;
};

/// What a handle refers to. A handle made by hand, default-constructed, or whose bytes came from
/// the other handle type has the wrong kind (or graph 0) and is refused.
enum class EdgeKind : std::uint8_t { kNone = 0, kPose = 1, kTwist = 2 };

/// A resolved pose edge, for O(1) value updates from a control loop (SceneGraph::SetPose).
/// It cannot lie: SetPose checks, in O(1), that it was made by this graph (graph), is a pose
/// handle (kind), names a frame of the graph that has a pose parent through a variable
/// (different-body) edge, and that the edge was not removed since (epoch); otherwise it returns
/// a code and writes nothing. Any handle passing these checks names an edge FindPoseEdge would
/// give a handle for, so a forged one can only do what a genuine one does.
struct PoseHandle {
  topology::FrameIndex child;  ///< the edge's head frame
  std::uint32_t epoch = 0;     ///< the edge's epoch when the handle was made
  std::uint32_t graph = 0;     ///< GraphId of the graph that made it
  EdgeKind kind = EdgeKind::kNone;
  friend bool operator==(const PoseHandle&, const PoseHandle&) = default;
};
/// A resolved twist edge, for O(1) value updates (SceneGraph::SetTwist); checked like
/// PoseHandle (graph, kind, a live slot, epoch).
struct TwistHandle {
  topology::TwistEdgeIndex slot;
  std::uint32_t epoch = 0;
  std::uint32_t graph = 0;
  EdgeKind kind = EdgeKind::kNone;
  friend bool operator==(const TwistHandle&, const TwistHandle&) = default;
};

/// The word indices K..., then kLast (a value's words, then one more word of its record).
template <std::size_t kLast, std::size_t... K>
constexpr auto ValueThen(std::index_sequence<K...>) noexcept {
  return std::index_sequence<K..., kLast>{};
}

template <coord::Backend B>
struct EdgeValues {
  StableArray<PoseValue<B>> X_PF;  ///< by frame
  StableArray<TwistValue> V_DH;    ///< by twist edge slot
  /// Accelerations (TwistAndAcceleration), by twist edge slot, grown with V_DH (a reader that
  /// sees a twist edge finds its record constructed). acceleration_on: the writer's own copy of
  /// each record's `present`, so that a twist store touches the record only when it held one.
  StableArray<AccelerationValue> A_DH;
  StableArray<std::uint8_t> acceleration_on;
  /// Stamped edges' samples (edge_history.h); X_PF / V_DH then hold the newest sample.
  EdgeHistories history;
  /// Covariances (ValueAndCovariance), by frame and by twist slot, grown lazily: only up to the
  /// highest edge that was given a covariance (or whose handle was made), so that a graph
  /// without covariances allocates nothing more. Readers see the published sizes
  /// (pose_covariance_size, twist_covariance_size; release / acquire). `mutable`: grown by
  /// build-time calls on the writer thread that are const for the graph (FindPoseEdge,
  /// FindTwistEdge). The flags (which records are active) are the writer's own.
  mutable StableArray<PoseCovarianceValue<B>> S_PF;
  mutable StableArray<TwistCovarianceValue> S_DH;
  mutable StableArray<std::uint8_t> pose_covariance_on, twist_covariance_on;
  /// A published size: an atomic that moves with the graph (exclusive access, as any move).
  struct Published {
    std::atomic<std::uint32_t> value{0};
    Published() = default;
    Published(Published&& o) noexcept : value(o.value.load(std::memory_order_relaxed)) {}
    Published& operator=(Published&& o) noexcept {
      value.store(o.value.load(std::memory_order_relaxed), std::memory_order_relaxed);
      return *this;
    }
    [[nodiscard]] std::uint32_t load(std::memory_order m) const noexcept { return value.load(m); }
    void store(std::uint32_t n, std::memory_order m) noexcept { value.store(n, m); }
  };
  mutable Published pose_covariance_size, twist_covariance_size;

  /// The value of a new frame: the identity (it has no pose parent yet).
  /// Its history entry too (null: timeless), so that every frame a reader knows has one.
  void AddFrame() {
    X_PF.EmplaceBack(B::Identity());
    history.pose.Grow(X_PF.size());
  }
  /// Makes room for the value (and the history entry) of twist edge slot `e`.
  void AddTwistSlot(topology::TwistEdgeIndex e) {
    if (V_DH.size() <= e.value()) V_DH.Resize(e.value() + 1);
    while (A_DH.size() < V_DH.size()) {
      A_DH.EmplaceBack();
      acceleration_on.EmplaceBack(std::uint8_t{0});
    }
    history.twist.Grow(V_DH.size());
  }
  /// Writer: a twist edge's acceleration (A non-null) or none (A null), with the twist V it goes
  /// with; stored before V_DH itself (as covariances). O(1), noexcept, allocation-free.
  void StoreAcceleration(std::uint32_t slot, const TwistNumbers& V,
                         const AccelerationNumbers* A) noexcept {
    if (A != nullptr) {
      A_DH[slot].Store(TwistAndAcceleration{V, *A, 1.0});
      acceleration_on[slot] = 1;
    } else if (acceleration_on[slot]) {
      A_DH[slot].Store(TwistAndAcceleration{
          V, AccelerationNumbers{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, 0.0});
      acceleration_on[slot] = 0;
    }
  }
  /// Writer: whether the twist edge slot carries an acceleration. O(1).
  [[nodiscard]] bool HasAcceleration(std::uint32_t slot) const noexcept {
    return slot < acceleration_on.size() && acceleration_on[slot] != 0;
  }
  /// Writer, build time (allocates): covariance records for frames [0, frames) / twist slots
  /// [0, slots), so that storing a covariance there allocates nothing.
  void ReservePoseCovariances(std::size_t frames) const {
    Grow(S_PF, pose_covariance_on, pose_covariance_size, frames);
  }
  void ReserveTwistCovariances(std::size_t slots) const {
    Grow(S_DH, twist_covariance_on, twist_covariance_size, slots);
  }
  /// Writer, build time (allocates once per history): room for a covariance in every sample of
  /// the stamped edge into `frame` / of twist slot `slot` (nothing for a timeless edge), so that
  /// a stamped update with a covariance allocates nothing.
  void ReservePoseSampleCovariances(std::uint32_t frame) const {
    if (const PoseHistory* h = history.pose_of(frame)) h->EnsureCovariances();
  }
  void ReserveTwistSampleCovariances(std::uint32_t slot) const {
    if (const TwistHistory* h = history.twist_of(slot)) h->EnsureCovariances();
  }
  /// Writer, build time: room for an acceleration in every sample of the stamped twist edge
  /// `slot` (nothing for a timeless one), as ReserveTwistSampleCovariances.
  void ReserveTwistSampleAccelerations(std::uint32_t slot) const {
    if (const TwistHistory* h = history.twist_of(slot)) h->EnsureAccelerations();
  }

  // Writer: the covariance record of an edge, stored before the value itself (so a reader
  // that loads the value, then the record, never pairs a new value with an old covariance).
  // S null: the value is exact (zero covariance). O(1), noexcept, allocation-free.
  /// (S non-null needs the record reserved: ReservePoseCovariances / ReserveTwistCovariances.)
  void StorePoseCovariance(std::uint32_t frame, const typename B::PoseCoords& X,
                           const coord::Covariance6* S) noexcept {
    if (S != nullptr || (frame < pose_covariance_on.size() && pose_covariance_on[frame])) {
      StoreCovariance(S_PF[frame], pose_covariance_on[frame], X, S);
    }
  }
  void StoreTwistCovariance(std::uint32_t slot, const TwistNumbers& V,
                            const coord::Covariance6* S) noexcept {
    if (S != nullptr || (slot < twist_covariance_on.size() && twist_covariance_on[slot])) {
      StoreCovariance(S_DH[slot], twist_covariance_on[slot], V, S);
    }
  }
  /// Writer: a removed (or stamped) edge's record goes inactive.
  void ClearPoseCovariance(std::uint32_t frame) noexcept {
    if (frame < pose_covariance_on.size()) {
      ClearCovariance(S_PF[frame], pose_covariance_on[frame], B::Identity());
    }
  }
  void ClearTwistCovariance(std::uint32_t slot) noexcept {
    if (slot < twist_covariance_on.size()) {
      ClearCovariance(S_DH[slot], twist_covariance_on[slot],
                      TwistNumbers{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
    }
  }
  /// Writer: the covariance stored with an edge (zero when none). O(1).
  [[nodiscard]] coord::Covariance6 PoseCovarianceOf(std::uint32_t frame) const noexcept {
    if (frame >= pose_covariance_on.size() || !pose_covariance_on[frame]) {
      return coord::Covariance6::Zero();
    }
    return S_PF[frame].Load().S;
  }
  [[nodiscard]] coord::Covariance6 TwistCovarianceOf(std::uint32_t slot) const noexcept {
    if (slot >= twist_covariance_on.size() || !twist_covariance_on[slot]) {
      return coord::Covariance6::Zero();
    }
    return S_DH[slot].Load().S;
  }
  /// Reader: an edge's value and the covariance of that value, consistent under a concurrent
  /// writer. O(1).
  void LoadPose(std::uint32_t frame, typename B::PoseCoords& X,
                coord::Covariance6& S) const noexcept {
    X = X_PF[frame].Load();
    if (frame < pose_covariance_size.load(std::memory_order_acquire)) {
      LoadCovariance(S_PF[frame], X, S);
    } else {
      S.setZero();
    }
  }
  /// Reader: LoadPose with the covariance's upper triangle put straight where the SIMD kernel
  /// reads it (covariance_lanes.h): word kCovarianceLaneWords[k] into S_lanes[4 k], the rows
  /// kS11 .. kS12 of one lane, from the same consistent read as the value. True when the edge
  /// carries a covariance (S_lanes written); false: X from X_PF, S_lanes unspecified. O(1).
  bool LoadPoseIntoLanes(std::uint32_t frame, typename B::PoseCoords& X,
                         double* S_lanes) const noexcept {
    if (frame < pose_covariance_size.load(std::memory_order_acquire)) {
      using Record = ValueAndCovariance<typename B::PoseCoords>;
      constexpr std::size_t kValueWords = (PosePayloadBytes<B>() + 7) / 8;
      constexpr std::size_t kAlign = alignof(coord::Covariance6);
      constexpr std::size_t kS =
          (sizeof(typename B::PoseCoords) + kAlign - 1) / kAlign * kAlign / 8;
      constexpr std::size_t kActive = kS + 36;
      static_assert(sizeof(Record) >= (kActive + 1) * 8 &&
                    sizeof(Record) <= (kActive + 1) * 8 + 56);
      static_assert(internal::LaneIndex(1, 0) - internal::LaneIndex(0, 0) == 4);
      double w[kValueWords + 1];  // the value's words, then `active`
      S_PF[frame].template LoadSelectedWords<4>(
          w, ValueThen<kActive>(std::make_index_sequence<kValueWords>{}), S_lanes,
          internal::CovarianceLaneWords<kS>(std::make_index_sequence<21>{}));
      if (w[kValueWords] != 0.0) {
        if constexpr (std::is_same_v<B, coord::QuaternionBackend>) {  // scalars: no wide reload
          X = {Eigen::Quaterniond(w[3], w[0], w[1], w[2]), Eigen::Vector3d(w[4], w[5], w[6])};
        } else {
          std::memcpy(static_cast<void*>(&X), static_cast<const void*>(w), PosePayloadBytes<B>());
        }
        return true;
      }
    }
    X = X_PF[frame].Load();
    return false;
  }
  void LoadTwist(std::uint32_t slot, TwistNumbers& V, coord::Covariance6& S) const noexcept {
    V = V_DH[slot].Load();
    if (slot < twist_covariance_size.load(std::memory_order_acquire)) {
      LoadCovariance(S_DH[slot], V, S);
    } else {
      S.setZero();
    }
  }
  /// Room for `frames` frame values / `slots` twist slot values in total (blocks of doubling
  /// size), so that AddFrame / AddTwistSlot up to there do not allocate. Build operations
  /// call these before their first change (all or nothing under std::bad_alloc).
  void ReserveFrames(std::size_t frames) {
    X_PF.Reserve(frames);
    history.pose.Reserve(frames);
  }
  void ReserveTwistSlots(std::size_t slots) {
    V_DH.Reserve(slots);
    A_DH.Reserve(slots);
    acceleration_on.Reserve(slots);
    history.twist.Reserve(slots);
  }
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    return X_PF.bytes() + V_DH.bytes() + A_DH.bytes() + acceleration_on.bytes() + S_PF.bytes() +
           S_DH.bytes() + pose_covariance_on.bytes() + twist_covariance_on.bytes() +
           history.ApproximateBytes();
  }

 private:
  template <class Records>
  static void Grow(Records& records, StableArray<std::uint8_t>& on, Published& published,
                   std::size_t n) {
    if (records.size() >= n) return;
    records.Reserve(n);
    on.Reserve(n);
    while (records.size() < n) {
      records.EmplaceBack();
      on.EmplaceBack(std::uint8_t{0});
    }
    published.store(static_cast<std::uint32_t>(n), std::memory_order_release);
  }
  template <class Slot, class T>
  static void StoreCovariance(Slot& slot, std::uint8_t& on, const T& x,
                              const coord::Covariance6* S) noexcept {
    if (S != nullptr) {
      slot.Store(ValueAndCovariance<T>{x, *S, 1.0});
      on = 1;
    } else if (on) {
      slot.Store(ValueAndCovariance<T>{x, coord::Covariance6::Zero(), 1.0});
    }
  }
  template <class Slot, class T>
  static void ClearCovariance(Slot& slot, std::uint8_t& on, const T& x) noexcept {
    if (!on) return;
    slot.Store(ValueAndCovariance<T>{x, coord::Covariance6::Zero(), 0.0});
    on = 0;
  }
  template <class Slot, class T>
  static void LoadCovariance(const Slot& slot, T& x, coord::Covariance6& S) noexcept {
    const ValueAndCovariance<T> r = slot.Load();
    if (r.active != 0.0) {
      x = r.value;
      S = r.S;
    } else {
      S.setZero();
    }
  }
};

}  // namespace semgraph::core
