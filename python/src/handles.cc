// PoseHandle and TwistHandle, and the SceneGraph methods that make and use them (pose_handle,
// twist_handle, set_pose, set_twist): O(1) updates of one edge.
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "common.h"
#include "docstrings.h"
#include "semgraph/coord/validate.h"
#include "timed.h"
#include "uncertainty.h"

namespace semgraph::python {

namespace {

// Why a stamped sample was refused (the codes of the stamped SetPose / SetTwist).
std::string StampWhy(ErrorCode code, const std::optional<core::Stamp>& t) {
  const std::string at = t ? " " + std::to_string(t->nanoseconds()) + " ns" : std::string();
  switch (code) {
    case ErrorCode::kStampMismatch:
      return t ? ": the edge is timeless (its first value had no stamp); remove and re-add it to "
                 "stamp it"
               : ": the edge is stamped; give stamp=";
    case ErrorCode::kStampTooOld:
      return ": the stamp" + at + " is older than the edge's newest sample minus the window";
    case ErrorCode::kDuplicateStamp:
      return ": the edge has another value at the stamp" + at + " (duplicate_stamp='reject')";
    case ErrorCode::kInvalidCovariance:
      return ": the covariance is not symmetric positive semidefinite, or has a convention the "
             "value cannot take ('body' is for poses only)";
    default:
      return "";
  }
}

void SetPose(GraphBox& box, const PoseHandleObject& h, py::handle position, py::handle rotation,
             py::handle quaternion, py::handle rotation_matrix, py::handle rpy, py::handle stamp,
             py::handle covariance, py::handle covariance_order, py::handle convention) {
  if (h.graph.get() != &box) {
    throw py::value_error("set_pose(): the handle belongs to another SceneGraph");
  }
  const Eigen::Vector3d p = Vector3Arg(position, "set_pose", "position");
  const RotationArg rot = RotationArgs(rotation, quaternion, rotation_matrix, rpy, "set_pose");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "set_pose", "stamp", false);
  const CovarianceArgs cov =
      ReadCovarianceArgs(covariance, covariance_order, convention, "set_pose");
  // The covariance setters take a quaternion: a matrix is validated here first, with the error
  // of the matrix setter.
  Eigen::Quaterniond q = rot.q;
  if (cov.given && rot.is_matrix) {
    auto M = coord::ValidateRotationMatrix(rot.R);
    if (!M) ThrowValue("set_pose", EdgeText(h.wrt, h.of), M.error(), box.names());
    q = Eigen::Quaterniond(*M);
  }
  core::UpdateError why;  // SetPose's own verdict: which number broke which limit
  ErrorCode code;
  {
    std::lock_guard<WriterMutex> lock(box.writer);
    code = box.Visit([&](auto& g) {
      if (cov.given) {
        return t ? g.SetPose(h.handle, q, p, *t, cov.Input(), &why)
                 : g.SetPose(h.handle, q, p, cov.Input(), &why);
      }
      if (t) {
        return rot.is_matrix ? g.SetPose(h.handle, rot.R, p, *t, &why)
                             : g.SetPose(h.handle, rot.q, p, *t, &why);
      }
      return rot.is_matrix ? g.SetPose(h.handle, rot.R, p, &why)
                           : g.SetPose(h.handle, rot.q, p, &why);
    });
  }
  if (code == ErrorCode::kNoSuchEdge) ThrowRemoved("set_pose", EdgeText(h.wrt, h.of));
  if (code == ErrorCode::kInvalidNumber || code == ErrorCode::kInvalidRotation) {
    ThrowValue("set_pose", EdgeText(h.wrt, h.of), why.error(), box.names());
  }
  if (code != ErrorCode::kOk) {
    ThrowRejected(code, "set_pose " + EdgeText(h.wrt, h.of) + " rejected (" +
                            std::string(ToString(code)) + ")" + StampWhy(code, t));
  }
}

void SetTwist(GraphBox& box, const TwistHandleObject& h, py::handle linear, py::handle angular,
              py::handle stamp, py::handle covariance, py::handle covariance_order) {
  if (h.graph.get() != &box) {
    throw py::value_error("set_twist(): the handle belongs to another SceneGraph");
  }
  const Eigen::Vector3d v = Vector3Arg(linear, "set_twist", "linear");
  const Eigen::Vector3d w = Vector3Arg(angular, "set_twist", "angular");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "set_twist", "stamp", false);
  const CovarianceArgs cov =
      ReadCovarianceArgs(covariance, covariance_order, py::none(), "set_twist");
  core::UpdateError why;  // SetTwist's own verdict: which number broke which limit
  ErrorCode code;
  {
    std::lock_guard<WriterMutex> lock(box.writer);
    code = box.Visit([&](auto& g) {
      if (cov.given) {
        return t ? g.SetTwist(h.handle, v, w, *t, cov.Input(), &why)
                 : g.SetTwist(h.handle, v, w, cov.Input(), &why);
      }
      return t ? g.SetTwist(h.handle, v, w, *t, &why) : g.SetTwist(h.handle, v, w, &why);
    });
  }
  if (code == ErrorCode::kNoSuchEdge) ThrowRemoved("set_twist", TwistEdgeText(h.ref_body, h.point));
  if (code == ErrorCode::kInvalidNumber) {
    ThrowValue("set_twist", TwistEdgeText(h.ref_body, h.point), why.error(), box.names());
  }
  if (code != ErrorCode::kOk) {
    ThrowRejected(code, "set_twist " + TwistEdgeText(h.ref_body, h.point) + " rejected (" +
                            std::string(ToString(code)) + ")" + StampWhy(code, t));
  }
}

}  // namespace

void BindHandles(py::module_& m) {
  py::class_<PoseHandleObject, std::shared_ptr<PoseHandleObject>>(
      m, "PoseHandle",
      R"(A resolved pose edge {wrt} -> {of} (SceneGraph.pose_handle), for O(1) updates with
SceneGraph.set_pose or a PoseBatch. It keeps its SceneGraph alive.)")
      .def_property_readonly(
          "of", [](const PoseHandleObject& h) { return h.of; }, "The edge's head frame.")
      .def_property_readonly(
          "wrt", [](const PoseHandleObject& h) { return h.wrt; }, "The edge's tail frame.")
      .def_property_readonly(
          "is_valid",
          [](const PoseHandleObject& h) {
            return h.graph->Visit([&](const auto& g) {
              auto current = g.FindPoseEdge(h.of, h.wrt);
              return current && SameHandle(*current, h.handle);
            });
          },
          "False once the edge was removed (even if an edge with the same frames was added again).")
      .def("__repr__", [](const PoseHandleObject& h) {
        return "PoseHandle(of='" + h.of + "', wrt='" + h.wrt + "')";
      });
  py::class_<TwistHandleObject, std::shared_ptr<TwistHandleObject>>(
      m, "TwistHandle",
      R"(A resolved twist edge ref_body -> {point} (SceneGraph.twist_handle), for O(1) updates
with SceneGraph.set_twist or a TwistBatch. It keeps its SceneGraph alive.)")
      .def_property_readonly("point", [](const TwistHandleObject& h) { return h.point; })
      .def_property_readonly("ref_body", [](const TwistHandleObject& h) { return h.ref_body; })
      .def_property_readonly("is_valid",
                             [](const TwistHandleObject& h) {
                               return h.graph->Visit([&](const auto& g) {
                                 auto current = g.FindTwistEdge(h.point, h.ref_body);
                                 return current && SameHandle(*current, h.handle);
                               });
                             })
      .def("__repr__", [](const TwistHandleObject& h) {
        return "TwistHandle(point='" + h.point + "', ref_body='" + h.ref_body + "')";
      });
}

void BindHandleMethods(GraphClass& graph) {
  graph.def(
      "pose_handle",
      [](const GraphBox& b, py::handle of, py::handle wrt) {
        const std::string_view o = NameArg(of, "pose_handle", "of");
        const std::string_view w = NameArg(wrt, "pose_handle", "wrt");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto h = g.FindPoseEdge(o, w);
          if (!h) ThrowRejected(h.error().code, h.error().message);
          return std::make_shared<PoseHandleObject>(
              PoseHandleObject{self, *h, std::string(o), std::string(w)});
        });
      },
      py::kw_only(), py::arg("of"), py::arg("wrt"),
      "The handle of the existing pose edge {wrt} -> {of} (a PoseHandle). RejectedError: "
      "unknown_frame, no_such_edge, constant_pose_change (a same-body edge cannot be updated).");
  graph.def(
      "twist_handle",
      [](const GraphBox& b, py::handle point, py::handle ref_body) {
        const std::string_view p = NameArg(point, "twist_handle", "point");
        const std::string_view r = NameArg(ref_body, "twist_handle", "ref_body");
        GraphPtr self = Self(b);
        return b.Visit([&](const auto& g) {
          auto h = g.FindTwistEdge(p, r);
          if (!h) ThrowRejected(h.error().code, h.error().message);
          return std::make_shared<TwistHandleObject>(
              TwistHandleObject{self, *h, std::string(p), std::string(r)});
        });
      },
      py::kw_only(), py::arg("point"), py::arg("ref_body"),
      "The handle of the existing twist edge ref_body -> {point} (a TwistHandle). RejectedError: "
      "unknown_frame, unknown_body, no_such_edge.");
  graph.def("set_pose", &SetPose, py::arg("handle"), py::kw_only(),
            py::arg("position") = py::none(), py::arg("rotation") = py::none(),
            py::arg("quaternion") = py::none(), py::arg("rotation_matrix") = py::none(),
            py::arg("rpy") = py::none(), py::arg("stamp") = py::none(),
            py::arg("covariance") = py::none(), py::arg("covariance_order") = py::none(),
            py::arg("convention") = py::none(),
            Doc(R"(New value of the edge behind `handle`: the head's origin in the tail (position,
default (0, 0, 0)) and the head's orientation in the tail, both in [tail]. O(1).
stamp: a new sample of a stamped edge (int nanoseconds or float seconds); never allocates.
covariance: the value's 6x6 covariance, as add_pose takes it (covariance_order, convention); a
stamped sample carries it; without it the value is exact (the edge's covariance becomes zero).
RejectedError: invalid_number, invalid_rotation, invalid_covariance, no_such_edge (removed
since the handle was made), stamp_mismatch (a stamp for a timeless edge, or none for a stamped
one), stamp_too_old, duplicate_stamp; the stored value is then unchanged. ValueError: a handle
of another SceneGraph, a covariance of another shape.
)",
                kRotationDoc)
                .c_str());
  graph.def("set_twist", &SetTwist, py::arg("handle"), py::kw_only(),
            py::arg("linear") = py::none(), py::arg("angular") = py::none(),
            py::arg("stamp") = py::none(), py::arg("covariance") = py::none(),
            py::arg("covariance_order") = py::none(),
            R"(New screw twist of the edge behind `handle`: velocity of the head frame's origin
and angular velocity of its body relative to the reference body, both in [head]. O(1).
stamp: a new sample of a stamped edge (int nanoseconds or float seconds).
covariance: the twist's 6x6 covariance (covariance_order as add_twist's); a stamped sample
carries it; without it the value is exact.
RejectedError: invalid_number, invalid_covariance, no_such_edge, stamp_mismatch, stamp_too_old,
duplicate_stamp.)");
}

}  // namespace semgraph::python
