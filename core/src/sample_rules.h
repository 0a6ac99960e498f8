// Private to core/src: the stamp rules of a value update and the one store of a sample, shared
// by every stamped value (pose and twist edges: time_add.cc; stored wrenches: wrenches.cc).
//   CheckSample   stamp_mismatch -> stamp_too_old -> duplicate_stamp; changes nothing
//   StoreSample   the value (untimed) or the history and, when newest, the value; no allocation
// noexcept; costs those of SampleHistory (edge_history.h).
#pragma once

#include <optional>
#include <type_traits>

#include "covariance_input.h"
#include "semgraph/core/edge_history.h"
#include "semgraph/core/timed_read.h"

namespace semgraph::core::internal {

// The covariance stored with the sample at s equals S (null: none = zero), §2's tolerance.
template <class History>
bool SameSampleCovariance(const History& h, std::int64_t s, const coord::Covariance6* S) noexcept {
  double c[21];
  coord::Covariance6 stored = coord::Covariance6::Zero();
  if (h.CovarianceAt(s, c)) internal::CovarianceFromWords(c, stored);
  return internal::SameCovariance(stored, S);
}

// `a`: the sample's acceleration words (twist samples; null: none).
template <class History, class Same>
ErrorCode CheckSample(const History* h, std::optional<Stamp> stamp, const TimeOptions& o,
                      const coord::Covariance6* S, const double* a, Same&& same) noexcept {
  if (!stamp) return h ? ErrorCode::kStampMismatch : ErrorCode::kOk;
  if (!h) return ErrorCode::kStampMismatch;
  const std::int64_t s = stamp->nanoseconds();
  if (s < SaturatingSub(h->newest_stamp(), o.window.nanoseconds())) return ErrorCode::kStampTooOld;
  double stored[History::kValueWords];
  if (s <= h->newest_stamp() && h->ValueAt(s, stored) &&
      !(same(stored) && SameSampleCovariance(*h, s, S) && SameSampleAcceleration(*h, s, a)) &&
      o.duplicate_stamp == DuplicatePolicy::kReject) {
    return ErrorCode::kDuplicateStamp;
  }
  return ErrorCode::kOk;
}

// The one store of a sample (after CheckSample accepted it): untimed, the value; stamped, into
// the history with its covariance S and acceleration words a (the same value, covariance and
// acceleration again at a stored stamp is kept as stored), and into the value when it becomes
// the newest sample (the untimed readers' value). record() stores the edge's covariance (and
// acceleration) record, before the value (edge_values.h).
// history() makes the history writable, only when stamped. Allocation-free once the history's
// capacity (and, for S, its covariance array and the record) is reserved.
template <class Slot, class T, class History, class Same, class ToWords, class Record>
void StoreSample(Slot& value, const T& x, std::optional<Stamp> stamp, std::int64_t window,
                 const coord::Covariance6* S, const double* a, History&& history, Same&& same,
                 ToWords&& to_words, Record&& record) noexcept {
  if (!stamp) {
    record();
    value.Store(x);
    return;
  }
  auto& h = history();
  const std::int64_t s = stamp->nanoseconds();
  double w[std::remove_reference_t<decltype(h)>::kValueWords], c[21];
  if (s <= h.newest_stamp() && h.ValueAt(s, w) && same(w) && SameSampleCovariance(h, s, S) &&
      SameSampleAcceleration(h, s, a)) {
    return;  // the same value again
  }
  to_words(w);
  if (S) internal::WordsFromCovariance(*S, c);
  const bool becomes_newest = s >= h.newest_stamp();
  h.Insert(s, w, window, S ? c : nullptr, a);
  if (becomes_newest) {
    record();
    value.Store(x);
  }
}

}  // namespace semgraph::core::internal
