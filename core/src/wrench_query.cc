// Wrench queries, one-shot and compiled (scene_graph.h "wrenches"; contract: wrenches.h). Both
// plan the same terms (PlanWrenchTerms) and move them with the one wrench move
// (internal::AccumulateWrench) over the one pose evaluator (evaluate.h). At a time policy the
// stored wrenches (internal::ReadWrenchAt) and the poses moving them are read through one
// TimeContext, driven by the one policy driver (internal::RunPolicy).
#include <string>

#include "semgraph/core/scene_graph.h"
#include "text.h"
#include "time_errors.h"
#include "wrench_plan.h"

namespace semgraph::core {

using base::Unexpected;

namespace {

// The query's checks in order (invalid_name -> unknown_frame -> unknown_body -> self_wrench ->
// no_wrench -> no_pose_path), its answer's semantics, and each term's plan passed to
// on_term(const WrenchTerm<ForestChain>&) -> bool (false: stop). No allocation.
template <class OnTerm>
std::optional<QueryError> PlanWrenchTerms(const topology::SceneTopology& t,
                                          const internal::WrenchStore& store,
                                          const WrenchSpec& spec, semantics::WrenchSemantics& sem,
                                          OnTerm&& on_term) noexcept {
  if (auto bad = internal::CheckWrenchNames(t, spec, false)) return bad;
  internal::WrenchNodes n;
  if (auto bad = internal::ResolveWrenchNodes(t, spec, n)) return bad;
  std::optional<QueryError> error;
  BodyIndex other;  // the one body the terms are by, while there is one
  bool several = false;
  const std::size_t count = internal::ForEachWrenchTerm(
      store, n.on, n.by, [&](std::uint32_t slot, double sign, BodyIndex by) {
        const FrameIndex s = store.slots[slot].frame;
        if (!t.SameTree(s, n.point) || !t.SameTree(s, n.frame)) {
          QueryError e = internal::WrenchError(ErrorCode::kNoPosePath, semantics::Field::kPoint,
                                               t.frame_name_id(n.point));
          e.other = t.frame_name_id(s);
          e.asked = t.frame_name_id(n.frame);
          error = e;
          return false;
        }
        several |= other.is_valid() && other != by;
        other = by;
        internal::WrenchTerm<ForestChain> term;
        term.steps = PlanPoseSteps(t, s, s, n.point, n.frame, n.frame);
        term.value = &store.values[slot];
        term.histories = &store.history;
        term.slot = slot;
        term.epoch = store.values[slot].epoch();
        term.sign = sign;
        return on_term(term);
      });
  if (count == 0) {
    QueryError e =
        internal::WrenchError(ErrorCode::kNoWrench, semantics::Field::kBody, t.body_name_id(n.on));
    if (n.by.is_valid()) e.other = t.body_name_id(n.by);
    return e;
  }
  if (error) return error;
  sem.point = t.FrameSem(n.point).origin();
  sem.on = t.BodySem(n.on);
  sem.by = several ? semantics::Body() : t.BodySem(other);
  sem.by_several = several;
  sem.coordinate_frame = t.FrameSem(n.frame).axes();
  return std::nullopt;
}

// A failure of a stored wrench's samples (TimeFailure::wrench) as the query's error: name and
// other are the pair's bodies.
QueryError WrenchTimeError(const topology::SceneTopology& t, const internal::WrenchStore& store,
                           const internal::TimeFailure& f) noexcept {
  QueryError e;
  e.code = f.code;
  e.time.wrench = true;
  e.time.first = f.first;
  e.time.last = f.last;
  e.time.asked = f.asked;
  const internal::WrenchSlot& w = store.slots[f.index];
  e.name = t.body_name_id(w.on);
  e.other = t.body_name_id(w.by);
  return e;
}

}  // namespace

template <coord::Backend B>
QueryResult<Timed<coord::Wrench>> SceneGraph<B>::GetWrench(
    const WrenchSpec& spec, const TimePolicy& policy) const noexcept {
  Timed<coord::Wrench> out{{{}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, {}};
  coord::Wrench& W = out.value;
  // invalid_name -> invalid_number (the policy's horizon) -> the plan's other errors.
  const internal::PolicyParts parts = internal::PartsOf(policy);
  auto bad = PlanWrenchTerms(topology_, wrenches_, spec, W.semantics,
                             [](const internal::WrenchTerm<ForestChain>&) { return true; });
  if (bad && bad->code == ErrorCode::kInvalidName) return Unexpected{*bad};
  if (!parts.valid()) return Unexpected{internal::InvalidHorizon()};
  if (bad) return Unexpected{*bad};
  internal::TimeContext base;
  base.histories = &values_.history;
  base.topology = &topology_;
  internal::TimeFailure failure;
  const ErrorCode code = internal::RunPolicy(
      parts, base,
      [&](internal::TimeContext& tc) {
        const internal::ForestSource<B> src(topology_, values_, &tc);
        semantics::WrenchSemantics sem;
        W.force.setZero();
        W.moment.setZero();
        (void)PlanWrenchTerms(topology_, wrenches_, spec, sem,
                              [&](const internal::WrenchTerm<ForestChain>& term) {
                                WrenchNumbers Wn;
                                internal::ReadWrenchAt(*term.value, wrenches_.history.of(term.slot),
                                                       term.slot, &tc, Wn);
                                return internal::AccumulateWrench<B>(src, term.steps, Wn, term.sign,
                                                                     W.force, W.moment);
                              });
        return ErrorCode::kOk;
      },
      out.time, &failure);
  if (code != ErrorCode::kOk) {
    return Unexpected{failure.wrench ? WrenchTimeError(topology_, wrenches_, failure)
                                     : internal::FromFailure(topology_, failure)};
  }
  return out;
}

template <coord::Backend B>
QueryResult<coord::Wrench> SceneGraph<B>::GetWrench(const WrenchSpec& spec) const noexcept {
  coord::Wrench W{{}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  const internal::ForestSource<B> src = source();
  auto bad = PlanWrenchTerms(
      topology_, wrenches_, spec, W.semantics, [&](const internal::WrenchTerm<ForestChain>& term) {
        return internal::AccumulateWrench<B>(src, term.steps, term.value->Load(), term.sign,
                                             W.force, W.moment);
      });
  if (bad) return Unexpected{*bad};
  return W;
}

template <coord::Backend B>
Expected<CompiledWrench<B>, QueryError> SceneGraph<B>::CompileWrench(const WrenchSpec& spec) const {
  std::vector<internal::WrenchTerm<ForestChain>> terms;
  terms.reserve(wrenches_.num_live);  // so that the planner's callback does not allocate
  semantics::WrenchSemantics sem;
  auto bad = PlanWrenchTerms(topology_, wrenches_, spec, sem,
                             [&](const internal::WrenchTerm<ForestChain>& term) {
                               terms.push_back(term);
                               return true;
                             });
  if (bad) return Unexpected{*bad};
  return CompiledWrench<B>(topology_, values_, sem, terms);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const WrenchSpec& spec) const {
  const topology::SceneTopology& t = topology_;
  const auto name = [&](NameId id, std::string_view given) {
    return id.is_valid() ? std::string(t.names().name(id)) : std::string(given);
  };
  const bool by_field = e.field == semantics::Field::kRefBody;
  const std::string field = e.field == semantics::Field::kBody    ? "on"
                            : by_field                            ? "by"
                            : e.field == semantics::Field::kPoint ? "point"
                                                                  : "coord";
  std::string reason;
  switch (e.code) {
    case ErrorCode::kInvalidName:
      reason = field + ": the name is missing or invalid";
      break;
    case ErrorCode::kUnknownFrame:
      reason =
          field + ": no frame named " +
          name(e.name, e.field == semantics::Field::kPoint ? spec.point : spec.coordinate_frame);
      break;
    case ErrorCode::kUnknownBody:
      reason = field + ": no body named " + name(e.name, by_field ? spec.by : spec.on);
      break;
    case ErrorCode::kSelfWrench:
      reason = "a body cannot exert a wrench on itself (on = by = " + std::string(spec.on) + ")";
      break;
    case ErrorCode::kNoWrench:
      reason = e.other.is_valid() ? "no wrench on " + name(e.name, spec.on) + " by " +
                                        name(e.other, spec.by) + " (nor its reaction) is stored"
                                  : "no wrench on or by " + name(e.name, spec.on) + " is stored";
      break;
    case ErrorCode::kExtrapolation:
    case ErrorCode::kStale:
      if (!e.time.wrench) {
        reason = text::QueryReason(t, e, nullptr);
        break;
      }
      reason = "the wrench on " + name(e.name, spec.on) + " by " + name(e.other, spec.by) +
               (e.code == ErrorCode::kStale
                    ? " is stale: its newest sample is at " + text::StampText(e.time.last) +
                          ", older than not_before " + text::StampText(e.time.asked)
                    : " has samples in " + text::StampRange(e.time.first, e.time.last) +
                          "; asked " + text::StampText(e.time.asked));
      break;
    case ErrorCode::kNoPosePath:
      reason = "a wrench is stored in {" + name(e.other, "") + "}, which is not in one pose " +
               "tree with point {" + name(e.name, spec.point) + "} and [" +
               name(e.asked, spec.coordinate_frame) + "]";
      break;
    default:
      reason = text::QueryReason(t, e, nullptr);
  }
  return "query failed (" + std::string(base::ToString(e.code)) + "): " + reason;
}

template <coord::Backend B>
CompiledWrench<B>::CompiledWrench(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                  const semantics::WrenchSemantics& semantics,
                                  const std::vector<internal::WrenchTerm<ForestChain>>& terms)
    : CompiledQuery<B>(t, values), semantics_(semantics) {
  terms_.reserve(terms.size());
  for (const auto& term : terms) {
    terms_.push_back(Term{this->Flatten(t, term.steps), term.value, term.histories, term.slot,
                          term.epoch, term.sign});
  }
}

// A stored wrench read from its history is bracketed by two epoch checks, as a twist edge's
// (evaluate.h FlatSource::LoadTwist): removal bumps the epoch before it retires the history.
template <coord::Backend B>
bool CompiledWrench<B>::Accumulate(internal::TimeContext* tc, Eigen::Vector3d& f,
                                   Eigen::Vector3d& m) const noexcept {
  f.setZero();
  m.setZero();
  const internal::FlatSource<B> src = tc ? this->source(*tc) : this->source();
  for (const Term& term : terms_) {
    WrenchNumbers W;
    if (tc == nullptr) {
      if (!term.value->Load(W, term.epoch)) return false;
    } else {
      if (term.value->epoch() != term.epoch) return false;
      internal::ReadWrenchAt(*term.value, term.histories->of(term.slot), term.slot, tc, W);
      if (term.value->epoch() != term.epoch) return false;
    }
    if (!internal::AccumulateWrench<B>(src, term.steps, W, term.sign, f, m)) return false;
  }
  return true;
}

template <coord::Backend B>
ErrorCode CompiledWrench<B>::Evaluate(Eigen::Vector3d& f_R, Eigen::Vector3d& m_Re) const noexcept {
  Eigen::Vector3d f, m;
  if (!Accumulate(nullptr, f, m)) return ErrorCode::kQueryInvalidated;
  f_R = f;
  m_Re = m;
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode CompiledWrench<B>::Evaluate(Eigen::Vector3d& f_R, Eigen::Vector3d& m_Re,
                                      const TimePolicy& policy, TimeReport& report) const noexcept {
  const internal::PolicyParts parts = internal::PartsOf(policy);
  if (!parts.valid()) return ErrorCode::kInvalidNumber;
  internal::TimeContext base;
  base.histories = &this->values_->history;
  base.topology = this->topology_;
  Eigen::Vector3d f, m;
  const ErrorCode code = internal::RunPolicy(
      parts, base,
      [&](internal::TimeContext& tc) {
        return Accumulate(&tc, f, m) ? ErrorCode::kOk : ErrorCode::kQueryInvalidated;
      },
      report);
  if (code != ErrorCode::kOk) return code;
  f_R = f;
  m_Re = m;
  return ErrorCode::kOk;
}

template class CompiledWrench<coord::QuaternionBackend>;
template class CompiledWrench<coord::HomogeneousBackend>;

#define SEMGRAPH_INSTANTIATE_WRENCH_QUERIES(B)                                                     \
  template QueryResult<coord::Wrench> SceneGraph<B>::GetWrench(const WrenchSpec&) const noexcept;  \
  template QueryResult<Timed<coord::Wrench>> SceneGraph<B>::GetWrench(                             \
      const WrenchSpec&, const TimePolicy&) const noexcept;                                        \
  template Expected<CompiledWrench<B>, QueryError> SceneGraph<B>::CompileWrench(const WrenchSpec&) \
      const;                                                                                       \
  template std::string SceneGraph<B>::Describe(const QueryError&, const WrenchSpec&) const;
SEMGRAPH_INSTANTIATE_WRENCH_QUERIES(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_WRENCH_QUERIES(coord::HomogeneousBackend)

}  // namespace semgraph::core
