// Covariances in Python (docs/uncertainty.md): the covariance keywords of add_pose / add_twist
// and the queries with the covariance of their answer, SceneGraph.pose_with_covariance ...
// angular_velocity_with_covariance, each returning (result, covariance) with the covariance a
// numpy (6, 6) or (3, 3) array (the C++ GetPoseWithCovariance ... as they are).
#include "uncertainty.h"

#include <memory>
#include <string>
#include <utility>

#include "docstrings.h"

namespace semgraph::python {

namespace {

std::string_view TextArg(py::handle value, const char* function, const char* argument) {
  if (!py::isinstance<py::str>(value)) {
    throw py::type_error(std::string(function) + "(): " + argument + " must be a str, got " +
                         TypeName(value));
  }
  return NameArg(value, function, argument);
}

template <int N>
py::tuple WithCovariance(py::object result, const Eigen::Matrix<double, N, N>& S) {
  const Eigen::Matrix<double, N, N, Eigen::RowMajor> rows = S;
  return py::make_tuple(std::move(result), Array(rows.data(), {N, N}));
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

constexpr const char* kCovDoc = R"(
Returns (result, covariance): the first-order covariance of the answer's coordinates
(docs/uncertainty.md) under the independent covariances of the edges it uses, of the current
values (no time keywords). covariance_order: 'linear_angular' (default) or 'angular_linear'
for the (6, 6) answers. QueryError as the plain query.)";

void BindPoseCovarianceQueries(GraphClass& graph) {
  graph.def(
      "pose_with_covariance",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point, py::handle ref_orientation,
         py::handle expressed_in, py::handle order) {
        const char* fn = "pose_with_covariance";
        const PoseNames n = ReadPoseNames(fn, of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::CovarianceOrder o = OrderOrDefault(order, fn);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          auto r = g.GetPoseWithCovariance(spec, o);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return WithCovariance(
              py::cast(MakePoseResult<B>(self, r->value.semantics, r->value.value)), r->covariance);
        });
      },
      py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),
      py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(), py::arg("point") = py::none(),
      py::arg("orientation") = py::none(), py::arg("ref_point") = py::none(),
      py::arg("ref_orientation") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("covariance_order") = py::none(),
      (std::string("pose() with the covariance of its answer, (6, 6): rows (dp, dtheta).") +
       kCovDoc)
          .c_str());
  const auto position_or_orientation = [&](const char* name, bool position) {
    graph.def(
        name,
        [name, position](const GraphBox& b, py::handle of, py::handle body, py::handle wrt,
                         py::handle ref_body, py::handle point, py::handle orientation,
                         py::handle ref_point, py::handle ref_orientation,
                         py::handle expressed_in) {
          const PoseNames n = ReadPoseNames(name, of, body, wrt, ref_body, point, orientation,
                                            ref_point, ref_orientation, expressed_in);
          const core::PoseSpec spec = n.Spec();
          GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
          return b.Visit([&](const auto& g) -> py::tuple {
            using B = typename std::decay_t<decltype(g)>::Backend;
            if (position) {
              auto r = g.GetPositionWithCovariance(spec);
              if (!r) ThrowPoseQuery(g, r.error(), spec, n);
              return WithCovariance(
                  py::cast(PositionResult{self, r->value.semantics, r->value.value}),
                  r->covariance);
            }
            auto r = g.GetOrientationWithCovariance(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return WithCovariance(
                py::cast(MakeOrientationResult<B>(self, r->value.semantics, r->value.value)),
                r->covariance);
          });
        },
        py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),
        py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),
        py::arg("point") = py::none(), py::arg("orientation") = py::none(),
        py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(),
        py::arg("expressed_in") = py::none(),
        (std::string(position ? "position() with the covariance of its answer, (3, 3) (dp)."
                              : "orientation() with the covariance of its answer, (3, 3) "
                                "(dtheta).") +
         kCovDoc)
            .c_str());
  };
  position_or_orientation("position_with_covariance", true);
  position_or_orientation("orientation_with_covariance", false);
}

void BindTwistCovarianceQueries(GraphClass& graph) {
  graph.def(
      "twist_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle order) {
        const char* fn = "twist_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        const core::CovarianceOrder o = OrderOrDefault(order, fn);
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.GetTwistWithCovariance(spec, o);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return WithCovariance(
              py::cast(TwistResult{self, r->value.semantics, r->value.linear, r->value.angular}),
              r->covariance);
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("covariance_order") = py::none(),
      (std::string("twist() with the covariance of its answer, (6, 6): rows (dv, dw).") + kCovDoc)
          .c_str());
  graph.def(
      "linear_velocity_with_covariance",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in) {
        const char* fn = "linear_velocity_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, point, body, ref_body, expressed_in);
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.GetLinearVelocityWithCovariance(spec);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return WithCovariance(
              py::cast(LinearVelocityResult{self, r->value.semantics, r->value.value}),
              r->covariance);
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      (std::string("linear_velocity() with the covariance of its answer, (3, 3).") + kCovDoc)
          .c_str());
  graph.def(
      "angular_velocity_with_covariance",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in) {
        const char* fn = "angular_velocity_with_covariance";
        const core::TwistSpec spec = ReadTwistSpec(fn, py::none(), body, ref_body, expressed_in);
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.GetAngularVelocityWithCovariance(spec);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return WithCovariance(
              py::cast(AngularVelocityResult{self, r->value.semantics, r->value.value}),
              r->covariance);
        });
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(),
      (std::string("angular_velocity() with the covariance of its answer, (3, 3).") + kCovDoc)
          .c_str());
}

}  // namespace

void BindUncertainty(GraphClass& graph) {
  BindPoseCovarianceQueries(graph);
  BindTwistCovarianceQueries(graph);
}

}  // namespace semgraph::python
