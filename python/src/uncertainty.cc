// Covariances in Python (docs/uncertainty.md): the covariance keywords of add_pose / add_twist
// and the queries with the covariance of their answer, SceneGraph.pose_with_covariance ...
// angular_velocity_with_covariance, each returning (result, covariance) with the covariance a
// numpy (6, 6) or (3, 3) array (the C++ GetPoseWithCovariance ... as they are), of the current
// values or, with the plain queries' time keywords (timed.h), at a time or a time travel (the
// result's .time then the TimeReport, as the plain timed queries').
#include "uncertainty.h"

#include <memory>
#include <string>
#include <utility>

#include "docstrings.h"
#include "timed.h"

namespace semgraph::python {

namespace {

std::string_view TextArg(py::handle value, const char* function, const char* argument) {
  if (!py::isinstance<py::str>(value)) {
    throw py::type_error(std::string(function) + "(): " + argument + " must be a str, got " +
                         TypeName(value));
  }
  return NameArg(value, function, argument);
}

core::CovarianceOrder OrderOrDefault(py::handle order, const char* function) {
  return CovarianceOrderArg(order, function, "covariance_order");
}

}  // namespace

core::CovarianceOrder CovarianceOrderArg(py::handle order, const char* function,
                                         const char* argument) {
  if (order.is_none()) return core::CovarianceOrder::kLinearAngular;
  const std::string_view s = TextArg(order, function, argument);
  if (s == "linear_angular") return core::CovarianceOrder::kLinearAngular;
  if (s == "angular_linear") return core::CovarianceOrder::kAngularLinear;
  throw py::value_error(std::string(function) + "(): " + argument +
                        " must be 'linear_angular' or 'angular_linear', got '" + std::string(s) +
                        "'");
}

CovarianceArgs ReadCovarianceArgs(py::handle covariance, py::handle order, py::handle convention,
                                  const char* function) {
  CovarianceArgs c;
  if (covariance.is_none()) {
    if (!order.is_none() || !convention.is_none()) {
      throw py::value_error(std::string(function) +
                            "(): covariance_order= and convention= need covariance=");
    }
    return c;
  }
  c.given = true;
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> rows;
  NumbersArg(covariance, 6, 36, rows.data(), function, "covariance");
  c.S = rows;
  c.order = CovarianceOrderArg(order, function, "covariance_order");
  if (!convention.is_none()) {
    const std::string_view s = TextArg(convention, function, "convention");
    if (s == "body") {
      c.convention = core::PoseCovarianceConvention::kBody;
    } else if (s != "coordinates") {
      throw py::value_error(std::string(function) +
                            "(): convention must be 'coordinates' or 'body', got '" +
                            std::string(s) + "'");
    }
  }
  return c;
}

namespace {

// The keywords of the queries with covariance (undefined at the end of the file): the names and
// time keywords of the plain queries (queries.cc), then covariance_order where it applies.
#define SEMGRAPH_COV_POSE_ARGS                                                               \
  py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),                   \
                 py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),              \
                 py::arg("point") = py::none(), py::arg("orientation") = py::none(),         \
                 py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(), \
                 py::arg("expressed_in") = py::none()
#define SEMGRAPH_COV_TIME_ARGS                                           \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
  py::arg("not_before") = py::none(), py::arg("ref_at") = py::none(),    \
  py::arg("fixed") = py::none()
#define SEMGRAPH_COV_TWIST_TIME_ARGS                                     \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(), \
  py::arg("not_before") = py::none(), py::arg("source") = py::none()

constexpr const char* kCovDoc = R"(
Returns (result, covariance): the first-order covariance of the answer's coordinates
(docs/uncertainty.md) under the independent covariances of the edges it uses.
covariance_order: 'linear_angular' (default) or 'angular_linear' for the (6, 6) answers.
Time (docs/uncertainty.md, "Covariances and time"; times are int nanoseconds or float seconds):
none given: each edge's current value and covariance, and result.time is None; given: the
timed query's answer with its .time (a TimeReport, as the plain query's) and each edge's
covariance at the time it is read (between samples i and i+1 at lambda:
(1 - lambda) S_i + lambda S_i+1 in the edge form; extrapolated pose edges propagate their
integration twist's covariance).
  at                 a time, 'latest' or 'latest_common' (as the plain query)
  max_extrapolation  with at=<time>: how far beyond an edge's samples it may be extrapolated
  not_before         any policy: an edge whose newest sample is older fails with stale)";
constexpr const char* kCovTravelDoc = R"(
  ref_at, fixed      time travel: the point side at `at`, the reference side at `ref_at`,
                     through the frame `fixed`; the two sides' perturbations are independent
                     (an edge used on both contributes twice))";
constexpr const char* kCovTwistDoc = R"(
  source             'twists' (default: the twist edges) or 'poses' (the time derivative of the
                     pose history: each differentiated edge's twist with the covariance from
                     its two bracketing samples, independent); no time travel.)";
constexpr const char* kCovErrors = R"(
QueryError as the plain query: invalid_name, unknown_frame, unknown_body, frame_body_mismatch,
no_pose_path, representation_constraint (no_twist_path for velocities); under a time policy
also invalid_number, extrapolation and stale. TypeError / ValueError for a bad keyword.)";

std::string CovDoc(const std::string& head, bool travel) {
  return head + kCovDoc + (travel ? kCovTravelDoc : kCovTwistDoc) + kCovErrors;
}

void BindPoseCovarianceQueries(GraphClass& graph) {
  graph.def(
      "pose_with_covariance",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle order, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const char* fn = "pose_with_covariance";
        const TimeQuery t =
            TimeQueryArgs(fn, at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames(fn, of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::CovarianceOrder o = OrderOrDefault(order, fn);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetPoseWithCovariance(spec, o);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return WithCovariance(
                py::cast(MakePoseResult<B>(self, r->value.semantics, r->value.value)),
                r->covariance);
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetPoseWithCovariance(spec, *t.travel, o)
                                                      : g.GetPoseWithCovariance(spec, t.policy, o);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          PoseResult out = MakePoseResult<B>(self, r->value.value.semantics, r->value.value.value);
          out.time = r->time;
          return WithCovariance(py::cast(std::move(out)), r->value.covariance);
        });
      },
      SEMGRAPH_COV_POSE_ARGS, py::arg("covariance_order") = py::none(), SEMGRAPH_COV_TIME_ARGS,
      CovDoc("pose() with the covariance of its answer, (6, 6): rows (dp, dtheta).", true).c_str());
  const auto position_or_orientation = [&](const char* name, bool position) {
    graph.def(
        name,
        [name, position](const GraphBox& b, py::handle of, py::handle body, py::handle wrt,
                         py::handle ref_body, py::handle point, py::handle orientation,
                         py::handle ref_point, py::handle ref_orientation, py::handle expressed_in,
                         py::handle at, py::handle max_extrapolation, py::handle not_before,
                         py::handle ref_at, py::handle fixed) {
          const TimeQuery t =
              TimeQueryArgs(name, at, max_extrapolation, not_before, ref_at, fixed, true);
          const PoseNames n = ReadPoseNames(name, of, body, wrt, ref_body, point, orientation,
                                            ref_point, ref_orientation, expressed_in);
          const core::PoseSpec spec = n.Spec();
          GraphPtr self = Self(b);
          const bool travel = t.kind == TimeQuery::Kind::kTravel;
          return b.Visit([&](const auto& g) -> py::tuple {
            using B = typename std::decay_t<decltype(g)>::Backend;
            if (position) {
              if (t.kind == TimeQuery::Kind::kNone) {
                auto r = g.GetPositionWithCovariance(spec);
                if (!r) ThrowPoseQuery(g, r.error(), spec, n);
                return WithCovariance(
                    py::cast(PositionResult{self, r->value.semantics, r->value.value}),
                    r->covariance);
              }
              auto r = travel ? g.GetPositionWithCovariance(spec, *t.travel)
                              : g.GetPositionWithCovariance(spec, t.policy);
              if (!r) ThrowPoseQuery(g, r.error(), spec, n);
              return WithCovariance(py::cast(PositionResult{self, r->value.value.semantics,
                                                            r->value.value.value, r->time}),
                                    r->value.covariance);
            }
            if (t.kind == TimeQuery::Kind::kNone) {
              auto r = g.GetOrientationWithCovariance(spec);
              if (!r) ThrowPoseQuery(g, r.error(), spec, n);
              return WithCovariance(
                  py::cast(MakeOrientationResult<B>(self, r->value.semantics, r->value.value)),
                  r->covariance);
            }
            auto r = travel ? g.GetOrientationWithCovariance(spec, *t.travel)
                            : g.GetOrientationWithCovariance(spec, t.policy);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            OrientationResult out =
                MakeOrientationResult<B>(self, r->value.value.semantics, r->value.value.value);
            out.time = r->time;
            return WithCovariance(py::cast(std::move(out)), r->value.covariance);
          });
        },
        SEMGRAPH_COV_POSE_ARGS, SEMGRAPH_COV_TIME_ARGS,
        CovDoc(position ? "position() with the covariance of its answer, (3, 3) (dp)."
                        : "orientation() with the covariance of its answer, (3, 3) (dtheta).",
               true)
            .c_str());
  };
  position_or_orientation("position_with_covariance", true);
  position_or_orientation("orientation_with_covariance", false);
}

// The twist kinds: as twist() / linear_velocity() / angular_velocity() read their time
// keywords (no ref_at / fixed keywords: a time travel has no twist), names first.
TimeQuery TwistTimeArgs(const char* fn, py::handle at, py::handle max_extrapolation,
                        py::handle not_before) {
  return TimeQueryArgs(fn, at, max_extrapolation, not_before, py::none(), py::none(), false);
}

void BindTwistCovarianceQueries(GraphClass& graph) {
  graph.def(
      "twist_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle order, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle source) {
        const char* fn = "twist_with_covariance";
        const core::TwistSource src = TwistSourceArg(source, fn);
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        const TimeQuery t = TwistTimeArgs(fn, at, max_extrapolation, not_before);
        const core::CovarianceOrder o = OrderOrDefault(order, fn);
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetTwistWithCovariance(spec, o);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return WithCovariance(
                py::cast(TwistResult{self, r->value.semantics, r->value.linear, r->value.angular}),
                r->covariance);
          }
          auto r = g.GetTwistWithCovariance(spec, t.policy, o, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          const auto& v = r->value.value;
          return WithCovariance(
              py::cast(TwistResult{self, v.semantics, v.linear, v.angular, r->time}),
              r->value.covariance);
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("covariance_order") = py::none(), SEMGRAPH_COV_TWIST_TIME_ARGS,
      CovDoc("twist() with the covariance of its answer, (6, 6): rows (dv, dw).", false).c_str());
  graph.def(
      "linear_velocity_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle source) {
        const char* fn = "linear_velocity_with_covariance";
        const core::TwistSource src = TwistSourceArg(source, fn);
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        const TimeQuery t = TwistTimeArgs(fn, at, max_extrapolation, not_before);
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetLinearVelocityWithCovariance(spec);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return WithCovariance(
                py::cast(LinearVelocityResult{self, r->value.semantics, r->value.value}),
                r->covariance);
          }
          auto r = g.GetLinearVelocityWithCovariance(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return WithCovariance(py::cast(LinearVelocityResult{self, r->value.value.semantics,
                                                              r->value.value.value, r->time}),
                                r->value.covariance);
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      SEMGRAPH_COV_TWIST_TIME_ARGS,
      CovDoc("linear_velocity() with the covariance of its answer, (3, 3).", false).c_str());
  graph.def(
      "angular_velocity_with_covariance",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in,
         py::handle at, py::handle max_extrapolation, py::handle not_before, py::handle source) {
        const char* fn = "angular_velocity_with_covariance";
        const core::TwistSource src = TwistSourceArg(source, fn);
        const core::TwistSpec spec = ReadTwistSpec(fn, py::none(), body, ref_body, expressed_in);
        const TimeQuery t = TwistTimeArgs(fn, at, max_extrapolation, not_before);
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone && src == core::TwistSource::kTwists) {
            auto r = g.GetAngularVelocityWithCovariance(spec);
            if (!r) ThrowTwistQuery(g, r.error(), spec);
            return WithCovariance(
                py::cast(AngularVelocityResult{self, r->value.semantics, r->value.value}),
                r->covariance);
          }
          auto r = g.GetAngularVelocityWithCovariance(spec, t.policy, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return WithCovariance(py::cast(AngularVelocityResult{self, r->value.value.semantics,
                                                               r->value.value.value, r->time}),
                                r->value.covariance);
        });
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), SEMGRAPH_COV_TWIST_TIME_ARGS,
      CovDoc("angular_velocity() with the covariance of its answer, (3, 3).", false).c_str());
}

#undef SEMGRAPH_COV_POSE_ARGS
#undef SEMGRAPH_COV_TIME_ARGS
#undef SEMGRAPH_COV_TWIST_TIME_ARGS

}  // namespace

void BindUncertainty(GraphClass& graph) {
  BindPoseCovarianceQueries(graph);
  BindTwistCovarianceQueries(graph);
}

}  // namespace semgraph::python
