// The SceneGraph class: its box (GraphBox), constructor and time options, counts and names,
// the build methods (add_*, remove_*) and the inspection methods (dump, check_invariants, dot,
// to_script). Queries, handles, batches, time and kinematics add their methods from their own
// files (queries.cc, handles.cc, batches.cc, timed.cc, kinematics.cc).
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "common.h"
#include "docstrings.h"
#include "semgraph/coord/validate.h"
#include "semgraph/core/scene_graph_debug.h"
#include "timed.h"
#include "uncertainty.h"

#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
#include "semgraph/script/scene_script.h"
#endif

namespace semgraph::python {

GraphBox::GraphBox(bool homogeneous)
    : graph(homogeneous ? decltype(graph)(std::in_place_index<1>)
                        : decltype(graph)(std::in_place_index<0>)) {}
GraphBox::GraphBox(bool, QuaternionGraph&& made) : graph(std::in_place_index<0>, std::move(made)) {}
GraphBox::GraphBox(bool, HomogeneousGraph&& made)
    : graph(std::in_place_index<1>, std::move(made)) {}

const char* GraphBox::representation() const noexcept {
  return Visit(
      [](const auto& g) -> const char* { return std::decay_t<decltype(g)>::Backend::kName; });
}

const semantics::NameTable& GraphBox::names() const noexcept {
  return Visit([](const auto& g) -> const semantics::NameTable& { return g.names(); });
}

namespace {

GraphPtr Make(py::handle representation, py::handle window, py::handle interpolation,
              py::handle duplicate_stamp, py::handle sample_capacity) {
  const std::string_view r = NameArg(representation, "SceneGraph", "representation");
  if (!(r == "quaternion" || r.empty() || r == "homogeneous")) {
    throw py::value_error(
        "SceneGraph(): representation must be 'quaternion' or 'homogeneous', not '" +
        std::string(r) + "'");
  }
  const bool homogeneous = r == "homogeneous";
  if (window.is_none() && interpolation.is_none() && duplicate_stamp.is_none() &&
      sample_capacity.is_none()) {
    return std::make_shared<GraphBox>(homogeneous);
  }
  core::TimeOptions options;
  if (!window.is_none()) {
    options.window =
        core::Duration::Nanoseconds(NanosecondsArg(window, "SceneGraph", "window", false));
  }
  if (!interpolation.is_none()) {
    const std::string_view i = NameArg(interpolation, "SceneGraph", "interpolation");
    if (i == "screw") {
      options.interpolation = core::Interpolation::kScrew;
    } else if (i == "linear") {
      options.interpolation = core::Interpolation::kLinear;
    } else {
      throw py::value_error("SceneGraph(): interpolation must be 'screw' or 'linear', not '" +
                            std::string(i) + "'");
    }
  }
  if (!duplicate_stamp.is_none()) {
    const std::string_view d = NameArg(duplicate_stamp, "SceneGraph", "duplicate_stamp");
    if (d == "replace") {
      options.duplicate_stamp = core::DuplicatePolicy::kReplace;
    } else if (d == "reject") {
      options.duplicate_stamp = core::DuplicatePolicy::kReject;
    } else {
      throw py::value_error("SceneGraph(): duplicate_stamp must be 'replace' or 'reject', not '" +
                            std::string(d) + "'");
    }
  }
  if (!sample_capacity.is_none()) {
    if (PyBool_Check(sample_capacity.ptr()) || !PyIndex_Check(sample_capacity.ptr())) {
      throw py::type_error("SceneGraph(): sample_capacity must be an int, not " +
                           TypeName(sample_capacity));
    }
    const auto n = sample_capacity.cast<long long>();
    // Negative: below the core's minimum of 2, which it refuses with its own message.
    options.sample_capacity = n < 0 ? 0 : static_cast<std::size_t>(n);
  }
  auto make = [&](auto tag) -> GraphPtr {
    using G = typename decltype(tag)::type;
    auto made = G::Create(options);
    if (!made) ThrowRejected(made.error());
    return std::make_shared<GraphBox>(homogeneous, std::move(*made));
  };
  if (homogeneous) return make(std::type_identity<HomogeneousGraph>{});
  return make(std::type_identity<QuaternionGraph>{});
}

// add_pose(): a timeless, stamped or repaired add (the docstring in BindBuild).
py::object AddPose(GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
                   py::handle point, py::handle orientation, py::handle ref_point,
                   py::handle ref_orientation, py::handle expressed_in, py::handle position,
                   py::handle rotation, py::handle quaternion, py::handle rotation_matrix,
                   py::handle rpy, py::handle stamp, py::handle repair, py::handle covariance,
                   py::handle covariance_order, py::handle convention) {
  const PoseNames n = ReadPoseNames("add_pose", of, body, wrt, ref_body, point, orientation,
                                    ref_point, ref_orientation, expressed_in);
  const Eigen::Vector3d p = Vector3Arg(position, "add_pose", "position");
  const RotationArg rot = RotationArgs(rotation, quaternion, rotation_matrix, rpy, "add_pose");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "add_pose", "stamp", false);
  const std::optional<core::RepairPolicy> policy = RepairArg(repair, "add_pose");
  if (t && policy) {
    throw py::value_error(
        "add_pose(): stamp= and repair= cannot be combined (repair applies to "
        "timeless relations)");
  }
  const CovarianceArgs cov =
      ReadCovarianceArgs(covariance, covariance_order, convention, "add_pose");
  if (cov.given && policy) {
    throw py::value_error("add_pose(): covariance= and repair= cannot be combined in this version");
  }
  const core::PoseSpec spec = n.Spec();
  std::lock_guard<WriterMutex> lock(b.writer);
  if (policy) {
    return b.Visit([&](auto& g) -> py::object {
      // The core repairs quaternion values: a valid matrix is converted; an invalid one is
      // refused by the plain add, with its message (and no change).
      Eigen::Quaterniond q = rot.q;
      if (rot.is_matrix) {
        if (!coord::ValidateRotationMatrix(rot.R)) Check(g.AddPose(spec, rot.R, p));
        q = Eigen::Quaterniond(rot.R).normalized();
      }
      auto r = g.AddPose(spec, q, p, *policy);
      if (!r) ThrowRejected(r.error());
      return py::cast(std::move(*r));
    });
  }
  Check(b.Visit([&](auto& g) {
    if (cov.given && t) {
      return rot.is_matrix ? g.AddPose(spec, rot.R, p, *t, cov.Input())
                           : g.AddPose(spec, rot.q, p, *t, cov.Input());
    }
    if (cov.given) {
      return rot.is_matrix ? g.AddPose(spec, rot.R, p, cov.Input())
                           : g.AddPose(spec, rot.q, p, cov.Input());
    }
    if (t) return rot.is_matrix ? g.AddPose(spec, rot.R, p, *t) : g.AddPose(spec, rot.q, p, *t);
    return rot.is_matrix ? g.AddPose(spec, rot.R, p) : g.AddPose(spec, rot.q, p);
  }));
  return py::none();
}

// add_twist(): as add_pose.
py::object AddTwist(GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
                    py::handle expressed_in, py::handle linear, py::handle angular,
                    py::handle stamp, py::handle repair, py::handle covariance,
                    py::handle covariance_order, py::handle linear_acceleration,
                    py::handle angular_acceleration) {
  const core::TwistSpec spec = ReadTwistSpec("add_twist", point, body, ref_body, expressed_in);
  const Eigen::Vector3d v = Vector3Arg(linear, "add_twist", "linear");
  const Eigen::Vector3d w = Vector3Arg(angular, "add_twist", "angular");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "add_twist", "stamp", false);
  const std::optional<core::RepairPolicy> policy = RepairArg(repair, "add_twist");
  if (t && policy) {
    throw py::value_error(
        "add_twist(): stamp= and repair= cannot be combined (repair applies "
        "to timeless relations)");
  }
  const CovarianceArgs cov =
      ReadCovarianceArgs(covariance, covariance_order, py::none(), "add_twist");
  if (cov.given && policy) {
    throw py::value_error(
        "add_twist(): covariance= and repair= cannot be combined in this version");
  }
  const bool accelerated = !linear_acceleration.is_none() || !angular_acceleration.is_none();
  const core::AccelerationInput acceleration{
      Vector3Arg(linear_acceleration, "add_twist", "linear_acceleration"),
      Vector3Arg(angular_acceleration, "add_twist", "angular_acceleration")};
  if (accelerated && (policy || cov.given)) {
    throw py::value_error(
        "add_twist(): linear_acceleration= / angular_acceleration= go with a value without "
        "repair or covariance in this version");
  }
  std::lock_guard<WriterMutex> lock(b.writer);
  if (accelerated) {
    Check(b.Visit([&](auto& g) {
      return t ? g.AddTwist(spec, v, w, *t, acceleration) : g.AddTwist(spec, v, w, acceleration);
    }));
    return py::none();
  }
  if (policy) {
    return b.Visit([&](auto& g) -> py::object {
      auto r = g.AddTwist(spec, v, w, *policy);
      if (!r) ThrowRejected(r.error());
      return py::cast(std::move(*r));
    });
  }
  Check(b.Visit([&](auto& g) {
    if (cov.given && t) return g.AddTwist(spec, v, w, *t, cov.Input());
    if (cov.given) return g.AddTwist(spec, v, w, cov.Input());
    return t ? g.AddTwist(spec, v, w, *t) : g.AddTwist(spec, v, w);
  }));
  return py::none();
}

}  // namespace

GraphClass BindSceneGraph(py::module_& m) {
  GraphClass graph(
      m, "SceneGraph",
      R"(A constraint-checking scene graph of poses and twists of rigid bodies (De Laet et al.,
IROS 2013).

Bodies contain frames; pose edges {wrt} -> {of} store the pose of a frame relative to another,
twist edges ref_body -> {point} the screw twist of a frame's body relative to another body.
Every add is checked (one pose parent per frame, no cycles, frames of one body connected
through constant same-body edges, one twist path, ...) and is atomic: a refused add raises
RejectedError and changes nothing. Queries compose the stored relations along the graph,
checking every step, and raise QueryError when the question has no answer.

representation: 'quaternion' (default; unit quaternion + vector, any semantics) or
'homogeneous' (4x4 matrices: poses must be between frame origins and expressed in the
reference orientation frame, else representation_constraint).)");
  graph.def(py::init(&Make), py::arg("representation") = "quaternion", py::kw_only(),
            py::arg("window") = py::none(), py::arg("interpolation") = py::none(),
            py::arg("duplicate_stamp") = py::none(), py::arg("sample_capacity") = py::none(),
            R"(A new, empty graph.

representation   'quaternion' (default) or 'homogeneous'
Time options (docs/time.md; used by stamped values, defaults in brackets):
window           the history kept per stamped edge [10 s]: samples older than the edge's newest
                 minus the window are dropped; a time (int nanoseconds or float seconds)
interpolation    'screw' [default] (constant screw twist between samples) or 'linear' (tf2's:
                 positions linearly, rotations by slerp)
duplicate_stamp  'replace' [default] or 'reject' (another value at an existing stamp is
                 refused with duplicate_stamp)
sample_capacity  samples per stamped edge, preallocated when the edge gets its first stamp [1024]
RejectedError invalid_number: a window that is not positive, a sample_capacity below 2.)");
  graph.def_property_readonly(
      "time_options",
      [](const GraphBox& b) {
        return b.Visit([](const auto& g) {
          const core::TimeOptions& o = g.time_options();
          py::dict d;
          d["window"] = static_cast<double>(o.window.nanoseconds()) / 1e9;
          d["window_ns"] = o.window.nanoseconds();
          d["interpolation"] = o.interpolation == core::Interpolation::kScrew ? "screw" : "linear";
          d["duplicate_stamp"] =
              o.duplicate_stamp == core::DuplicatePolicy::kReplace ? "replace" : "reject";
          d["sample_capacity"] = o.sample_capacity;
          return d;
        });
      },
      "The graph's time options as a dict: window (s), window_ns, interpolation, duplicate_stamp, "
      "sample_capacity.");
  graph.def_property_readonly("representation", &GraphBox::representation,
                              "'quaternion' or 'homogeneous'.");
  graph.def_property_readonly("num_frames", [](const GraphBox& b) {
    return b.Visit([](const auto& g) { return g.num_frames(); });
  });
  graph.def_property_readonly("num_bodies", [](const GraphBox& b) {
    return b.Visit([](const auto& g) { return g.num_bodies(); });
  });
  graph.def_property_readonly("num_pose_edges", [](const GraphBox& b) {
    return b.Visit([](const auto& g) { return g.num_pose_edges(); });
  });
  graph.def_property_readonly("num_twist_edges", [](const GraphBox& b) {
    return b.Visit([](const auto& g) { return g.num_twist_edges(); });
  });
  graph.def_property_readonly(
      "frames",
      [](const GraphBox& b) {
        return b.Visit([](const auto& g) {
          std::vector<std::string> out;
          for (std::uint32_t i = 0; i < g.num_frames(); ++i)
            out.emplace_back(g.frame_name(core::FrameIndex(i)));
          return out;
        });
      },
      "Frame names, in creation order.");
  graph.def_property_readonly(
      "bodies",
      [](const GraphBox& b) {
        return b.Visit([](const auto& g) {
          std::vector<std::string> out;
          for (std::uint32_t i = 0; i < g.num_bodies(); ++i)
            out.emplace_back(g.body_name(core::BodyIndex(i)));
          return out;
        });
      },
      "Body names, in creation order.");
  graph.def(
      "body_of",
      [](const GraphBox& b, py::handle frame) -> py::object {
        const std::string_view name = NameArg(frame, "body_of", "frame");
        return b.Visit([&](const auto& g) -> py::object {
          const core::FrameIndex f = g.FindFrame(name);
          if (!f.is_valid()) return py::none();
          return py::str(std::string(g.body_name(g.body_of(f))));
        });
      },
      py::arg("frame"), "The name of the body a frame is fixed to, or None for an unknown frame.");
  graph.def("__repr__", [](const GraphBox& b) {
    return b.Visit([&](const auto& g) {
      return "SceneGraph(representation='" + std::string(b.representation()) +
             "', frames=" + std::to_string(g.num_frames()) +
             ", bodies=" + std::to_string(g.num_bodies()) +
             ", pose_edges=" + std::to_string(g.num_pose_edges()) +
             ", twist_edges=" + std::to_string(g.num_twist_edges()) + ")";
    });
  });
  return graph;
}

void BindBuild(GraphClass& graph) {
  graph.def(
      "add_body",
      [](GraphBox& b, py::handle name) {
        const std::string_view n = NameArg(name, "add_body", "name");
        std::lock_guard<WriterMutex> lock(b.writer);
        Check(b.Visit([&](auto& g) { return g.AddBody(n); }));
      },
      py::arg("name"), "Adds a body. RejectedError: invalid_name, duplicate_body.");
  graph.def(
      "add_frame",
      [](GraphBox& b, py::handle name, py::handle body) {
        const std::string_view n = NameArg(name, "add_frame", "name");
        const std::string_view bd = NameArg(body, "add_frame", "body");
        std::lock_guard<WriterMutex> lock(b.writer);
        Check(b.Visit([&](auto& g) { return g.AddFrame(n, bd); }));
      },
      py::arg("name"), py::arg("body"),
      "Adds a frame fixed to an existing body. RejectedError: invalid_name, frame_without_body, "
      "duplicate_frame, unknown_body.");
  graph.def(
      "add_pose", &AddPose, py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),
      py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(), py::arg("point") = py::none(),
      py::arg("orientation") = py::none(), py::arg("ref_point") = py::none(),
      py::arg("ref_orientation") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("position") = py::none(), py::arg("rotation") = py::none(),
      py::arg("quaternion") = py::none(), py::arg("rotation_matrix") = py::none(),
      py::arg("rpy") = py::none(), py::arg("stamp") = py::none(), py::arg("repair") = py::none(),
      py::arg("covariance") = py::none(), py::arg("covariance_order") = py::none(),
      py::arg("convention") = py::none(),
      Doc(R"(Adds the pose of `of` (body `body`) relative to `wrt` (body `ref_body`), stored as the
edge {wrt} -> {of}, or updates the value of that existing edge. Frames and bodies that do not
exist yet are created. A pose in a non-edge form (other point, reference point or coordinate
frame) is converted once. position: of's origin relative to wrt's origin, in [expressed_in]
(default [wrt]); default (0, 0, 0).
stamp   a stamped sample (docs/time.md): int nanoseconds or float seconds. The edge becomes
        stamped on its first value; a value in another form is converted with the graph's
        values at the stamp. Same-body edges are timeless (the stamp only serves the conversion).
repair  True or a RepairPolicy: repair a rejection by P1 / pose_cycle (docs/repair.md) and
        return a RepairReport; without it (the default) the add returns None. Not with stamp.
covariance  the value's 6x6 covariance (docs/uncertainty.md; none: exact), rows (dp, dtheta);
        covariance_order 'linear_angular' (default) or 'angular_linear'; convention
        'coordinates' (default: p + dp, Exp(dtheta) R) or 'body' (X Exp(xi), edge form only).
        With stamp: the sample's own covariance (docs/uncertainty.md, "Covariances and time").
        Not with repair in this version.
RejectedError (code): invalid_name, invalid_number, invalid_rotation, invalid_covariance,
frame_body_mismatch, self_edge, representation_constraint, pose_not_convertible, constant_pose_change,
multiple_pose_parents, pose_cycle, duplicate_pose_path, twist_merge_conflict, joint_edge;
with a stamp stamp_mismatch, stamp_too_old, duplicate_stamp, extrapolation (a conversion at a
stamp the other edges have no values for); with repair a refused consistency check keeps its
code and has .discrepancy = (position, angle).
)",
          (std::string(kPoseNamesDoc) + kRotationDoc).c_str())
          .c_str());
  graph.def("add_twist", &AddTwist, py::kw_only(), py::arg("point") = py::none(),
            py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
            py::arg("expressed_in") = py::none(), py::arg("linear") = py::none(),
            py::arg("angular") = py::none(), py::arg("stamp") = py::none(),
            py::arg("repair") = py::none(), py::arg("covariance") = py::none(),
            py::arg("covariance_order") = py::none(), py::arg("linear_acceleration") = py::none(),
            py::arg("angular_acceleration") = py::none(),
            R"(Adds the twist of body `body` (default: the body of frame `point`) relative to body
`ref_body`, as the twist edge ref_body -> {point}, or updates it.
linear: velocity of the point of `body` at the origin of `point`; angular: angular velocity;
both expressed in [expressed_in] (converted to [point] once when different); default zero.
stamp: a stamped sample (int nanoseconds or float seconds), as for add_pose.
repair: True or a RepairPolicy: repair a rejection by W1 (the inverse twist on a frame of the
reference body) or duplicate_twist_path (consistency check); returns a RepairReport.
covariance: the value's 6x6 covariance, rows (dv, dw) (covariance_order 'angular_linear' for
(dw, dv)); as for add_pose (with stamp: the sample's own).
linear_acceleration, angular_acceleration: the edge's acceleration (a of the same point, alpha;
in [expressed_in]; either given: the other defaults to zero), stored with the twist; without
them the edge carries no acceleration (a previous one is cleared); with stamp, the sample's.
Not with repair or covariance in this version.
RejectedError: invalid_name, invalid_number, invalid_covariance, unknown_frame, unknown_body,
frame_body_mismatch,
twist_same_body, twist_not_convertible, multiple_twist_parents, duplicate_twist_path,
joint_edge; with a stamp stamp_mismatch, stamp_too_old, duplicate_stamp, extrapolation.)");
  graph.def(
      "remove_pose",
      [](GraphBox& b, py::handle of, py::handle wrt) {
        const std::string_view o = NameArg(of, "remove_pose", "of");
        const std::string_view w = NameArg(wrt, "remove_pose", "wrt");
        std::lock_guard<WriterMutex> lock(b.writer);
        Check(b.Visit([&](auto& g) { return g.RemovePose(o, w); }));
        ++b.topology_generation;
      },
      py::kw_only(), py::arg("of"), py::arg("wrt"),
      "Removes the pose edge {wrt} -> {of}. RejectedError: invalid_name, unknown_frame, "
      "no_such_edge. Compiled queries and handles that read it become invalid.");
  graph.def(
      "remove_twist",
      [](GraphBox& b, py::handle point, py::handle ref_body) {
        const std::string_view p = NameArg(point, "remove_twist", "point");
        const std::string_view r = NameArg(ref_body, "remove_twist", "ref_body");
        std::lock_guard<WriterMutex> lock(b.writer);
        Check(b.Visit([&](auto& g) { return g.RemoveTwist(p, r); }));
        ++b.topology_generation;
      },
      py::kw_only(), py::arg("point"), py::arg("ref_body"),
      "Removes the twist edge ref_body -> {point}. RejectedError: invalid_name, unknown_frame, "
      "unknown_body, no_such_edge.");
}

void BindInspection(GraphClass& graph) {
  graph.def(
      "dump", [](const GraphBox& b) { return b.Visit([](const auto& g) { return Dump(g); }); },
      "A canonical, complete text dump of the graph (names, topology, values), e.g. to "
      "compare states.");
  graph.def(
      "check_invariants",
      [](const GraphBox& b) { return b.Visit([](const auto& g) { return CheckInvariants(g); }); },
      "Verifies every invariant of the graph from scratch (slow); '' when all hold.");
  graph.def(
      "dot",
      [](const GraphBox& b) -> std::string {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
        return b.Visit([](const auto& g) { return script::WriteDot(g); });
#else
        (void)b;
        throw std::runtime_error(
            "dot(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
      },
      R"(The graph as Graphviz DOT in the style of the paper's Fig. 8: a cluster per body holding its
frames, pose edges solid (tail -> head), twist edges dashed (reference body -> head frame).)");
  graph.def(
      "to_script",
      [](const GraphBox& b) -> std::string {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
        return b.Visit([](const auto& g) { return script::WriteScene(g); });
#else
        (void)b;
        throw std::runtime_error(
            "to_script(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
      },
      R"(The graph as a scene script (YAML, like `semgraph export`) that rebuilds it:
run_script_text(g.to_script()).graph has the same names, ids, edges and values (its dump() is
g.dump()). Save it to a file to load the scene later with run_script.)");
}

}  // namespace semgraph::python
