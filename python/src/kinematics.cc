// Joints, joint states, semantic Jacobians and URDF models (docs/kinematics.md), over the
// core's SceneGraph joint API and semgraph::models. Nothing is computed here: a joint's poses
// and twists, its limits and the Jacobian columns are the core's.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "semgraph/core/jacobian.h"
#include "timed.h"

#ifdef SEMGRAPH_PYTHON_WITH_MODELS
#include "semgraph/models/urdf.h"
#endif

namespace semgraph::python {

namespace {

/// A joint-state layout (core::JointGroup) with the names of its joints.
struct JointGroupObject {
  GraphPtr graph;
  core::JointGroup group;
  std::vector<std::string> names;
};

struct JacobianResult {
  GraphPtr graph;
  semantics::TwistSemantics semantics;
  std::vector<std::string> joints;
  core::JacobianMatrix J;
};

struct CompiledJacobianObject {
  GraphPtr graph;
  PerBackend<core::CompiledJacobian> query;
  std::vector<std::string> joints;
};

struct RobotObject {
  std::string name, prefix, root;
  std::vector<std::string> links, joints, mimic_joints, fixed_joints, floating_joints;
  std::shared_ptr<JointGroupObject> group;
};

double FloatArg(py::handle value, double fallback, const char* fn, const char* argument) {
  if (value.is_none()) return fallback;
  if (PyUnicode_Check(value.ptr()) || PyBool_Check(value.ptr()) || !PyNumber_Check(value.ptr())) {
    throw py::type_error(std::string(fn) + "(): " + argument + " must be a number, not " +
                         TypeName(value));
  }
  const double x = PyFloat_AsDouble(value.ptr());
  if (x == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

core::JointType JointTypeArg(py::handle value) {
  if (!PyUnicode_Check(value.ptr())) {
    throw py::type_error(
        "add_joint(): type must be a str ('revolute', 'continuous', 'prismatic' or 'fixed'), not " +
        TypeName(value));
  }
  const std::string t = value.cast<std::string>();
  if (t == "revolute") return core::JointType::kRevolute;
  if (t == "continuous") return core::JointType::kContinuous;
  if (t == "prismatic") return core::JointType::kPrismatic;
  if (t == "fixed") return core::JointType::kFixed;
  throw py::value_error(
      "add_joint(): type must be 'revolute', 'continuous', 'prismatic' or 'fixed', not '" + t +
      "'");
}

template <class G>
std::vector<std::string> JointNames(const G& g, const std::vector<core::JointHandle>& joints) {
  std::vector<std::string> out;
  out.reserve(joints.size());
  for (const core::JointHandle& j : joints) out.emplace_back(g.joint_name(j));
  return out;
}

/// names=: None -> every independent movable joint, a JointGroup of this graph, or a sequence of
/// joint names (MakeJointGroup: RejectedError unknown_joint, mimic_joint, duplicate_joint).
std::shared_ptr<JointGroupObject> GroupArg(GraphBox& box, py::handle names, const char* fn,
                                           bool with_names = true) {
  if (py::isinstance<JointGroupObject>(names)) {
    auto group = names.cast<std::shared_ptr<JointGroupObject>>();
    if (group->graph.get() != &box) {
      throw py::value_error(std::string(fn) + "(): the JointGroup belongs to another SceneGraph");
    }
    return group;
  }
  auto out = std::make_shared<JointGroupObject>();
  out->graph = box.shared_from_this();
  if (names.is_none()) {
    box.Visit([&](const auto& g) {
      out->group = g.AllJoints();
      if (with_names) out->names = JointNames(g, out->group.joints);
    });
    return out;
  }
  if (PyUnicode_Check(names.ptr()) || !PySequence_Check(names.ptr())) {
    throw py::type_error(std::string(fn) +
                         "(): names must be a sequence of joint names, a JointGroup or None, not " +
                         TypeName(names));
  }
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(names);
  std::vector<py::object> keep;
  std::vector<std::string_view> views;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    keep.push_back(seq[i]);
    const std::string arg = "names[" + std::to_string(i) + "]";
    views.push_back(NameArg(keep.back(), fn, arg.c_str()));
  }
  box.Visit([&](const auto& g) {
    auto group = g.MakeJointGroup(views);
    if (!group) ThrowRejected(group.error());
    out->group = std::move(*group);
    out->names = JointNames(g, out->group.joints);
  });
  return out;
}

/// A 1-D float64 array of exactly `n` values.
py::array_t<double, py::array::c_style> StateArg(py::handle value, std::size_t n, const char* fn,
                                                 const char* argument) {
  auto a = FloatArrayArg(value, fn, argument);
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n) {
    throw py::value_error(std::string(fn) + "(): " + argument + " must have shape (" +
                          std::to_string(n) + ",), one value per joint of the group, got " +
                          ShapeText(a));
  }
  return a;
}

void SetJointsByName(GraphBox& box, py::handle positions, py::handle velocities,
                     py::handle accelerations, std::optional<core::Stamp> stamp) {
  std::vector<core::JointValue> q, qdot, qddot;
  std::vector<py::object> keep;
  auto read = [&](py::handle d, std::vector<core::JointValue>& out, const char* argument) {
    if (d.is_none()) return;
    for (auto item : py::reinterpret_borrow<py::dict>(d)) {
      keep.push_back(py::reinterpret_borrow<py::object>(item.first));
      const std::string_view name =
          NameArg(item.first, "set_joints", (std::string(argument) + " key").c_str());
      const std::string what = std::string(argument) + "['" + std::string(name) + "']";
      out.push_back({name, FloatArg(item.second, 0.0, "set_joints", what.c_str())});
    }
  };
  read(positions, q, "positions");
  read(velocities, qdot, "velocities");
  read(accelerations, qddot, "accelerations");
  std::lock_guard<WriterMutex> lock(box.writer);
  Check(box.Visit([&](auto& g) {
    return stamp ? g.SetJoints(q, qdot, qddot, *stamp) : g.SetJoints(q, qdot, qddot);
  }));
}

// A stamped state given as arrays: by the group's names, through the stamped SetJoints (which
// also takes a joint's first stamped state; the real-time stamped setters need one already).
void SetStampedJointArrays(GraphBox& box, const JointGroupObject& group,
                           const py::array_t<double, py::array::c_style>* arrays[3],
                           core::Stamp stamp) {
  std::lock_guard<WriterMutex> lock(box.writer);
  Check(box.Visit([&](auto& g) {
    std::vector<core::JointValue> values[3];
    for (int k = 0; k < 3; ++k) {
      if (arrays[k] == nullptr) continue;
      for (std::size_t i = 0; i < group.group.size(); ++i) {
        values[k].push_back({g.joint_name(group.group.joints[i]), arrays[k]->data()[i]});
      }
    }
    return g.SetJoints(values[0], values[1], values[2], stamp);
  }));
}

void SetJoints(GraphBox& box, py::handle positions, py::handle velocities, py::handle accelerations,
               py::handle names, py::handle stamp_arg) {
  const std::optional<core::Stamp> stamp =
      OptionalStampArg(stamp_arg, "set_joints", "stamp", false);
  const py::handle given[] = {positions, velocities, accelerations};
  bool any_dict = false, all_dicts = true;
  for (py::handle h : given) {
    any_dict |= PyDict_Check(h.ptr());
    all_dicts &= PyDict_Check(h.ptr()) || h.is_none();
  }
  if (any_dict) {
    if (!all_dicts) {
      throw py::type_error(
          "set_joints(): positions, velocities and accelerations must all be dicts (by joint "
          "name) or all arrays (in the order of names)");
    }
    if (!names.is_none())
      throw py::value_error("set_joints(): names= applies to arrays, not to dicts");
    SetJointsByName(box, positions, velocities, accelerations, stamp);
    return;
  }
  if (positions.is_none() && velocities.is_none() && accelerations.is_none()) return;
  const auto group = GroupArg(box, names, "set_joints", false);
  const std::size_t n = group->group.size();
  // (A default py::array is an empty array, not a null one: track what was given explicitly.)
  const bool has_q = !positions.is_none(), has_qdot = !velocities.is_none(),
             has_qddot = !accelerations.is_none();
  py::array_t<double, py::array::c_style> q_array, qdot_array, qddot_array;
  if (has_q) q_array = StateArg(positions, n, "set_joints", "positions");
  if (has_qdot) qdot_array = StateArg(velocities, n, "set_joints", "velocities");
  if (has_qddot) qddot_array = StateArg(accelerations, n, "set_joints", "accelerations");
  if (stamp) {
    const py::array_t<double, py::array::c_style>* arrays[3] = {has_q ? &q_array : nullptr,
                                                                has_qdot ? &qdot_array : nullptr,
                                                                has_qddot ? &qddot_array : nullptr};
    SetStampedJointArrays(box, *group, arrays, *stamp);
    return;
  }
  std::lock_guard<WriterMutex> lock(box.writer);
  box.Visit([&](auto& g) {
    const bool q = has_q, qdot = has_qdot, qddot = has_qddot;
    // With accelerations and only one of q, qdot, the other is the joints' own (under the
    // writer lock), so that the one all-or-nothing setter SetJointState(q, qdot, qddot) applies.
    std::vector<double> kept;
    if (qddot && q != qdot) {
      kept.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        kept[i] =
            q ? g.joint_velocity(group->group.joints[i]) : g.joint_position(group->group.joints[i]);
        if (std::isnan(kept[i])) kept[i] = 0;  // a removed joint: unknown_joint below
      }
    }
    const std::span<const double> sq(q ? q_array.data() : kept.data(), q || !kept.empty() ? n : 0);
    const std::span<const double> sv(qdot ? qdot_array.data() : kept.data(),
                                     qdot || !kept.empty() ? n : 0);
    const std::span<const double> sa(qddot ? qddot_array.data() : nullptr, qddot ? n : 0);
    ErrorCode code;
    core::UpdateError why;  // the setter's verdict: which joint, which value, which limit
    if (qddot && (q || qdot)) {
      code = g.SetJointState(group->group, sq, sv, sa, &why);
    } else if (qddot) {
      code = g.SetJointAccelerations(group->group, sa, &why);
    } else if (q && qdot) {
      code = g.SetJointState(group->group, sq, sv, &why);
    } else if (q) {
      code = g.SetJointPositions(group->group, sq, &why);
    } else {
      code = g.SetJointVelocities(group->group, sv, &why);
    }
    if (code == ErrorCode::kOk) return;
    if (code == ErrorCode::kInvalidNumber || code == ErrorCode::kJointLimit) {
      ThrowRejected(code, "set_joints() rejected (" + std::string(ToString(code)) + "): joint " +
                              std::string(g.joint_name(group->group.joints[why.joint])) + ": " +
                              core::Describe(why));
    }
    ThrowRejected(code, "set_joints() rejected (" + std::string(ToString(code)) + ")" +
                            (code == ErrorCode::kUnknownJoint
                                 ? ": a joint of the group was removed since the group "
                                   "was made; make the group again"
                                 : ""));
  });
}

// field: 0 positions, 1 velocities, 2 accelerations (NaN for a joint never given one).
py::array_t<double> JointValues(GraphBox& box, py::handle names, int field, const char* fn) {
  const auto group = GroupArg(box, names, fn, false);
  py::array_t<double> out(static_cast<py::ssize_t>(group->group.size()));
  double* x = out.mutable_data();
  box.Visit([&](const auto& g) {
    for (std::size_t i = 0; i < group->group.size(); ++i) {
      const core::JointHandle j = group->group.joints[i];
      x[i] = field == 2   ? g.joint_acceleration(j)
             : field == 1 ? g.joint_velocity(j)
                          : g.joint_position(j);
    }
  });
  return out;
}

py::array_t<double> Rows(const core::JacobianMatrix& J, int first, int count) {
  const auto n = static_cast<py::ssize_t>(J.cols());
  py::array_t<double> a({static_cast<py::ssize_t>(count), n});
  double* x = a.mutable_data();
  for (int r = 0; r < count; ++r) {
    for (py::ssize_t c = 0; c < n; ++c) x[r * n + c] = J(first + r, c);
  }
  return a;
}

std::string NamesText(const std::vector<std::string>& names) {
  std::string s = "[";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", '" : "'") + names[i] + "'";
  return s + "]";
}

#ifdef SEMGRAPH_PYTHON_WITH_MODELS
RobotObject MakeRobot(GraphBox& box, const models::Robot& r) {
  RobotObject out{r.name,         r.prefix,          r.root, r.links, r.joints, r.mimic_joints,
                  r.fixed_joints, r.floating_joints, {}};
  out.group = std::make_shared<JointGroupObject>(
      JointGroupObject{box.shared_from_this(), r.group, r.joints});
  return out;
}

RobotObject LoadUrdf(GraphBox& box, const std::string& text, const std::string& prefix, bool file) {
  std::optional<core::BuildError> error;
  std::optional<models::Robot> robot;
  {
    py::gil_scoped_release release;
    std::lock_guard<WriterMutex> lock(box.writer);
    box.Visit([&](auto& g) {
      auto r =
          file ? models::LoadUrdfFile(g, text, prefix) : models::LoadUrdfString(g, text, prefix);
      if (r) {
        robot = std::move(*r);
      } else {
        error = std::move(r.error());
      }
    });
  }
  if (error) ThrowRejected(*error);
  return MakeRobot(box, *robot);
}
#endif

void BindKinematicsClasses(py::module_& m) {
  py::class_<JointGroupObject, std::shared_ptr<JointGroupObject>>(
      m, "JointGroup",
      R"(The layout of a joint-state vector: these joints in this order (SceneGraph.joint_group, a
Robot's .group). Pass it as names= to set_joints / joint_positions / joint_velocities to skip
the name lookups. Only independent movable joints (no fixed, no mimic joints).)")
      .def_readonly("names", &JointGroupObject::names, "The joints' names, in vector order.")
      .def("__len__", [](const JointGroupObject& g) { return g.group.size(); })
      .def("__repr__",
           [](const JointGroupObject& g) { return "JointGroup(" + NamesText(g.names) + ")"; });

  py::class_<JacobianResult>(m, "Jacobian",
                             R"(A semantic Jacobian: Jacobian(e|C, D, [r]), the 6 x n matrix J with
TwistCoord(e|C, D, [r]) = J qdot + (the twists of the non-joint twist edges on the path).

matrix     (6, n): rows v_x v_y v_z (velocity of the point of C at e) then w_x w_y w_z
           (angular velocity), both relative to D and in [r]; column i is joints[i]
linear     (3, n): the rows of v;  angular: (3, n): the rows of w
joints     the columns' joints: the independent movable joints on the twist path, in path
           order from D to C (a mimic adds multiplier x its column to its master's)
semantics  the twist it maps to, in the paper's notation)")
      .def_property_readonly("matrix", [](const JacobianResult& r) { return Rows(r.J, 0, 6); })
      .def_property_readonly("linear", [](const JacobianResult& r) { return Rows(r.J, 0, 3); })
      .def_property_readonly("angular", [](const JacobianResult& r) { return Rows(r.J, 3, 3); })
      .def_readonly("joints", &JacobianResult::joints)
      .def_property_readonly(
          "semantics", [](const JacobianResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def("__repr__", [](const JacobianResult& r) {
        return "Jacobian(" + SemanticsText(r.graph, r.semantics) +
               ", joints=" + NamesText(r.joints) + ", shape=(6, " + std::to_string(r.J.cols()) +
               "))";
      });

  py::class_<CompiledJacobianObject, std::shared_ptr<CompiledJacobianObject>>(
      m, "CompiledJacobian",
      R"(A compiled Jacobian query (SceneGraph.compile_jacobian): the path and columns resolved once;
evaluate() reads the current joint states. It keeps its SceneGraph alive; after an edge it
reads is removed, evaluate() raises QueryError('query_invalidated').)")
      .def(
          "evaluate",
          [](const CompiledJacobianObject& c) {
            return std::visit(
                [&](const auto& q) {
                  core::JacobianMatrix J(6, static_cast<Eigen::Index>(q.num_columns()));
                  J.setZero();
                  if (q.Evaluate(J) != ErrorCode::kOk) {
                    ThrowQuery(ErrorCode::kQueryInvalidated,
                               "the compiled Jacobian " + SemanticsText(c.graph, q.semantics()) +
                                   " reads a pose or twist edge that was removed after it was "
                                   "compiled; compile it again",
                               nullptr, nullptr);
                  }
                  return JacobianResult{c.graph, q.semantics(), c.joints, std::move(J)};
                },
                c.query);
          },
          "The Jacobian now (a Jacobian).")
      .def_readonly("joints", &CompiledJacobianObject::joints, "The columns' joints.")
      .def_property_readonly(
          "is_valid",
          [](const CompiledJacobianObject& c) {
            return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
          },
          "True while every edge the query reads still exists.")
      .def("__repr__", [](const CompiledJacobianObject& c) {
        return "CompiledJacobian(" +
               std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); },
                          c.query) +
               ", joints=" + NamesText(c.joints) + ")";
      });

  py::class_<RobotObject>(m, "Robot", R"(What SceneGraph.load_urdf created (names with the prefix).

name             the URDF's robot name
prefix           the prefix given
root             the root link's frame (and body): attach the robot with an ordinary pose
links            link frames, depth-first from the root (siblings by joint name)
joints           the independent movable joints in that order (= group)
mimic_joints, fixed_joints
floating_joints  ordinary edges ('child wrt parent' by link frames), updated with add_pose
group            a JointGroup of `joints`, for set_joints(..., names=robot.group))")
      .def_readonly("name", &RobotObject::name)
      .def_readonly("prefix", &RobotObject::prefix)
      .def_readonly("root", &RobotObject::root)
      .def_readonly("links", &RobotObject::links)
      .def_readonly("joints", &RobotObject::joints)
      .def_readonly("mimic_joints", &RobotObject::mimic_joints)
      .def_readonly("fixed_joints", &RobotObject::fixed_joints)
      .def_readonly("floating_joints", &RobotObject::floating_joints)
      .def_readonly("group", &RobotObject::group)
      .def("__repr__", [](const RobotObject& r) {
        return "Robot(name='" + r.name + "', prefix='" + r.prefix + "', root='" + r.root +
               "', links=" + std::to_string(r.links.size()) + ", joints=" + NamesText(r.joints) +
               ")";
      });
}

void BindJointMethods(GraphClass& graph) {
  graph.def(
      "add_joint",
      [](GraphBox& b, py::handle name, py::handle type, py::handle parent, py::handle child,
         py::handle parent_body, py::handle child_body, py::handle position, py::handle rotation,
         py::handle quaternion, py::handle rotation_matrix, py::handle rpy, py::handle axis,
         py::handle lower, py::handle upper, py::handle mimic, py::handle multiplier,
         py::handle offset) {
        core::JointSpec spec;
        spec.name = NameArg(name, "add_joint", "name");
        spec.type = JointTypeArg(type);
        spec.parent = NameArg(parent, "add_joint", "parent");
        spec.parent_body = NameArg(parent_body, "add_joint", "parent_body");
        spec.child = NameArg(child, "add_joint", "child");
        spec.child_body = NameArg(child_body, "add_joint", "child_body");
        spec.p_origin = Vector3Arg(position, "add_joint", "position");
        const RotationArg rot =
            RotationArgs(rotation, quaternion, rotation_matrix, rpy, "add_joint");
        if (rot.is_matrix) {
          spec.R_origin = rot.R;
        } else {
          spec.q_origin = rot.q;
        }
        if (!axis.is_none()) spec.axis = Vector3Arg(axis, "add_joint", "axis");
        spec.lower = FloatArg(lower, 0.0, "add_joint", "lower");
        spec.upper = FloatArg(upper, 0.0, "add_joint", "upper");
        spec.mimic = NameArg(mimic, "add_joint", "mimic");
        spec.multiplier = FloatArg(multiplier, 1.0, "add_joint", "multiplier");
        spec.offset = FloatArg(offset, 0.0, "add_joint", "offset");
        std::lock_guard<WriterMutex> lock(b.writer);
        Check(b.Visit([&](auto& g) { return g.AddJoint(spec); }));
      },
      py::arg("name"), py::kw_only(), py::arg("type"), py::arg("parent"), py::arg("child"),
      py::arg("parent_body") = py::none(), py::arg("child_body") = py::none(),
      py::arg("position") = py::none(), py::arg("rotation") = py::none(),
      py::arg("quaternion") = py::none(), py::arg("rotation_matrix") = py::none(),
      py::arg("rpy") = py::none(), py::arg("axis") = py::none(), py::arg("lower") = py::none(),
      py::arg("upper") = py::none(), py::arg("mimic") = py::none(),
      py::arg("multiplier") = py::none(), py::arg("offset") = py::none(),
      R"(Adds a joint (docs/kinematics.md): the pose edge {parent} -> {child} with value
X_origin * M(q) and the twist edge parent_body -> {child} with the twist of qdot, both driven by
the joint's state only. Missing frames are created with their bodies (parent_body, child_body).

type         'revolute' (q in rad, limited), 'continuous' (rad, unlimited), 'prismatic' (m,
             limited) or 'fixed'
position, rotation / quaternion / rotation_matrix / rpy
             X_origin: {child} relative to {parent} at q = 0 (as add_pose)
axis         u in [child], normalized; default (1, 0, 0)
lower, upper position limits (revolute, prismatic); default 0, 0
mimic        the master joint's name: q = multiplier * q_master + offset (defaults 1, 0)
The state starts at q = 0 clamped into the limits, qdot = 0.
RejectedError: invalid_name, invalid_number, invalid_rotation, invalid_model (axis, limits,
mimic), duplicate_joint, frame_body_mismatch, self_edge, twist_same_body, joint_edge,
multiple_pose_parents, pose_cycle, duplicate_pose_path, multiple_twist_parents, ...)");
  graph.def_property_readonly(
      "num_joints",
      [](const GraphBox& b) { return b.Visit([](const auto& g) { return g.num_joints(); }); },
      "Joints, fixed and mimic joints included.");
  graph.def_property_readonly(
      "joint_names",
      [](const GraphBox& b) {
        return b.Visit([](const auto& g) { return JointNames(g, g.AllJoints().joints); });
      },
      "The independent movable joints (no fixed, no mimic joints), in the order they were added: "
      "the "
      "default layout of set_joints / joint_positions arrays.");
  graph.def(
      "joint_group",
      [](GraphBox& b, py::handle names) { return GroupArg(b, names, "joint_group"); },
      py::arg("names"),
      "A JointGroup of these joints, in this order. RejectedError: unknown_joint, mimic_joint (a "
      "mimic "
      "follows its master), duplicate_joint.");
  graph.def(
      "set_joints", &SetJoints, py::arg("positions") = py::none(),
      py::arg("velocities") = py::none(), py::arg("accelerations") = py::none(), py::kw_only(),
      py::arg("names") = py::none(), py::arg("stamp") = py::none(),
      R"(Sets joint positions, velocities and/or accelerations, all or nothing; a joint keeps what
it is not given. A joint given an acceleration makes its twist edge carry it (acceleration
queries); a joint never given one carries none (no_acceleration).

positions, velocities, accelerations
                       arrays (lists or numpy, one value per joint of `names`), or dicts
                       {joint name: value} (any joints, by name; names= is then not used)
names                  the arrays' layout: None (joint_names), a JointGroup, or a list of names
stamp                  a sample at this time (as add_pose's stamp=): the joints' edges keep
                       histories; a field not given keeps the joint's newest sample's
RejectedError: invalid_number -> unknown_joint -> mimic_joint -> joint_limit (a position
outside [lower, upper]) -> with a stamp: stamp_mismatch (a joint set without stamps before, or
the reverse), stamp_too_old, duplicate_stamp; nothing changes. ValueError: an array of the wrong
length.)");
  graph.def(
      "joint_positions",
      [](GraphBox& b, py::handle names) { return JointValues(b, names, 0, "joint_positions"); },
      py::arg("names") = py::none(),
      "Joint positions (a float64 array) in the layout of `names` (as set_joints).");
  graph.def(
      "joint_velocities",
      [](GraphBox& b, py::handle names) { return JointValues(b, names, 1, "joint_velocities"); },
      py::arg("names") = py::none(),
      "Joint velocities (a float64 array) in the layout of `names`.");
  graph.def(
      "joint_accelerations",
      [](GraphBox& b, py::handle names) { return JointValues(b, names, 2, "joint_accelerations"); },
      py::arg("names") = py::none(),
      "Joint accelerations (a float64 array) in the layout of `names`; NaN for a joint whose "
      "acceleration was never given.");
}

void BindJacobianMethods(GraphClass& graph) {
  constexpr const char* kJacobianDoc = R"(
Names (keyword-only), those of twist():
  point         the point e: the velocity is that of the point of `body` at this frame's origin
  body          the moving body C (default: the body of `point`'s frame)
  ref_body      the reference body D
  expressed_in  the coordinate frame [r]
Conventions: KDL's base Jacobian is point=ee, ref_body=Base, expressed_in=base; Pinocchio's
LOCAL point=ee, ref_body=World, expressed_in=ee; LOCAL_WORLD_ALIGNED expressed_in=world.
QueryError: the errors of twist() (unknown_frame, no_pose_path, no_twist_path, ...).)";
  graph.def(
      "jacobian",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in) {
        const core::TwistSpec spec = ReadTwistSpec("jacobian", point, body, ref_body, expressed_in);
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.GetJacobian(spec);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          return JacobianResult{self, r->semantics, JointNames(g, r->joints), std::move(r->J)};
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      (std::string("The semantic Jacobian of TwistCoord(point|body, ref_body, [expressed_in]) at "
                   "the current joint "
                   "positions (a Jacobian: .matrix 6 x n, .linear, .angular, .joints).\n") +
       kJacobianDoc)
          .c_str());
  graph.def(
      "compile_jacobian",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_jacobian", point, body, ref_body, expressed_in);
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto r = g.CompileJacobian(spec);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          std::vector<std::string> names = JointNames(g, r->joints());
          return std::make_shared<CompiledJacobianObject>(
              CompiledJacobianObject{self, std::move(*r), std::move(names)});
        });
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      "The query of jacobian(), compiled (a CompiledJacobian); the same QueryErrors.");
}

void BindUrdfMethods(GraphClass& graph) {
  constexpr const char* kUrdfDoc = R"(
Links become bodies with one frame each (prefix + link name), joints become joints (prefix +
joint name; revolute, continuous, prismatic, fixed, mimic), floating joints ordinary edges. The
root link's frame is a new tree's root: attach it with add_pose. Atomic: RejectedError
invalid_model (unreadable file, urdfdom's refusal quoted, package:// URIs, planar joints, bad
numbers, axis, limits or mimic), duplicate_joint, duplicate_body, duplicate_frame; nothing is
created then. Runs without the GIL. Returns a Robot.)";
#ifdef SEMGRAPH_PYTHON_WITH_MODELS
  graph.def(
      "load_urdf",
      [](GraphBox& b, py::handle path, const std::string& prefix) {
        py::object p = py::module_::import("os").attr("fspath")(path);
        if (!PyUnicode_Check(p.ptr()))
          throw py::type_error("load_urdf(): path must be a str or os.PathLike of str");
        return LoadUrdf(b, p.cast<std::string>(), prefix, true);
      },
      py::arg("path"), py::kw_only(), py::arg("prefix") = "",
      (std::string("Loads a URDF file (a path, or a file:// URI) into the graph, names prefixed "
                   "with `prefix`.\n") +
       kUrdfDoc)
          .c_str());
  graph.def(
      "load_urdf_string",
      [](GraphBox& b, const std::string& xml, const std::string& prefix) {
        return LoadUrdf(b, xml, prefix, false);
      },
      py::arg("xml"), py::kw_only(), py::arg("prefix") = "",
      (std::string("Loads a URDF document given as text, as load_urdf.\n") + kUrdfDoc).c_str());
#else
  auto unavailable = [](py::args, py::kwargs) -> py::object {
    throw std::runtime_error(
        "load_urdf(): semgraph was built without robot models (SEMGRAPH_BUILD_MODELS=OFF or "
        "urdfdom missing)");
  };
  graph.def("load_urdf", unavailable,
            (std::string("Unavailable in this build.\n") + kUrdfDoc).c_str());
  graph.def("load_urdf_string", unavailable,
            (std::string("Unavailable in this build.\n") + kUrdfDoc).c_str());
#endif
}

}  // namespace

void BindKinematics(py::module_& m, GraphClass& graph) {
  BindKinematicsClasses(m);
  BindJointMethods(graph);
  BindJacobianMethods(graph);
  BindUrdfMethods(graph);
}

}  // namespace semgraph::python
