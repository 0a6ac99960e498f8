// SceneGraph.add_wrench, remove_wrench, wrench, force, moment and num_wrenches, and the Wrench
// result class (wrenches.h).
#include "wrenches.h"

#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "common.h"

namespace semgraph::python {

namespace {

/// The answer of a wrench query: WrenchCoord(e|C, D or several, [r]).
struct WrenchResult {
  GraphPtr graph;
  semantics::WrenchSemantics semantics;
  Eigen::Vector3d f;
  Eigen::Vector3d m;
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

WrenchResult Query(const GraphBox& b, const char* fn, py::handle on, py::handle by,
                   py::handle point, py::handle expressed_in) {
  const core::WrenchSpec spec = ReadWrenchSpec(fn, on, by, point, expressed_in);
  GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
  return b.Visit([&](const auto& g) {
    auto r = g.GetWrench(spec);
    if (!r) {
      const char* argument = WrenchArgument(r.error());
      ThrowQuery(r.error().code, g.Describe(r.error(), spec),
                 argument ? RoleName(r.error().field) : nullptr, argument);
    }
    return WrenchResult{self, r->semantics, r->force, r->moment};
  });
}

void AddWrench(GraphBox& b, py::handle on, py::handle by, py::handle point, py::handle expressed_in,
               py::handle force, py::handle moment) {
  const core::WrenchSpec spec = ReadWrenchSpec("add_wrench", on, by, point, expressed_in);
  const Eigen::Vector3d f = Vector3Arg(force, "add_wrench", "force");
  const Eigen::Vector3d m = Vector3Arg(moment, "add_wrench", "moment");
  std::lock_guard<WriterMutex> lock(b.writer);
  Check(b.Visit([&](auto& g) { return g.AddWrench(spec, f, m); }));
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
none on or by C), no_pose_path (e, [r] and a stored wrench not in one pose tree).)";

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
      .def("__repr__", [](const WrenchResult& r) {
        return "Wrench(" + SemanticsText(r.graph, r.semantics) + ", force=" + VectorText(r.f) +
               ", moment=" + VectorText(r.m) + ")";
      });
}

void BindWrenches(GraphClass& graph) {
  graph.def_property_readonly(
      "num_wrenches",
      [](const GraphBox& b) { return b.Visit([](const auto& g) { return g.num_wrenches(); }); },
      "The number of stored wrenches.");
  graph.def("add_wrench", &AddWrench, py::kw_only(), py::arg("on") = py::none(),
            py::arg("by") = py::none(), py::arg("point") = py::none(),
            py::arg("expressed_in") = py::none(), py::arg("force") = py::none(),
            py::arg("moment") = py::none(),
            R"(Adds the wrench exerted on body `on` by body `by` (WrenchCoord(point|on, by,
[expressed_in])), or updates the stored wrench of that pair. At most one wrench is stored per
ordered pair, at the origin of a frame s of `on` in [s] (the point's frame when it is a frame of
`on`); a value given elsewhere is converted once with the current poses.
force   f, in [expressed_in]; default zero
moment  m, about the origin of `point`, in [expressed_in]; default zero
expressed_in defaults to `point`. Frames and bodies are not created by a wrench.
RejectedError (code), graph unchanged: invalid_name, invalid_number, unknown_frame (point, then
expressed_in), unknown_body (on, then by), self_wrench (on == by), wrench_not_convertible (no
pose path between the point, the frame and a frame of `on`), duplicate_wrench (the wrench on
`by` by `on` is stored: this one is its reaction).)");
  graph.def("remove_wrench", &RemoveWrench, py::kw_only(), py::arg("on"), py::arg("by"),
            "Removes the wrench on body `on` by body `by`. RejectedError: invalid_name, "
            "unknown_body, self_wrench, no_wrench.");
  graph.def(
      "wrench",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point,
         py::handle expressed_in) { return Query(b, "wrench", on, by, point, expressed_in); },
      py::kw_only(), py::arg("on") = py::none(), py::arg("by") = py::none(),
      py::arg("point") = py::none(), py::arg("expressed_in") = py::none(),
      (std::string("The wrench on `on` by `by` (or its reaction, when the wrench on `by` by `on` "
                   "is stored), or the net wrench on `on`, about `point`, in `expressed_in` (a "
                   "Wrench).\n") +
       kQueryDoc)
          .c_str());
  graph.def(
      "force",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point,
         py::handle expressed_in) {
        return VectorArray(Query(b, "force", on, by, point, expressed_in).f);
      },
      py::kw_only(), py::arg("on") = py::none(), py::arg("by") = py::none(),
      py::arg("point") = py::none(), py::arg("expressed_in") = py::none(),
      (std::string("The force of wrench(): a numpy array of 3.\n") + kQueryDoc).c_str());
  graph.def(
      "moment",
      [](const GraphBox& b, py::handle on, py::handle by, py::handle point,
         py::handle expressed_in) {
        return VectorArray(Query(b, "moment", on, by, point, expressed_in).m);
      },
      py::kw_only(), py::arg("on") = py::none(), py::arg("by") = py::none(),
      py::arg("point") = py::none(), py::arg("expressed_in") = py::none(),
      (std::string("The moment of wrench() about `point`: a numpy array of 3.\n") + kQueryDoc)
          .c_str());
}

}  // namespace semgraph::python
