// Time arguments (timed.h), the TimeReport and EdgeUse classes, and the diagnostic queries
// SceneGraph.explain_pose / explain_twist. Every number comes from the core's time API.
#include "timed.h"

#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

#include "common.h"

namespace semgraph::python {

namespace {

bool IsNumpyFloating(py::handle value) {
  static py::handle floating = py::object(py::module_::import("numpy").attr("floating")).release();
  return PyObject_IsInstance(value.ptr(), floating.ptr()) == 1;
}

[[noreturn]] void ThrowBadTime(const std::string& text, bool query) {
  if (query) ThrowQuery(ErrorCode::kInvalidNumber, text, nullptr, nullptr);
  ThrowRejected(ErrorCode::kInvalidNumber, text);
}

std::string SecondsText(std::int64_t ns) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.9f s", static_cast<double>(ns) / 1e9);
  return buf;
}

std::optional<double> Seconds(const std::optional<core::Stamp>& s) {
  if (!s) return std::nullopt;
  return static_cast<double>(s->nanoseconds()) / 1e9;
}
std::optional<std::int64_t> Nanos(const std::optional<core::Stamp>& s) {
  if (!s) return std::nullopt;
  return s->nanoseconds();
}

/// One edge a query used (core::EdgeUse with its names copied: the core's are views).
struct EdgeUseObject {
  std::string kind, of, relative_to;
  bool stamped = false;
  std::optional<core::Stamp> first, last, read_from, read_to;
  bool extrapolated = false;
};

std::vector<EdgeUseObject> EdgeUses(const std::vector<core::EdgeUse>& uses) {
  std::vector<EdgeUseObject> out;
  out.reserve(uses.size());
  for (const core::EdgeUse& u : uses) {
    const char* kind = u.kind == core::EdgeUse::Kind::kPose    ? "pose"
                       : u.kind == core::EdgeUse::Kind::kTwist ? "twist"
                                                               : "pose_derivative";
    out.push_back({kind, std::string(u.of), std::string(u.relative_to), u.stamped, u.first, u.last,
                   u.read_from, u.read_to, u.extrapolated});
  }
  return out;
}

std::string RangeText(const std::optional<core::Stamp>& a, const std::optional<core::Stamp>& b) {
  if (!a) return "None";
  if (!b || *a == *b) return SecondsText(a->nanoseconds());
  return "[" + SecondsText(a->nanoseconds()) + ", " + SecondsText(b->nanoseconds()) + "]";
}

}  // namespace

std::int64_t NanosecondsArg(py::handle value, const char* function, const char* argument,
                            bool query) {
  PyObject* o = value.ptr();
  if (PyBool_Check(o)) {
    throw py::type_error(std::string(function) + "(): " + argument +
                         " must be a time: an int (nanoseconds) or a float (seconds), not bool");
  }
  if (PyFloat_Check(o) || IsNumpyFloating(value)) {
    const double s = value.cast<double>();
    auto ns = core::NanosecondsFromSeconds(s);
    if (!ns) {
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%g", s);
      ThrowBadTime(
          std::string(function) + "(): " + argument + "=" + buf +
              " s is not a time (invalid_number): seconds must be finite and within ±9.2e9",
          query);
    }
    return *ns;
  }
  if (PyIndex_Check(o)) {  // int, numpy integers
    py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(o));
    if (!index) throw py::error_already_set();
    int overflow = 0;
    const long long ns = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (overflow != 0) {
      ThrowBadTime(std::string(function) + "(): " + argument +
                       " is not a time (invalid_number): nanoseconds must fit in 64 bits",
                   query);
    }
    return ns;
  }
  throw py::type_error(std::string(function) + "(): " + argument +
                       " must be a time: an int (nanoseconds) or a float (seconds), not " +
                       TypeName(value));
}

std::optional<core::Stamp> OptionalStampArg(py::handle value, const char* function,
                                            const char* argument, bool query) {
  if (value.is_none()) return std::nullopt;
  return StampArg(value, function, argument, query);
}

TimeQuery TimeQueryArgs(const char* fn, py::handle at, py::handle max_extrapolation,
                        py::handle not_before, py::handle ref_at, py::handle fixed,
                        bool allow_travel) {
  const std::string f(fn);
  TimeQuery t;
  const std::optional<core::Stamp> nb = OptionalStampArg(not_before, fn, "not_before", true);
  enum { kNone, kLatest, kLatestCommon, kAt } mode = kNone;
  std::optional<core::Stamp> time;
  if (PyUnicode_Check(at.ptr())) {
    const std::string s = at.cast<std::string>();
    if (s == "latest") {
      mode = kLatest;
    } else if (s == "latest_common") {
      mode = kLatestCommon;
    } else {
      throw py::value_error(f + "(): at must be a time, 'latest' or 'latest_common', not '" + s +
                            "'");
    }
  } else if (!at.is_none()) {
    mode = kAt;
    time = StampArg(at, fn, "at", true);
  }
  const bool travel = !ref_at.is_none() || !fixed.is_none();
  if (travel) {
    if (!allow_travel) {
      throw py::value_error(
          f +
          "(): time travel (ref_at=, fixed=) applies to pose, position and orientation "
          "queries only");
    }
    if (ref_at.is_none() || fixed.is_none()) {
      throw py::value_error(
          f +
          "(): time travel needs both ref_at= (the reference side's time) and fixed= (the "
          "frame assumed fixed between the two times)");
    }
    if (mode != kAt)
      throw py::value_error(f + "(): time travel needs at=<time> for the point side");
  }
  if (!max_extrapolation.is_none() && mode != kAt && mode != kLatestCommon) {
    throw py::value_error(f + "(): max_extrapolation= needs at=<time> or at='latest_common'");
  }
  const core::Duration horizon = max_extrapolation.is_none()
                                     ? core::Duration{}
                                     : core::Duration::Nanoseconds(NanosecondsArg(
                                           max_extrapolation, fn, "max_extrapolation", true));
  if (travel) {
    t.kind = TimeQuery::Kind::kTravel;
    t.travel.emplace(*time, StampArg(ref_at, fn, "ref_at", true), NameArg(fixed, fn, "fixed"),
                     horizon, nb);
    return t;
  }
  if (mode == kNone && !nb) return t;
  t.kind = TimeQuery::Kind::kPolicy;
  switch (mode) {
    case kAt:
      t.policy = core::At{*time, horizon, nb};
      break;
    case kLatestCommon:
      t.policy = core::LatestCommon{horizon, nb};
      break;
    default:
      t.policy = core::Latest{nb};
      break;
  }
  return t;
}

core::TwistSource TwistSourceArg(py::handle value, const char* fn) {
  const std::string_view s = NameArg(value, fn, "source");
  if (s.empty() || s == "twists") return core::TwistSource::kTwists;
  if (s == "poses") return core::TwistSource::kPoses;
  throw py::value_error(std::string(fn) + "(): source must be 'twists' or 'poses', not '" +
                        std::string(s) + "'");
}

py::object TimeReportObject(const core::TimeReport& report) { return py::cast(report); }

std::string TimeReportText(const core::TimeReport& r) {
  auto t = [](const std::optional<core::Stamp>& s) {
    return s ? SecondsText(s->nanoseconds()) : std::string("None");
  };
  std::string out = "TimeReport(time=" + t(r.time);
  if (r.ref_time) out += ", ref_time=" + t(r.ref_time);
  return out + ", oldest=" + t(r.oldest) + ", newest=" + t(r.newest) +
         ", extrapolated=" + (r.extrapolated ? "True" : "False") + ")";
}

std::string TimeSuffix(const std::optional<core::TimeReport>& r) {
  return r ? ", time=" + TimeReportText(*r) : std::string();
}

void BindTime(py::module_& m, GraphClass& graph) {
  py::class_<core::TimeReport>(m, "TimeReport",
                               R"(What a timed query read (the `time` of its result).

time, time_ns          the time answered (at=; latest_common when a stamped edge was used), or None
ref_time, ref_time_ns  time travel: the reference side's time, or None
oldest, oldest_ns      the oldest stamp of the samples read, or None (only timeless edges read)
newest, newest_ns      the newest stamp of the samples read, or None
extrapolated           True when an edge was extrapolated (at= with max_extrapolation=)
Times are float seconds; the *_ns twins are the exact int nanoseconds.)")
      .def_property_readonly("time", [](const core::TimeReport& r) { return Seconds(r.time); })
      .def_property_readonly("time_ns", [](const core::TimeReport& r) { return Nanos(r.time); })
      .def_property_readonly("ref_time",
                             [](const core::TimeReport& r) { return Seconds(r.ref_time); })
      .def_property_readonly("ref_time_ns",
                             [](const core::TimeReport& r) { return Nanos(r.ref_time); })
      .def_property_readonly("oldest", [](const core::TimeReport& r) { return Seconds(r.oldest); })
      .def_property_readonly("oldest_ns", [](const core::TimeReport& r) { return Nanos(r.oldest); })
      .def_property_readonly("newest", [](const core::TimeReport& r) { return Seconds(r.newest); })
      .def_property_readonly("newest_ns", [](const core::TimeReport& r) { return Nanos(r.newest); })
      .def_property_readonly("extrapolated",
                             [](const core::TimeReport& r) { return r.extrapolated; })
      .def("__repr__", [](const core::TimeReport& r) { return TimeReportText(r); });

  py::class_<EdgeUseObject>(m, "EdgeUse",
                            R"(One edge a query uses (SceneGraph.explain_pose / explain_twist).

kind                 'pose' (a pose edge), 'twist' (a twist edge) or 'pose_derivative' (a pose
                     edge differentiated for source='poses')
of                   the edge's head frame
relative_to          its tail: a frame (pose edges) or a body (twist edges)
stamped              False for a timeless or constant edge
first, last          the edge's whole sample range (float seconds; None when timeless)
read_from, read_to   the samples read: one stamp (equal), or the bracket around the time
extrapolated         True when the value was extrapolated beyond the samples
The *_ns twins of the times are exact int nanoseconds.)")
      .def_readonly("kind", &EdgeUseObject::kind)
      .def_readonly("of", &EdgeUseObject::of)
      .def_readonly("relative_to", &EdgeUseObject::relative_to)
      .def_readonly("stamped", &EdgeUseObject::stamped)
      .def_readonly("extrapolated", &EdgeUseObject::extrapolated)
      .def_property_readonly("first", [](const EdgeUseObject& u) { return Seconds(u.first); })
      .def_property_readonly("first_ns", [](const EdgeUseObject& u) { return Nanos(u.first); })
      .def_property_readonly("last", [](const EdgeUseObject& u) { return Seconds(u.last); })
      .def_property_readonly("last_ns", [](const EdgeUseObject& u) { return Nanos(u.last); })
      .def_property_readonly("read_from",
                             [](const EdgeUseObject& u) { return Seconds(u.read_from); })
      .def_property_readonly("read_from_ns",
                             [](const EdgeUseObject& u) { return Nanos(u.read_from); })
      .def_property_readonly("read_to", [](const EdgeUseObject& u) { return Seconds(u.read_to); })
      .def_property_readonly("read_to_ns", [](const EdgeUseObject& u) { return Nanos(u.read_to); })
      .def("__repr__", [](const EdgeUseObject& u) {
        std::string out = "EdgeUse(" + u.kind + " " + u.relative_to + " -> {" + u.of + "}";
        if (!u.stamped) return out + ", timeless)";
        return out + ", samples=" + RangeText(u.first, u.last) +
               ", read=" + RangeText(u.read_from, u.read_to) +
               (u.extrapolated ? ", extrapolated)" : ")");
      });

  graph.def(
      "explain_pose",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before) {
        const PoseNames n = ReadPoseNames("explain_pose", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        const TimeQuery t = TimeQueryArgs("explain_pose", at, max_extrapolation, not_before,
                                          py::none(), py::none(), false);
        return b.Visit([&](const auto& g) {
          auto r = g.ExplainPose(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return EdgeUses(*r);
        });
      },
      py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),
      py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(), py::arg("point") = py::none(),
      py::arg("orientation") = py::none(), py::arg("ref_point") = py::none(),
      py::arg("ref_orientation") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
      py::arg("not_before") = py::none(),
      R"(The edges the pose query pose(...) with the same names and time keywords uses, with their
samples and the ones read (a list of EdgeUse). Works also when that query fails with
extrapolation or stale, which is when it is needed. No time keyword: as at='latest'.
QueryError: the pose query's naming errors (invalid_name, unknown_frame, no_pose_path, ...).)");
  graph.def(
      "explain_twist",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("explain_twist", point, body, ref_body, expressed_in);
        const TimeQuery t = TimeQueryArgs("explain_twist", at, max_extrapolation, not_before,
                                          py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "explain_twist");
        return b.Visit([&](const auto& g) {
          auto r = g.ExplainTwist(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return EdgeUses(*r);
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
      py::arg("not_before") = py::none(), py::arg("source") = py::none(),
      R"(The edges the twist query twist(...) with the same names, time keywords and source uses (a
list of EdgeUse): twist edges, or with source='poses' the differentiated pose edges.
QueryError: the twist query's naming errors.)");
}

}  // namespace semgraph::python
