// The real-time write path: handles made at build time, then SetPose / SetTwist (noexcept,
// allocation-free, lock-free, string-free). Contract: scene_graph.h, docs/realtime.md.
#include <atomic>
#include <cmath>

#include "covariance_input.h"
#include "edge_lookup.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "text.h"

namespace semgraph::core {

using base::Unexpected;
using text::Reject;

std::uint32_t GraphId::Next() noexcept {
  static std::atomic<std::uint32_t> counter{0};
  std::uint32_t id = counter.fetch_add(1, std::memory_order_relaxed) + 1;
  while (id == 0) id = counter.fetch_add(1, std::memory_order_relaxed) + 1;  // 0 means "no graph"
  return id;
}

template <coord::Backend B>
Expected<PoseHandle, BuildError> SceneGraph<B>::FindPoseEdge(std::string_view of,
                                                             std::string_view relative_to) const {
  const auto what = [&] {
    return "handle of the pose of {" + std::string(of) + "} wrt {" + std::string(relative_to) + "}";
  };
  // invalid_name -> unknown_frame -> no_such_edge (the finder RemovePose uses) -> joint_edge ->
  // constant_pose_change.
  const topology::SceneTopology& t = topology_;
  const internal::EdgeLookup l = internal::LookUpPoseEdge(t, of, relative_to);
  if (l.code != ErrorCode::kOk) {
    return Unexpected{Reject(l.code, what(), text::EdgeReason(t, l, relative_to, false)).error()};
  }
  if (const internal::JointRecord* j = joints_.OfChild(l.head)) {
    return Unexpected{Reject(ErrorCode::kJointEdge, what(),
                             "the edge belongs to joint " + std::string(joints_.name(*j)) +
                                 ": set the joint's position instead")
                          .error()};
  }
  if (topology::IsConstantEdge(t, l.tail, l.head)) {
    return Unexpected{Reject(ErrorCode::kConstantPoseChange, what(),
                             text::Frame(t, l.head) + " and " + text::Frame(t, l.tail) +
                                 " are fixed to one body: their pose is constant")
                          .error()};
  }
  // Room for the edge's covariance, so that SetPose with one never allocates (edge_values.h);
  // for a stamped edge in every sample too.
  values_.ReservePoseCovariances(l.head.value() + 1);
  values_.ReservePoseSampleCovariances(l.head.value());
  return PoseHandle{l.head, values_.X_PF[l.head.value()].epoch(), id_.value(), EdgeKind::kPose};
}

template <coord::Backend B>
Expected<TwistHandle, BuildError> SceneGraph<B>::FindTwistEdge(std::string_view of,
                                                               std::string_view relative_to) const {
  const auto what = [&] {
    return "handle of the twist of " + std::string(of) + " wrt " + std::string(relative_to);
  };
  // invalid_name -> unknown_frame -> unknown_body -> no_such_edge (the finder RemoveTwist uses)
  // -> joint_edge.
  const topology::SceneTopology& t = topology_;
  const internal::EdgeLookup l = internal::LookUpTwistEdge(t, of, relative_to);
  if (l.code != ErrorCode::kOk) {
    return Unexpected{Reject(l.code, what(), text::EdgeReason(t, l, relative_to, false)).error()};
  }
  if (const internal::JointRecord* j = joints_.OfChild(l.head)) {
    return Unexpected{Reject(ErrorCode::kJointEdge, what(),
                             "the edge belongs to joint " + std::string(joints_.name(*j)) +
                                 ": set the joint's velocity instead")
                          .error()};
  }
  values_.ReserveTwistCovariances(l.edge.value() + 1);  // as FindPoseEdge
  values_.ReserveTwistSampleCovariances(l.edge.value());
  values_.ReserveTwistSampleAccelerations(l.edge.value());  // SetAcceleration at a stamp
  return TwistHandle{l.edge, values_.V_DH[l.edge.value()].epoch(), id_.value(), EdgeKind::kTwist};
}

namespace {
// The handle cannot lie (edge_values.h): this graph's, a pose handle, a frame with a pose
// parent, the epoch it was made at, and a variable edge. O(1): a few loads.
template <coord::Backend B>
ErrorCode CheckPoseHandle(const PoseHandle& edge, std::uint32_t graph,
                          const topology::SceneTopology& t, const EdgeValues<B>& values) noexcept {
  if (edge.graph != graph || edge.kind != EdgeKind::kPose ||
      edge.child.value() >= values.X_PF.size() ||
      values.X_PF[edge.child.value()].epoch() != edge.epoch) {
    return ErrorCode::kNoSuchEdge;
  }
  const FrameIndex tail = t.pose_parent(edge.child);
  if (!tail.is_valid()) return ErrorCode::kNoSuchEdge;  // a root: no edge into it
  if (t.body_of(tail) == t.body_of(edge.child))
    return ErrorCode::kConstantPoseChange;  // P4: constant
  return ErrorCode::kOk;
}

// The same for a twist handle: this graph's, a twist handle, a live slot, its epoch.
template <coord::Backend B>
ErrorCode CheckTwistHandle(const TwistHandle& edge, std::uint32_t graph,
                           const topology::SceneTopology& t, const EdgeValues<B>& values) noexcept {
  if (edge.graph != graph || edge.kind != EdgeKind::kTwist ||
      edge.slot.value() >= t.num_twist_edge_slots() || !t.twist_edge(edge.slot).alive ||
      values.V_DH[edge.slot.value()].epoch() != edge.epoch) {
    return ErrorCode::kNoSuchEdge;
  }
  return ErrorCode::kOk;
}

// The rotation of a real-time pose update, validated (and normalized) without allocating.
inline auto ValidateRotation(const Eigen::Quaterniond& q) noexcept {
  return coord::ValidateQuaternion(q);
}
inline auto ValidateRotation(const Eigen::Matrix3d& R) noexcept {
  return coord::ValidateRotationMatrix(R);
}
}  // namespace

template <coord::Backend B>
template <class R>
ErrorCode SceneGraph<B>::SetPoseImpl(PoseHandle edge, const R& rotation,
                                     const Eigen::Vector3d& p_ToHo_T, std::optional<Stamp> stamp,
                                     UpdateError* why) noexcept {
  using internal::Report;
  const ErrorCode handle = CheckPoseHandle(edge, id_.value(), topology_, values_);
  if (handle != ErrorCode::kOk) return Report(why, handle);
  auto p = coord::ValidateVector(p_ToHo_T, coord::ValueRole::kPosition);
  if (!p) return Report(why, p.error());
  auto M = ValidateRotation(rotation);
  if (!M) return Report(why, M.error());
  typename B::PoseCoords X;
  if constexpr (std::is_same_v<R, Eigen::Quaterniond>) {
    X = B::MakePose(B::FromQuaternion(*M), *p);
  } else {
    X = B::MakePose(B::FromMatrix(*M), *p);
  }
  // The stamp rules (time_add.cc): a timeless edge takes unstamped values only, and back.
  if (const ErrorCode code = CheckPoseSample(edge.child, X, stamp); code != ErrorCode::kOk) {
    return Report(why, code);
  }
  StorePoseSample(edge.child, X, stamp);
  return Report(why, ErrorCode::kOk);
}

// With a covariance (docs/uncertainty.md): the handle, the value, then the covariance's checks
// (kInvalidNumber, kInvalidCovariance: as AddPose's order), then the stamp rules and the store
// (a stamped sample carries it). noexcept and allocation-free (the checks' eigen decomposition is
// fixed-size; FindPoseEdge / FindTwistEdge reserved the record and a stamped edge's samples').
template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPoseWithCovariance(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                               const Eigen::Vector3d& p_ToHo_T,
                                               std::optional<Stamp> stamp,
                                               const CovarianceInput& covariance,
                                               UpdateError* why) noexcept {
  using internal::Report;
  const ErrorCode handle = CheckPoseHandle(edge, id_.value(), topology_, values_);
  if (handle != ErrorCode::kOk) return Report(why, handle);
  auto p = coord::ValidateVector(p_ToHo_T, coord::ValueRole::kPosition);
  if (!p) return Report(why, p.error());
  auto q = coord::ValidateQuaternion(q_TH);
  if (!q) return Report(why, q.error());
  const typename B::PoseCoords X = B::MakePose(B::FromQuaternion(*q), *p);
  if (covariance.matrix == nullptr) return SetPoseImpl(edge, *q, *p, stamp, why);
  const coord::CovarianceCheck check = coord::CheckCovariance(*covariance.matrix);
  if (!check.ok()) return Report(why, check.error());
  const coord::Covariance6 S = internal::CoordinatesCovariance(covariance, q->toRotationMatrix());
  // A handle that passed the checks but has no room (one copied from a handle of this graph's
  // FindPoseEdge always has it) names no edge with a covariance.
  const PoseHistory* history = values_.history.pose_of(edge.child.value());
  if (edge.child.value() >= values_.pose_covariance_on.size() ||
      (history != nullptr && !history->has_covariances())) {
    return Report(why, ErrorCode::kNoSuchEdge);
  }
  if (const ErrorCode code = CheckPoseSample(edge.child, X, stamp, &S); code != ErrorCode::kOk) {
    return Report(why, code);
  }
  StorePoseSample(edge.child, X, stamp, &S);
  return Report(why, ErrorCode::kOk);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwistWithCovariance(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                                const Eigen::Vector3d& w_DH_H,
                                                std::optional<Stamp> stamp,
                                                const CovarianceInput& covariance,
                                                UpdateError* why) noexcept {
  using internal::Report;
  const ErrorCode handle = CheckTwistHandle(edge, id_.value(), topology_, values_);
  if (handle != ErrorCode::kOk) return Report(why, handle);
  auto v = coord::ValidateVector(v_DHo_H, coord::ValueRole::kLinearVelocity);
  if (!v) return Report(why, v.error());
  auto w = coord::ValidateVector(w_DH_H, coord::ValueRole::kAngularVelocity);
  if (!w) return Report(why, w.error());
  if (covariance.matrix == nullptr) return Report(why, SetTwistSample(edge, {*v, *w}, stamp));
  const coord::CovarianceCheck check = coord::CheckCovariance(*covariance.matrix);
  if (!check.ok()) return Report(why, check.error());
  if (covariance.convention != PoseCovarianceConvention::kCoordinates) {
    return Report(why, ErrorCode::kInvalidCovariance);  // a twist has no convention
  }
  const coord::Covariance6 S =
      internal::CoordinatesCovariance(covariance, Eigen::Matrix3d::Identity());
  const TwistNumbers V{*v, *w};
  const TwistHistory* history = values_.history.twist_of(edge.slot.value());
  if (edge.slot.value() >= values_.twist_covariance_on.size() ||  // as SetPose's
      (history != nullptr && !history->has_covariances())) {
    return Report(why, ErrorCode::kNoSuchEdge);
  }
  if (const ErrorCode code = CheckTwistSample(edge.slot, V, stamp, &S); code != ErrorCode::kOk) {
    return Report(why, code);
  }
  StoreTwistSample(edge.slot, V, stamp, &S);
  return Report(why, ErrorCode::kOk);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                 const Eigen::Vector3d& p_ToHo_T, const CovarianceInput& covariance,
                                 UpdateError* why) noexcept {
  return SetPoseWithCovariance(edge, q_TH, p_ToHo_T, std::nullopt, covariance, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                  const Eigen::Vector3d& w_DH_H, const CovarianceInput& covariance,
                                  UpdateError* why) noexcept {
  return SetTwistWithCovariance(edge, v_DHo_H, w_DH_H, std::nullopt, covariance, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                 const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                 const CovarianceInput& covariance, UpdateError* why) noexcept {
  return SetPoseWithCovariance(edge, q_TH, p_ToHo_T, stamp, covariance, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                  const Eigen::Vector3d& w_DH_H, Stamp stamp,
                                  const CovarianceInput& covariance, UpdateError* why) noexcept {
  return SetTwistWithCovariance(edge, v_DHo_H, w_DH_H, stamp, covariance, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                 const Eigen::Vector3d& p_ToHo_T, UpdateError* why) noexcept {
  return SetPoseImpl(edge, q_TH, p_ToHo_T, std::nullopt, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                 const Eigen::Vector3d& p_ToHo_T, UpdateError* why) noexcept {
  return SetPoseImpl(edge, R_TH, p_ToHo_T, std::nullopt, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPoseUnchecked(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                          const Eigen::Vector3d& p_ToHo_T) noexcept {
  if (const ErrorCode c = CheckPoseHandle(edge, id_.value(), topology_, values_);
      c != ErrorCode::kOk)
    return c;
#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
  SEMGRAPH_DEMAND(coord::ValidateVector(p_ToHo_T, coord::ValueRole::kPosition).has_value());
  SEMGRAPH_DEMAND(q_TH.coeffs().allFinite() && std::abs(q_TH.squaredNorm() - 1.0) <= 1e-12);
#endif
  if (values_.history.pose_of(edge.child.value()))
    return ErrorCode::kStampMismatch;  // a stamped edge
  const typename B::PoseCoords X = B::MakePose(B::FromQuaternion(q_TH), p_ToHo_T);
  values_.StorePoseCovariance(edge.child.value(), X, nullptr);  // exact: a zero covariance
  values_.X_PF[edge.child.value()].Store(X);
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                  const Eigen::Vector3d& w_DH_H, UpdateError* why) noexcept {
  return SetTwistImpl(edge, v_DHo_H, w_DH_H, std::nullopt, why);
}

// Stamped updates (docs/time.md): the same validation, then the stamp rules and the sample.
template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                 const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                 UpdateError* why) noexcept {
  return SetPoseImpl(edge, q_TH, p_ToHo_T, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                 const Eigen::Vector3d& p_ToHo_T, Stamp stamp,
                                 UpdateError* why) noexcept {
  return SetPoseImpl(edge, R_TH, p_ToHo_T, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                  const Eigen::Vector3d& w_DH_H, Stamp stamp,
                                  UpdateError* why) noexcept {
  return SetTwistImpl(edge, v_DHo_H, w_DH_H, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwistImpl(TwistHandle edge, const Eigen::Vector3d& v_DHo_H,
                                      const Eigen::Vector3d& w_DH_H, std::optional<Stamp> stamp,
                                      UpdateError* why) noexcept {
  using internal::Report;
  const ErrorCode handle = CheckTwistHandle(edge, id_.value(), topology_, values_);
  if (handle != ErrorCode::kOk) return Report(why, handle);
  auto v = coord::ValidateVector(v_DHo_H, coord::ValueRole::kLinearVelocity);
  if (!v) return Report(why, v.error());
  auto w = coord::ValidateVector(w_DH_H, coord::ValueRole::kAngularVelocity);
  if (!w) return Report(why, w.error());
  return Report(why, SetTwistSample(edge, TwistNumbers{*v, *w}, stamp));
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwistSample(TwistHandle edge, const TwistNumbers& V,
                                        std::optional<Stamp> stamp) noexcept {
  if (const ErrorCode code = CheckTwistSample(edge.slot, V, stamp); code != ErrorCode::kOk)
    return code;
  StoreTwistSample(edge.slot, V, stamp);
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetAcceleration(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                         const Eigen::Vector3d& alpha_DH_H,
                                         UpdateError* why) noexcept {
  return SetAccelerationImpl(edge, a_DHo_H, alpha_DH_H, std::nullopt, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetAcceleration(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                         const Eigen::Vector3d& alpha_DH_H, Stamp stamp,
                                         UpdateError* why) noexcept {
  return SetAccelerationImpl(edge, a_DHo_H, alpha_DH_H, stamp, why);
}

// The handle, joint_edge, the stamp rule (a stamped edge takes stamped values only, and a
// stamped acceleration needs the twist sample of its stamp: stamp_mismatch), the numbers; then
// the record (timeless) or the sample's words (stamped; reserved by FindTwistEdge).
template <coord::Backend B>
ErrorCode SceneGraph<B>::SetAccelerationImpl(TwistHandle edge, const Eigen::Vector3d& a_DHo_H,
                                             const Eigen::Vector3d& alpha_DH_H,
                                             std::optional<Stamp> stamp,
                                             UpdateError* why) noexcept {
  using internal::Report;
  const ErrorCode handle = CheckTwistHandle(edge, id_.value(), topology_, values_);
  if (handle != ErrorCode::kOk) return Report(why, handle);
  if (joints_.OfChild(topology_.twist_edge(edge.slot).head) != nullptr) {
    return Report(why, ErrorCode::kJointEdge);
  }
  const TwistHistory* h = values_.history.twist_of(edge.slot.value());
  double w[6];
  if ((h != nullptr) != stamp.has_value() ||
      (h != nullptr && (!h->has_accelerations() || !h->ValueAt(stamp->nanoseconds(), w)))) {
    return Report(why, ErrorCode::kStampMismatch);
  }
  auto a = coord::ValidateVector(a_DHo_H, coord::ValueRole::kLinearAcceleration);
  if (!a) return Report(why, a.error());
  auto alpha = coord::ValidateVector(alpha_DH_H, coord::ValueRole::kAngularAcceleration);
  if (!alpha) return Report(why, alpha.error());
  const AccelerationNumbers A{*a, *alpha};
  if (h != nullptr) return Report(why, StoreSampleAcceleration(edge.slot, *stamp, A));
  values_.StoreAcceleration(edge.slot.value(), values_.V_DH[edge.slot.value()].Load(), &A);
  return Report(why, ErrorCode::kOk);
}

#define SEMGRAPH_INSTANTIATE_REALTIME(B)                                                           \
  template Expected<PoseHandle, BuildError> SceneGraph<B>::FindPoseEdge(std::string_view,          \
                                                                        std::string_view) const;   \
  template Expected<TwistHandle, BuildError> SceneGraph<B>::FindTwistEdge(std::string_view,        \
                                                                          std::string_view) const; \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Quaterniond&,                 \
                                            const Eigen::Vector3d&, UpdateError*) noexcept;        \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Matrix3d&,                    \
                                            const Eigen::Vector3d&, UpdateError*) noexcept;        \
  template ErrorCode SceneGraph<B>::SetTwist(TwistHandle, const Eigen::Vector3d&,                  \
                                             const Eigen::Vector3d&, UpdateError*) noexcept;       \
  template ErrorCode SceneGraph<B>::SetAcceleration(                                               \
      TwistHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, UpdateError*) noexcept;         \
  template ErrorCode SceneGraph<B>::SetAcceleration(                                               \
      TwistHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, Stamp, UpdateError*) noexcept;  \
  template ErrorCode SceneGraph<B>::SetAccelerationImpl(                                           \
      TwistHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, std::optional<Stamp>,           \
      UpdateError*) noexcept;                                                                      \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Quaterniond&,                 \
                                            const Eigen::Vector3d&, Stamp, UpdateError*) noexcept; \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Matrix3d&,                    \
                                            const Eigen::Vector3d&, Stamp, UpdateError*) noexcept; \
  template ErrorCode SceneGraph<B>::SetTwist(                                                      \
      TwistHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, Stamp, UpdateError*) noexcept;  \
  template ErrorCode SceneGraph<B>::SetTwistImpl(TwistHandle, const Eigen::Vector3d&,              \
                                                 const Eigen::Vector3d&, std::optional<Stamp>,     \
                                                 UpdateError*) noexcept;                           \
  template ErrorCode SceneGraph<B>::SetTwistSample(TwistHandle, const TwistNumbers&,               \
                                                   std::optional<Stamp>) noexcept;                 \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Quaterniond&,                 \
                                            const Eigen::Vector3d&, const CovarianceInput&,        \
                                            UpdateError*) noexcept;                                \
  template ErrorCode SceneGraph<B>::SetTwist(TwistHandle, const Eigen::Vector3d&,                  \
                                             const Eigen::Vector3d&, const CovarianceInput&,       \
                                             UpdateError*) noexcept;                               \
  template ErrorCode SceneGraph<B>::SetPose(PoseHandle, const Eigen::Quaterniond&,                 \
                                            const Eigen::Vector3d&, Stamp, const CovarianceInput&, \
                                            UpdateError*) noexcept;                                \
  template ErrorCode SceneGraph<B>::SetTwist(TwistHandle, const Eigen::Vector3d&,                  \
                                             const Eigen::Vector3d&, Stamp,                        \
                                             const CovarianceInput&, UpdateError*) noexcept;       \
  template ErrorCode SceneGraph<B>::SetPoseWithCovariance(                                         \
      PoseHandle, const Eigen::Quaterniond&, const Eigen::Vector3d&, std::optional<Stamp>,         \
      const CovarianceInput&, UpdateError*) noexcept;                                              \
  template ErrorCode SceneGraph<B>::SetTwistWithCovariance(                                        \
      TwistHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, std::optional<Stamp>,           \
      const CovarianceInput&, UpdateError*) noexcept;                                              \
  template ErrorCode SceneGraph<B>::SetPoseUnchecked(PoseHandle, const Eigen::Quaterniond&,        \
                                                     const Eigen::Vector3d&) noexcept;
SEMGRAPH_INSTANTIATE_REALTIME(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_REALTIME(coord::HomogeneousBackend)

}  // namespace semgraph::core
