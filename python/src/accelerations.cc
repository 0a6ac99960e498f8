// SceneGraph.add_acceleration, set_acceleration, acceleration, linear_acceleration,
// angular_acceleration and compile_acceleration, and the classes Acceleration and
// CompiledAcceleration (accelerations.h).
#include "accelerations.h"

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "common.h"
#include "docstrings.h"
#include "timed.h"

namespace semgraph::python {

namespace {

/// The answer of an acceleration query: AccelerationCoord(e|C, D, [r]). (linear_acceleration and
/// angular_acceleration return numpy arrays, as force and moment.)
struct AccelerationResult {
  GraphPtr graph;
  semantics::AccelerationSemantics semantics;
  Eigen::Vector3d a, alpha;
  std::optional<core::TimeReport> time = std::nullopt;  ///< given a time policy
};
struct CompiledAccelerationObject {
  GraphPtr graph;
  PerBackend<core::CompiledAcceleration> query;
};

// The time keywords of the acceleration queries (no time travel, no source).
TimeQuery TimeArgs(const char* fn, py::handle at, py::handle max_extrapolation,
                   py::handle not_before) {
  return TimeQueryArgs(fn, at, max_extrapolation, not_before, py::none(), py::none(), false);
}

AccelerationResult Query(const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
                         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
                         py::handle not_before) {
  const core::TwistSpec spec = ReadTwistSpec("acceleration", point, body, ref_body, expressed_in);
  const TimeQuery t = TimeArgs("acceleration", at, max_extrapolation, not_before);
  GraphPtr self = Self(b);
  return b.Visit([&](const auto& g) {
    if (t.kind == TimeQuery::Kind::kNone) {
      auto r = g.GetAcceleration(spec);
      if (!r) ThrowTwistQuery(g, r.error(), spec);
      return AccelerationResult{self, r->semantics, r->linear, r->angular};
    }
    auto r = g.GetAcceleration(spec, t.policy);
    if (!r) ThrowTwistQuery(g, r.error(), spec);
    return AccelerationResult{self, r->value.semantics, r->value.linear, r->value.angular, r->time};
  });
}

Eigen::Vector3d QueryLinear(const GraphBox& b, py::handle point, py::handle body,
                            py::handle ref_body, py::handle expressed_in, py::handle at,
                            py::handle max_extrapolation, py::handle not_before) {
  const core::TwistSpec spec =
      ReadTwistSpec("linear_acceleration", point, body, ref_body, expressed_in);
  const TimeQuery t = TimeArgs("linear_acceleration", at, max_extrapolation, not_before);
  return b.Visit([&](const auto& g) {
    auto r = g.GetLinearAcceleration(spec, t.policy);
    if (!r) ThrowTwistQuery(g, r.error(), spec);
    return r->value.value;
  });
}

Eigen::Vector3d QueryAngular(const GraphBox& b, py::handle body, py::handle ref_body,
                             py::handle expressed_in, py::handle at, py::handle max_extrapolation,
                             py::handle not_before) {
  const core::TwistSpec spec =
      ReadTwistSpec("angular_acceleration", py::none(), body, ref_body, expressed_in);
  const TimeQuery t = TimeArgs("angular_acceleration", at, max_extrapolation, not_before);
  return b.Visit([&](const auto& g) {
    auto r = g.GetAngularAcceleration(spec, t.policy);
    if (!r) ThrowTwistQuery(g, r.error(), spec);
    return r->value.value;
  });
}

std::shared_ptr<CompiledAccelerationObject> Compile(const GraphBox& b, py::handle point,
                                                    py::handle body, py::handle ref_body,
                                                    py::handle expressed_in) {
  const core::TwistSpec spec =
      ReadTwistSpec("compile_acceleration", point, body, ref_body, expressed_in);
  GraphPtr self = Self(b);
  return b.Visit([&](const auto& g) {
    auto r = g.CompileAcceleration(spec);
    if (!r) ThrowTwistQuery(g, r.error(), spec);
    return std::make_shared<CompiledAccelerationObject>(
        CompiledAccelerationObject{self, std::move(*r)});
  });
}

AccelerationResult Evaluate(CompiledAccelerationObject& c) {
  Eigen::Vector3d a, alpha;
  semantics::AccelerationSemantics s;
  const ErrorCode code = std::visit(
      [&](auto& q) {
        s = q.semantics();
        return q.Evaluate(a, alpha);
      },
      c.query);
  if (code == ErrorCode::kNoAcceleration) {
    ThrowQuery(code,
               "the compiled query " + SemanticsText(c.graph, s) +
                   " reads a twist edge that carries no acceleration now (never given, or "
                   "cleared by a twist given without one); acceleration() with the same names "
                   "names the edge",
               nullptr, nullptr);
  }
  if (code != ErrorCode::kOk) {
    ThrowQuery(ErrorCode::kQueryInvalidated,
               "the compiled query " + SemanticsText(c.graph, s) +
                   " reads a pose or twist edge that was removed after it was compiled; compile "
                   "it again",
               nullptr, nullptr);
  }
  return AccelerationResult{c.graph, s, a, alpha};
}

void AddAcceleration(GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
                     py::handle expressed_in, py::handle linear, py::handle angular,
                     py::handle stamp) {
  const core::TwistSpec spec =
      ReadTwistSpec("add_acceleration", point, body, ref_body, expressed_in);
  const Eigen::Vector3d a = Vector3Arg(linear, "add_acceleration", "linear");
  const Eigen::Vector3d alpha = Vector3Arg(angular, "add_acceleration", "angular");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "add_acceleration", "stamp", false);
  std::lock_guard<WriterMutex> lock(b.writer);
  Check(b.Visit([&](auto& g) {
    return t ? g.AddAcceleration(spec, a, alpha, *t) : g.AddAcceleration(spec, a, alpha);
  }));
}

void SetAcceleration(GraphBox& box, const TwistHandleObject& h, py::handle linear,
                     py::handle angular, py::handle stamp) {
  if (h.graph.get() != &box) {
    throw py::value_error("set_acceleration(): the handle belongs to another SceneGraph");
  }
  const Eigen::Vector3d a = Vector3Arg(linear, "set_acceleration", "linear");
  const Eigen::Vector3d alpha = Vector3Arg(angular, "set_acceleration", "angular");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "set_acceleration", "stamp", false);
  core::UpdateError why;
  ErrorCode code;
  {
    std::lock_guard<WriterMutex> lock(box.writer);
    code = box.Visit([&](auto& g) {
      return t ? g.SetAcceleration(h.handle, a, alpha, *t, &why)
               : g.SetAcceleration(h.handle, a, alpha, &why);
    });
  }
  const std::string edge = TwistEdgeText(h.ref_body, h.point);
  if (code == ErrorCode::kNoSuchEdge) ThrowRemoved("set_acceleration", edge);
  if (code == ErrorCode::kInvalidNumber) {
    ThrowValue("set_acceleration", edge, why.error(), box.names());
  }
  if (code == ErrorCode::kStampMismatch) {
    ThrowRejected(code, "set_acceleration " + edge +
                            (t ? " rejected (stamp_mismatch): the edge is timeless, or has no "
                                 "twist sample at that stamp (set_twist at the stamp first)"
                               : " rejected (stamp_mismatch): the edge is stamped: give stamp="));
  }
  if (code != ErrorCode::kOk) {
    ThrowRejected(code,
                  "set_acceleration " + edge + " rejected (" + std::string(ToString(code)) + ")");
  }
}

constexpr const char* kNamesDoc = R"(
point         a frame: the acceleration is that of the point of `body` at this frame's origin
body          the moving body C (default: the body of `point`'s frame)
ref_body      the reference body D
expressed_in  the coordinate frame [r])";
constexpr const char* kTimeDoc = R"(
Time (keyword-only, as twist(); no source=): at= a time, 'latest' or 'latest_common';
max_extrapolation=, not_before=. Each edge's twist and acceleration are read at that time (between
two samples: interpolated linearly, an acceleration only when both samples carry one; past them
within max_extrapolation: the nearest sample held). acceleration() then has .time.)";
constexpr const char* kQueryErrors = R"(
QueryError (code, and .argument: the keyword at fault where there is one): invalid_name,
unknown_frame, unknown_body, frame_body_mismatch, no_pose_path, no_twist_path, and
no_acceleration (a twist edge on the path carries none; the message names it).)";

}  // namespace

void BindAccelerationResults(py::module_& m) {
  py::class_<AccelerationResult>(
      m, "Acceleration",
      R"(The result of an acceleration query: AccelerationCoord(e|C, D, [r]).

linear     a: classical acceleration of the point of body C at e, relative to body D, in [r]
angular    alpha: angular acceleration of C relative to D, in [r]
semantics  the relation in the paper's notation
time       a TimeReport when the query was given a time (at=, not_before=), else None)")
      .def_property_readonly("linear", [](const AccelerationResult& r) { return VectorArray(r.a); })
      .def_property_readonly("angular",
                             [](const AccelerationResult& r) { return VectorArray(r.alpha); })
      .def_property_readonly(
          "semantics",
          [](const AccelerationResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time",
                             [](const AccelerationResult& r) -> py::object {
                               if (!r.time) return py::none();
                               return TimeReportObject(*r.time);
                             })
      .def("__repr__", [](const AccelerationResult& r) {
        return "Acceleration(" + SemanticsText(r.graph, r.semantics) +
               ", linear=" + VectorText(r.a) + ", angular=" + VectorText(r.alpha) + ")";
      });
  py::class_<CompiledAccelerationObject, std::shared_ptr<CompiledAccelerationObject>>(
      m, "CompiledAcceleration",
      R"(A compiled acceleration query (SceneGraph.compile_acceleration; evaluate() returns an
Acceleration). The semantics were checked and the path resolved once; evaluate() sees every later
set_twist / set_acceleration / add_twist update of the edges it reads. It keeps its SceneGraph
alive. evaluate() raises QueryError 'no_acceleration' while an edge of the path carries none
(e.g. after a twist was given without one), and 'query_invalidated' after an edge it reads was
removed (never a wrong number): compile again.)")
      .def("evaluate", &Evaluate, "The acceleration now (an Acceleration).")
      .def_property_readonly("is_valid",
                             [](const CompiledAccelerationObject& c) {
                               return std::visit([](const auto& q) { return q.is_valid(); },
                                                 c.query);
                             })
      .def_property_readonly(
          "num_twist_edges",
          [](const CompiledAccelerationObject& c) {
            return std::visit([](const auto& q) { return q.num_twist_edges(); }, c.query);
          },
          "Twist edges read per evaluation.")
      .def("__repr__", [](const CompiledAccelerationObject& c) {
        return "CompiledAcceleration(" +
               std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); },
                          c.query) +
               ")";
      });
}

void BindAccelerations(GraphClass& graph) {
  graph.def(
      "add_acceleration", &AddAcceleration, py::kw_only(), py::arg("point") = py::none(),
      py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), py::arg("linear") = py::none(),
      py::arg("angular") = py::none(), py::arg("stamp") = py::none(),
      R"(Sets the acceleration of the existing twist edge ref_body -> body (the one in the pose
tree of `point`): AccelerationCoord(point|body, ref_body, [expressed_in]), converted once to the
edge's point and frame with the current poses and the edge's twist. A stamped edge takes
stamp=: the acceleration of its twist sample at that stamp, converted with the poses then.
linear   a: classical acceleration of the point of `body` at the origin of `point`; default zero
angular  alpha: angular acceleration of `body` relative to `ref_body`; default zero
both in [expressed_in]. A later twist given without an acceleration clears it.
RejectedError (code), graph unchanged: invalid_name, invalid_number, unknown_frame (point, then
expressed_in), unknown_body (body, ref_body), no_such_edge (no twist edge ref_body -> body),
joint_edge, stamp_mismatch (a stamped edge without stamp=, a timeless one with it),
acceleration_not_convertible ([expressed_in] not in the point's pose tree; no twist sample at
the stamp; a pose without a value at the stamp), duplicate_stamp (another acceleration on that
sample, under the graph's reject policy).)");
  graph.def("set_acceleration", &SetAcceleration, py::arg("handle"), py::kw_only(),
            py::arg("linear") = py::none(), py::arg("angular") = py::none(),
            py::arg("stamp") = py::none(),
            R"(O(1) update of the acceleration of a twist edge by its handle (twist_handle), in the
edge's form: a of the head frame's origin and alpha, both in [head frame]; default zero. A
stamped edge takes stamp=: the acceleration of its twist sample at that stamp (set_twist first).
RejectedError: no_such_edge (removed), invalid_number, joint_edge, stamp_mismatch,
duplicate_stamp; nothing written then.)");
#define SEMGRAPH_ACCELERATION_TIME_ARGS                                  \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
  py::arg("not_before") = py::none()
  graph.def("acceleration", &Query, py::kw_only(), py::arg("point") = py::none(),
            py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
            py::arg("expressed_in") = py::none(), SEMGRAPH_ACCELERATION_TIME_ARGS,
            Doc("The acceleration of `body` at `point` relative to `ref_body`, in `expressed_in` "
                "(an Acceleration): the twist path's edge accelerations composed with the "
                "Coriolis and centripetal terms.\n",
                (std::string(kNamesDoc) + kTimeDoc + kQueryErrors).c_str())
                .c_str());
  graph.def(
      "linear_acceleration",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before) {
        return VectorArray(
            QueryLinear(b, point, body, ref_body, expressed_in, at, max_extrapolation, not_before));
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      SEMGRAPH_ACCELERATION_TIME_ARGS,
      Doc("The linear part of acceleration(): a numpy array of 3.\n",
          (std::string(kNamesDoc) + kTimeDoc + kQueryErrors).c_str())
          .c_str());
  graph.def(
      "angular_acceleration",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before) {
        return VectorArray(
            QueryAngular(b, body, ref_body, expressed_in, at, max_extrapolation, not_before));
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), SEMGRAPH_ACCELERATION_TIME_ARGS,
      Doc("The angular acceleration of `body` relative to `ref_body` in `expressed_in`: a numpy "
          "array of 3. No point is needed.\n",
          (std::string(kTimeDoc) + kQueryErrors).c_str())
          .c_str());
#undef SEMGRAPH_ACCELERATION_TIME_ARGS
  graph.def("compile_acceleration", &Compile, py::kw_only(), py::arg("point") = py::none(),
            py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
            py::arg("expressed_in") = py::none(),
            "The query of acceleration(), compiled (a CompiledAcceleration); the QueryErrors of "
            "acceleration() but no_acceleration, which evaluate() raises while an edge of the "
            "path carries none.");
}

}  // namespace semgraph::python
