// Queries under a time policy (docs/time.md): plan (query_plan.cc, time_plan.h) -> the policy
// (internal::RunPolicy: latest common probes, then evaluates) -> the one evaluator over a
// ForestSource that reads each edge at the policy's time. Time travel composes two evaluations
// through the fixed frame; the diagnostic call records every edge the evaluation reads.
#include <algorithm>

#include "angular_velocity.h"
#include "optimistic_read.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/time_plan.h"
#include "text.h"
#include "time_errors.h"

namespace semgraph::core {

using base::Unexpected;
using internal::FromFailure;
using internal::InvalidHorizon;
using internal::Part;
using internal::PlanOrPolicyError;
using internal::PolicyParts;
using internal::RepresentationError;
using internal::TimeContext;
using internal::TimeFailure;
using semantics::Field;

// ====================================================================== plan

Expected<PoseTwistPlan, QueryError> PlanPoseTwist(const topology::SceneTopology& t,
                                                  const TwistSpec& spec) noexcept {
  auto twist = PlanTwist(t, spec);
  if (!twist && twist.error().code != ErrorCode::kNoTwistPath) return Unexpected{twist.error()};
  PoseTwistPlan plan;
  // Every name check passed (no_twist_path is the planner's last check): resolve again.
  const FrameIndex e = t.FindFrame(spec.point), r = t.FindFrame(spec.coordinate_frame);
  const BodyIndex C = spec.body.empty() ? t.body_of(e) : t.FindBody(spec.body);
  const BodyIndex D = t.FindBody(spec.ref_body);
  plan.point = e;
  plan.frame = r;
  plan.semantics = semantics::TwistSemantics{t.FrameSem(e).origin(), t.BodySem(C), t.BodySem(D),
                                             t.FrameSem(r).axes()};
  if (C == D) return plan;  // zero; no edge used
  plan.c = t.SomeFrameOfBodyInTree(C, e);
  plan.d = t.SomeFrameOfBodyInTree(D, e);
  for (const auto& [frame, body] : {std::pair{plan.c, C}, std::pair{plan.d, D}}) {
    if (!frame.is_valid()) {
      QueryError err;
      err.code = ErrorCode::kNoPosePath;
      err.field = body == C ? Field::kBody : Field::kRefBody;
      err.name = t.frame_name_id(e);
      err.other = t.body_name_id(body);
      return Unexpected{err};
    }
  }
  return plan;
}

// ====================================================================== helpers

namespace {

// The frame a time travel's fixed frame must share a tree with: the query's reference frame.
NameId RefFrameOf(const semantics::PoseSemantics& q) { return q.ref_orientation.id(); }
NameId RefFrameOf(const semantics::PositionSemantics& q) { return q.ref_point.id(); }
NameId RefFrameOf(const semantics::OrientationSemantics& q) { return q.ref_orientation.id(); }

// A time travel's fixed frame {x} is resolved with the query's other frames (docs/time.md §4),
// in the rules' order: invalid_name (the query's names, then {x}) -> invalid_number (the
// horizon) -> unknown_frame (the query's, then {x}) -> the plan's other errors -> no_pose_path
// ({x} outside the query's tree), which comes before the caller's representation_constraint.
template <class Plan>
std::optional<QueryError> ResolveFixedFrame(const topology::SceneTopology& t,
                                            const Expected<Plan, QueryError>& plan,
                                            const TimeTravel& travel, FrameIndex& x) noexcept {
  const auto plan_fails_with = [&](ErrorCode code) { return !plan && plan.error().code == code; };
  QueryError fixed;
  fixed.time.fixed_frame = true;
  if (plan_fails_with(ErrorCode::kInvalidName)) return plan.error();
  if (!semantics::ValidateName(travel.fixed_frame)) {
    fixed.code = ErrorCode::kInvalidName;
    return fixed;
  }
  if (travel.max_extrapolation.nanoseconds() < 0) return InvalidHorizon();
  if (plan_fails_with(ErrorCode::kUnknownFrame)) return plan.error();
  x = t.FindFrame(travel.fixed_frame);
  if (!x.is_valid()) {
    fixed.code = ErrorCode::kUnknownFrame;
    fixed.name = t.names().Find(travel.fixed_frame);
    return fixed;
  }
  if (!plan) return plan.error();
  const FrameIndex b = t.FrameOfName(RefFrameOf(plan->semantics));
  if (!t.SameTree(x, b)) {
    fixed.code = ErrorCode::kNoPosePath;
    fixed.name = t.frame_name_id(x);
    fixed.other = t.frame_name_id(b);
    return fixed;
  }
  return std::nullopt;
}

// GetPose / GetPosition / GetOrientation at a policy, one body for the three parts: the plan's
// and the policy's errors, the backend's check where the part has one (not a position), then
// the evaluator under the policy: run(report, eval) calls eval(source) at the policy's time.
template <coord::Backend B, class Plan, class Run>
auto TimedAnswer(const Expected<Plan, QueryError>& plan, bool policy_valid, Run&& run) noexcept
    -> QueryResult<Timed<typename internal::PartTraits<B, internal::kPartOf<Plan>>::Result>> {
  constexpr Part P = internal::kPartOf<Plan>;
  using Result = typename internal::PartTraits<B, P>::Result;
  if (auto e = PlanOrPolicyError(plan, policy_valid)) return Unexpected{*e};
  if constexpr (P != Part::kTranslation) {
    if (auto e = RepresentationError<B>(plan->semantics)) return Unexpected{*e};
  }
  Result answer{plan->semantics, internal::PartTraits<B, P>::Initial()};
  TimeReport report;
  if (auto e = run(report, [&](const internal::ForestSource<B>& src) {
        internal::EvaluatePart<B, P>(src, plan->steps, answer.value);
      })) {
    return Unexpected{*e};
  }
  return Timed<Result>{answer, report};
}

}  // namespace

template <coord::Backend B>
auto SceneGraph<B>::AtPolicy(const TimePolicy& policy) const noexcept {
  return [this, &policy](TimeReport& report, auto&& eval) {
    return RunTimed(policy, report, nullptr, [&](TimeContext& tc) {
      eval(internal::ForestSource<B>(topology_, values_, &tc));
    });
  };
}

// ====================================================================== pose, position,
// orientation

template <coord::Backend B>
QueryResult<Timed<typename SceneGraph<B>::Pose>> SceneGraph<B>::GetPose(
    const PoseSpec& spec, const TimePolicy& policy) const noexcept {
  return internal::ReadValidated(topology_, [&] {
    return TimedAnswer<B>(PlanPose(topology_, spec), internal::PartsOf(policy).valid(),
                          AtPolicy(policy));
  });
}

template <coord::Backend B>
QueryResult<Timed<coord::Position>> SceneGraph<B>::GetPosition(
    const PoseSpec& spec, const TimePolicy& policy) const noexcept {
  return internal::ReadValidated(topology_, [&] {
    return TimedAnswer<B>(PlanPosition(topology_, spec), internal::PartsOf(policy).valid(),
                          AtPolicy(policy));
  });
}

template <coord::Backend B>
QueryResult<Timed<typename SceneGraph<B>::Orientation>> SceneGraph<B>::GetOrientation(
    const PoseSpec& spec, const TimePolicy& policy) const noexcept {
  return internal::ReadValidated(topology_, [&] {
    return TimedAnswer<B>(PlanOrientation(topology_, spec), internal::PartsOf(policy).valid(),
                          AtPolicy(policy));
  });
}

// ====================================================================== time travel

// X = PoseCoord((e,[a]), (f,[b]), [r]) with the point side at t1 and the reference side at t2,
// through {x} (resolved and checked by ResolveFixedFrame):
//   Y1 = (e,[a]) wrt {x} in [x] at t1;  Y2 = {x} wrt (f,[b]) in [b] at t2;
//   X in [b] = Y2 * Y1 (one chain composition), then [b] -> [r] with R_RB at t2.
template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::TimeTravelPose(FrameIndex e, FrameIndex a, FrameIndex f,
                                                        FrameIndex b, FrameIndex r, FrameIndex x,
                                                        const TimeTravel& travel,
                                                        typename B::PoseCoords& X,
                                                        TimeReport& report) const noexcept {
  const auto side = [&](Stamp t, const PoseSteps<ForestChain>& steps, typename B::PoseCoords& Y,
                        TimeReport& rep) -> std::optional<QueryError> {
    typename B::PoseCoords X = B::Identity();
    const TimePolicy at = At{t, travel.max_extrapolation, travel.not_before};
    if (auto err = RunTimed(at, rep, nullptr, [&](TimeContext& tc) {
          const internal::ForestSource<B> src(topology_, values_, &tc);
          internal::EvaluatePart<B, Part::kPose>(src, steps, X);
        })) {
      return err;
    }
    Y = X;
    return std::nullopt;
  };
  typename B::PoseCoords Y1, Y2;
  TimeReport r1, r2;
  if (auto err = side(travel.time, PlanPoseSteps(topology_, e, a, x, x, x), Y1, r1)) return err;
  if (auto err = side(travel.ref_time, PlanPoseSteps(topology_, x, x, f, b, b), Y2, r2)) return err;
  X = B::ComposeChain(Y1, Y2);
  if (r != b) {
    TimeReport r3;
    typename B::PoseCoords X_RB;
    const TimePolicy at = At{travel.ref_time, travel.max_extrapolation, travel.not_before};
    if (auto err = RunTimed(at, r3, nullptr, [&](TimeContext& tc) {
          internal::EvalBasic<B>(internal::ForestSource<B>(topology_, values_, &tc),
                                 PlanBasic(topology_, b, r), X_RB);
        })) {
      return err;
    }
    X = coord::kernels::Reexpress<B>(X, B::RotationOf(X_RB));
    for (const TimeReport* s : {&r3}) {
      if (s->oldest) r2.oldest = r2.oldest ? std::min(*r2.oldest, *s->oldest) : s->oldest;
      if (s->newest) r2.newest = r2.newest ? std::max(*r2.newest, *s->newest) : s->newest;
      r2.extrapolated |= s->extrapolated;
    }
  }
  report = TimeReport{};
  report.time = travel.time;
  report.ref_time = travel.ref_time;
  for (const TimeReport* s : {&r1, &r2}) {
    if (s->oldest) report.oldest = report.oldest ? std::min(*report.oldest, *s->oldest) : s->oldest;
    if (s->newest) report.newest = report.newest ? std::max(*report.newest, *s->newest) : s->newest;
    report.extrapolated |= s->extrapolated;
  }
  return std::nullopt;
}

template <coord::Backend B>
QueryResult<Timed<typename SceneGraph<B>::Pose>> SceneGraph<B>::GetPose(
    const PoseSpec& spec, const TimeTravel& travel) const noexcept {
  return internal::ReadValidated(topology_, [&]() -> QueryResult<Timed<Pose>> {
    auto plan = PlanPose(topology_, spec);
    FrameIndex x;
    if (auto e = ResolveFixedFrame(topology_, plan, travel, x)) return Unexpected{*e};
    if (auto e = RepresentationError<B>(plan->semantics)) return Unexpected{*e};
    const auto& q = plan->semantics;
    const auto F = [&](NameId id) { return topology_.FrameOfName(id); };
    Timed<Pose> out{Pose{q, {}}, {}};
    if (auto e = TimeTravelPose(F(q.point.id()), F(q.orientation.id()), F(q.ref_point.id()),
                                F(q.ref_orientation.id()), F(q.coordinate_frame.id()), x, travel,
                                out.value.value, out.time)) {
      return Unexpected{*e};
    }
    return out;
  });
}

template <coord::Backend B>
QueryResult<Timed<coord::Position>> SceneGraph<B>::GetPosition(
    const PoseSpec& spec, const TimeTravel& travel) const noexcept {
  return internal::ReadValidated(topology_, [&]() -> QueryResult<Timed<coord::Position>> {
    auto plan = PlanPosition(topology_, spec);
    FrameIndex x;
    if (auto e = ResolveFixedFrame(topology_, plan, travel, x)) return Unexpected{*e};
    const auto& q = plan->semantics;
    const FrameIndex e = topology_.FrameOfName(q.point.id()),
                     f = topology_.FrameOfName(q.ref_point.id());
    typename B::PoseCoords X;
    TimeReport report;
    const FrameIndex r = topology_.FrameOfName(q.coordinate_frame.id());
    if (auto err = TimeTravelPose(e, e, f, f, r, x, travel, X, report)) {
      return Unexpected{*err};
    }
    return Timed<coord::Position>{coord::Position{q, B::TranslationOf(X)}, report};
  });
}

template <coord::Backend B>
QueryResult<Timed<typename SceneGraph<B>::Orientation>> SceneGraph<B>::GetOrientation(
    const PoseSpec& spec, const TimeTravel& travel) const noexcept {
  return internal::ReadValidated(topology_, [&]() -> QueryResult<Timed<Orientation>> {
    auto plan = PlanOrientation(topology_, spec);
    FrameIndex x;
    if (auto e = ResolveFixedFrame(topology_, plan, travel, x)) return Unexpected{*e};
    if (auto e = RepresentationError<B>(plan->semantics)) return Unexpected{*e};
    const auto& q = plan->semantics;
    const FrameIndex a = topology_.FrameOfName(q.orientation.id()),
                     b = topology_.FrameOfName(q.ref_orientation.id());
    typename B::PoseCoords X;
    TimeReport report;
    const FrameIndex r = topology_.FrameOfName(q.coordinate_frame.id());
    if (auto err = TimeTravelPose(a, a, b, b, r, x, travel, X, report)) {
      return Unexpected{*err};
    }
    return Timed<Orientation>{Orientation{q, B::RotationOf(X)}, report};
  });
}

// ====================================================================== twists

template <coord::Backend B>
QueryResult<Timed<coord::Twist>> SceneGraph<B>::GetTwist(const TwistSpec& spec,
                                                         const TimePolicy& policy,
                                                         TwistSource source) const noexcept {
  return internal::ReadValidated(topology_,
                                 [&] { return TimedTwist(spec, policy, source, nullptr); });
}

template <coord::Backend B>
QueryResult<Timed<coord::Twist>> SceneGraph<B>::TimedTwist(
    const TwistSpec& spec, const TimePolicy& policy, TwistSource source,
    internal::EdgeRecorder* recorder) const noexcept {
  const bool valid = internal::PartsOf(policy).valid();
  // One body for both sources; they differ in the plan, its step walk and the horizon.
  const auto run = [&](const auto& plan, bool no_horizon,
                       const auto& for_each_step) -> QueryResult<Timed<coord::Twist>> {
    if (auto e = PlanOrPolicyError(plan, valid)) return Unexpected{*e};
    // Source poses: nothing extrapolated.
    const TimePolicy run_policy = no_horizon ? internal::WithoutExtrapolation(policy) : policy;
    Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    TimeReport report;
    if (auto e = RunTimed(run_policy, report, recorder, [&](TimeContext& tc) {
          const internal::ForestSource<B> src(topology_, values_, &tc);
          v.setZero();
          w.setZero();
          for_each_step(*plan, [&](const TwistStep<ForestChain>& step) {
            internal::AccumulateTwistStep<B>(src, step, v, w);
          });
        })) {
      return Unexpected{*e};
    }
    return Timed<coord::Twist>{coord::Twist{plan->semantics, v, w}, report};
  };
  if (source == TwistSource::kPoses) {
    return run(PlanPoseTwist(topology_, spec), true, [&](const auto& plan, const auto& f) {
      ForEachPoseDerivativeStep(topology_, plan, f);
    });
  }
  return run(PlanTwist(topology_, spec), false,
             [&](const auto& plan, const auto& f) { ForEachTwistStep(topology_, plan, f); });
}

template <coord::Backend B>
QueryResult<Timed<coord::LinearVelocity>> SceneGraph<B>::GetLinearVelocity(
    const TwistSpec& spec, const TimePolicy& policy, TwistSource source) const noexcept {
  auto tw = GetTwist(spec, policy, source);
  if (!tw) return Unexpected{tw.error()};
  return Timed<coord::LinearVelocity>{coord::LinearOf(tw->value), tw->time};
}

template <coord::Backend B>
QueryResult<Timed<coord::AngularVelocity>> SceneGraph<B>::GetAngularVelocity(
    const TwistSpec& spec, const TimePolicy& policy, TwistSource source) const noexcept {
  auto tw = internal::TwistOfAngularVelocity(
      spec, [&](const TwistSpec& s) { return GetTwist(s, policy, source); });
  if (!tw) return Unexpected{tw.error()};
  return Timed<coord::AngularVelocity>{coord::AngularOf(tw->value), tw->time};
}

template <coord::Backend B>
Expected<CompiledTwist<B>, QueryError> SceneGraph<B>::CompileTwist(const TwistSpec& spec,
                                                                   TwistSource source) const {
  if (source == TwistSource::kTwists) return CompileTwist(spec);
  auto plan = PlanPoseTwist(topology_, spec);
  if (!plan) return Unexpected{plan.error()};
  return CompiledTwist<B>(topology_, values_, *plan);
}

// ====================================================================== diagnostics

namespace {

class CollectingRecorder final : public internal::EdgeRecorder {
 public:
  void Record(const internal::EdgeRead& r) noexcept override {
    try {
      reads.push_back(r);
    } catch (...) {
      overflow = true;
    }
  }
  std::vector<internal::EdgeRead> reads;
  bool overflow = false;
};

template <coord::Backend B>
std::vector<EdgeUse> Summarize(const topology::SceneTopology& t,
                               const std::vector<internal::EdgeRead>& reads) {
  std::vector<EdgeUse> out;
  std::vector<std::pair<int, std::uint32_t>> keys;
  for (const internal::EdgeRead& r : reads) {
    const std::pair<int, std::uint32_t> key{static_cast<int>(r.kind), r.index};
    auto it = std::find(keys.begin(), keys.end(), key);
    EdgeUse* use;
    if (it == keys.end()) {
      keys.push_back(key);
      out.emplace_back();
      use = &out.back();
      use->kind = static_cast<EdgeUse::Kind>(r.kind);
      if (r.kind == internal::EdgeRead::Kind::kTwist) {
        const auto& e = t.twist_edge(TwistEdgeIndex(r.index));
        use->of = t.frame_name(e.head);
        use->relative_to = t.body_name(e.tail);
      } else {
        use->of = t.frame_name(FrameIndex(r.index));
        use->relative_to = t.frame_name(t.pose_parent(FrameIndex(r.index)));
      }
      use->stamped = r.stamped;
      if (r.stamped) {
        use->first = Stamp::Nanoseconds(r.first);
        use->last = Stamp::Nanoseconds(r.last);
      }
    } else {
      use = &out[static_cast<std::size_t>(it - keys.begin())];
    }
    if (r.has_read) {
      use->read_from = use->read_from ? std::min(*use->read_from, Stamp::Nanoseconds(r.read_from))
                                      : Stamp::Nanoseconds(r.read_from);
      use->read_to = use->read_to ? std::max(*use->read_to, Stamp::Nanoseconds(r.read_to))
                                  : Stamp::Nanoseconds(r.read_to);
    }
    use->extrapolated |= r.extrapolated;
  }
  return out;
}

}  // namespace

template <coord::Backend B>
Expected<std::vector<EdgeUse>, QueryError> SceneGraph<B>::ExplainPose(
    const PoseSpec& spec, const TimePolicy& policy) const {
  auto plan = PlanPose(topology_, spec);
  if (auto e = PlanOrPolicyError(plan, internal::PartsOf(policy).valid())) return Unexpected{*e};
  CollectingRecorder recorder;
  typename B::PoseCoords X = B::Identity();
  TimeReport report;
  // The edges are listed even when the query fails at its time: what failed is what the user
  // asks about.
  (void)RunTimed(policy, report, &recorder, [&](TimeContext& tc) {
    const internal::ForestSource<B> src(topology_, values_, &tc);
    internal::EvaluatePart<B, Part::kPose>(src, plan->steps, X);
  });
  return Summarize<B>(topology_, recorder.reads);
}

template <coord::Backend B>
Expected<std::vector<EdgeUse>, QueryError> SceneGraph<B>::ExplainTwist(const TwistSpec& spec,
                                                                       const TimePolicy& policy,
                                                                       TwistSource source) const {
  CollectingRecorder recorder;
  auto tw = TimedTwist(spec, policy, source, &recorder);
  if (!tw &&
      (tw.error().code != ErrorCode::kExtrapolation && tw.error().code != ErrorCode::kStale)) {
    return Unexpected{tw.error()};
  }
  return Summarize<B>(topology_, recorder.reads);
}

// ====================================================================== Jacobian at a time

// The Jacobian's poses (and the joints' twist edges it checks) read at the policy's time, by the
// one evaluator of GetJacobian (joints.cc).
template <coord::Backend B>
Expected<Timed<Jacobian>, QueryError> SceneGraph<B>::GetJacobian(const TwistSpec& spec,
                                                                 const TimePolicy& policy) const {
  auto plan = PlanJacobian(spec);
  if (auto e = PlanOrPolicyError(plan, internal::PartsOf(policy).valid())) return Unexpected{*e};
  Timed<Jacobian> out;
  out.value.semantics = plan->twist.semantics;
  out.value.joints = plan->columns;
  out.value.J.setZero(6, static_cast<Eigen::Index>(plan->columns.size()));
  if (auto e = RunTimed(policy, out.time, nullptr, [&](TimeContext& tc) {
        internal::EvaluateJacobian<B>(internal::ForestSource<B>(topology_, values_, &tc),
                                      plan->change_point, plan->er, plan->e_chained, plan->e_rest,
                                      plan->steps, out.value.J);
      })) {
    return Unexpected{*e};
  }
  return out;
}

// AtPolicy too: its return type is deduced, so without this a build that does not inline it
// (Debug) finds no definition (SceneGraph<B> is an extern template in the other units).
#define SEMGRAPH_INSTANTIATE_TIME_QUERY(B)                                                        \
  template auto SceneGraph<B>::AtPolicy(const TimePolicy&) const noexcept;                        \
  template std::optional<QueryError> SceneGraph<B>::TimeTravelPose(                               \
      FrameIndex, FrameIndex, FrameIndex, FrameIndex, FrameIndex, FrameIndex, const TimeTravel&,  \
      typename B::PoseCoords&, TimeReport&) const noexcept;                                       \
  template QueryResult<Timed<coord::Twist>> SceneGraph<B>::TimedTwist(                            \
      const TwistSpec&, const TimePolicy&, TwistSource, internal::EdgeRecorder*) const noexcept;  \
  template QueryResult<Timed<SceneGraph<B>::Pose>> SceneGraph<B>::GetPose(                        \
      const PoseSpec&, const TimePolicy&) const noexcept;                                         \
  template QueryResult<Timed<coord::Position>> SceneGraph<B>::GetPosition(                        \
      const PoseSpec&, const TimePolicy&) const noexcept;                                         \
  template QueryResult<Timed<SceneGraph<B>::Orientation>> SceneGraph<B>::GetOrientation(          \
      const PoseSpec&, const TimePolicy&) const noexcept;                                         \
  template QueryResult<Timed<SceneGraph<B>::Pose>> SceneGraph<B>::GetPose(                        \
      const PoseSpec&, const TimeTravel&) const noexcept;                                         \
  template QueryResult<Timed<coord::Position>> SceneGraph<B>::GetPosition(                        \
      const PoseSpec&, const TimeTravel&) const noexcept;                                         \
  template QueryResult<Timed<SceneGraph<B>::Orientation>> SceneGraph<B>::GetOrientation(          \
      const PoseSpec&, const TimeTravel&) const noexcept;                                         \
  template QueryResult<Timed<coord::Twist>> SceneGraph<B>::GetTwist(                              \
      const TwistSpec&, const TimePolicy&, TwistSource) const noexcept;                           \
  template QueryResult<Timed<coord::LinearVelocity>> SceneGraph<B>::GetLinearVelocity(            \
      const TwistSpec&, const TimePolicy&, TwistSource) const noexcept;                           \
  template QueryResult<Timed<coord::AngularVelocity>> SceneGraph<B>::GetAngularVelocity(          \
      const TwistSpec&, const TimePolicy&, TwistSource) const noexcept;                           \
  template Expected<CompiledTwist<B>, QueryError> SceneGraph<B>::CompileTwist(const TwistSpec&,   \
                                                                              TwistSource) const; \
  template Expected<std::vector<EdgeUse>, QueryError> SceneGraph<B>::ExplainPose(                 \
      const PoseSpec&, const TimePolicy&) const;                                                  \
  template Expected<std::vector<EdgeUse>, QueryError> SceneGraph<B>::ExplainTwist(                \
      const TwistSpec&, const TimePolicy&, TwistSource) const;                                    \
  template Expected<Timed<Jacobian>, QueryError> SceneGraph<B>::GetJacobian(                      \
      const TwistSpec&, const TimePolicy&) const;
SEMGRAPH_INSTANTIATE_TIME_QUERY(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_TIME_QUERY(coord::HomogeneousBackend)

}  // namespace semgraph::core
