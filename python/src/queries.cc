// The SceneGraph queries (pose, position, orientation, twist, linear_velocity,
// angular_velocity) and their compiled forms (compile_*; the classes are in compiled.cc).
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "common.h"
#include "docstrings.h"
#include "semgraph/semantics/operations.h"
#include "timed.h"

namespace semgraph::python {

namespace {

// The keywords of the queries (undefined at the end of the file).
#define SEMGRAPH_POSE_ARGS                                                                   \
  py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),                   \
                 py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),              \
                 py::arg("point") = py::none(), py::arg("orientation") = py::none(),         \
                 py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(), \
                 py::arg("expressed_in") = py::none()
#define SEMGRAPH_TWIST_ARGS                                                   \
  py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(), \
                 py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none()
#define SEMGRAPH_TIME_ARGS                                               \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
  py::arg("not_before") = py::none(), py::arg("ref_at") = py::none(),    \
  py::arg("fixed") = py::none()
#define SEMGRAPH_TWIST_TIME_ARGS                                         \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
  py::arg("not_before") = py::none(), py::arg("source") = py::none()

// Docstring parts of the queries.
constexpr const char* kQueryErrors = R"(
QueryError (code, and .argument: the keyword at fault where there is one): invalid_name,
unknown_frame, unknown_body, frame_body_mismatch, no_pose_path, representation_constraint, and
for velocities no_twist_path; under a time policy also invalid_number (a negative
max_extrapolation), extrapolation (an edge has no sample around the time; the message names it
and its range) and stale (not_before).)";
constexpr const char* kTimeCommonDoc = R"(
Time (docs/time.md; times are int nanoseconds or float seconds; none given: each edge's current
value, and .time is None; given: the result's .time is a TimeReport):
  at                 a time: every stamped edge at that time (interpolated); 'latest': each
                     edge's newest sample; 'latest_common': at the newest time all stamped
                     edges used have (tf2's Time(0))
  max_extrapolation  with at=<time>: how far beyond an edge's samples it may be extrapolated
                     (with the twists the graph has); default 0, never
  not_before         any policy: an edge whose newest sample is older fails with stale)";

void BindPoseQueries(GraphClass& graph) {
  const std::string time_doc = std::string(kTimeCommonDoc) + R"(
  ref_at, fixed      time travel: the point side at `at`, the reference side at `ref_at`,
                     through the frame `fixed`, assumed fixed between the two)";
  const char* kTimeDoc = time_doc.c_str();
  graph.def(
      "pose",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t =
            TimeQueryArgs("pose", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("pose", of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetPose(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return MakePoseResult<B>(self, r->semantics, r->value);
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetPose(spec, *t.travel)
                                                      : g.GetPose(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          PoseResult out = MakePoseResult<B>(self, r->value.semantics, r->value.value);
          out.time = r->time;
          return out;
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The pose of `of` relative to `wrt`, expressed in `expressed_in` (a Pose).\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str())
          .c_str());
  graph.def(
      "position",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t =
            TimeQueryArgs("position", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("position", of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetPosition(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return PositionResult{self, r->semantics, r->value};
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetPosition(spec, *t.travel)
                                                      : g.GetPosition(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return PositionResult{self, r->value.semantics, r->value.value, r->time};
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The position of the origin of `of` (or `point`) relative to the origin of `wrt` (or "
          "`ref_point`), in `expressed_in` (a Position). Orientation names are ignored.\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str())
          .c_str());
  graph.def(
      "orientation",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t =
            TimeQueryArgs("orientation", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("orientation", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetOrientation(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return MakeOrientationResult<B>(self, r->semantics, r->value);
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetOrientation(spec, *t.travel)
                                                      : g.GetOrientation(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          OrientationResult out =
              MakeOrientationResult<B>(self, r->value.semantics, r->value.value);
          out.time = r->time;
          return out;
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The orientation of [of] (or [orientation]) relative to [wrt] (or [ref_orientation]), "
          "in `expressed_in` (an Orientation). Point names are ignored.\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str())
          .c_str());
}

void BindTwistQueries(GraphClass& graph) {
  const std::string twist_time_doc = std::string(kTimeCommonDoc) + R"(
  source             'twists' (default: the twist edges) or 'poses' (the time derivative of the
                     pose history; no twist edge read))";
  const char* kTwistTimeDoc = twist_time_doc.c_str();
  constexpr const char* kTwistNamesDoc = R"(
Names (keyword-only):
  point         a frame: the velocity is that of the point of `body` at this frame's origin
  body          the moving body C (default: the body of `point`'s frame)
  ref_body      the reference body D
  expressed_in  the coordinate frame [r])";
  graph.def(
      "twist",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle source) {
        const core::TwistSpec spec = ReadTwistSpec("twist", point, body, ref_body, expressed_in);
        const TimeQuery t = TimeQueryArgs("twist", at, max_extrapolation, not_before, py::none(),
                                          py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "twist");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetTwist(spec);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return TwistResult{self, r->semantics, r->linear, r->angular};
          }
          auto r = g.GetTwist(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return TwistResult{self, r->value.semantics, r->value.linear, r->value.angular, r->time};
        });
      },
      SEMGRAPH_TWIST_ARGS, SEMGRAPH_TWIST_TIME_ARGS,
      Doc("The twist of `body` at `point` relative to `ref_body`, in `expressed_in` (a Twist).\n",
          (std::string(kTwistNamesDoc) + kTwistTimeDoc + kQueryErrors).c_str())
          .c_str());
  graph.def(
      "linear_velocity",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("linear_velocity", point, body, ref_body, expressed_in);
        const TimeQuery t = TimeQueryArgs("linear_velocity", at, max_extrapolation, not_before,
                                          py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "linear_velocity");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetLinearVelocity(spec);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return LinearVelocityResult{self, r->semantics, r->value};
          }
          auto r = g.GetLinearVelocity(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return LinearVelocityResult{self, r->value.semantics, r->value.value, r->time};
        });
      },
      SEMGRAPH_TWIST_ARGS, SEMGRAPH_TWIST_TIME_ARGS,
      Doc("The velocity of the point of `body` at `point` relative to `ref_body`, in "
          "`expressed_in` (a LinearVelocity).\n",
          (std::string(kTwistNamesDoc) + kTwistTimeDoc + kQueryErrors).c_str())
          .c_str());
  graph.def(
      "angular_velocity",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("angular_velocity", py::none(), body, ref_body, expressed_in);
        const TimeQuery t = TimeQueryArgs("angular_velocity", at, max_extrapolation, not_before,
                                          py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "angular_velocity");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetAngularVelocity(spec);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return AngularVelocityResult{self, r->semantics, r->value};
          }
          auto r = g.GetAngularVelocity(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return AngularVelocityResult{self, r->value.semantics, r->value.value, r->time};
        });
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), SEMGRAPH_TWIST_TIME_ARGS,
      Doc("The angular velocity of `body` relative to `ref_body`, in `expressed_in` (an "
          "AngularVelocity). No point is needed.\n",
          (std::string(kTwistTimeDoc) + kQueryErrors).c_str())
          .c_str());
}

void BindCompilePoseQueries(GraphClass& graph) {
  graph.def(
      "compile_pose",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_pose", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompilePose(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledPoseObject>(CompiledPoseObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS,
      "The pose query of pose(), compiled (a CompiledPose); the same QueryErrors as pose().");
  graph.def(
      "compile_position",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_position", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompilePosition(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledPositionObject>(
              CompiledPositionObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS, "The query of position(), compiled (a CompiledPosition).");
  graph.def(
      "compile_orientation",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_orientation", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompileOrientation(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledOrientationObject>(
              CompiledOrientationObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS, "The query of orientation(), compiled (a CompiledOrientation).");
}

void BindCompileTwistQueries(GraphClass& graph) {
  graph.def(
      "compile_twist",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_twist", point, body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_twist");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompileTwist(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          auto c = std::make_shared<CompiledTwistObject>(
              CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kTwist;
          return c;
        });
      },
      SEMGRAPH_TWIST_ARGS, py::arg("source") = py::none(),
      "The query of twist(), compiled (a CompiledTwist returning Twist). source: 'twists' "
      "(default) "
      "or 'poses' (the pose history's time derivative; evaluate under a time policy).");
  graph.def(
      "compile_linear_velocity",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_linear_velocity", point, body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_linear_velocity");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          semantics::LinearVelocitySemantics linear;
          if (src == core::TwistSource::kTwists) {
            auto checked = g.GetLinearVelocity(spec);  // its semantics and errors
            if (!checked) ThrowTwistQuery(g, checked.error(), spec);
            linear = checked->semantics;
          }
          auto r = g.CompileTwist(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          // From poses there is no untimed query to ask: the linear part of the compiled twist.
          if (src == core::TwistSource::kPoses) linear = semantics::LinearOf(r->semantics());
          auto c = std::make_shared<CompiledTwistObject>(
              CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kLinear;
          c->linear_semantics = linear;
          return c;
        });
      },
      SEMGRAPH_TWIST_ARGS, py::arg("source") = py::none(),
      "The query of linear_velocity(), compiled (a CompiledTwist returning LinearVelocity); source "
      "as "
      "compile_twist.");
  graph.def(
      "compile_angular_velocity",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in,
         py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_angular_velocity", py::none(), body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_angular_velocity");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          semantics::AngularVelocitySemantics angular;
          if (src == core::TwistSource::kTwists) {
            auto checked = g.GetAngularVelocity(spec);
            if (!checked) ThrowTwistQuery(g, checked.error(), spec);
            angular = checked->semantics;
          }
          // As GetAngularVelocity does: the twist at the coordinate frame's origin.
          core::TwistSpec at_r = spec;
          at_r.point = spec.coordinate_frame;
          auto r = g.CompileTwist(at_r, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          if (src == core::TwistSource::kPoses) angular = semantics::AngularOf(r->semantics());
          auto c = std::make_shared<CompiledTwistObject>(
              CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kAngular;
          c->angular_semantics = angular;
          return c;
        });
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), py::arg("source") = py::none(),
      "The query of angular_velocity(), compiled (a CompiledTwist returning AngularVelocity); "
      "source as "
      "compile_twist.");
}

#undef SEMGRAPH_POSE_ARGS
#undef SEMGRAPH_TWIST_ARGS
#undef SEMGRAPH_TIME_ARGS
#undef SEMGRAPH_TWIST_TIME_ARGS

}  // namespace

void BindQueries(GraphClass& graph) {
  BindPoseQueries(graph);
  BindTwistQueries(graph);
  BindCompilePoseQueries(graph);
  BindCompileTwistQueries(graph);
}

}  // namespace semgraph::python
