// File: semgraph/core/edge_values.h
//
// EdgeValues<B>: the numbers of a scene graph, apart from its topology. One sequence-locked
// value per frame, X_PF (the pose of frame F in its pose parent P, in [P]; the identity for a
// root), and one per twist edge slot, the screw twist V_DH of the edge D -> {h}|H (velocity of
// h's origin and angular velocity of H relative to D, both in [h]). Indexed by the topology's
// FrameIndex and TwistEdgeIndex.
//
// Invariants: X_PF.size() == number of frames; V_DH.size() == number of twist edge slots; every
// stored rotation is valid for B (validated before Store); each value's epoch is bumped when its
// edge is removed, so handles and compiled queries made before see kNoSuchEdge /
// kQueryInvalidated instead of another edge's numbers.
// Costs: AddFrame / AddTwistSlot O(1) amortized (they allocate); Load/Store O(1), noexcept,
// lock-free, allocation-free (seqlock_value.h).
// Thread safety: one writer (Store, BumpEpoch) with any number of concurrent readers; growing
// the arrays (AddFrame, AddTwistSlot) needs exclusive access.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "semgraph/coord/backend.h"
#include "semgraph/core/edge_history.h"
#include "semgraph/core/seqlock_value.h"
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

/// A resolved pose edge, for O(1) value updates from a control loop (SceneGraph::SetPose).
struct PoseHandle {
  topology::FrameIndex child;  ///< the edge's head frame
  std::uint32_t epoch = 0;     ///< the edge's epoch when the handle was made
};
/// A resolved twist edge, for O(1) value updates (SceneGraph::SetTwist).
struct TwistHandle {
  topology::TwistEdgeIndex slot;
  std::uint32_t epoch = 0;
};

template <coord::Backend B>
struct EdgeValues {
  std::vector<PoseValue<B>> X_PF;  ///< by frame
  std::vector<TwistValue> V_DH;    ///< by twist edge slot
  /// Stamped edges' samples (edge_history.h); X_PF / V_DH then hold the newest sample.
  EdgeHistories history;

  /// The value of a new frame: the identity (it has no pose parent yet).
  void AddFrame() {
    X_PF.emplace_back(B::MakePose(B::FromQuaternion(Eigen::Quaterniond::Identity()), Eigen::Vector3d::Zero()));
  }
  /// Makes room for the value of twist edge slot `e`.
  void AddTwistSlot(topology::TwistEdgeIndex e) {
    if (V_DH.size() <= e.value()) V_DH.resize(e.value() + 1);
  }
  [[nodiscard]] std::size_t ApproximateBytes() const noexcept {
    return X_PF.capacity() * sizeof(PoseValue<B>) + V_DH.capacity() * sizeof(TwistValue) + history.ApproximateBytes();
  }
};

}  // namespace semgraph::core
