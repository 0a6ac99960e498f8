// Queries with the covariance of their answer under a time policy or a time travel
// (docs/uncertainty.md, "Time"): the timed query's answer and report (time_query.cc), then the
// one propagation of propagate.h over the same frames, run by the same driver (RunTimed) at
// the time the answer was read, each edge read with its covariance at that time
// (timed_covariance.h). A time travel: the point side at its time (in the fixed frame), the
// reference side at its own with the point side attached rigidly to the fixed frame; the two
// independent, summed.
#include "angular_velocity.h"
#include "optimistic_read.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/timed_covariance.h"
#include "time_errors.h"

namespace semgraph::core {

using base::Unexpected;

namespace {

// The policy that reads at the time the answer was read at: latest common's resolved time.
TimePolicy SameTime(const TimePolicy& policy, const TimeReport& report) noexcept {
  if (const auto* c = std::get_if<LatestCommon>(&policy); c != nullptr && report.time) {
    return At{*report.time, c->max_extrapolation, c->not_before};
  }
  return policy;
}

// f() (an optional error) on a validated snapshot of the topology (optimistic_read.h): the
// propagation walks the pose tree, which a writer may be changing.
template <class F>
std::optional<QueryError> Validated(const topology::SceneTopology& t, F&& f) noexcept {
  const auto r = internal::ReadValidated(t, [&]() -> Expected<base::Ok, QueryError> {
    if (auto e = f()) return Unexpected{*e};
    return base::Ok{};
  });
  if (!r) return r.error();
  return std::nullopt;
}

template <class Q>
void FramesOf(const topology::SceneTopology& t, const Q& q, FrameIndex (&k)[5]) noexcept {
  const auto F = [&](NameId id) { return t.FrameOfName(id); };
  k[0] = F(q.point.id());
  k[1] = F(q.orientation.id());
  k[2] = F(q.ref_point.id());
  k[3] = F(q.ref_orientation.id());
  k[4] = F(q.coordinate_frame.id());
}
// A position (an orientation) names one frame per side: it fills both roles of FramesOf above.
void FramesOf(const topology::SceneTopology& t, const semantics::PositionSemantics& q,
              FrameIndex (&k)[5]) noexcept {
  k[0] = k[1] = t.FrameOfName(q.point.id());
  k[2] = k[3] = t.FrameOfName(q.ref_point.id());
  k[4] = t.FrameOfName(q.coordinate_frame.id());
}
void FramesOf(const topology::SceneTopology& t, const semantics::OrientationSemantics& q,
              FrameIndex (&k)[5]) noexcept {
  k[0] = k[1] = t.FrameOfName(q.orientation.id());
  k[2] = k[3] = t.FrameOfName(q.ref_orientation.id());
  k[4] = t.FrameOfName(q.coordinate_frame.id());
}

}  // namespace

// PoseCovariance at the context's time; when an edge was extrapolated, with its Jacobians keyed
// so that an edge shared by an integration twist and the query is perturbed once
// (timed_covariance.h KeyedSink).
template <coord::Backend B>
void KeyedPoseCovariance(const topology::SceneTopology& t, const EdgeValues<B>& v,
                         internal::TimeContext& tc, bool extrapolated, const FrameIndex (&k)[5],
                         Covariance6& S, const internal::Rigid* attached = nullptr) noexcept {
  if (!extrapolated) {
    internal::PoseCovariance<B>(t, k, internal::TimedPoseCovarianceReader(v, tc), S, attached);
    return;
  }
  internal::SharedPerturbations acc;
  internal::KeyedSink<B> sink{&v, &tc, &acc};
  internal::PoseCovariance<B>(t, k, internal::TimedPoseCovarianceReader(v, tc), S, attached, sink);
}

template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::TimedPoseCovariance(const FrameIndex (&k)[5],
                                                             const TimePolicy& policy,
                                                             Covariance6& S,
                                                             bool extrapolated) const noexcept {
  return Validated(topology_, [&] {
    TimeReport report;
    return RunTimed(policy, report, nullptr, [&](internal::TimeContext& tc) {
      KeyedPoseCovariance<B>(topology_, values_, tc, extrapolated, k, S);
    });
  });
}

// k = {e, a, f, b, r}; x the fixed frame. Side 1 at time: (e,[a]) wrt (x,[x]) in [x], value Y1
// and covariance S1; side 2 at ref_time: the answer with e and [a] attached to {x} at Y1
// (covariance S2, in [r]), and R_RX to carry S1 into [r].
template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::TimeTravelCovariance(const FrameIndex (&k)[5],
                                                              FrameIndex x,
                                                              const TimeTravel& travel,
                                                              Covariance6& S) const noexcept {
  return Validated(topology_, [&] { return TimeTravelCovarianceOnce(k, x, travel, S); });
}

template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::TimeTravelCovarianceOnce(const FrameIndex (&k)[5],
                                                                  FrameIndex x,
                                                                  const TimeTravel& travel,
                                                                  Covariance6& S) const noexcept {
  const TimePolicy at1 = At{travel.time, travel.max_extrapolation, travel.not_before};
  const TimePolicy at2 = At{travel.ref_time, travel.max_extrapolation, travel.not_before};
  const FrameIndex k1[5] = {k[0], k[1], x, x, x};
  const PoseSteps<ForestChain> steps1 = PlanPoseSteps(topology_, k[0], k[1], x, x, x);
  typename B::PoseCoords Y1 = B::Identity(), X_RX = B::Identity();
  Covariance6 S1, S2;
  TimeReport report;
  if (auto e = RunTimed(at1, report, nullptr, [&](internal::TimeContext& tc) {
        const internal::ForestSource<B> src(topology_, values_, &tc);
        internal::EvaluatePart<B, internal::Part::kPose>(src, steps1, Y1);
        KeyedPoseCovariance<B>(topology_, values_, tc, true, k1, S1);
      })) {
    return e;
  }
  const internal::Rigid off = internal::ToRigid<B>(Y1), none;
  const internal::Rigid attached[5] = {off, off, none, none, none};
  const FrameIndex k2[5] = {x, x, k[2], k[3], k[4]};
  if (auto e = RunTimed(at2, report, nullptr, [&](internal::TimeContext& tc) {
        const internal::ForestSource<B> src(topology_, values_, &tc);
        internal::EvalBasic<B>(src, PlanBasic(topology_, x, k[4]), X_RX);
        KeyedPoseCovariance<B>(topology_, values_, tc, true, k2, S2, attached);
      })) {
    return e;
  }
  S = coord::jacobians::RotateRows(B::ToMatrix(B::RotationOf(X_RX)), S1) + S2;
  return std::nullopt;
}

// ---------------------------------------------------------------- pose, position, orientation

template <coord::Backend B>
QueryResult<Timed<WithCovariance<typename SceneGraph<B>::Pose, 6>>>
SceneGraph<B>::GetPoseWithCovariance(const PoseSpec& spec, const TimePolicy& policy,
                                     CovarianceOrder order) const noexcept {
  auto answer = GetPose(spec, policy);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Timed<WithCovariance<Pose, 6>> out{{answer->value, Covariance6::Zero()}, answer->time};
  if (auto e = TimedPoseCovariance(k, SameTime(policy, answer->time), out.value.covariance,
                                   answer->time.extrapolated)) {
    return Unexpected{*e};
  }
  out.value.covariance = coord::Reorder(out.value.covariance, order);
  return out;
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<coord::Position, 3>>> SceneGraph<B>::GetPositionWithCovariance(
    const PoseSpec& spec, const TimePolicy& policy) const noexcept {
  auto answer = GetPosition(spec, policy);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Covariance6 S;
  if (auto err =
          TimedPoseCovariance(k, SameTime(policy, answer->time), S, answer->time.extrapolated)) {
    return Unexpected{*err};
  }
  return Timed<WithCovariance<coord::Position, 3>>{{answer->value, S.topLeftCorner<3, 3>()},
                                                   answer->time};
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<typename SceneGraph<B>::Orientation, 3>>>
SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec& spec,
                                            const TimePolicy& policy) const noexcept {
  auto answer = GetOrientation(spec, policy);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Covariance6 S;
  if (auto err =
          TimedPoseCovariance(k, SameTime(policy, answer->time), S, answer->time.extrapolated)) {
    return Unexpected{*err};
  }
  return Timed<WithCovariance<Orientation, 3>>{{answer->value, S.bottomRightCorner<3, 3>()},
                                               answer->time};
}

// ---------------------------------------------------------------- time travel

template <coord::Backend B>
QueryResult<Timed<WithCovariance<typename SceneGraph<B>::Pose, 6>>>
SceneGraph<B>::GetPoseWithCovariance(const PoseSpec& spec, const TimeTravel& travel,
                                     CovarianceOrder order) const noexcept {
  auto answer = GetPose(spec, travel);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Timed<WithCovariance<Pose, 6>> out{{answer->value, Covariance6::Zero()}, answer->time};
  const FrameIndex x = topology_.FindFrame(travel.fixed_frame);
  if (auto e = TimeTravelCovariance(k, x, travel, out.value.covariance)) return Unexpected{*e};
  out.value.covariance = coord::Reorder(out.value.covariance, order);
  return out;
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<coord::Position, 3>>> SceneGraph<B>::GetPositionWithCovariance(
    const PoseSpec& spec, const TimeTravel& travel) const noexcept {
  auto answer = GetPosition(spec, travel);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Covariance6 S;
  if (auto err = TimeTravelCovariance(k, topology_.FindFrame(travel.fixed_frame), travel, S)) {
    return Unexpected{*err};
  }
  return Timed<WithCovariance<coord::Position, 3>>{{answer->value, S.topLeftCorner<3, 3>()},
                                                   answer->time};
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<typename SceneGraph<B>::Orientation, 3>>>
SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec& spec,
                                            const TimeTravel& travel) const noexcept {
  auto answer = GetOrientation(spec, travel);
  if (!answer) return Unexpected{answer.error()};
  FrameIndex k[5];
  FramesOf(topology_, answer->value.semantics, k);
  Covariance6 S;
  if (auto err = TimeTravelCovariance(k, topology_.FindFrame(travel.fixed_frame), travel, S)) {
    return Unexpected{*err};
  }
  return Timed<WithCovariance<Orientation, 3>>{{answer->value, S.bottomRightCorner<3, 3>()},
                                               answer->time};
}

// ---------------------------------------------------------------- twists

// Source poses: the twist query's own plan (PlanPoseTwist), every edge read with no horizon
// (WithoutExtrapolation, as the plain query), each derivative with its samples' covariances.
template <coord::Backend B>
QueryResult<Timed<WithCovariance<coord::Twist, 6>>> SceneGraph<B>::GetTwistWithCovariance(
    const TwistSpec& spec, const TimePolicy& policy, CovarianceOrder order,
    TwistSource source) const noexcept {
  auto answer = GetTwist(spec, policy, source);
  if (!answer) return Unexpected{answer.error()};
  Timed<WithCovariance<coord::Twist, 6>> out{{answer->value, Covariance6::Zero()}, answer->time};
  Covariance6& S = out.value.covariance;
  const TimePolicy at = SameTime(policy, answer->time);
  if (auto e = Validated(topology_, [&]() -> std::optional<QueryError> {
        TimeReport report;
        if (source == TwistSource::kPoses) {
          auto plan = PlanPoseTwist(topology_, spec);  // planned by the query above
          if (!plan) return plan.error();
          return RunTimed(internal::WithoutExtrapolation(at), report, nullptr,
                          [&](internal::TimeContext& tc) {
                            internal::PoseTwistCovariance<B>(
                                topology_, *plan, internal::TimedPoseCovarianceReader(values_, tc),
                                internal::TimedDerivativeCovarianceReader(values_, tc), S);
                          });
        }
        auto plan = PlanTwist(topology_, spec);  // planned by the query above
        if (!plan) return plan.error();
        return RunTimed(at, report, nullptr, [&](internal::TimeContext& tc) {
          const auto read_pose = internal::TimedPoseCovarianceReader(values_, tc);
          const auto read_twist = internal::TimedTwistCovarianceReader(values_, tc);
          if (!answer->time.extrapolated) {
            internal::TwistCovariance<B>(topology_, *plan, read_pose, read_twist, S);
            return;
          }
          // An edge shared by an integration twist and the query: perturbed once.
          internal::SharedPerturbations acc;
          internal::KeyedSink<B> sink{&values_, &tc, &acc};
          internal::TwistCovariance<B>(topology_, *plan, read_pose, read_twist, S, sink);
        });
      })) {
    return Unexpected{*e};
  }
  S = coord::Reorder(S, order);
  return out;
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<coord::LinearVelocity, 3>>>
SceneGraph<B>::GetLinearVelocityWithCovariance(const TwistSpec& spec, const TimePolicy& policy,
                                               TwistSource source) const noexcept {
  auto tw = GetTwistWithCovariance(spec, policy, CovarianceOrder::kLinearAngular, source);
  if (!tw) return Unexpected{tw.error()};
  return Timed<WithCovariance<coord::LinearVelocity, 3>>{
      {coord::LinearOf(tw->value.value), tw->value.covariance.template topLeftCorner<3, 3>()},
      tw->time};
}

template <coord::Backend B>
QueryResult<Timed<WithCovariance<coord::AngularVelocity, 3>>>
SceneGraph<B>::GetAngularVelocityWithCovariance(const TwistSpec& spec, const TimePolicy& policy,
                                                TwistSource source) const noexcept {
  auto tw = internal::TwistOfAngularVelocity(spec, [&](const TwistSpec& s) {
    return GetTwistWithCovariance(s, policy, CovarianceOrder::kLinearAngular, source);
  });
  if (!tw) return Unexpected{tw.error()};
  return Timed<WithCovariance<coord::AngularVelocity, 3>>{
      {coord::AngularOf(tw->value.value), tw->value.covariance.template bottomRightCorner<3, 3>()},
      tw->time};
}

#define SEMGRAPH_INSTANTIATE_TIME_UNCERTAINTY(B)                                                   \
  template std::optional<QueryError> SceneGraph<B>::TimedPoseCovariance(                           \
      const FrameIndex(&)[5], const TimePolicy&, Covariance6&, bool) const noexcept;               \
  template std::optional<QueryError> SceneGraph<B>::TimeTravelCovariance(                          \
      const FrameIndex(&)[5], FrameIndex, const TimeTravel&, Covariance6&) const noexcept;         \
  template std::optional<QueryError> SceneGraph<B>::TimeTravelCovarianceOnce(                      \
      const FrameIndex(&)[5], FrameIndex, const TimeTravel&, Covariance6&) const noexcept;         \
  template QueryResult<Timed<WithCovariance<SceneGraph<B>::Pose, 6>>>                              \
  SceneGraph<B>::GetPoseWithCovariance(const PoseSpec&, const TimePolicy&, CovarianceOrder)        \
      const noexcept;                                                                              \
  template QueryResult<Timed<WithCovariance<coord::Position, 3>>>                                  \
  SceneGraph<B>::GetPositionWithCovariance(const PoseSpec&, const TimePolicy&) const noexcept;     \
  template QueryResult<Timed<WithCovariance<SceneGraph<B>::Orientation, 3>>>                       \
  SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec&, const TimePolicy&) const noexcept;  \
  template QueryResult<Timed<WithCovariance<SceneGraph<B>::Pose, 6>>>                              \
  SceneGraph<B>::GetPoseWithCovariance(const PoseSpec&, const TimeTravel&, CovarianceOrder)        \
      const noexcept;                                                                              \
  template QueryResult<Timed<WithCovariance<coord::Position, 3>>>                                  \
  SceneGraph<B>::GetPositionWithCovariance(const PoseSpec&, const TimeTravel&) const noexcept;     \
  template QueryResult<Timed<WithCovariance<SceneGraph<B>::Orientation, 3>>>                       \
  SceneGraph<B>::GetOrientationWithCovariance(const PoseSpec&, const TimeTravel&) const noexcept;  \
  template QueryResult<Timed<WithCovariance<coord::Twist, 6>>>                                     \
  SceneGraph<B>::GetTwistWithCovariance(const TwistSpec&, const TimePolicy&, CovarianceOrder,      \
                                        TwistSource) const noexcept;                               \
  template QueryResult<Timed<WithCovariance<coord::LinearVelocity, 3>>>                            \
  SceneGraph<B>::GetLinearVelocityWithCovariance(const TwistSpec&, const TimePolicy&, TwistSource) \
      const noexcept;                                                                              \
  template QueryResult<Timed<WithCovariance<coord::AngularVelocity, 3>>>                           \
  SceneGraph<B>::GetAngularVelocityWithCovariance(const TwistSpec&, const TimePolicy&,             \
                                                  TwistSource) const noexcept;
SEMGRAPH_INSTANTIATE_TIME_UNCERTAINTY(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_TIME_UNCERTAINTY(coord::HomogeneousBackend)

}  // namespace semgraph::core
