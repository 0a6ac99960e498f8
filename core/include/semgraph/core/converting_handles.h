// File: semgraph/core/converting_handles.h
//
// Handles that take an edge's new value in another form than the one the edge stores, and
// convert it on the real-time path (docs/realtime.md):
//
//   ConvertingTwistHandle  the twist edge D -> {h}|H fed with the twist of H wrt D measured in
//                          another frame [r] of h's pose tree, e.g. a camera's velocity
//                          estimate in the camera frame: SetTwist rotates it into [h] by R_HR,
//                          as AddTwist(TwistSpec::Of(h).RelativeTo(D).ExpressedIn(r)) does.
//   ConvertingPoseHandle   the pose edge {b} -> {a} fed with the pose in any form AddPose takes
//                          (another point, reference point or coordinate frame): SetPose runs
//                          the same edge-form conversion AddPose runs (evaluate.h ToEdgeForm).
//
// Made at build time by SceneGraph::FindTwistEdge(of, relative_to, expressed_in) and
// SceneGraph::FindPoseEdge(spec), with the checks and rich errors of the adds. The conversion
// is resolved once: its plan's chains are flattened into the edges it reads, with their epochs,
// exactly as a compiled query's are (compiled_query.h, whose machinery these classes share).
// SetTwist / SetPose then cost the compositions on those chains, through the one evaluator:
// noexcept, allocation-free, lock-free, string-free.
//
// Invariants: the handle holds the edge's plain handle (edge(): what FindTwistEdge(of,
// relative_to) / FindPoseEdge(of, relative_to) give) and the conversion's edges; the converted
// value is written through the plain handle, with all of its checks. A conversion whose edges
// changed (one was removed since) fails with kQueryInvalidated and writes nothing: make the
// handle again. No conversion chain crosses the edge being set (such a frame is refused at
// build time), so the value never depends on itself. The handle refers to its graph, which
// must outlive it and must not move. Copies are independent and cheap to use.
#pragma once

#include "semgraph/coord/jacobians.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/edge_values.h"
#include "semgraph/core/export.h"
#include "semgraph/core/query_plan.h"

namespace semgraph::core {

/// The twist edge D -> {h}|H, taking TwistCoord(h|H, D, [r]): the velocity of h's origin and
/// the angular velocity of H relative to D, both in [r] (any frame of h's pose tree).
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT ConvertingTwistHandle : public CompiledQuery<B> {
 public:
  ConvertingTwistHandle() = default;
  /// Build time: `edge` is the plain handle of D -> {h}; r is in h's tree.
  ConvertingTwistHandle(const topology::SceneTopology& t, const EdgeValues<B>& values,
                        TwistHandle edge, topology::FrameIndex h, topology::FrameIndex r,
                        const semantics::TwistSemantics& given);
  /// The edge's plain handle (SetTwist in [h]).
  [[nodiscard]] TwistHandle edge() const noexcept { return edge_; }
  /// What the handle takes: TwistCoord(h|H, D, [r]).
  [[nodiscard]] const semantics::TwistSemantics& semantics() const noexcept { return semantics_; }
  /// (v, w) in [r] -> in [h]: v_H = R_HR v_R, w_H = R_HR w_R, and a covariance S of (v, w)
  /// (linear first) with them: S_H = J S J^T, J = diag(R_HR, R_HR) (the rotation exact). False
  /// when an edge of the conversion changed epoch (v, w, S then unspecified). O(edges between r
  /// and h).
  [[nodiscard]] bool ToEdgeFrame(Eigen::Vector3d& v, Eigen::Vector3d& w,
                                 coord::Covariance6* S = nullptr) const noexcept;

 private:
  TwistHandle edge_;
  bool change_frame_ = false;
  BasicPath<internal::FlatChain> rh_;  // X_HR: [r] wrt [h], in [h]
  semantics::TwistSemantics semantics_;
};

/// The pose edge {b} -> {a}, taking PoseCoord((e,[a])|C, (f,[b])|D, [r]) as AddPose does.
template <coord::Backend B>
class SEMGRAPH_CORE_EXPORT ConvertingPoseHandle : public CompiledQuery<B> {
 public:
  ConvertingPoseHandle() = default;
  /// Build time: `edge` is the plain handle of {b} -> {a}; `steps` the plan's changes
  /// (PlanChanges).
  ConvertingPoseHandle(const topology::SceneTopology& t, const EdgeValues<B>& values,
                       PoseHandle edge, const PoseSteps<ForestChain>& steps,
                       const semantics::PoseSemantics& given);
  /// The edge's plain handle (SetPose in edge form).
  [[nodiscard]] PoseHandle edge() const noexcept { return edge_; }
  /// What the handle takes: PoseCoord((e,[a])|C, (f,[b])|D, [r]).
  [[nodiscard]] const semantics::PoseSemantics& semantics() const noexcept { return semantics_; }
  /// Whether it takes the edge form itself (nothing converted): the body convention of a
  /// covariance applies to such a handle only, as to AddPose.
  [[nodiscard]] bool edge_form() const noexcept {
    return !steps_.change_ref_point && !steps_.change_point && !steps_.change_frame;
  }
  /// The given pose -> the edge form X_BA (a wrt b in [b]). False when an edge of the
  /// conversion changed epoch. O(edges of the conversion's chains).
  [[nodiscard]] bool ToEdgeForm(const typename B::PoseCoords& X_given,
                                typename B::PoseCoords& X_BA) const noexcept;
  /// With a covariance S_given of the given pose (coordinates convention, linear first): S_BA,
  /// the edge form's, through the conversion's Jacobian (propagate.h ToEdgeFormCovariance, the
  /// one AddPose uses; the conversion's values exact). False as ToEdgeForm.
  [[nodiscard]] bool ToEdgeForm(const typename B::PoseCoords& X_given,
                                const coord::Covariance6& S_given, typename B::PoseCoords& X_BA,
                                coord::Covariance6& S_BA) const noexcept;

 private:
  PoseHandle edge_;
  PoseSteps<internal::FlatChain> steps_;
  semantics::PoseSemantics semantics_;
};

extern template class ConvertingTwistHandle<coord::QuaternionBackend>;
extern template class ConvertingTwistHandle<coord::HomogeneousBackend>;
extern template class ConvertingPoseHandle<coord::QuaternionBackend>;
extern template class ConvertingPoseHandle<coord::HomogeneousBackend>;

}  // namespace semgraph::core
