// Wrench adds, removals and value updates (scene_graph.h "wrenches", contract: wrenches.h).
// Every check runs before the first change, so a rejected call leaves the graph as it was.
// A stamped value follows the stamp rules of every stamped value (sample_rules.h) and is
// converted at its stamp (the conversion context of time_add.cc).
#include <string>

#include "sample_rules.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/scene_graph.h"
#include "text.h"
#include "wrench_plan.h"

namespace semgraph::core {

using base::Unexpected;
using text::Reject;

namespace {

std::string WrenchAdd(const WrenchSpec& spec) {
  return "wrench on " + std::string(spec.on) + " by " + std::string(spec.by) + " at {" +
         std::string(spec.point) + "} in [" + std::string(spec.coordinate_frame) + "]";
}

std::string_view WrenchFieldName(semantics::Field f) noexcept {
  switch (f) {
    case semantics::Field::kBody:
      return "on";
    case semantics::Field::kRefBody:
      return "by";
    case semantics::Field::kPoint:
      return "point";
    default:
      return "coord";
  }
}

// The rejection of a failed resolution (wrench_plan.h) as a build error.
BuildResult RejectResolution(const topology::SceneTopology& t, const QueryError& e,
                             const WrenchSpec& spec, const std::string& what) {
  const std::string field(WrenchFieldName(e.field));
  const std::string name = e.name.is_valid() ? std::string(t.names().name(e.name)) : "";
  switch (e.code) {
    case ErrorCode::kInvalidName:
      return Reject(e.code, what, field + ": the name is missing or invalid");
    case ErrorCode::kUnknownFrame:
      return Reject(e.code, what, field + ": no frame named " + name);
    case ErrorCode::kUnknownBody:
      return Reject(
          e.code, what,
          field + ": no body named " +
              (name.empty() ? std::string(e.field == semantics::Field::kBody ? spec.on : spec.by)
                            : name));
    default:
      return Reject(e.code, what, "a body cannot exert a wrench on itself (on = by)");
  }
}

// on and by of a removal or a handle: invalid_name -> unknown_body -> self_wrench; the slot.
std::optional<QueryError> FindPair(const topology::SceneTopology& t,
                                   const internal::WrenchStore& store, std::string_view on,
                                   std::string_view by, int& slot) {
  WrenchSpec spec = WrenchSpec::On(on).By(by);
  spec.point = spec.coordinate_frame = on;  // not resolved below; valid if `on` is
  if (auto bad = internal::CheckWrenchNames(t, spec, true)) return bad;
  const NameId C = t.names().Find(on), D = t.names().Find(by);
  const BodyIndex c = t.BodyOfName(C), d = t.BodyOfName(D);
  using semantics::Field;
  if (!c.is_valid()) return internal::WrenchError(ErrorCode::kUnknownBody, Field::kBody, C);
  if (!d.is_valid()) return internal::WrenchError(ErrorCode::kUnknownBody, Field::kRefBody, D);
  if (c == d) return internal::WrenchError(ErrorCode::kSelfWrench, Field::kRefBody, D);
  slot = store.Find(c, d);
  if (slot < 0) return internal::WrenchError(ErrorCode::kNoWrench, Field::kBody, C);
  return std::nullopt;
}

BuildResult RejectPair(const topology::SceneTopology& t, const QueryError& e, std::string_view on,
                       std::string_view by, const std::string& what) {
  if (e.code != ErrorCode::kNoWrench)
    return RejectResolution(t, e, WrenchSpec::On(on).By(by), what);
  return Reject(e.code, what,
                "no wrench on " + std::string(on) + " by " + std::string(by) + " is stored");
}

// A stored sample equal to W: each vector within 1e-6 max(1, |stored|) (the twists' rule).
bool SameWrench(const double (&stored)[6], const WrenchNumbers& W) noexcept {
  const WrenchNumbers S = internal::WrenchFromWords(stored);
  return (S.f_S - W.f_S).norm() <= 1e-6 * std::max(1.0, S.f_S.norm()) &&
         (S.m_So_S - W.m_So_S).norm() <= 1e-6 * std::max(1.0, S.m_So_S.norm());
}

// The stamp rules of a value of the pair in `slot` (sample_rules.h).
ErrorCode CheckWrenchSample(const internal::WrenchStore& store, std::uint32_t slot,
                            const WrenchNumbers& W, std::optional<Stamp> stamp,
                            const TimeOptions& o) noexcept {
  return internal::CheckSample(store.history.of(slot), stamp, o, nullptr, nullptr,
                               [&](const double(&w)[6]) { return SameWrench(w, W); });
}

// The one store of a value of the pair in `slot` (after CheckWrenchSample accepted it).
void StoreWrenchSample(internal::WrenchStore& store, std::uint32_t slot, const WrenchNumbers& W,
                       std::optional<Stamp> stamp, const TimeOptions& o) noexcept {
  internal::StoreSample(
      store.values[slot], W, stamp, o.window.nanoseconds(), nullptr, nullptr,
      [&]() -> WrenchHistory& { return store.history.writable(slot); },
      [&](const double(&w)[6]) { return SameWrench(w, W); },
      [&](double(&w)[6]) { internal::WordsFromWrench(W, w); }, [] {});
}

// The message of a refused stamp rule, as DescribeSampleRejection's for edges.
std::string DescribeWrenchSampleRejection(const topology::SceneTopology& t,
                                          const internal::WrenchStore& store, std::uint32_t slot,
                                          ErrorCode code, std::optional<Stamp> stamp,
                                          const TimeOptions& o) {
  const internal::WrenchSlot& w = store.slots[slot];
  const std::string pair =
      "the wrench on " + std::string(t.body_name(w.on)) + " by " + std::string(t.body_name(w.by));
  const WrenchHistory* h = store.history.of(slot);
  const std::string range = h ? text::StampRange(h->oldest_stamp(), h->newest_stamp()) : "";
  switch (code) {
    case ErrorCode::kStampMismatch:
      return h ? pair + " is stamped (samples in " + range + "): its values need a stamp"
               : pair + " is timeless (its first value had no stamp): it takes no stamped value";
    case ErrorCode::kStampTooOld:
      return "stamp " + text::StampText(stamp->nanoseconds()) + " is older than the newest " +
             "sample of " + pair + " (" + text::StampText(h->newest_stamp()) +
             ") minus the window (" + text::StampText(o.window.nanoseconds()) + ")";
    case ErrorCode::kDuplicateStamp:
      return pair + " already has another value at " + text::StampText(stamp->nanoseconds()) +
             " (duplicate stamps are rejected by this graph's policy)";
    default:
      return std::string(base::ToString(code));
  }
}

}  // namespace

template <coord::Backend B>
BuildResult SceneGraph<B>::AddWrench(const WrenchSpec& spec, const Eigen::Vector3d& f,
                                     const Eigen::Vector3d& m) {
  return AddWrench(spec, f, m, std::nullopt);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddWrench(const WrenchSpec& spec, const Eigen::Vector3d& f,
                                     const Eigen::Vector3d& m, std::optional<Stamp> stamp) {
  const topology::SceneTopology& t = topology_;
  const auto what = [&spec] { return WrenchAdd(spec); };  // formatted only on rejection
  // invalid_name -> invalid_number -> unknown_frame -> unknown_body -> self_wrench.
  if (auto bad = internal::CheckWrenchNames(t, spec, true)) {
    return RejectResolution(t, *bad, spec, what());
  }
  auto f_ok = coord::ValidateVector(f, coord::ValueRole::kForce);
  if (!f_ok) return Reject(f_ok.error().code, what(), coord::Describe(f_ok.error(), names()));
  auto m_ok = coord::ValidateVector(m, coord::ValueRole::kMoment);
  if (!m_ok) return Reject(m_ok.error().code, what(), coord::Describe(m_ok.error(), names()));
  internal::WrenchNodes n;
  if (auto bad = internal::ResolveWrenchNodes(t, spec, n)) {
    return RejectResolution(t, *bad, spec, what());
  }
  // wrench_not_convertible: the storage frame (kept by an update) in one tree with e and [r].
  const int existing = wrenches_.Find(n.on, n.by);
  const FrameIndex s = existing >= 0 ? wrenches_.slots[static_cast<std::size_t>(existing)].frame
                                     : internal::ChooseWrenchFrame(t, n);
  if (!s.is_valid() || !t.SameTree(s, n.point) || !t.SameTree(s, n.frame)) {
    return Reject(ErrorCode::kWrenchNotConvertible, what(),
                  s.is_valid()
                      ? "the wrench is stored in " + text::Frame(t, s) +
                            ", which is not in one pose tree with {" + std::string(spec.point) +
                            "} and [" + std::string(spec.coordinate_frame) + "]"
                      : "body " + std::string(spec.on) + " has no frame in the pose " +
                            "tree of {" + std::string(spec.point) + "}");
  }
  // The stored form: (f, m) about e in [r] moved by the pose of (e,[r]) wrt (s,[s]) in [s], with
  // the poses at the stamp of a stamped value (none there: extrapolation, in the place of
  // wrench_not_convertible).
  const PoseSteps<ForestChain> steps = PlanPoseSteps(t, n.point, n.frame, s, s, s);
  WrenchNumbers W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  internal::TimeContext at_stamp = ConversionContext(stamp);
  internal::AccumulateWrench<B>(
      internal::ForestSource<B>(topology_, values_, stamp ? &at_stamp : nullptr), steps,
      WrenchNumbers{*f_ok, *m_ok}, 1.0, W.f_S, W.m_So_S);
  if (at_stamp.error() != ErrorCode::kOk) {
    return Reject(ErrorCode::kExtrapolation, what(), DescribeConversionGap(at_stamp, *stamp));
  }
  if (wrenches_.Find(n.by, n.on) >= 0) {
    return Reject(ErrorCode::kDuplicateWrench, what(),
                  "the wrench on " + std::string(spec.by) + " by " + std::string(spec.on) +
                      " is stored: this one is its reaction (update or remove that one)");
  }
  const TimeOptions& o = values_.history.options;
  if (existing >= 0) {  // an update: stamp_mismatch -> stamp_too_old -> duplicate_stamp
    const auto slot = static_cast<std::uint32_t>(existing);
    if (const ErrorCode code = CheckWrenchSample(wrenches_, slot, W, stamp, o);
        code != ErrorCode::kOk) {
      return Reject(code, what(),
                    DescribeWrenchSampleRejection(t, wrenches_, slot, code, stamp, o));
    }
    StoreWrenchSample(wrenches_, slot, W, stamp, o);
    return Ok{};
  }
  // A new pair: every allocation (the slot, a stamped pair's history), then the changes.
  HistoryTable<WrenchHistory>::Lease history;
  if (stamp) history = wrenches_.history.New(o.sample_capacity);
  const std::uint32_t slot = wrenches_.NewSlot();
  wrenches_.values[slot].Store(W);
  if (history) {
    double w[6];
    internal::WordsFromWrench(W, w);
    wrenches_.history.Install(slot, std::move(history), stamp->nanoseconds(), w);
  }
  wrenches_.slots[slot] = internal::WrenchSlot{n.on, n.by, s, true};
  ++wrenches_.num_live;
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveWrench(std::string_view on, std::string_view by) {
  int slot = -1;
  if (auto bad = FindPair(topology_, wrenches_, on, by, slot)) {
    return RejectPair(topology_, *bad, on, by,
                      "removal of the wrench on " + std::string(on) + " by " + std::string(by));
  }
  const auto i = static_cast<std::size_t>(slot);
  wrenches_.values[i].BumpEpoch();  // handles and compiled queries of it are refused from now
  wrenches_.history.Retire(i);      // after the bump (edge_history.h HistoryTable)
  wrenches_.slots[i].live = false;
  --wrenches_.num_live;
  return Ok{};
}

template <coord::Backend B>
Expected<WrenchHandle, BuildError> SceneGraph<B>::FindWrench(std::string_view on,
                                                             std::string_view by) const {
  int slot = -1;
  if (auto bad = FindPair(topology_, wrenches_, on, by, slot)) {
    return Unexpected{
        RejectPair(topology_, *bad, on, by,
                   "handle of the wrench on " + std::string(on) + " by " + std::string(by))
            .error()};
  }
  const auto i = static_cast<std::size_t>(slot);
  return WrenchHandle{static_cast<std::uint32_t>(slot), wrenches_.values[i].epoch(), id_.value(),
                      wrenches_.slots[i].frame};
}

namespace {
// SetWrench, timeless or stamped: the handle (it cannot lie: this graph's, a live slot, the
// epoch it was made at), the numbers, the stamp rules, then the one store. No allocation.
ErrorCode SetWrenchValue(internal::WrenchStore& store, std::uint32_t graph, const TimeOptions& o,
                         WrenchHandle handle, const Eigen::Vector3d& f_S,
                         const Eigen::Vector3d& m_So_S, std::optional<Stamp> stamp,
                         UpdateError* why) noexcept {
  using internal::Report;
  if (handle.graph != graph || handle.slot >= store.slots.size() ||
      !store.slots[handle.slot].live || store.values[handle.slot].epoch() != handle.epoch) {
    return Report(why, ErrorCode::kNoWrench);
  }
  auto f = coord::ValidateVector(f_S, coord::ValueRole::kForce);
  if (!f) return Report(why, f.error());
  auto m = coord::ValidateVector(m_So_S, coord::ValueRole::kMoment);
  if (!m) return Report(why, m.error());
  const WrenchNumbers W{*f, *m};
  if (const ErrorCode code = CheckWrenchSample(store, handle.slot, W, stamp, o);
      code != ErrorCode::kOk) {
    return Report(why, code);
  }
  StoreWrenchSample(store, handle.slot, W, stamp, o);
  return Report(why, ErrorCode::kOk);
}
}  // namespace

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetWrench(WrenchHandle handle, const Eigen::Vector3d& f_S,
                                   const Eigen::Vector3d& m_So_S, UpdateError* why) noexcept {
  return SetWrenchValue(wrenches_, id_.value(), values_.history.options, handle, f_S, m_So_S,
                        std::nullopt, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetWrench(WrenchHandle handle, const Eigen::Vector3d& f_S,
                                   const Eigen::Vector3d& m_So_S, Stamp stamp,
                                   UpdateError* why) noexcept {
  return SetWrenchValue(wrenches_, id_.value(), values_.history.options, handle, f_S, m_So_S, stamp,
                        why);
}

#define SEMGRAPH_INSTANTIATE_WRENCHES(B)                                                         \
  template BuildResult SceneGraph<B>::AddWrench(const WrenchSpec&, const Eigen::Vector3d&,       \
                                                const Eigen::Vector3d&);                         \
  template BuildResult SceneGraph<B>::AddWrench(const WrenchSpec&, const Eigen::Vector3d&,       \
                                                const Eigen::Vector3d&, std::optional<Stamp>);   \
  template BuildResult SceneGraph<B>::RemoveWrench(std::string_view, std::string_view);          \
  template Expected<WrenchHandle, BuildError> SceneGraph<B>::FindWrench(std::string_view,        \
                                                                        std::string_view) const; \
  template ErrorCode SceneGraph<B>::SetWrench(WrenchHandle, const Eigen::Vector3d&,              \
                                              const Eigen::Vector3d&, UpdateError*) noexcept;    \
  template ErrorCode SceneGraph<B>::SetWrench(                                                   \
      WrenchHandle, const Eigen::Vector3d&, const Eigen::Vector3d&, Stamp, UpdateError*) noexcept;
SEMGRAPH_INSTANTIATE_WRENCHES(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_WRENCHES(coord::HomogeneousBackend)

}  // namespace semgraph::core
