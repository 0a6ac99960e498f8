// SceneGraph.compile_pose_with_covariance ... compile_angular_velocity_with_covariance and the
// classes they return, CompiledPoseWithCovariance ... CompiledTwistWithCovariance
// (compiled_covariance.h).
#include "compiled_covariance.h"

#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "common.h"
#include "docstrings.h"
#include "semgraph/semantics/operations.h"
#include "timed.h"
#include "uncertainty.h"

namespace semgraph::python {

namespace {

using QB = coord::QuaternionBackend;
using HB = coord::HomogeneousBackend;

struct CompiledPoseCovObject {
  GraphPtr graph;
  PerBackend<core::CompiledPoseWithCovariance> query;
  core::CovarianceOrder order = core::CovarianceOrder::kLinearAngular;
};
struct CompiledPositionCovObject {
  GraphPtr graph;
  PerBackend<core::CompiledPositionWithCovariance> query;
};
struct CompiledOrientationCovObject {
  GraphPtr graph;
  PerBackend<core::CompiledOrientationWithCovariance> query;
};
/// Twist, linear velocity and angular velocity: one Python class, as CompiledTwist. `twist` is
/// the semantics of the twist the core object computes (the velocity kinds' core objects keep
/// none): the answer's for a twist, its linear part's for a linear velocity, and for an
/// angular velocity the twist at [r]'s origin's angular part's (as the one-shot queries).
struct CompiledTwistCovObject {
  GraphPtr graph;
  std::variant<core::CompiledTwistWithCovariance<QB>, core::CompiledTwistWithCovariance<HB>,
               core::CompiledLinearVelocityWithCovariance<QB>,
               core::CompiledLinearVelocityWithCovariance<HB>,
               core::CompiledAngularVelocityWithCovariance<QB>,
               core::CompiledAngularVelocityWithCovariance<HB>>
      query;
  semantics::TwistSemantics twist;
  core::CovarianceOrder order = core::CovarianceOrder::kLinearAngular;
};

core::CovarianceOrder OrderArg(py::handle order, const char* function) {
  return CovarianceOrderArg(order, function, "covariance_order");
}

// ---------------------------------------------------------------- evaluation

template <coord::Backend B>
py::tuple Answer(const CompiledPoseCovObject& c, core::CompiledPoseWithCovariance<B>& q,
                 const core::TimePolicy* policy) {
  typename B::PoseCoords X;
  core::Covariance6 S;
  core::TimeReport report;
  const ErrorCode code =
      policy ? q.Evaluate(X, S, *policy, report, c.order) : q.Evaluate(X, S, c.order);
  // The message only on failure (the semantics text allocates).
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, q.semantics()));
  PoseResult r = MakePoseResult<B>(c.graph, q.semantics(), X);
  if (policy) r.time = report;
  return WithCovariance(py::cast(std::move(r)), S);
}
template <coord::Backend B>
py::tuple Answer(const CompiledPositionCovObject& c, core::CompiledPositionWithCovariance<B>& q,
                 const core::TimePolicy* policy) {
  Eigen::Vector3d p;
  Eigen::Matrix3d S;
  core::TimeReport report;
  const ErrorCode code = policy ? q.Evaluate(p, S, *policy, report) : q.Evaluate(p, S);
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, q.semantics()));
  PositionResult r{c.graph, q.semantics(), p};
  if (policy) r.time = report;
  return WithCovariance(py::cast(std::move(r)), S);
}
template <coord::Backend B>
py::tuple Answer(const CompiledOrientationCovObject& c,
                 core::CompiledOrientationWithCovariance<B>& q, const core::TimePolicy* policy) {
  typename B::Rotation M;
  Eigen::Matrix3d S;
  core::TimeReport report;
  const ErrorCode code = policy ? q.Evaluate(M, S, *policy, report) : q.Evaluate(M, S);
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, q.semantics()));
  OrientationResult r = MakeOrientationResult<B>(c.graph, q.semantics(), M);
  if (policy) r.time = report;
  return WithCovariance(py::cast(std::move(r)), S);
}

// The twist kinds. From poses, the untimed evaluation reads under Latest: its codes are the
// timed ones (extrapolation, stale), which CheckCompiled reports as such.
std::optional<core::TimeReport> TimeOf(const core::TimePolicy* policy,
                                       const core::TimeReport& report) {
  if (policy == nullptr) return std::nullopt;
  return report;
}

template <coord::Backend B>
py::tuple Answer(const CompiledTwistCovObject& c, core::CompiledTwistWithCovariance<B>& q,
                 const core::TimePolicy* policy) {
  Eigen::Vector3d v, w;
  core::Covariance6 S;
  core::TimeReport report;
  const ErrorCode code =
      policy ? q.Evaluate(v, w, S, *policy, report, c.order) : q.Evaluate(v, w, S, c.order);
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, c.twist));
  return WithCovariance(py::cast(TwistResult{c.graph, c.twist, v, w, TimeOf(policy, report)}), S);
}
template <coord::Backend B>
py::tuple Answer(const CompiledTwistCovObject& c, core::CompiledLinearVelocityWithCovariance<B>& q,
                 const core::TimePolicy* policy) {
  const semantics::LinearVelocitySemantics s = semantics::LinearOf(c.twist);
  Eigen::Vector3d v;
  Eigen::Matrix3d S;
  core::TimeReport report;
  const ErrorCode code = policy ? q.Evaluate(v, S, *policy, report) : q.Evaluate(v, S);
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, s));
  return WithCovariance(py::cast(LinearVelocityResult{c.graph, s, v, TimeOf(policy, report)}), S);
}
template <coord::Backend B>
py::tuple Answer(const CompiledTwistCovObject& c, core::CompiledAngularVelocityWithCovariance<B>& q,
                 const core::TimePolicy* policy) {
  const semantics::AngularVelocitySemantics s = semantics::AngularOf(c.twist);
  Eigen::Vector3d w;
  Eigen::Matrix3d S;
  core::TimeReport report;
  const ErrorCode code = policy ? q.Evaluate(w, S, *policy, report) : q.Evaluate(w, S);
  if (code != ErrorCode::kOk) CheckCompiled(code, SemanticsText(c.graph, s));
  return WithCovariance(py::cast(AngularVelocityResult{c.graph, s, w, TimeOf(policy, report)}), S);
}

template <class C>
py::tuple Evaluate(C& c, const core::TimePolicy* policy = nullptr) {
  return std::visit([&](auto& q) { return Answer(c, q, policy); }, c.query);
}

// evaluate(*, at=, max_extrapolation=, not_before=): the compiled query under that policy (as
// compiled.cc's; no time travel).
template <class C>
py::tuple EvaluateAt(C& c, py::handle at, py::handle max_extrapolation, py::handle not_before) {
  const TimeQuery t =
      TimeQueryArgs("evaluate", at, max_extrapolation, not_before, py::none(), py::none(), false);
  if (t.kind == TimeQuery::Kind::kNone) return Evaluate(c);
  return Evaluate(c, &t.policy);
}

std::string TwistText(const CompiledTwistCovObject& c) {
  return std::visit(
      [&](const auto& q) {
        using T = std::decay_t<decltype(q)>;
        if constexpr (std::is_same_v<T, core::CompiledLinearVelocityWithCovariance<QB>> ||
                      std::is_same_v<T, core::CompiledLinearVelocityWithCovariance<HB>>) {
          return SemanticsText(c.graph, semantics::LinearOf(c.twist));
        } else if constexpr (std::is_same_v<T, core::CompiledAngularVelocityWithCovariance<QB>> ||
                             std::is_same_v<T, core::CompiledAngularVelocityWithCovariance<HB>>) {
          return SemanticsText(c.graph, semantics::AngularOf(c.twist));
        } else {
          return SemanticsText(c.graph, c.twist);
        }
      },
      c.query);
}

constexpr const char* kCompiledCovDoc = R"(
Made by SceneGraph.compile_*_with_covariance(): the semantics were checked and the edges it reads
listed once; evaluate() returns (result, covariance) as the one-shot *_with_covariance query
(the same numbers, up to rounding: docs/uncertainty.md), reading each edge's value and covariance
of one write, and sees every later set_pose / set_twist / add_pose / add_twist update (with or
without a covariance) of the edges it reads. covariance_order was fixed at compile time. It keeps
its SceneGraph alive. After an edge it reads is removed, evaluate() raises QueryError with code
'query_invalidated' (never a wrong number): compile again (after any topology change when it
extrapolates: each pose edge's integration twist was planned at compile time).)";
constexpr const char* kEvaluateDoc = R"(
Without keywords: each edge's current value and covariance, and result.time is None. With at= /
max_extrapolation= / not_before= (as the plain compiled queries' evaluate: a time, 'latest',
'latest_common'; no time travel): under that time policy, what the one-shot query with the same
keywords answers, result.time its TimeReport. Raises QueryError('query_invalidated') after a
removal, and extrapolation / stale / invalid_number under a time policy.)";

// The evaluate overloads of one class: the untimed one first, so that the real-time call
// evaluate() does not pay for parsing the time keywords.
template <class C, class Class>
void DefEvaluate(Class& cls, const char* result) {
  cls.def("evaluate", [](C& c) { return Evaluate(c); })
      .def(
          "evaluate",
          [](C& c, py::handle at, py::handle max_extrapolation, py::handle not_before) {
            return EvaluateAt(c, at, max_extrapolation, not_before);
          },
          py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
          py::arg("not_before") = py::none(), Doc(result, kEvaluateDoc).c_str());
}

template <class C>
std::string PoseKindText(const C& c) {
  return std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); }, c.query);
}

}  // namespace

void BindCompiledCovariance(py::module_& m) {
  py::class_<CompiledPoseCovObject, std::shared_ptr<CompiledPoseCovObject>> pose(
      m, "CompiledPoseWithCovariance",
      Doc("A compiled pose query with covariance (evaluate(): a Pose and its (6, 6) covariance).",
          kCompiledCovDoc)
          .c_str());
  DefEvaluate<CompiledPoseCovObject>(pose, "(Pose, covariance (6, 6) numpy array).");
  pose.def("__repr__", [](const CompiledPoseCovObject& c) {
    return "CompiledPoseWithCovariance(" + PoseKindText(c) + ")";
  });
  py::class_<CompiledPositionCovObject, std::shared_ptr<CompiledPositionCovObject>> position(
      m, "CompiledPositionWithCovariance",
      Doc("A compiled position query with covariance (evaluate(): a Position and its (3, 3) "
          "covariance).",
          kCompiledCovDoc)
          .c_str());
  DefEvaluate<CompiledPositionCovObject>(position, "(Position, covariance (3, 3) numpy array).");
  position.def("__repr__", [](const CompiledPositionCovObject& c) {
    return "CompiledPositionWithCovariance(" + PoseKindText(c) + ")";
  });
  py::class_<CompiledOrientationCovObject, std::shared_ptr<CompiledOrientationCovObject>>
      orientation(m, "CompiledOrientationWithCovariance",
                  Doc("A compiled orientation query with covariance (evaluate(): an Orientation "
                      "and its (3, 3) covariance).",
                      kCompiledCovDoc)
                      .c_str());
  DefEvaluate<CompiledOrientationCovObject>(orientation,
                                            "(Orientation, covariance (3, 3) numpy array).");
  orientation.def("__repr__", [](const CompiledOrientationCovObject& c) {
    return "CompiledOrientationWithCovariance(" + PoseKindText(c) + ")";
  });
  py::class_<CompiledTwistCovObject, std::shared_ptr<CompiledTwistCovObject>> twist(
      m, "CompiledTwistWithCovariance",
      Doc("A compiled twist, linear velocity or angular velocity query with covariance "
          "(evaluate(): a Twist and its (6, 6) covariance, or a LinearVelocity or "
          "AngularVelocity and its (3, 3) covariance, as compiled).",
          kCompiledCovDoc)
          .c_str());
  DefEvaluate<CompiledTwistCovObject>(twist,
                                      "(Twist, (6, 6)), (LinearVelocity, (3, 3)) or "
                                      "(AngularVelocity, (3, 3)) covariance, as compiled.");
  twist.def("__repr__", [](const CompiledTwistCovObject& c) {
    return "CompiledTwistWithCovariance(" + TwistText(c) + ")";
  });
}

namespace {

// The keywords of the compile methods (undefined below): the one-shot queries' names, then
// covariance_order where it applies (uncertainty.cc), then source for the twist kinds.
#define SEMGRAPH_COMPILE_COV_POSE_ARGS                                                       \
  py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),                   \
                 py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),              \
                 py::arg("point") = py::none(), py::arg("orientation") = py::none(),         \
                 py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(), \
                 py::arg("expressed_in") = py::none()

constexpr const char* kCompileCovErrors = R"(
QueryError as the one-shot query without time keywords (invalid_name, unknown_frame,
unknown_body, frame_body_mismatch, no_pose_path, representation_constraint; no_twist_path for
velocities); ValueError for a bad covariance_order or source.)";

// compile_position_with_covariance and compile_orientation_with_covariance: the pose query's
// keywords, one part of its answer (`compile`: the graph's Compile...WithCovariance).
template <class Object, class Compile>
void DefCompilePart(GraphClass& graph, const char* name, Compile compile, const char* summary) {
  graph.def(
      name,
      [name, compile](const GraphBox& b, py::handle of, py::handle body, py::handle wrt,
                      py::handle ref_body, py::handle point, py::handle orientation,
                      py::handle ref_point, py::handle ref_orientation, py::handle expressed_in) {
        const PoseNames n = ReadPoseNames(name, of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = compile(g, spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<Object>(Object{self, std::move(*r)});
        });
      },
      SEMGRAPH_COMPILE_COV_POSE_ARGS, Doc(summary, kCompileCovErrors).c_str());
}

void BindCompilePoseCovariance(GraphClass& graph) {
  graph.def(
      "compile_pose_with_covariance",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle order) {
        const char* fn = "compile_pose_with_covariance";
        const PoseNames n = ReadPoseNames(fn, of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::CovarianceOrder o = OrderArg(order, fn);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompilePoseWithCovariance(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledPoseCovObject>(
              CompiledPoseCovObject{self, std::move(*r), o});
        });
      },
      SEMGRAPH_COMPILE_COV_POSE_ARGS, py::arg("covariance_order") = py::none(),
      Doc("The query of pose_with_covariance(), compiled (a CompiledPoseWithCovariance); "
          "covariance_order: 'linear_angular' (default) or 'angular_linear', the rows of every "
          "evaluation's (6, 6) covariance.",
          kCompileCovErrors)
          .c_str());
  DefCompilePart<CompiledPositionCovObject>(
      graph, "compile_position_with_covariance",
      [](const auto& g, const core::PoseSpec& spec) {
        return g.CompilePositionWithCovariance(spec);
      },
      "The query of position_with_covariance(), compiled (a CompiledPositionWithCovariance).");
  DefCompilePart<CompiledOrientationCovObject>(
      graph, "compile_orientation_with_covariance",
      [](const auto& g, const core::PoseSpec& spec) {
        return g.CompileOrientationWithCovariance(spec);
      },
      "The query of orientation_with_covariance(), compiled (a "
      "CompiledOrientationWithCovariance).");
}

#undef SEMGRAPH_COMPILE_COV_POSE_ARGS

std::shared_ptr<CompiledTwistCovObject> TwistObject(GraphPtr self, core::CovarianceOrder order) {
  auto c = std::make_shared<CompiledTwistCovObject>();
  c->graph = std::move(self);
  c->order = order;
  return c;
}

constexpr const char* kSourceDoc =
    " source: 'twists' (default) or 'poses' (the pose history's time derivative, each "
    "differentiated edge's covariance from its two bracketing samples; evaluate under a time "
    "policy, or now: the newest samples).";

void BindCompileTwistCovariance(GraphClass& graph) {
  graph.def(
      "compile_twist_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle order, py::handle source) {
        const char* fn = "compile_twist_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        const core::CovarianceOrder o = OrderArg(order, fn);
        const core::TwistSource src = TwistSourceArg(source, fn);
        auto c = TwistObject(Self(b), o);
        b.Visit([&](const auto& g) {
          auto r = g.CompileTwistWithCovariance(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          c->twist = r->semantics();
          c->query = std::move(*r);
        });
        return c;
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("covariance_order") = py::none(), py::arg("source") = py::none(),
      Doc("The query of twist_with_covariance(), compiled (a CompiledTwistWithCovariance "
          "returning a Twist and its (6, 6) covariance, rows in covariance_order: "
          "'linear_angular' (default) or 'angular_linear').",
          (std::string(kSourceDoc) + kCompileCovErrors).c_str())
          .c_str());
  graph.def(
      "compile_linear_velocity_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle source) {
        const char* fn = "compile_linear_velocity_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, fn);
        auto c = TwistObject(Self(b), core::CovarianceOrder::kLinearAngular);
        b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          // What CompileLinearVelocityWithCovariance wraps (its errors too), whose semantics
          // the wrapper does not keep.
          auto r = g.CompileTwistWithCovariance(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          c->twist = r->semantics();
          c->query = core::CompiledLinearVelocityWithCovariance<B>(std::move(*r));
        });
        return c;
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("source") = py::none(),
      Doc("The query of linear_velocity_with_covariance(), compiled (a "
          "CompiledTwistWithCovariance returning a LinearVelocity and its (3, 3) covariance).",
          (std::string(kSourceDoc) + kCompileCovErrors).c_str())
          .c_str());
  graph.def(
      "compile_angular_velocity_with_covariance",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in,
         py::handle source) {
        const char* fn = "compile_angular_velocity_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, py::none(), body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, fn);
        auto c = TwistObject(Self(b), core::CovarianceOrder::kLinearAngular);
        b.Visit([&](const auto& g) {
          auto r = g.CompileAngularVelocityWithCovariance(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          // The semantics of the twist it wraps, at [r]'s origin (as the core compiles it; the
          // same plan, so this succeeds too): build time only.
          core::TwistSpec at_r = spec;
          at_r.point = spec.coordinate_frame;
          auto twist = g.CompileTwistWithCovariance(at_r, src);
          if (!twist) ThrowTwistQuery(g, twist.error(), spec);
          c->twist = twist->semantics();
          c->query = std::move(*r);
        });
        return c;
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), py::arg("source") = py::none(),
      Doc("The query of angular_velocity_with_covariance(), compiled (a "
          "CompiledTwistWithCovariance returning an AngularVelocity and its (3, 3) covariance).",
          (std::string(kSourceDoc) + kCompileCovErrors).c_str())
          .c_str());
}

}  // namespace

void BindCompiledCovarianceMethods(GraphClass& graph) {
  BindCompilePoseCovariance(graph);
  BindCompileTwistCovariance(graph);
}

}  // namespace semgraph::python
