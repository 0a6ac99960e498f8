// SceneGraph.add_wrench, remove_wrench, wrench, force, moment and num_wrenches, and the Wrench
// result class (wrenches.h).
#include "wrenches.h"

#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "common.h"
#include "timed.h"

namespace semgraph::python {

namespace {

/// The answer of a wrench query: WrenchCoord(e|C, D or several, [r]).
struct WrenchResult {
  GraphPtr graph;
  semantics::WrenchSemantics semantics;
  Eigen::Vector3d f;
  Eigen::Vector3d m;
  std::optional<core::TimeReport> time = std::nullopt;
};

/// The names of a wrench as the keywords gave them. expressed_in defaults to the point's frame.
core::WrenchSpec ReadWrenchSpec(const char* fn, py::handle on, py::handle by, py::handle point,
                                py::handle expressed_in) {
  core::WrenchSpec spec = core::WrenchSpec::On(NameArg(on, fn, "on"))
                              .By(NameArg(by, fn, "by"))
                              .At(NameArg(point, fn, "point"));
  const std::string_view r = NameArg(expressed_in, fn, "expressed_in");
  if (!r.empty()) spec.ExpressedIn(r);
  return spec;
}

/// The keyword at fault in a wrench query's error (Describe's words: on, by, point, coordinate
/// frame).
const char* WrenchArgument(const core::QueryError& e) {
  if (!FieldApplies(e.code)) return nullptr;
  switch (e.field) {
    case Field::kBody:
      return "on";
    case Field::kRefBody:
      return "by";
    case Field::kPoint:
      return "point";
    default:
      return "expressed_in";
  }
}

template <class G>
[[noreturn]] void ThrowWrenchQuery(const G& g, const core::QueryError& e,
                                   const core::WrenchSpec& spec) {
  const char* argument = WrenchArgument(e);
  ThrowQuery(e.code, g.Describe(e, spec), argument ? RoleName(e.field) : nullptr, argument);
}

// A wrench query, under a time policy when a time keyword is given (the twist queries' rules).
WrenchResult Query(const GraphBox& b, const char* fn, py::handle on, py::handle by,
                   py::handle point, py::handle expressed_in, py::handle at,
                   py::handle max_extrapolation, py::handle not_before) {
  const core::WrenchSpec spec = ReadWrenchSpec(fn, on, by, point, expressed_in);
  const TimeQuery t =
      TimeQueryArgs(fn, at, max_extrapolation, not_before, py::none(), py::none(), false);
  GraphPtr self = Self(b);
  return b.Visit([&](const auto& g) {
    if (t.kind == TimeQuery::Kind::kNone) {
      auto r = g.GetWrench(spec);
      if (!r) ThrowWrenchQuery(g, r.error(), spec);
      return WrenchResult{self, r->semantics, r->force, r->moment};
    }
    auto r = g.GetWrench(spec, t.policy);
    if (!r) ThrowWrenchQuery(g, r.error(), spec);
    return WrenchResult{self, r->value.semantics, r->value.force, r->value.moment, r->time};
  });
}

void AddWrench(GraphBox& b, py::handle on, py::handle by, py::handle point, py::handle expressed_in,
               py::handle force, py::handle moment, py::handle stamp) {
  const core::WrenchSpec spec = ReadWrenchSpec("add_wrench", on, by, point, expressed_in);
  const Eigen::Vector3d f = Vector3Arg(force, "add_wrench", "force");
  const Eigen::Vector3d m = Vector3Arg(moment, "add_wrench", "moment");
  const std::optional<core::Stamp> s = OptionalStampArg(stamp, "add_wrench", "stamp", false);
  std::lock_guard<WriterMutex> lock(b.writer);
  Check(b.Visit([&](auto& g) { return g.AddWrench(spec, f, m, s); }));
}

void RemoveWrench(GraphBox& b, py::handle on, py::handle by) {
  const std::string_view o = NameArg(on, "remove_wrench", "on");
  const std::string_view d = NameArg(by, "remove_wrench", "by");
  std::lock_guard<WriterMutex> lock(b.writer);
  Check(b.Visit([&](auto& g) { return g.RemoveWrench(o, d); }));
  ++b.topology_generation;
}

constexpr const char* kQueryDoc = R"(
on            the body C the wrench acts on
by            the body D that exerts it; None (default): the net wrench on C, the sum of every
              stored wrench on C and of the reaction of every stored wrench by C
point         the frame e whose origin the moment is taken about
expressed_in  the coordinate frame [r] (default: point)
QueryError (code, and .argument: the keyword at fault where there is one): invalid_name,
unknown_frame, unknown_body, self_wrench (by == on), no_wrench (none stored for the pair, or
none on or by C), no_pose_path (e, [r] and a stored wrench not in one pose tree); with a time:
invalid_number (a negative horizon), extrapolation, stale (of a pose edge or of a stamped
wrench, named in the message).
Time (docs/time.md; times are int nanoseconds or float seconds; none given: each wrench's and
edge's current value, and .time is None):
  at                 a time: every stamped wrench and edge at that time (a wrench's samples
                     interpolated linearly); 'latest': each one's newest sample;
                     'latest_common': at the newest time all stamped ones used have
  max_extrapolation  with at=<time>: how far beyond its samples a wrench (held) or an edge may
                     be read; default 0, never
  not_before         any policy: a wrench or edge whose newest sample is older fails with stale)";

}  // namespace

void BindWrenchResult(py::module_& m) {
  py::class_<WrenchResult>(m, "Wrench",
                           R"(The result of a wrench query: WrenchCoord(e|C, D, [r]).

force      f: the force on body C by body D (or by several bodies: a net wrench), in [r]
moment     m: its moment about the origin of e, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("force", [](const WrenchResult& r) { return VectorArray(r.f); })
      .def_property_readonly("moment", [](const WrenchResult& r) { return VectorArray(r.m); })
      .def_property_readonly(
          "semantics", [](const WrenchResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const WrenchResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const WrenchResult& r) {
        return "Wrench(" + SemanticsText(r.graph, r.semantics) + ", force=" + VectorText(r.f) +
               ", moment=" + VectorText(r.m) + TimeSuffix(r.time) + ")";
      });
}

#define SEMGRAPH_WRENCH_ARGS                                                            \
  py::kw_only(), py::arg("on") = py::none(), py::arg("by") = py::none(),                \
                 py::arg("point") = py::none(), py::arg("expressed_in") = py::none(),   \
                 py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
                 py::arg("not_before") = py::none()

void BindWrenches(GraphClass& graph) {
  graph.def_property_readonly(
      "num_wrenches",
      [](const GraphBox& b) { return b.Visit([](const auto& g) { return g.num_wrenches(); }); },
      "The number of stored wrenches.");
  graph.def("add_wrench", &AddWrench, py::kw_only(), py::arg("on") = py::none(),
            py::arg("by") = py::none(), py::arg("point") = py::none(),
            py::arg("expressed_in") = py::none(), py::arg("force") = py::none(),
            py::arg("moment") = py::none(), py::arg("stamp") = py::none(),
            R"(Adds the wrench exerted on body `on` by body `by` (WrenchCoord(point|on, by,
[expressed_in])), or updates the stored wrench of that pair. At most one wrench is stored per
ordered pair, at the origin of a frame s of `on` in [s] (the point's frame when it is a frame of
`on`); a value given elsewhere is converted once with the current poses.
force   f, in [expressed_in]; default zero
moment  m, about the origin of `point`, in [expressed_in]; default zero
stamp   None (default): a timeless value; a time (int nanoseconds or float seconds): a sample
        at that time, converted with the poses at that time; the pair's first value decides
        whether it is stamped
expressed_in defaults to `point`. Frames and bodies are not created by a wrench.
RejectedError (code), graph unchanged: invalid_name, invalid_number, unknown_frame (point, then
expressed_in), unknown_body (on, then by), self_wrench (on == by), wrench_not_convertible (no
pose path between the point, the frame and a frame of `on`), extrapolation (a stamped value
whose conversion finds no poses at its stamp), duplicate_wrench (the wrench on `by` by `on` is
stored: this one is its reaction), stamp_mismatch (a stamped value for a timeless pair or the
reverse), stamp_too_old, duplicate_stamp.)");
  graph.def("remove_wrench", &RemoveWrench, py::kw_only(), py::arg("on"), py::arg("by"),
            "Removes the wrench on body `on` by body `by`. RejectedError: invalid_name, "
            "unknown_body, self_wrench, no_wrench.");
  graph.def(
      "wrench",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before) {
        return Query(b, "wrench", on, by, point, expressed_in, at, max_extrapolation, not_before);
      },
      SEMGRAPH_WRENCH_ARGS,
      (std::string("The wrench on `on` by `by` (or its reaction, when the wrench on `by` by `on` "
                   "is stored), or the net wrench on `on`, about `point`, in `expressed_in` (a "
                   "Wrench).\n") +
       kQueryDoc)
          .c_str());
  graph.def(
      "force",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before) {
        return VectorArray(
            Query(b, "force", on, by, point, expressed_in, at, max_extrapolation, not_before).f);
      },
      SEMGRAPH_WRENCH_ARGS,
      (std::string("The force of wrench(): a numpy array of 3.\n") + kQueryDoc).c_str());
  graph.def(
      "moment",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before) {
        return VectorArray(
            Query(b, "moment", on, by, point, expressed_in, at, max_extrapolation, not_before).m);
      },
      SEMGRAPH_WRENCH_ARGS,
      (std::string("The moment of wrench() about `point`: a numpy array of 3.\n") + kQueryDoc)
          .c_str());
}

}  // namespace semgraph::python
