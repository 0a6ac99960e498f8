// RepairPolicy and RepairReport (docs/repair.md): the core's structs, exposed as they are. The
// repair itself is the core's (SceneGraph::AddPose / AddTwist with a RepairPolicy).
#include <pybind11/pybind11.h>

#include <string>

#include "common.h"

namespace semgraph::python {

std::optional<core::RepairPolicy> RepairArg(py::handle repair, const char* fn) {
  if (repair.is_none()) return std::nullopt;
  if (PyBool_Check(repair.ptr())) {
    if (repair.ptr() == Py_True) return core::RepairPolicy{};
    return std::nullopt;
  }
  if (py::isinstance<core::RepairPolicy>(repair)) return repair.cast<core::RepairPolicy>();
  throw py::type_error(std::string(fn) + "(): repair must be a bool or a RepairPolicy, not " +
                       TypeName(repair));
}

namespace {
std::string Number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", x);
  return buf;
}
}  // namespace

void BindRepair(py::module_& m) {
  py::class_<core::RepairPolicy>(
      m, "RepairPolicy",
      R"(How add_pose / add_twist(..., repair=) repairs a rejected relation (docs/repair.md).

invert              P1 multiple_pose_parents / W1 multiple_twist_parents: add the inverse
                    relation instead [True]
reroot              the inverse's head has a pose parent too: re-root its tree first [True]
check_consistency   an already determined relation (pose_cycle, P1 within one tree,
                    duplicate_twist_path): accept it as a no-op when it equals the value the
                    graph derives within the tolerances, else refuse it with the discrepancy [True]
position_tolerance  m (m/s for twists) [1e-9]
angle_tolerance     rad (rad/s for twists) [1e-9]
Each strategy is tried only for the rule it answers; others keep their error.)")
      .def(py::init([](bool invert, bool reroot, bool check_consistency, double position_tolerance,
                       double angle_tolerance) {
             return core::RepairPolicy{invert, reroot, check_consistency, position_tolerance,
                                       angle_tolerance};
           }),
           py::kw_only(), py::arg("invert") = true, py::arg("reroot") = true,
           py::arg("check_consistency") = true, py::arg("position_tolerance") = 1e-9,
           py::arg("angle_tolerance") = 1e-9)
      .def_readwrite("invert", &core::RepairPolicy::invert)
      .def_readwrite("reroot", &core::RepairPolicy::reroot)
      .def_readwrite("check_consistency", &core::RepairPolicy::check_consistency)
      .def_readwrite("position_tolerance", &core::RepairPolicy::position_tolerance)
      .def_readwrite("angle_tolerance", &core::RepairPolicy::angle_tolerance)
      .def("__repr__", [](const core::RepairPolicy& p) {
        auto b = [](bool x) { return x ? std::string("True") : std::string("False"); };
        return "RepairPolicy(invert=" + b(p.invert) + ", reroot=" + b(p.reroot) +
               ", check_consistency=" + b(p.check_consistency) +
               ", position_tolerance=" + Number(p.position_tolerance) +
               ", angle_tolerance=" + Number(p.angle_tolerance) + ")";
      });
  py::class_<core::RepairReport>(m, "RepairReport",
                                 R"(What add_pose / add_twist(..., repair=) did (its return value).

applied         'none' (accepted as given), 'inverted' (the inverse relation was added),
                'rerooted' (a tree was re-rooted, then the inverse added), 'consistent' (already
                determined and equal within the tolerances: nothing added)
change          the relation actually added, or why it was a no-op
reversed_edges  'rerooted': the number of pose edges reversed (their handles and the compiled
                queries reading them are invalidated)
discrepancy     'consistent': (position, angle), the measured difference; None otherwise)")
      .def_property_readonly(
          "applied", [](const core::RepairReport& r) { return std::string(ToString(r.applied)); })
      .def_readonly("change", &core::RepairReport::change)
      .def_readonly("reversed_edges", &core::RepairReport::reversed_edges)
      .def_property_readonly("discrepancy",
                             [](const core::RepairReport& r) -> py::object {
                               if (r.applied != core::RepairKind::kConsistent) return py::none();
                               return py::make_tuple(r.discrepancy.position, r.discrepancy.angle);
                             })
      .def("__repr__", [](const core::RepairReport& r) {
        std::string out = "RepairReport(applied='" + std::string(ToString(r.applied)) + "'";
        if (!r.change.empty()) out += ", change='" + r.change + "'";
        if (r.applied == core::RepairKind::kRerooted)
          out += ", reversed_edges=" + std::to_string(r.reversed_edges);
        if (r.applied == core::RepairKind::kConsistent) {
          out += ", discrepancy=(" + Number(r.discrepancy.position) + ", " +
                 Number(r.discrepancy.angle) + ")";
        }
        return out + ")";
      });
}

}  // namespace semgraph::python
