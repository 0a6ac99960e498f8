// Queries with the covariance of their answer (docs/uncertainty.md §3): the plain query's
// answer (scene_graph.cc: the one evaluator), then the one propagation of propagate.h over the
// same plan's frames, each edge read with its covariance (EdgeValues::LoadPose / LoadTwist).
#include <utility>

#include "angular_velocity.h"
#include "semgraph/core/propagate.h"
#include "semgraph/core/scene_graph.h"
#include "time_errors.h"

namespace semgraph::core {

using base::Unexpected;

namespace {

// Readers of the untimed values with their covariances.
template <coord::Backend B>
auto PoseReader(const EdgeValues<B>& v) noexcept {
  return [&v](FrameIndex g, typename B::PoseCoords& X, coord::Covariance6& S) {
    v.LoadPose(g.value(), X, S);
  };
}
template <coord::Backend B>
auto TwistReader(const EdgeValues<B>& v) noexcept {
  return [&v](TwistEdgeIndex e, TwistNumbers& V, coord::Covariance6& S) {
    v.LoadTwist(e.value(), V, S);
  };
}

}  // namespace

template <coord::Backend B>
QueryResult<WithCovariance<typename SceneGraph<B>::Pose, 6>> SceneGraph<B>::GetPoseWithCovariance(
    const PoseSpec& spec, CovarianceOrder order) const noexcept {
  auto answer = GetPose(spec);
  if (!answer) return Unexpected{answer.error()};
  const topology::SceneTopology& t = topology_;
  const semantics::PoseSemantics& q = answer->semantics;
  const FrameIndex k[5] = {t.FrameOfName(q.point.id()), t.FrameOfName(q.orientation.id()),
                           t.FrameOfName(q.ref_point.id()), t.FrameOfName(q.ref_orientation.id()),
                           t.FrameOfName(q.coordinate_frame.id())};
  WithCovariance<Pose, 6> out{*answer, Covariance6::Zero()};
  internal::PoseCovariance<B>(t, k, PoseReader(values_), out.covariance);
  out.covariance = coord::Reorder(out.covariance, order);
  return out;
}

template <coord::Backend B>
QueryResult<WithCovariance<coord::Position, 3>> SceneGraph<B>::GetPositionWithCovariance(
    const PoseSpec& spec) const noexcept {
  auto answer = GetPosition(spec);
  if (!answer) return Unexpected{answer.error()};
  const topology::SceneTopology& t = topology_;
  const semantics::PositionSemantics& q = answer->semantics;
  const FrameIndex e = t.FrameOfName(q.point.id()), f = t.FrameOfName(q.ref_point.id());
  const FrameIndex k[5] = {e, e, f, f, t.FrameOfName(q.coordinate_frame.id())};
  Covariance6 S;
  internal::PoseCovariance<B>(t, k, PoseReader(values_), S);
  return WithCovariance<coord::Position, 3>{*answer, S.topLeftCorner<3, 3>()};
}

template <coord::Backend B>
QueryResult<WithCovariance<typename SceneGraph<B>::Orientation, 3>>
SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec& spec) const noexcept {
  auto answer = GetOrientation(spec);
  if (!answer) return Unexpected{answer.error()};
  const topology::SceneTopology& t = topology_;
  const semantics::OrientationSemantics& q = answer->semantics;
  const FrameIndex a = t.FrameOfName(q.orientation.id());
  const FrameIndex b = t.FrameOfName(q.ref_orientation.id());
  const FrameIndex k[5] = {a, a, b, b, t.FrameOfName(q.coordinate_frame.id())};
  Covariance6 S;
  internal::PoseCovariance<B>(t, k, PoseReader(values_), S);
  return WithCovariance<Orientation, 3>{*answer, S.bottomRightCorner<3, 3>()};
}

template <coord::Backend B>
QueryResult<WithCovariance<coord::Twist, 6>> SceneGraph<B>::GetTwistWithCovariance(
    const TwistSpec& spec, CovarianceOrder order) const noexcept {
  auto plan = PlanTwist(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  auto answer = GetTwist(plan->semantics);
  if (!answer) return Unexpected{answer.error()};
  WithCovariance<coord::Twist, 6> out{*answer, Covariance6::Zero()};
  internal::TwistCovariance<B>(topology_, *plan, PoseReader(values_), TwistReader(values_),
                               out.covariance);
  out.covariance = coord::Reorder(out.covariance, order);
  return out;
}

template <coord::Backend B>
QueryResult<WithCovariance<coord::LinearVelocity, 3>>
SceneGraph<B>::GetLinearVelocityWithCovariance(const TwistSpec& spec) const noexcept {
  auto tw = GetTwistWithCovariance(spec);
  if (!tw) return Unexpected{tw.error()};
  return WithCovariance<coord::LinearVelocity, 3>{coord::LinearOf(tw->value),
                                                  tw->covariance.template topLeftCorner<3, 3>()};
}

template <coord::Backend B>
QueryResult<WithCovariance<coord::AngularVelocity, 3>>
SceneGraph<B>::GetAngularVelocityWithCovariance(const TwistSpec& spec) const noexcept {
  auto tw = internal::TwistOfAngularVelocity(
      spec, [this](const TwistSpec& s) { return GetTwistWithCovariance(s); });
  if (!tw) return Unexpected{tw.error()};
  return WithCovariance<coord::AngularVelocity, 3>{
      coord::AngularOf(tw->value), tw->covariance.template bottomRightCorner<3, 3>()};
}

template <coord::Backend B>
Expected<CompiledPoseWithCovariance<B>, QueryError> SceneGraph<B>::CompilePoseWithCovariance(
    const PoseSpec& spec) const {
  auto plan = PlanPose(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  if (auto e = internal::RepresentationError<B>(plan->semantics)) return Unexpected{*e};
  const topology::SceneTopology& t = topology_;
  const semantics::PoseSemantics& q = plan->semantics;
  const FrameIndex k[5] = {t.FrameOfName(q.point.id()), t.FrameOfName(q.orientation.id()),
                           t.FrameOfName(q.ref_point.id()), t.FrameOfName(q.ref_orientation.id()),
                           t.FrameOfName(q.coordinate_frame.id())};
  return CompiledPoseWithCovariance<B>(t, values_, q, k);
}

template <coord::Backend B>
Expected<CompiledPositionWithCovariance<B>, QueryError>
SceneGraph<B>::CompilePositionWithCovariance(const PoseSpec& spec) const {
  auto plan = PlanPosition(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  const topology::SceneTopology& t = topology_;
  const semantics::PositionSemantics& q = plan->semantics;
  const FrameIndex e = t.FrameOfName(q.point.id()), f = t.FrameOfName(q.ref_point.id());
  const FrameIndex k[5] = {e, e, f, f, t.FrameOfName(q.coordinate_frame.id())};
  // The pose of {e} wrt {f} in [r], whose translation and linear block are the answer.
  const semantics::PoseSemantics s{
      q.point,           semantics::OrientationFrame(q.point.id()),     q.body,
      q.ref_point,       semantics::OrientationFrame(q.ref_point.id()), q.ref_body,
      q.coordinate_frame};
  return CompiledPositionWithCovariance<B>(q, CompiledPoseWithCovariance<B>(t, values_, s, k));
}

template <coord::Backend B>
Expected<CompiledOrientationWithCovariance<B>, QueryError>
SceneGraph<B>::CompileOrientationWithCovariance(const PoseSpec& spec) const {
  auto plan = PlanOrientation(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  if (auto e = internal::RepresentationError<B>(plan->semantics)) return Unexpected{*e};
  const topology::SceneTopology& t = topology_;
  const semantics::OrientationSemantics& q = plan->semantics;
  const FrameIndex a = t.FrameOfName(q.orientation.id());
  const FrameIndex b = t.FrameOfName(q.ref_orientation.id());
  const FrameIndex k[5] = {a, a, b, b, t.FrameOfName(q.coordinate_frame.id())};
  // The pose of {a} wrt {b} in [r], whose rotation and angular block are the answer.
  const semantics::PoseSemantics s{semantics::Point(q.orientation.id()),
                                   q.orientation,
                                   q.body,
                                   semantics::Point(q.ref_orientation.id()),
                                   q.ref_orientation,
                                   q.ref_body,
                                   q.coordinate_frame};
  return CompiledOrientationWithCovariance<B>(q, CompiledPoseWithCovariance<B>(t, values_, s, k));
}

template <coord::Backend B>
Covariance6 SceneGraph<B>::pose_covariance(FrameIndex f) const noexcept {
  if (!f.is_valid() || f.value() >= values_.X_PF.size()) return Covariance6::Zero();
  return values_.PoseCovarianceOf(f.value());
}

template <coord::Backend B>
Covariance6 SceneGraph<B>::twist_covariance(FrameIndex f) const noexcept {
  if (!f.is_valid() || f.value() >= values_.X_PF.size()) return Covariance6::Zero();
  const TwistEdgeIndex e = topology_.twist_edge_of(f);
  return e.is_valid() ? values_.TwistCovarianceOf(e.value()) : Covariance6::Zero();
}

template <coord::Backend B>
Expected<CompiledTwistWithCovariance<B>, QueryError> SceneGraph<B>::CompileTwistWithCovariance(
    const TwistSpec& spec) const {
  auto plan = PlanTwist(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  return CompiledTwistWithCovariance<B>(topology_, values_, *plan);
}

template <coord::Backend B>
Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>
SceneGraph<B>::CompileLinearVelocityWithCovariance(const TwistSpec& spec) const {
  auto twist = CompileTwistWithCovariance(spec);
  if (!twist) return Unexpected{twist.error()};
  return CompiledLinearVelocityWithCovariance<B>(std::move(*twist));
}

template <coord::Backend B>
Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>
SceneGraph<B>::CompileAngularVelocityWithCovariance(const TwistSpec& spec) const {
  auto twist = internal::TwistOfAngularVelocity(
      spec, [this](const TwistSpec& s) { return CompileTwistWithCovariance(s); });
  if (!twist) return Unexpected{twist.error()};
  return CompiledAngularVelocityWithCovariance<B>(std::move(*twist));
}

template <coord::Backend B>
Expected<CompiledTwistWithCovariance<B>, QueryError> SceneGraph<B>::CompileTwistWithCovariance(
    const TwistSpec& spec, TwistSource source) const {
  if (source == TwistSource::kTwists) return CompileTwistWithCovariance(spec);
  auto plan = PlanPoseTwist(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  return CompiledTwistWithCovariance<B>(topology_, values_, *plan);
}

template <coord::Backend B>
Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>
SceneGraph<B>::CompileLinearVelocityWithCovariance(const TwistSpec& spec,
                                                   TwistSource source) const {
  auto twist = CompileTwistWithCovariance(spec, source);
  if (!twist) return Unexpected{twist.error()};
  return CompiledLinearVelocityWithCovariance<B>(std::move(*twist));
}

template <coord::Backend B>
Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>
SceneGraph<B>::CompileAngularVelocityWithCovariance(const TwistSpec& spec,
                                                    TwistSource source) const {
  auto twist = internal::TwistOfAngularVelocity(
      spec, [this, source](const TwistSpec& s) { return CompileTwistWithCovariance(s, source); });
  if (!twist) return Unexpected{twist.error()};
  return CompiledAngularVelocityWithCovariance<B>(std::move(*twist));
}

#define SEMGRAPH_INSTANTIATE_UNCERTAINTY(B)                                                    \
  template QueryResult<WithCovariance<SceneGraph<B>::Pose, 6>>                                 \
  SceneGraph<B>::GetPoseWithCovariance(const PoseSpec&, CovarianceOrder) const noexcept;       \
  template QueryResult<WithCovariance<coord::Position, 3>>                                     \
  SceneGraph<B>::GetPositionWithCovariance(const PoseSpec&) const noexcept;                    \
  template QueryResult<WithCovariance<SceneGraph<B>::Orientation, 3>>                          \
  SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec&) const noexcept;                 \
  template QueryResult<WithCovariance<coord::Twist, 6>> SceneGraph<B>::GetTwistWithCovariance( \
      const TwistSpec&, CovarianceOrder) const noexcept;                                       \
  template QueryResult<WithCovariance<coord::LinearVelocity, 3>>                               \
  SceneGraph<B>::GetLinearVelocityWithCovariance(const TwistSpec&) const noexcept;             \
  template QueryResult<WithCovariance<coord::AngularVelocity, 3>>                              \
  SceneGraph<B>::GetAngularVelocityWithCovariance(const TwistSpec&) const noexcept;            \
  template Expected<CompiledPoseWithCovariance<B>, QueryError>                                 \
  SceneGraph<B>::CompilePoseWithCovariance(const PoseSpec&) const;                             \
  template Expected<CompiledTwistWithCovariance<B>, QueryError>                                \
  SceneGraph<B>::CompileTwistWithCovariance(const TwistSpec&) const;                           \
  template Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>                       \
  SceneGraph<B>::CompileLinearVelocityWithCovariance(const TwistSpec&) const;                  \
  template Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>                      \
  SceneGraph<B>::CompileAngularVelocityWithCovariance(const TwistSpec&) const;                 \
  template Expected<CompiledTwistWithCovariance<B>, QueryError>                                \
  SceneGraph<B>::CompileTwistWithCovariance(const TwistSpec&, TwistSource) const;              \
  template Expected<CompiledLinearVelocityWithCovariance<B>, QueryError>                       \
  SceneGraph<B>::CompileLinearVelocityWithCovariance(const TwistSpec&, TwistSource) const;     \
  template Expected<CompiledAngularVelocityWithCovariance<B>, QueryError>                      \
  SceneGraph<B>::CompileAngularVelocityWithCovariance(const TwistSpec&, TwistSource) const;    \
  template Expected<CompiledPositionWithCovariance<B>, QueryError>                             \
  SceneGraph<B>::CompilePositionWithCovariance(const PoseSpec&) const;                         \
  template Expected<CompiledOrientationWithCovariance<B>, QueryError>                          \
  SceneGraph<B>::CompileOrientationWithCovariance(const PoseSpec&) const;                      \
  template Covariance6 SceneGraph<B>::pose_covariance(FrameIndex) const noexcept;              \
  template Covariance6 SceneGraph<B>::twist_covariance(FrameIndex) const noexcept;
SEMGRAPH_INSTANTIATE_UNCERTAINTY(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_UNCERTAINTY(coord::HomogeneousBackend)

}  // namespace semgraph::core
