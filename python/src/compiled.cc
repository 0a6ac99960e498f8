// The compiled queries CompiledPose, CompiledPosition, CompiledOrientation and CompiledTwist
// (SceneGraph.compile_*, queries.cc): evaluation with or without a time policy, the core's
// codes raised as QueryError.
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "common.h"
#include "docstrings.h"
#include "timed.h"

namespace semgraph::python {

namespace {

// ---------------------------------------------------------------- compiled evaluation

[[noreturn]] void ThrowInvalidated(const std::string& what) {
  ThrowQuery(ErrorCode::kQueryInvalidated,
             "the compiled query " + what +
                 " reads a pose or twist edge that was removed after it was compiled; compile "
                 "it again",
             nullptr, nullptr);
}

}  // namespace

void CheckCompiled(ErrorCode code, const std::string& what) {
  if (code == ErrorCode::kOk) return;
  // Untimed, only a removal fails, except a twist from poses, which reads under Latest.
  if (code == ErrorCode::kQueryInvalidated) ThrowInvalidated(what);
  std::string why;
  switch (code) {
    case ErrorCode::kExtrapolation:
      why =
          "an edge it reads has no sample around the time asked and may not be extrapolated there";
      break;
    case ErrorCode::kStale:
      why = "an edge it reads has no sample at or after not_before";
      break;
    case ErrorCode::kInvalidNumber:
      why = "max_extrapolation is negative";
      break;
    default:
      why = "the time policy cannot be answered";
      break;
  }
  ThrowQuery(code,
             "the compiled query " + what + " failed (" + std::string(ToString(code)) +
                 "): " + why +
                 "; explain_pose / explain_twist with the same names and time keywords lists the "
                 "edges and "
                 "their samples",
             nullptr, nullptr);
}

namespace {

PoseResult Evaluate(const CompiledPoseObject& c, const core::TimePolicy* policy = nullptr) {
  return std::visit(
      [&](const auto& q) {
        using B = BackendOfT<decltype(q)>;
        typename B::PoseCoords X;
        core::TimeReport report;
        CheckCompiled(policy ? q.Evaluate(X, *policy, report) : q.Evaluate(X),
                      SemanticsText(c.graph, q.semantics()));
        PoseResult r = MakePoseResult<B>(c.graph, q.semantics(), X);
        if (policy) r.time = report;
        return r;
      },
      c.query);
}
PositionResult Evaluate(const CompiledPositionObject& c, const core::TimePolicy* policy = nullptr) {
  return std::visit(
      [&](const auto& q) {
        Eigen::Vector3d p;
        core::TimeReport report;
        CheckCompiled(policy ? q.Evaluate(p, *policy, report) : q.Evaluate(p),
                      SemanticsText(c.graph, q.semantics()));
        PositionResult r{c.graph, q.semantics(), p};
        if (policy) r.time = report;
        return r;
      },
      c.query);
}
OrientationResult Evaluate(const CompiledOrientationObject& c,
                           const core::TimePolicy* policy = nullptr) {
  return std::visit(
      [&](const auto& q) {
        using B = BackendOfT<decltype(q)>;
        typename B::Rotation M;
        core::TimeReport report;
        CheckCompiled(policy ? q.Evaluate(M, *policy, report) : q.Evaluate(M),
                      SemanticsText(c.graph, q.semantics()));
        OrientationResult r = MakeOrientationResult<B>(c.graph, q.semantics(), M);
        if (policy) r.time = report;
        return r;
      },
      c.query);
}
std::string CompiledText(const CompiledTwistObject& c) {
  return std::visit(
      [&](const auto& q) {
        switch (c.kind) {
          case CompiledKind::kLinear:
            return SemanticsText(c.graph, c.linear_semantics);
          case CompiledKind::kAngular:
            return SemanticsText(c.graph, c.angular_semantics);
          default:
            return SemanticsText(c.graph, q.semantics());
        }
      },
      c.query);
}
py::object Evaluate(const CompiledTwistObject& c, const core::TimePolicy* policy = nullptr) {
  Eigen::Vector3d v, w;
  core::TimeReport report;
  const ErrorCode code = std::visit(
      [&](const auto& q) { return policy ? q.Evaluate(v, w, *policy, report) : q.Evaluate(v, w); },
      c.query);
  if (code != ErrorCode::kOk) CheckCompiled(code, CompiledText(c));
  std::optional<core::TimeReport> time;
  if (policy) time = report;
  switch (c.kind) {
    case CompiledKind::kLinear:
      return py::cast(LinearVelocityResult{c.graph, c.linear_semantics, v, time});
    case CompiledKind::kAngular:
      return py::cast(AngularVelocityResult{c.graph, c.angular_semantics, w, time});
    default:
      return py::cast(TwistResult{
          c.graph, std::visit([](const auto& q) { return q.semantics(); }, c.query), v, w, time});
  }
}

// evaluate(*, at=, max_extrapolation=, not_before=): the compiled query under that policy.
template <class C>
py::object EvaluateAt(const C& c, py::handle at, py::handle max_extrapolation,
                      py::handle not_before) {
  const TimeQuery t =
      TimeQueryArgs("evaluate", at, max_extrapolation, not_before, py::none(), py::none(), false);
  auto object = [](auto&& result) -> py::object {
    if constexpr (std::is_same_v<std::decay_t<decltype(result)>, py::object>) {
      return std::move(result);
    } else {
      return py::cast(std::move(result));
    }
  };
  if (t.kind == TimeQuery::Kind::kNone) return object(Evaluate(c));
  return object(Evaluate(c, &t.policy));
}

constexpr const char* kCompiledDoc = R"(
Made by SceneGraph.compile_*(): the semantics were checked and the path resolved once; evaluate()
costs only the compositions along the path and sees every later set_pose/set_twist/add_pose
update of the edges it reads. It keeps its SceneGraph alive. After an edge it reads is removed,
evaluate() raises QueryError with code 'query_invalidated' (never a wrong number): compile again.)";

// CompiledPose and CompiledPosition.
void BindCompiledPoseAndPosition(py::module_& m) {
  py::class_<CompiledPoseObject, std::shared_ptr<CompiledPoseObject>>(
      m, "CompiledPose", Doc("A compiled pose query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledPoseObject& c) { return Evaluate(c); })
      .def(
          "evaluate",
          [](const CompiledPoseObject& c, py::handle at, py::handle max_extrapolation,
             py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
          py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
          py::arg("not_before") = py::none(),
          "The pose now (a Pose); with at= / not_before= (as SceneGraph.pose: a time, 'latest', "
          "'latest_common') under that time policy, with .time. Raises "
          "QueryError('query_invalidated') "
          "after a removal, and extrapolation / stale / invalid_number under a time policy.")
      .def_property_readonly(
          "is_valid",
          [](const CompiledPoseObject& c) {
            return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
          },
          "True while every edge the query reads still exists.")
      .def_property_readonly(
          "num_pose_edges",
          [](const CompiledPoseObject& c) {
            return std::visit([](const auto& q) { return q.num_pose_edges(); }, c.query);
          },
          "Pose edges read per evaluation.")
      .def("__repr__", [](const CompiledPoseObject& c) {
        return "CompiledPose(" +
               std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); },
                          c.query) +
               ")";
      });
  py::class_<CompiledPositionObject, std::shared_ptr<CompiledPositionObject>>(
      m, "CompiledPosition", Doc("A compiled position query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledPositionObject& c) { return Evaluate(c); })
      .def(
          "evaluate",
          [](const CompiledPositionObject& c, py::handle at, py::handle max_extrapolation,
             py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
          py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
          py::arg("not_before") = py::none(), "The position now (a Position).")
      .def_property_readonly("is_valid",
                             [](const CompiledPositionObject& c) {
                               return std::visit([](const auto& q) { return q.is_valid(); },
                                                 c.query);
                             })
      .def_property_readonly("num_pose_edges",
                             [](const CompiledPositionObject& c) {
                               return std::visit([](const auto& q) { return q.num_pose_edges(); },
                                                 c.query);
                             })
      .def("__repr__", [](const CompiledPositionObject& c) {
        return "CompiledPosition(" +
               std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); },
                          c.query) +
               ")";
      });
}

// CompiledOrientation and CompiledTwist.
void BindCompiledOrientationAndTwist(py::module_& m) {
  py::class_<CompiledOrientationObject, std::shared_ptr<CompiledOrientationObject>>(
      m, "CompiledOrientation", Doc("A compiled orientation query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledOrientationObject& c) { return Evaluate(c); })
      .def(
          "evaluate",
          [](const CompiledOrientationObject& c, py::handle at, py::handle max_extrapolation,
             py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
          py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
          py::arg("not_before") = py::none(), "The orientation now (an Orientation).")
      .def_property_readonly("is_valid",
                             [](const CompiledOrientationObject& c) {
                               return std::visit([](const auto& q) { return q.is_valid(); },
                                                 c.query);
                             })
      .def_property_readonly("num_pose_edges",
                             [](const CompiledOrientationObject& c) {
                               return std::visit([](const auto& q) { return q.num_pose_edges(); },
                                                 c.query);
                             })
      .def("__repr__", [](const CompiledOrientationObject& c) {
        return "CompiledOrientation(" +
               std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); },
                          c.query) +
               ")";
      });
  py::class_<CompiledTwistObject, std::shared_ptr<CompiledTwistObject>>(
      m, "CompiledTwist",
      Doc("A compiled twist, linear velocity or angular velocity query (evaluate() returns a "
          "Twist, LinearVelocity or AngularVelocity, as compiled).",
          kCompiledDoc)
          .c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledTwistObject& c) { return Evaluate(c); })
      .def(
          "evaluate",
          [](const CompiledTwistObject& c, py::handle at, py::handle max_extrapolation,
             py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
          py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
          py::arg("not_before") = py::none(), "The twist (or linear / angular velocity) now.")
      .def_property_readonly("is_valid",
                             [](const CompiledTwistObject& c) {
                               return std::visit([](const auto& q) { return q.is_valid(); },
                                                 c.query);
                             })
      .def_property_readonly("num_pose_edges",
                             [](const CompiledTwistObject& c) {
                               return std::visit([](const auto& q) { return q.num_pose_edges(); },
                                                 c.query);
                             })
      .def_property_readonly(
          "num_twist_edges",
          [](const CompiledTwistObject& c) {
            return std::visit([](const auto& q) { return q.num_twist_edges(); }, c.query);
          },
          "Twist edges read per evaluation.")
      .def("__repr__",
           [](const CompiledTwistObject& c) { return "CompiledTwist(" + CompiledText(c) + ")"; });
}

}  // namespace

void BindCompiled(py::module_& m) {
  BindCompiledPoseAndPosition(m);
  BindCompiledOrientationAndTwist(m);
}

}  // namespace semgraph::python
