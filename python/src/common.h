// File: python/src/common.h
//
// Helpers shared by the binding files (one per Python class or family, module.cc lists them):
// raising the core's errors as Python exceptions (defined in common.cc), reading the name
// keywords into the core's specs, the keyword at fault in a query error, and numpy / text
// output. No geometry here.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "arguments.h"
#include "graph.h"
#include "semgraph/semantics/describe.h"

namespace semgraph::python {

using core::ErrorCode;
using semantics::Field;

// ====================================================================== errors (common.cc)

/// Stores the exception classes defined in semgraph/_errors.py (called once, at import).
void InitErrors(py::module_ errors);
/// Raises semgraph.RejectedError(code, message[, discrepancy]).
[[noreturn]] void ThrowRejected(core::ErrorCode code, const std::string& message);
[[noreturn]] void ThrowRejected(const core::BuildError& error);
/// Raises semgraph.QueryError(code, message, field, argument).
[[noreturn]] void ThrowQuery(core::ErrorCode code, const std::string& message, const char* field,
                             const char* argument);

/// Raises RejectedError "<what> <context> rejected (<code>): <what is wrong with the value>".
[[noreturn]] void ThrowValue(const char* what, const std::string& context, const coord::Error& e,
                             const semantics::NameTable& names);
/// Raises RejectedError no_such_edge: an update through a handle whose edge was removed.
[[noreturn]] void ThrowRemoved(const char* what, const std::string& context);
/// The context of an update's error: "of the pose edge {wrt} -> {of}".
std::string EdgeText(std::string_view wrt, std::string_view of);
/// "of the twist edge ref_body -> {point}".
std::string TwistEdgeText(std::string_view ref_body, std::string_view point);

// Whether a handle is the current one of its edge (a removed and re-added edge has a new one).
inline bool SameHandle(const core::PoseHandle& a, const core::PoseHandle& b) { return a == b; }
inline bool SameHandle(const core::TwistHandle& a, const core::TwistHandle& b) { return a == b; }

// ====================================================================== helpers

template <class T>
struct BackendOf {
  using type = typename T::Backend;
};
template <coord::Backend B>
struct BackendOf<core::CompiledPose<B>> {
  using type = B;
};
template <coord::Backend B>
struct BackendOf<core::CompiledPosition<B>> {
  using type = B;
};
template <coord::Backend B>
struct BackendOf<core::CompiledOrientation<B>> {
  using type = B;
};
template <coord::Backend B>
struct BackendOf<core::CompiledTwist<B>> {
  using type = B;
};
template <class T>
using BackendOfT = typename BackendOf<std::decay_t<T>>::type;

inline void Check(const core::BuildResult& r) {
  if (!r) ThrowRejected(r.error().code, r.error().message);
}

inline const char* RoleName(Field f) {
  switch (f) {
    case Field::kPoint:
      return "point";
    case Field::kOrientation:
      return "orientation";
    case Field::kBody:
      return "body";
    case Field::kRefPoint:
      return "ref_point";
    case Field::kRefOrientation:
      return "ref_orientation";
    case Field::kRefBody:
      return "ref_body";
    case Field::kCoordinateFrame:
      return "coordinate_frame";
  }
  return "argument";
}

// Whether QueryError::field names the culprit for this code.
inline bool FieldApplies(ErrorCode code) {
  return code == ErrorCode::kInvalidName || code == ErrorCode::kUnknownFrame ||
         code == ErrorCode::kUnknownBody || code == ErrorCode::kFrameBodyMismatch;
}

// The names of a pose/position/orientation, as the Python keywords gave them.
struct PoseNames {
  std::string_view of, body, wrt, ref_body, point, orientation, ref_point, ref_orientation,
      expressed_in;

  [[nodiscard]] core::PoseSpec Spec() const {
    core::PoseSpec s = core::PoseSpec::Of(of, body).RelativeTo(wrt, ref_body);
    if (!point.empty()) s.point = point;
    if (!orientation.empty()) s.orientation = orientation;
    if (!ref_point.empty()) s.ref_point = ref_point;
    if (!ref_orientation.empty()) s.ref_orientation = ref_orientation;
    if (!expressed_in.empty()) s.coordinate_frame = expressed_in;
    return s;
  }
  // The keyword that supplied a field.
  [[nodiscard]] const char* Argument(Field f) const {
    switch (f) {
      case Field::kPoint:
        return point.empty() ? "of" : "point";
      case Field::kOrientation:
        return orientation.empty() ? "of" : "orientation";
      case Field::kBody:
        return "body";
      case Field::kRefPoint:
        return ref_point.empty() ? "wrt" : "ref_point";
      case Field::kRefOrientation:
        return ref_orientation.empty() ? "wrt" : "ref_orientation";
      case Field::kRefBody:
        return "ref_body";
      case Field::kCoordinateFrame:
        return expressed_in.empty() ? "wrt" : "expressed_in";
    }
    return nullptr;
  }
};

inline PoseNames ReadPoseNames(const char* fn, py::handle of, py::handle body, py::handle wrt,
                               py::handle ref_body, py::handle point, py::handle orientation,
                               py::handle ref_point, py::handle ref_orientation,
                               py::handle expressed_in) {
  PoseNames n;
  n.of = NameArg(of, fn, "of");
  n.body = NameArg(body, fn, "body");
  n.wrt = NameArg(wrt, fn, "wrt");
  n.ref_body = NameArg(ref_body, fn, "ref_body");
  n.point = NameArg(point, fn, "point");
  n.orientation = NameArg(orientation, fn, "orientation");
  n.ref_point = NameArg(ref_point, fn, "ref_point");
  n.ref_orientation = NameArg(ref_orientation, fn, "ref_orientation");
  n.expressed_in = NameArg(expressed_in, fn, "expressed_in");
  return n;
}

inline core::TwistSpec ReadTwistSpec(const char* fn, py::handle point, py::handle body,
                                     py::handle ref_body, py::handle expressed_in) {
  return core::TwistSpec::Of(NameArg(point, fn, "point"), NameArg(body, fn, "body"))
      .RelativeTo(NameArg(ref_body, fn, "ref_body"))
      .ExpressedIn(NameArg(expressed_in, fn, "expressed_in"));
}

inline const char* TwistArgument(Field f) {
  switch (f) {
    case Field::kPoint:
      return "point";
    case Field::kBody:
      return "body";
    case Field::kRefBody:
      return "ref_body";
    case Field::kCoordinateFrame:
      return "expressed_in";
    default:
      return nullptr;
  }
}

template <class G>
[[noreturn]] void ThrowPoseQuery(const G& g, const core::QueryError& e, const core::PoseSpec& spec,
                                 const PoseNames& n) {
  // Time keywords at fault: the fixed frame of a time travel, a negative horizon.
  if (e.time.fixed_frame) ThrowQuery(e.code, g.Describe(e, spec), nullptr, "fixed");
  if (e.code == ErrorCode::kInvalidNumber)
    ThrowQuery(e.code, g.Describe(e, spec), nullptr, "max_extrapolation");
  const bool field = FieldApplies(e.code);
  ThrowQuery(e.code, g.Describe(e, spec), field ? RoleName(e.field) : nullptr,
             field ? n.Argument(e.field) : nullptr);
}

template <class G>
[[noreturn]] void ThrowTwistQuery(const G& g, const core::QueryError& e,
                                  const core::TwistSpec& spec) {
  if (e.code == ErrorCode::kInvalidNumber)
    ThrowQuery(e.code, g.Describe(e, spec), nullptr, "max_extrapolation");
  const bool field = FieldApplies(e.code);
  ThrowQuery(e.code, g.Describe(e, spec), field ? RoleName(e.field) : nullptr,
             field ? TwistArgument(e.field) : nullptr);
}

// ---------------------------------------------------------------- numpy out

inline py::array_t<double> Array(const double* data, std::initializer_list<py::ssize_t> shape) {
  py::array_t<double> a{std::vector<py::ssize_t>(shape)};
  py::ssize_t n = 1;
  for (py::ssize_t s : shape) n *= s;
  std::memcpy(a.mutable_data(), data, static_cast<std::size_t>(n) * sizeof(double));
  return a;
}
inline py::array_t<double> VectorArray(const Eigen::Vector3d& v) { return Array(v.data(), {3}); }
inline py::array_t<double> QuaternionArray(const Eigen::Quaterniond& q) {
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  return Array(wxyz, {4});
}
inline py::array_t<double> MatrixArray(const Eigen::Quaterniond& q) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = q.toRotationMatrix();
  return Array(R.data(), {3, 3});
}
inline py::array_t<double> HomogeneousArray(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> T =
      Eigen::Matrix<double, 4, 4, Eigen::RowMajor>::Identity();
  T.topLeftCorner<3, 3>() = q.toRotationMatrix();
  T.topRightCorner<3, 1>() = p;
  return Array(T.data(), {4, 4});
}

inline std::string Numbers(const double* x, int n) {
  std::string s = "[";
  char buf[32];
  for (int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof(buf), "%.6g", x[i] == 0.0 ? 0.0 : x[i]);
    s += (i ? ", " : "") + std::string(buf);
  }
  return s + "]";
}
inline std::string VectorText(const Eigen::Vector3d& v) { return Numbers(v.data(), 3); }
inline std::string QuaternionText(const Eigen::Quaterniond& q) {
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  return Numbers(wxyz, 4);
}

template <class S>
std::string SemanticsText(const GraphPtr& graph, const S& s) {
  return Describe(s, graph->names());
}

// ---------------------------------------------------------------- results from core values

template <coord::Backend B>
PoseResult MakePoseResult(const GraphPtr& graph, const semantics::PoseSemantics& s,
                          const typename B::PoseCoords& X) {
  return PoseResult{graph, s, CanonicalQuaternion(B::ToQuaternion(B::RotationOf(X))),
                    B::TranslationOf(X)};
}
template <coord::Backend B>
OrientationResult MakeOrientationResult(const GraphPtr& graph,
                                        const semantics::OrientationSemantics& s,
                                        const typename B::Rotation& M) {
  return OrientationResult{graph, s, CanonicalQuaternion(B::ToQuaternion(M))};
}

}  // namespace semgraph::python
