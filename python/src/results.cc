// The query results Pose, Position, Orientation, Twist, LinearVelocity, AngularVelocity: core
// values kept as they are and turned into numpy arrays when a property is read.
#include <pybind11/stl.h>

#include <string>

#include "common.h"
#include "timed.h"

namespace semgraph::python {

Eigen::Quaterniond CanonicalQuaternion(Eigen::Quaterniond q) noexcept {
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  for (double x : c) {
    if (x != 0.0) {
      if (x < 0.0) q.coeffs() = -q.coeffs();
      break;
    }
  }
  return q;
}

namespace {

void BindPoseResults(py::module_& m) {
  py::class_<PoseResult>(m, "Pose",
                         R"(The result of a pose query: PoseCoord((e,[a])|C, (f,[b])|D, [r]).

position         p: position of the point e relative to the reference point f, in [r]
quaternion       (w, x, y, z), w >= 0: the orientation of [a] relative to [b] as an operator
                 expressed in [r] (when [r] = [b]: the rotation R_ba, columns = axes of [a] in [b])
rotation_matrix  the same rotation as a 3x3 matrix
matrix           the 4x4 homogeneous matrix [R p; 0 0 0 1]
semantics        the relation in the paper's notation, e.g. 'PoseCoord({f1}|O1, {o2}|O2, [o2])')")
      .def_property_readonly("position", [](const PoseResult& r) { return VectorArray(r.p); })
      .def_property_readonly("quaternion", [](const PoseResult& r) { return QuaternionArray(r.q); })
      .def_property_readonly("rotation_matrix",
                             [](const PoseResult& r) { return MatrixArray(r.q); })
      .def_property_readonly("matrix",
                             [](const PoseResult& r) { return HomogeneousArray(r.q, r.p); })
      .def_property_readonly(
          "semantics", [](const PoseResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const PoseResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const PoseResult& r) {
        return "Pose(" + SemanticsText(r.graph, r.semantics) + ", position=" + VectorText(r.p) +
               ", quaternion=" + QuaternionText(r.q) + TimeSuffix(r.time) + ")";
      });
  py::class_<PositionResult>(m, "Position",
                             R"(The result of a position query: PositionCoord(e|C, f|D, [r]).

position   p: position of the point e relative to the point f, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("position", [](const PositionResult& r) { return VectorArray(r.p); })
      .def_property_readonly(
          "semantics", [](const PositionResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const PositionResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const PositionResult& r) {
        return "Position(" + SemanticsText(r.graph, r.semantics) + ", position=" + VectorText(r.p) +
               TimeSuffix(r.time) + ")";
      });
  py::class_<OrientationResult>(
      m, "Orientation", R"(The result of an orientation query: OrientationCoord([a]|C, [b]|D, [r]).

quaternion       (w, x, y, z), w >= 0: the operator carrying [b] onto [a], expressed in [r]
                 (when [r] = [b]: R_ba, the columns are the axes of [a] in [b])
rotation_matrix  the same as a 3x3 matrix
semantics        the relation in the paper's notation)")
      .def_property_readonly("quaternion",
                             [](const OrientationResult& r) { return QuaternionArray(r.q); })
      .def_property_readonly("rotation_matrix",
                             [](const OrientationResult& r) { return MatrixArray(r.q); })
      .def_property_readonly(
          "semantics",
          [](const OrientationResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const OrientationResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const OrientationResult& r) {
        return "Orientation(" + SemanticsText(r.graph, r.semantics) +
               ", quaternion=" + QuaternionText(r.q) + TimeSuffix(r.time) + ")";
      });
}

void BindTwistResults(py::module_& m) {
  py::class_<TwistResult>(m, "Twist", R"(The result of a twist query: TwistCoord(e|C, D, [r]).

linear     v: velocity of the point of body C at e, relative to body D, in [r]
angular    w: angular velocity of C relative to D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("linear", [](const TwistResult& r) { return VectorArray(r.v); })
      .def_property_readonly("angular", [](const TwistResult& r) { return VectorArray(r.w); })
      .def_property_readonly(
          "semantics", [](const TwistResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const TwistResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const TwistResult& r) {
        return "Twist(" + SemanticsText(r.graph, r.semantics) + ", linear=" + VectorText(r.v) +
               ", angular=" + VectorText(r.w) + TimeSuffix(r.time) + ")";
      });
  py::class_<LinearVelocityResult>(
      m, "LinearVelocity",
      R"(The result of a linear velocity query: LinearVelocityCoord(e|C, D, [r]).

linear     v: velocity of the point of body C at e, relative to body D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("linear",
                             [](const LinearVelocityResult& r) { return VectorArray(r.v); })
      .def_property_readonly(
          "semantics",
          [](const LinearVelocityResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const LinearVelocityResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const LinearVelocityResult& r) {
        return "LinearVelocity(" + SemanticsText(r.graph, r.semantics) +
               ", linear=" + VectorText(r.v) + TimeSuffix(r.time) + ")";
      });
  py::class_<AngularVelocityResult>(
      m, "AngularVelocity",
      R"(The result of an angular velocity query: AngularVelocityCoord(C, D, [r]).

angular    w: angular velocity of body C relative to body D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("angular",
                             [](const AngularVelocityResult& r) { return VectorArray(r.w); })
      .def_property_readonly(
          "semantics",
          [](const AngularVelocityResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly(
          "time",
          [](const AngularVelocityResult& r) -> py::object {
            return r.time ? TimeReportObject(*r.time) : py::none();
          },
          "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const AngularVelocityResult& r) {
        return "AngularVelocity(" + SemanticsText(r.graph, r.semantics) +
               ", angular=" + VectorText(r.w) + TimeSuffix(r.time) + ")";
      });
}

}  // namespace

void BindResults(py::module_& m) {
  BindPoseResults(m);
  BindTwistResults(m);
}

}  // namespace semgraph::python
