// File: python/src/timed.h
//
// Time arguments from Python (docs/python.md, "Time"). One rule for every time argument
// (stamp=, at=, ref_at=, not_before=, max_extrapolation=, window=): an int (Python int or a
// numpy integer) is integer nanoseconds, exactly; a float (Python float or a numpy floating)
// is seconds, rounded once to the nearest nanosecond by the core (StampFromSeconds). bool is
// refused (TypeError), so is anything else. A float that is not finite or beyond ±9.2e9 s, or
// an int beyond int64, is the core's invalid_number (RejectedError for adds, QueryError for
// queries, as the C++ API reports it).
//
// A query's policy comes from its keywords:
//   (none)                         the untimed query (each edge's current value; no report)
//   at="latest"  | not_before=t    Latest{not_before}
//   at=t [, max_extrapolation=h]   At{t, h, not_before}
//   at="latest_common" [, max_extrapolation=h]   LatestCommon{h, not_before}
//   at=t, ref_at=t2, fixed="f"     TimeTravel{t, t2, "f", h, not_before} (pose kinds only)
// Cost: O(1); no allocation.
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <string_view>

#include "semgraph/core/time.h"

namespace semgraph::python {

namespace py = pybind11;

/// Nanoseconds of a time argument (the rule above); `query` picks the exception class of an
/// out-of-range value.
std::int64_t NanosecondsArg(py::handle value, const char* function, const char* argument,
                            bool query);
inline core::Stamp StampArg(py::handle value, const char* function, const char* argument,
                            bool query) {
  return core::Stamp::Nanoseconds(NanosecondsArg(value, function, argument, query));
}
/// None -> nullopt, else StampArg.
std::optional<core::Stamp> OptionalStampArg(py::handle value, const char* function,
                                            const char* argument, bool query);

/// The time policy a query's keywords ask for (see the file comment). `fixed` is a view into
/// the Python string, valid while the argument lives.
struct TimeQuery {
  enum class Kind : std::uint8_t { kNone, kPolicy, kTravel };
  Kind kind = Kind::kNone;
  core::TimePolicy policy = core::Latest{};
  std::optional<core::TimeTravel> travel;
};
TimeQuery TimeQueryArgs(const char* function, py::handle at, py::handle max_extrapolation,
                        py::handle not_before, py::handle ref_at, py::handle fixed,
                        bool allow_travel);

/// source=: None / 'twists' -> kTwists, 'poses' -> kPoses.
core::TwistSource TwistSourceArg(py::handle value, const char* function);

/// A Python TimeReport object (the class registered by BindTime).
py::object TimeReportObject(const core::TimeReport& report);
/// "TimeReport(time=0.450000000 s, oldest=..., newest=..., extrapolated=False)".
std::string TimeReportText(const core::TimeReport& report);
/// ", time=TimeReport(...)" for a result's repr, or "" for an untimed result.
std::string TimeSuffix(const std::optional<core::TimeReport>& report);

}  // namespace semgraph::python
