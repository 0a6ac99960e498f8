#include "graph.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <cstring>
#include <optional>
#include <type_traits>
#include <utility>

#include "arguments.h"
#include "common.h"
#include "timed.h"
#include "semgraph/coord/validate.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/semantics/describe.h"
#include "semgraph/semantics/operations.h"

#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
#include "semgraph/script/scene_script.h"
#endif

namespace semgraph::python {

using core::ErrorCode;
using semantics::Field;

GraphBox::GraphBox(bool homogeneous)
    : graph(homogeneous ? decltype(graph)(std::in_place_index<1>)
                        : decltype(graph)(std::in_place_index<0>)) {}
GraphBox::GraphBox(bool, QuaternionGraph&& made) : graph(std::in_place_index<0>, std::move(made)) {}
GraphBox::GraphBox(bool, HomogeneousGraph&& made) : graph(std::in_place_index<1>, std::move(made)) {}

const char* GraphBox::representation() const noexcept {
  return Visit([](const auto& g) -> const char* {
    return std::decay_t<decltype(g)>::Backend::kName;
  });
}

const semantics::NameTable& GraphBox::names() const noexcept {
  return Visit([](const auto& g) -> const semantics::NameTable& { return g.names(); });
}

Eigen::Quaterniond CanonicalQuaternion(Eigen::Quaterniond q) noexcept {
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  for (double x : c) {
    if (x != 0.0) {
      if (x < 0.0) q.coeffs() = -q.coeffs();
      break;
    }
  }
  return q;
}

// ====================================================================== errors

namespace {
py::handle g_rejected_error;
py::handle g_query_error;
}  // namespace

void InitErrors(py::module_ errors) {
  // Kept for the life of the process (never decref'd: the interpreter may be finalizing when
  // static destructors run).
  g_rejected_error = py::object(errors.attr("RejectedError")).release();
  g_query_error = py::object(errors.attr("QueryError")).release();
}

void ThrowRejected(ErrorCode code, const std::string& message) {
  py::object exc = g_rejected_error(py::str(std::string(ToString(code))), py::str(message));
  PyErr_SetObject(g_rejected_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ThrowRejected(const core::BuildError& error) {
  if (!error.discrepancy) ThrowRejected(error.code, error.message);
  py::object d = py::make_tuple(error.discrepancy->position, error.discrepancy->angle);
  py::object exc = g_rejected_error(py::str(std::string(ToString(error.code))), py::str(error.message), d);
  PyErr_SetObject(g_rejected_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ThrowQuery(ErrorCode code, const std::string& message, const char* field,
                const char* argument) {
  py::object f = field ? py::object(py::str(field)) : py::object(py::none());
  py::object a = argument ? py::object(py::str(argument)) : py::object(py::none());
  py::object exc = g_query_error(py::str(std::string(ToString(code))), py::str(message), f, a);
  PyErr_SetObject(g_query_error.ptr(), exc.ptr());
  throw py::error_already_set();
}

namespace {

// ---------------------------------------------------------------- compiled evaluation

[[noreturn]] void ThrowInvalidated(const std::string& what) {
  ThrowQuery(ErrorCode::kQueryInvalidated,
             "the compiled query " + what +
                 " reads a pose or twist edge that was removed after it was compiled; compile "
                 "it again",
             nullptr, nullptr);
}

// A compiled query's code under a time policy: kOk, or raises (QueryError).
void CheckCompiled(ErrorCode code, const std::string& what, const core::TimePolicy* policy) {
  if (code == ErrorCode::kOk) return;
  if (code == ErrorCode::kQueryInvalidated || policy == nullptr) ThrowInvalidated(what);
  std::string why;
  switch (code) {
    case ErrorCode::kExtrapolation:
      why = "an edge it reads has no sample around the time asked and may not be extrapolated there";
      break;
    case ErrorCode::kStale: why = "an edge it reads has no sample at or after not_before"; break;
    case ErrorCode::kInvalidNumber: why = "max_extrapolation is negative"; break;
    default: why = "the time policy cannot be answered"; break;
  }
  ThrowQuery(code,
             "the compiled query " + what + " failed (" + std::string(ToString(code)) + "): " + why +
                 "; explain_pose / explain_twist with the same names and time keywords lists the edges and "
                 "their samples",
             nullptr, nullptr);
}

PoseResult Evaluate(const CompiledPoseObject& c, const core::TimePolicy* policy = nullptr) {
  return std::visit(
      [&](const auto& q) {
        using B = BackendOfT<decltype(q)>;
        typename B::PoseCoords X;
        core::TimeReport report;
        CheckCompiled(policy ? q.Evaluate(X, *policy, report) : q.Evaluate(X),
                      SemanticsText(c.graph, q.semantics()), policy);
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
                      SemanticsText(c.graph, q.semantics()), policy);
        PositionResult r{c.graph, q.semantics(), p};
        if (policy) r.time = report;
        return r;
      },
      c.query);
}
OrientationResult Evaluate(const CompiledOrientationObject& c, const core::TimePolicy* policy = nullptr) {
  return std::visit(
      [&](const auto& q) {
        using B = BackendOfT<decltype(q)>;
        typename B::Rotation M;
        core::TimeReport report;
        CheckCompiled(policy ? q.Evaluate(M, *policy, report) : q.Evaluate(M),
                      SemanticsText(c.graph, q.semantics()), policy);
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
          case CompiledKind::kLinear: return SemanticsText(c.graph, c.linear_semantics);
          case CompiledKind::kAngular: return SemanticsText(c.graph, c.angular_semantics);
          default: return SemanticsText(c.graph, q.semantics());
        }
      },
      c.query);
}
py::object Evaluate(const CompiledTwistObject& c, const core::TimePolicy* policy = nullptr) {
  Eigen::Vector3d v, w;
  core::TimeReport report;
  const ErrorCode code = std::visit(
      [&](const auto& q) { return policy ? q.Evaluate(v, w, *policy, report) : q.Evaluate(v, w); }, c.query);
  if (code != ErrorCode::kOk) CheckCompiled(code, CompiledText(c), policy);
  std::optional<core::TimeReport> time;
  if (policy) time = report;
  switch (c.kind) {
    case CompiledKind::kLinear: return py::cast(LinearVelocityResult{c.graph, c.linear_semantics, v, time});
    case CompiledKind::kAngular: return py::cast(AngularVelocityResult{c.graph, c.angular_semantics, w, time});
    default:
      return py::cast(TwistResult{
          c.graph, std::visit([](const auto& q) { return q.semantics(); }, c.query), v, w, time});
  }
}

// evaluate(*, at=, max_extrapolation=, not_before=): the compiled query under that policy.
template <class C>
py::object EvaluateAt(const C& c, py::handle at, py::handle max_extrapolation, py::handle not_before) {
  const TimeQuery t = TimeQueryArgs("evaluate", at, max_extrapolation, not_before, py::none(), py::none(), false);
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

// ---------------------------------------------------------------- graph methods

GraphPtr Make(py::handle representation, py::handle window, py::handle interpolation,
               py::handle duplicate_stamp, py::handle sample_capacity) {
  const std::string_view r = NameArg(representation, "SceneGraph", "representation");
  if (!(r == "quaternion" || r.empty() || r == "homogeneous")) {
    throw py::value_error("SceneGraph(): representation must be 'quaternion' or 'homogeneous', not '" +
                          std::string(r) + "'");
  }
  const bool homogeneous = r == "homogeneous";
  if (window.is_none() && interpolation.is_none() && duplicate_stamp.is_none() && sample_capacity.is_none()) {
    return std::make_shared<GraphBox>(homogeneous);
  }
  core::TimeOptions options;
  if (!window.is_none()) {
    options.window = core::Duration::Nanoseconds(NanosecondsArg(window, "SceneGraph", "window", false));
  }
  if (!interpolation.is_none()) {
    const std::string_view i = NameArg(interpolation, "SceneGraph", "interpolation");
    if (i == "screw") {
      options.interpolation = core::Interpolation::kScrew;
    } else if (i == "linear") {
      options.interpolation = core::Interpolation::kLinear;
    } else {
      throw py::value_error("SceneGraph(): interpolation must be 'screw' or 'linear', not '" + std::string(i) + "'");
    }
  }
  if (!duplicate_stamp.is_none()) {
    const std::string_view d = NameArg(duplicate_stamp, "SceneGraph", "duplicate_stamp");
    if (d == "replace") {
      options.duplicate_stamp = core::DuplicatePolicy::kReplace;
    } else if (d == "reject") {
      options.duplicate_stamp = core::DuplicatePolicy::kReject;
    } else {
      throw py::value_error("SceneGraph(): duplicate_stamp must be 'replace' or 'reject', not '" + std::string(d) +
                            "'");
    }
  }
  if (!sample_capacity.is_none()) {
    if (PyBool_Check(sample_capacity.ptr()) || !PyIndex_Check(sample_capacity.ptr())) {
      throw py::type_error("SceneGraph(): sample_capacity must be an int, not " + TypeName(sample_capacity));
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

[[noreturn]] void ThrowValue(const char* what, const std::string& context, const coord::Error& e,
                             const semantics::NameTable& names) {
  ThrowRejected(e.code, std::string(what) + " " + context + " rejected (" +
                            std::string(ToString(e.code)) + "): " + coord::Describe(e, names));
}

std::string EdgeText(std::string_view wrt, std::string_view of) {
  return "of the pose edge {" + std::string(wrt) + "} -> {" + std::string(of) + "}";
}
std::string TwistEdgeText(std::string_view ref_body, std::string_view point) {
  return "of the twist edge " + std::string(ref_body) + " -> {" + std::string(point) + "}";
}

[[noreturn]] void ThrowRemoved(const char* what, const std::string& context) {
  ThrowRejected(ErrorCode::kNoSuchEdge, std::string(what) + " " + context +
                                            " rejected (no_such_edge): the edge was removed "
                                            "after the handle was made");
}

// Why a stamped sample was refused (the codes of the stamped SetPose / SetTwist).
std::string StampWhy(ErrorCode code, const std::optional<core::Stamp>& t) {
  const std::string at = t ? " " + std::to_string(t->nanoseconds()) + " ns" : std::string();
  switch (code) {
    case ErrorCode::kStampMismatch:
      return t ? ": the edge is timeless (its first value had no stamp); remove and re-add it to stamp it"
               : ": the edge is stamped; give stamp=";
    case ErrorCode::kStampTooOld: return ": the stamp" + at + " is older than the edge's newest sample minus the window";
    case ErrorCode::kDuplicateStamp:
      return ": the edge has another value at the stamp" + at + " (duplicate_stamp='reject')";
    default: return "";
  }
}

void SetPose(GraphBox& box, const PoseHandleObject& h, py::handle position, py::handle rotation,
             py::handle quaternion, py::handle rotation_matrix, py::handle rpy, py::handle stamp) {
  if (h.graph.get() != &box) {
    throw py::value_error("set_pose(): the handle belongs to another SceneGraph");
  }
  const Eigen::Vector3d p = Vector3Arg(position, "set_pose", "position");
  const RotationArg rot = RotationArgs(rotation, quaternion, rotation_matrix, rpy, "set_pose");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "set_pose", "stamp", false);
  core::UpdateError why;  // SetPose's own verdict: which number broke which limit
  ErrorCode code;
  {
    std::lock_guard<std::mutex> lock(box.writer);
    code = box.Visit([&](auto& g) {
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
              py::handle stamp) {
  if (h.graph.get() != &box) {
    throw py::value_error("set_twist(): the handle belongs to another SceneGraph");
  }
  const Eigen::Vector3d v = Vector3Arg(linear, "set_twist", "linear");
  const Eigen::Vector3d w = Vector3Arg(angular, "set_twist", "angular");
  const std::optional<core::Stamp> t = OptionalStampArg(stamp, "set_twist", "stamp", false);
  core::UpdateError why;  // SetTwist's own verdict: which number broke which limit
  ErrorCode code;
  {
    std::lock_guard<std::mutex> lock(box.writer);
    code = box.Visit([&](auto& g) {
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

// ---------------------------------------------------------------- batches

// Why a batch update was refused (filled without the GIL, raised with it).
struct BatchFailure {
  bool failed = false;
  std::size_t row = 0;
  bool removed = false;
  coord::Error error;
};

bool SameHandle(const core::PoseHandle& a, const core::PoseHandle& b) { return a == b; }
bool SameHandle(const core::TwistHandle& a, const core::TwistHandle& b) { return a == b; }

// Rows of a pose batch: (N, 7) [x y z qw qx qy qz] or (N, 4, 4) homogeneous matrices.
struct PoseRow {
  Eigen::Vector3d p;
  bool is_matrix;
  Eigen::Quaterniond q;
  Eigen::Matrix3d R;
};
PoseRow ReadPoseRow(const double* data, bool matrices, std::size_t i) {
  PoseRow row;
  row.is_matrix = matrices;
  if (matrices) {
    const double* T = data + 16 * i;
    row.R << T[0], T[1], T[2], T[4], T[5], T[6], T[8], T[9], T[10];
    row.p = {T[3], T[7], T[11]};
  } else {
    const double* x = data + 7 * i;
    row.p = {x[0], x[1], x[2]};
    row.q = Eigen::Quaterniond(x[3], x[4], x[5], x[6]);
  }
  return row;
}

void SetPoseBatch(PoseBatchObject& batch, py::handle values) {
  auto array = FloatArrayArg(values, "PoseBatch.set", "values");
  const auto n = static_cast<py::ssize_t>(batch.handles.size());
  const bool rows7 = array.ndim() == 2 && array.shape(1) == 7;
  const bool mats = array.ndim() == 3 && array.shape(1) == 4 && array.shape(2) == 4;
  if (!rows7 && !mats) {
    throw py::value_error("PoseBatch.set(): values must have shape (N, 7) [x, y, z, qw, qx, qy, "
                          "qz] or (N, 4, 4), got " + ShapeText(array));
  }
  if (array.shape(0) != n) {
    throw py::value_error("PoseBatch.set(): values has " + std::to_string(array.shape(0)) +
                          " rows, the batch has " + std::to_string(n) + " edges");
  }
  const double* data = array.data();
  GraphBox& box = *batch.graph;
  BatchFailure failure;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(box.writer);
    box.Visit([&](auto& g) {
      const std::size_t count = batch.handles.size();
      if (batch.checked_generation != box.topology_generation) {
        for (std::size_t i = 0; i < count; ++i) {
          auto current = g.FindPoseEdge(batch.of[i], batch.wrt[i]);
          if (!current || !SameHandle(*current, batch.handles[i])) {
            failure = {true, i, true, {}};
            return;
          }
        }
        batch.checked_generation = box.topology_generation;
      }
      // Every row is validated before any is stored: a refused batch changes nothing.
      for (std::size_t i = 0; i < count; ++i) {
        const PoseRow row = ReadPoseRow(data, mats, i);
        auto vp = coord::ValidateVector(row.p, coord::ValueRole::kPosition);
        if (!vp) {
          failure = {true, i, false, vp.error()};
          return;
        }
        if (mats) {
          const double* T = data + 16 * i;
          if (T[12] != 0.0 || T[13] != 0.0 || T[14] != 0.0 || T[15] != 1.0) {
            coord::Error e;
            e.code = ErrorCode::kInvalidRotation;
            e.value.problem = coord::ValueProblem::kNotRigidTransform;
            e.value.role = coord::ValueRole::kHomogeneousMatrix;
            failure = {true, i, false, e};
            return;
          }
          auto v = coord::ValidateRotationMatrix(row.R);
          if (!v) {
            failure = {true, i, false, v.error()};
            return;
          }
        } else {
          auto v = coord::ValidateQuaternion(row.q);
          if (!v) {
            failure = {true, i, false, v.error()};
            return;
          }
        }
      }
      for (std::size_t i = 0; i < count; ++i) {
        const PoseRow row = ReadPoseRow(data, mats, i);
        const ErrorCode code = mats ? g.SetPose(batch.handles[i], row.R, row.p)
                                    : g.SetPose(batch.handles[i], row.q, row.p);
        if (code != ErrorCode::kOk) {  // not expected: every row and edge was checked above
          coord::Error e;
          e.code = code;
          failure = {true, i, code == ErrorCode::kNoSuchEdge, e};
          return;
        }
      }
    });
  }
  if (!failure.failed) return;
  const std::string context =
      "row " + std::to_string(failure.row) + " " + EdgeText(batch.wrt[failure.row], batch.of[failure.row]);
  if (failure.removed) ThrowRemoved("PoseBatch.set", context);
  ThrowValue("PoseBatch.set", context, failure.error, box.names());
}

void SetTwistBatch(TwistBatchObject& batch, py::handle values) {
  auto array = FloatArrayArg(values, "TwistBatch.set", "values");
  const auto n = static_cast<py::ssize_t>(batch.handles.size());
  if (array.ndim() != 2 || array.shape(1) != 6) {
    throw py::value_error("TwistBatch.set(): values must have shape (N, 6) [vx, vy, vz, wx, wy, "
                          "wz], got " + ShapeText(array));
  }
  if (array.shape(0) != n) {
    throw py::value_error("TwistBatch.set(): values has " + std::to_string(array.shape(0)) +
                          " rows, the batch has " + std::to_string(n) + " edges");
  }
  const double* data = array.data();
  GraphBox& box = *batch.graph;
  BatchFailure failure;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(box.writer);
    box.Visit([&](auto& g) {
      const std::size_t count = batch.handles.size();
      if (batch.checked_generation != box.topology_generation) {
        for (std::size_t i = 0; i < count; ++i) {
          auto current = g.FindTwistEdge(batch.point[i], batch.ref_body[i]);
          if (!current || !SameHandle(*current, batch.handles[i])) {
            failure = {true, i, true, {}};
            return;
          }
        }
        batch.checked_generation = box.topology_generation;
      }
      for (std::size_t i = 0; i < count; ++i) {
        const double* x = data + 6 * i;
        auto vv = coord::ValidateVector(Eigen::Vector3d(x[0], x[1], x[2]),
                                        coord::ValueRole::kLinearVelocity);
        if (!vv) {
          failure = {true, i, false, vv.error()};
          return;
        }
        auto vw = coord::ValidateVector(Eigen::Vector3d(x[3], x[4], x[5]),
                                        coord::ValueRole::kAngularVelocity);
        if (!vw) {
          failure = {true, i, false, vw.error()};
          return;
        }
      }
      for (std::size_t i = 0; i < count; ++i) {
        const double* x = data + 6 * i;
        const ErrorCode code = g.SetTwist(batch.handles[i], Eigen::Vector3d(x[0], x[1], x[2]),
                                          Eigen::Vector3d(x[3], x[4], x[5]));
        if (code != ErrorCode::kOk) {
          coord::Error e;
          e.code = code;
          failure = {true, i, code == ErrorCode::kNoSuchEdge, e};
          return;
        }
      }
    });
  }
  if (!failure.failed) return;
  const std::string context = "row " + std::to_string(failure.row) + " " +
                              TwistEdgeText(batch.ref_body[failure.row], batch.point[failure.row]);
  if (failure.removed) ThrowRemoved("TwistBatch.set", context);
  ThrowValue("TwistBatch.set", context, failure.error, box.names());
}

template <class T>
std::vector<std::shared_ptr<T>> HandleList(py::handle handles, const char* fn, const char* type) {
  if (PyUnicode_Check(handles.ptr()) || !PySequence_Check(handles.ptr())) {
    throw py::type_error(std::string(fn) + "(): handles must be a sequence of " + type +
                         ", not " + TypeName(handles));
  }
  std::vector<std::shared_ptr<T>> out;
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(handles);
  for (std::size_t i = 0; i < seq.size(); ++i) {
    py::object item = seq[i];
    if (!py::isinstance<T>(item)) {
      throw py::type_error(std::string(fn) + "(): handles[" + std::to_string(i) + "] must be a " +
                           type + ", not " + TypeName(item));
    }
    out.push_back(item.cast<std::shared_ptr<T>>());
  }
  return out;
}

// ---------------------------------------------------------------- docstrings

constexpr const char* kPoseNamesDoc = R"(
Names, by role (all keyword-only; a body may be omitted when its frame exists, and is checked
when given):
  of            the frame whose pose is meant: point = origin of `of`, orientation = [of]
  body          the body `of` (and point/orientation) are fixed to
  wrt           the reference frame: ref point = origin of `wrt`, ref orientation = [wrt],
                and the coordinate frame [wrt] unless expressed_in is given
  ref_body      the body `wrt` is fixed to
  point, orientation, ref_point, ref_orientation
                override the point / orientation frame / reference point / reference
                orientation frame set by `of` and `wrt` (the paper's non-frame forms)
  expressed_in  the coordinate frame [r] the result is expressed in)";

constexpr const char* kRotationDoc = R"(
Rotation, at most one of (identity when none is given):
  rotation         a quaternion (w, x, y, z) or a 3x3 rotation matrix, told apart by shape
  quaternion       (w, x, y, z), Hamilton convention, unit within 1e-6
  rotation_matrix  3x3, rows as written; its columns are the axes of [orientation] in
                   [ref_orientation]
  rpy              (roll, pitch, yaw) in radians, R = Rz(yaw) Ry(pitch) Rx(roll)
Numbers: lists, tuples or numpy arrays (converted to float64).)";

std::string Doc(const char* head, const char* tail = "") {
  return std::string(head) + tail;
}

}  // namespace

// ====================================================================== bindings

void BindGraph(py::module_& m) {
  // ------------------------------------------------------------ results
  py::class_<PoseResult>(m, "Pose", R"(The result of a pose query: PoseCoord((e,[a])|C, (f,[b])|D, [r]).

position         p: position of the point e relative to the reference point f, in [r]
quaternion       (w, x, y, z), w >= 0: the orientation of [a] relative to [b] as an operator
                 expressed in [r] (when [r] = [b]: the rotation R_ba, columns = axes of [a] in [b])
rotation_matrix  the same rotation as a 3x3 matrix
matrix           the 4x4 homogeneous matrix [R p; 0 0 0 1]
semantics        the relation in the paper's notation, e.g. 'PoseCoord({f1}|O1, {o2}|O2, [o2])')")
      .def_property_readonly("position", [](const PoseResult& r) { return VectorArray(r.p); })
      .def_property_readonly("quaternion", [](const PoseResult& r) { return QuaternionArray(r.q); })
      .def_property_readonly("rotation_matrix", [](const PoseResult& r) { return MatrixArray(r.q); })
      .def_property_readonly("matrix", [](const PoseResult& r) { return HomogeneousArray(r.q, r.p); })
      .def_property_readonly("semantics", [](const PoseResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const PoseResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const PoseResult& r) {
        return "Pose(" + SemanticsText(r.graph, r.semantics) + ", position=" + VectorText(r.p) +
               ", quaternion=" + QuaternionText(r.q) + TimeSuffix(r.time) + ")";
      });
  py::class_<PositionResult>(m, "Position", R"(The result of a position query: PositionCoord(e|C, f|D, [r]).

position   p: position of the point e relative to the point f, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("position", [](const PositionResult& r) { return VectorArray(r.p); })
      .def_property_readonly("semantics", [](const PositionResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const PositionResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const PositionResult& r) {
        return "Position(" + SemanticsText(r.graph, r.semantics) + ", position=" + VectorText(r.p) +
               TimeSuffix(r.time) + ")";
      });
  py::class_<OrientationResult>(m, "Orientation", R"(The result of an orientation query: OrientationCoord([a]|C, [b]|D, [r]).

quaternion       (w, x, y, z), w >= 0: the operator carrying [b] onto [a], expressed in [r]
                 (when [r] = [b]: R_ba, the columns are the axes of [a] in [b])
rotation_matrix  the same as a 3x3 matrix
semantics        the relation in the paper's notation)")
      .def_property_readonly("quaternion", [](const OrientationResult& r) { return QuaternionArray(r.q); })
      .def_property_readonly("rotation_matrix", [](const OrientationResult& r) { return MatrixArray(r.q); })
      .def_property_readonly("semantics", [](const OrientationResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const OrientationResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const OrientationResult& r) {
        return "Orientation(" + SemanticsText(r.graph, r.semantics) + ", quaternion=" + QuaternionText(r.q) +
               TimeSuffix(r.time) + ")";
      });
  py::class_<TwistResult>(m, "Twist", R"(The result of a twist query: TwistCoord(e|C, D, [r]).

linear     v: velocity of the point of body C at e, relative to body D, in [r]
angular    w: angular velocity of C relative to D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("linear", [](const TwistResult& r) { return VectorArray(r.v); })
      .def_property_readonly("angular", [](const TwistResult& r) { return VectorArray(r.w); })
      .def_property_readonly("semantics", [](const TwistResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const TwistResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const TwistResult& r) {
        return "Twist(" + SemanticsText(r.graph, r.semantics) + ", linear=" + VectorText(r.v) +
               ", angular=" + VectorText(r.w) + TimeSuffix(r.time) + ")";
      });
  py::class_<LinearVelocityResult>(m, "LinearVelocity", R"(The result of a linear velocity query: LinearVelocityCoord(e|C, D, [r]).

linear     v: velocity of the point of body C at e, relative to body D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("linear", [](const LinearVelocityResult& r) { return VectorArray(r.v); })
      .def_property_readonly("semantics", [](const LinearVelocityResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const LinearVelocityResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const LinearVelocityResult& r) {
        return "LinearVelocity(" + SemanticsText(r.graph, r.semantics) + ", linear=" + VectorText(r.v) +
               TimeSuffix(r.time) + ")";
      });
  py::class_<AngularVelocityResult>(m, "AngularVelocity", R"(The result of an angular velocity query: AngularVelocityCoord(C, D, [r]).

angular    w: angular velocity of body C relative to body D, in [r]
semantics  the relation in the paper's notation)")
      .def_property_readonly("angular", [](const AngularVelocityResult& r) { return VectorArray(r.w); })
      .def_property_readonly("semantics", [](const AngularVelocityResult& r) { return SemanticsText(r.graph, r.semantics); })
      .def_property_readonly("time", [](const AngularVelocityResult& r) -> py::object {
        return r.time ? TimeReportObject(*r.time) : py::none();
      }, "What a timed query read (a TimeReport), or None for a query without time keywords.")
      .def("__repr__", [](const AngularVelocityResult& r) {
        return "AngularVelocity(" + SemanticsText(r.graph, r.semantics) + ", angular=" + VectorText(r.w) +
               TimeSuffix(r.time) + ")";
      });

  // ------------------------------------------------------------ compiled queries
  constexpr const char* kCompiledDoc = R"(
Made by SceneGraph.compile_*(): the semantics were checked and the path resolved once; evaluate()
costs only the compositions along the path and sees every later set_pose/set_twist/add_pose
update of the edges it reads. It keeps its SceneGraph alive. After an edge it reads is removed,
evaluate() raises QueryError with code 'query_invalidated' (never a wrong number): compile again.)";
  py::class_<CompiledPoseObject, std::shared_ptr<CompiledPoseObject>>(
      m, "CompiledPose", Doc("A compiled pose query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledPoseObject& c) { return Evaluate(c); })
      .def("evaluate", [](const CompiledPoseObject& c, py::handle at, py::handle max_extrapolation,
                          py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
           py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
           py::arg("not_before") = py::none(),
           "The pose now (a Pose); with at= / not_before= (as SceneGraph.pose: a time, 'latest', "
           "'latest_common') under that time policy, with .time. Raises QueryError('query_invalidated') "
           "after a removal, and extrapolation / stale / invalid_number under a time policy.")
      .def_property_readonly("is_valid", [](const CompiledPoseObject& c) {
        return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
      }, "True while every edge the query reads still exists.")
      .def_property_readonly("num_pose_edges", [](const CompiledPoseObject& c) {
        return std::visit([](const auto& q) { return q.num_pose_edges(); }, c.query);
      }, "Pose edges read per evaluation.")
      .def("__repr__", [](const CompiledPoseObject& c) {
        return "CompiledPose(" + std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); }, c.query) + ")";
      });
  py::class_<CompiledPositionObject, std::shared_ptr<CompiledPositionObject>>(
      m, "CompiledPosition", Doc("A compiled position query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledPositionObject& c) { return Evaluate(c); })
      .def("evaluate", [](const CompiledPositionObject& c, py::handle at, py::handle max_extrapolation,
                          py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
           py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
           py::arg("not_before") = py::none(),
           "The position now (a Position).")
      .def_property_readonly("is_valid", [](const CompiledPositionObject& c) {
        return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
      })
      .def_property_readonly("num_pose_edges", [](const CompiledPositionObject& c) {
        return std::visit([](const auto& q) { return q.num_pose_edges(); }, c.query);
      })
      .def("__repr__", [](const CompiledPositionObject& c) {
        return "CompiledPosition(" + std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); }, c.query) + ")";
      });
  py::class_<CompiledOrientationObject, std::shared_ptr<CompiledOrientationObject>>(
      m, "CompiledOrientation", Doc("A compiled orientation query.", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledOrientationObject& c) { return Evaluate(c); })
      .def("evaluate", [](const CompiledOrientationObject& c, py::handle at, py::handle max_extrapolation,
                          py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
           py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
           py::arg("not_before") = py::none(),
           "The orientation now (an Orientation).")
      .def_property_readonly("is_valid", [](const CompiledOrientationObject& c) {
        return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
      })
      .def_property_readonly("num_pose_edges", [](const CompiledOrientationObject& c) {
        return std::visit([](const auto& q) { return q.num_pose_edges(); }, c.query);
      })
      .def("__repr__", [](const CompiledOrientationObject& c) {
        return "CompiledOrientation(" + std::visit([&](const auto& q) { return SemanticsText(c.graph, q.semantics()); }, c.query) + ")";
      });
  py::class_<CompiledTwistObject, std::shared_ptr<CompiledTwistObject>>(
      m, "CompiledTwist",
      Doc("A compiled twist, linear velocity or angular velocity query (evaluate() returns a "
          "Twist, LinearVelocity or AngularVelocity, as compiled).", kCompiledDoc).c_str())
      // Two overloads: the untimed one first, so that the real-time call evaluate() does not pay
      // for parsing the time keywords.
      .def("evaluate", [](const CompiledTwistObject& c) { return Evaluate(c); })
      .def("evaluate", [](const CompiledTwistObject& c, py::handle at, py::handle max_extrapolation,
                          py::handle not_before) { return EvaluateAt(c, at, max_extrapolation, not_before); },
           py::kw_only(), py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),
           py::arg("not_before") = py::none(),
           "The twist (or linear / angular velocity) now.")
      .def_property_readonly("is_valid", [](const CompiledTwistObject& c) {
        return std::visit([](const auto& q) { return q.is_valid(); }, c.query);
      })
      .def_property_readonly("num_pose_edges", [](const CompiledTwistObject& c) {
        return std::visit([](const auto& q) { return q.num_pose_edges(); }, c.query);
      })
      .def_property_readonly("num_twist_edges", [](const CompiledTwistObject& c) {
        return std::visit([](const auto& q) { return q.num_twist_edges(); }, c.query);
      }, "Twist edges read per evaluation.")
      .def("__repr__", [](const CompiledTwistObject& c) { return "CompiledTwist(" + CompiledText(c) + ")"; });

  // ------------------------------------------------------------ handles and batches
  py::class_<PoseHandleObject, std::shared_ptr<PoseHandleObject>>(m, "PoseHandle",
      R"(A resolved pose edge {wrt} -> {of} (SceneGraph.pose_handle), for O(1) updates with
SceneGraph.set_pose or a PoseBatch. It keeps its SceneGraph alive.)")
      .def_property_readonly("of", [](const PoseHandleObject& h) { return h.of; }, "The edge's head frame.")
      .def_property_readonly("wrt", [](const PoseHandleObject& h) { return h.wrt; }, "The edge's tail frame.")
      .def_property_readonly("is_valid", [](const PoseHandleObject& h) {
        return h.graph->Visit([&](const auto& g) {
          auto current = g.FindPoseEdge(h.of, h.wrt);
          return current && SameHandle(*current, h.handle);
        });
      }, "False once the edge was removed (even if an edge with the same frames was added again).")
      .def("__repr__", [](const PoseHandleObject& h) {
        return "PoseHandle(of='" + h.of + "', wrt='" + h.wrt + "')";
      });
  py::class_<TwistHandleObject, std::shared_ptr<TwistHandleObject>>(m, "TwistHandle",
      R"(A resolved twist edge ref_body -> {point} (SceneGraph.twist_handle), for O(1) updates
with SceneGraph.set_twist or a TwistBatch. It keeps its SceneGraph alive.)")
      .def_property_readonly("point", [](const TwistHandleObject& h) { return h.point; })
      .def_property_readonly("ref_body", [](const TwistHandleObject& h) { return h.ref_body; })
      .def_property_readonly("is_valid", [](const TwistHandleObject& h) {
        return h.graph->Visit([&](const auto& g) {
          auto current = g.FindTwistEdge(h.point, h.ref_body);
          return current && SameHandle(*current, h.handle);
        });
      })
      .def("__repr__", [](const TwistHandleObject& h) {
        return "TwistHandle(point='" + h.point + "', ref_body='" + h.ref_body + "')";
      });
  py::class_<PoseBatchObject, std::shared_ptr<PoseBatchObject>>(m, "PoseBatch",
      R"(N pose edges updated together from one array (SceneGraph.pose_batch).)")
      .def("set", &SetPoseBatch, py::arg("values"),
           R"(Sets the N edges from `values`: shape (N, 7), rows [x, y, z, qw, qx, qy, qz] (position
of the head's origin in the tail, then the head's orientation in the tail as a unit quaternion),
or shape (N, 4, 4), homogeneous matrices [R p; 0 0 0 1]. Every row is checked before any is
stored, so a refused batch (RejectedError naming the row: invalid_number, invalid_rotation,
no_such_edge) changes nothing. Runs without the GIL.)")
      .def("__len__", [](const PoseBatchObject& b) { return b.handles.size(); })
      .def("__repr__", [](const PoseBatchObject& b) {
        return "PoseBatch(" + std::to_string(b.handles.size()) + " edges)";
      });
  py::class_<TwistBatchObject, std::shared_ptr<TwistBatchObject>>(m, "TwistBatch",
      R"(N twist edges updated together from one array (SceneGraph.twist_batch).)")
      .def("set", &SetTwistBatch, py::arg("values"),
           R"(Sets the N screw twists from `values` of shape (N, 6), rows [vx, vy, vz, wx, wy, wz]:
velocity of the head frame's origin and angular velocity of its body relative to the reference
body, both in [head]. Checked first, atomic, without the GIL, as PoseBatch.set.)")
      .def("__len__", [](const TwistBatchObject& b) { return b.handles.size(); })
      .def("__repr__", [](const TwistBatchObject& b) {
        return "TwistBatch(" + std::to_string(b.handles.size()) + " edges)";
      });

  BindRepair(m);

  // ------------------------------------------------------------ SceneGraph
  GraphClass graph(m, "SceneGraph", R"(A constraint-checking scene graph of poses and twists of rigid bodies (De Laet et al.,
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
  graph.def_property_readonly("time_options", [](const GraphBox& b) {
    return b.Visit([](const auto& g) {
      const core::TimeOptions& o = g.time_options();
      py::dict d;
      d["window"] = static_cast<double>(o.window.nanoseconds()) / 1e9;
      d["window_ns"] = o.window.nanoseconds();
      d["interpolation"] = o.interpolation == core::Interpolation::kScrew ? "screw" : "linear";
      d["duplicate_stamp"] = o.duplicate_stamp == core::DuplicatePolicy::kReplace ? "replace" : "reject";
      d["sample_capacity"] = o.sample_capacity;
      return d;
    });
  }, "The graph's time options as a dict: window (s), window_ns, interpolation, duplicate_stamp, "
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
  graph.def_property_readonly("frames", [](const GraphBox& b) {
    return b.Visit([](const auto& g) {
      std::vector<std::string> out;
      for (std::uint32_t i = 0; i < g.num_frames(); ++i) out.emplace_back(g.frame_name(core::FrameIndex(i)));
      return out;
    });
  }, "Frame names, in creation order.");
  graph.def_property_readonly("bodies", [](const GraphBox& b) {
    return b.Visit([](const auto& g) {
      std::vector<std::string> out;
      for (std::uint32_t i = 0; i < g.num_bodies(); ++i) out.emplace_back(g.body_name(core::BodyIndex(i)));
      return out;
    });
  }, "Body names, in creation order.");
  graph.def("body_of", [](const GraphBox& b, py::handle frame) -> py::object {
    const std::string_view name = NameArg(frame, "body_of", "frame");
    return b.Visit([&](const auto& g) -> py::object {
      const core::FrameIndex f = g.FindFrame(name);
      if (!f.is_valid()) return py::none();
      return py::str(std::string(g.body_name(g.body_of(f))));
    });
  }, py::arg("frame"), "The name of the body a frame is fixed to, or None for an unknown frame.");
  graph.def("__repr__", [](const GraphBox& b) {
    return b.Visit([&](const auto& g) {
      return "SceneGraph(representation='" + std::string(b.representation()) + "', frames=" +
             std::to_string(g.num_frames()) + ", bodies=" + std::to_string(g.num_bodies()) +
             ", pose_edges=" + std::to_string(g.num_pose_edges()) + ", twist_edges=" +
             std::to_string(g.num_twist_edges()) + ")";
    });
  });

  // ---- build
  graph.def("add_body", [](GraphBox& b, py::handle name) {
    const std::string_view n = NameArg(name, "add_body", "name");
    std::lock_guard<std::mutex> lock(b.writer);
    Check(b.Visit([&](auto& g) { return g.AddBody(n); }));
  }, py::arg("name"), "Adds a body. RejectedError: invalid_name, duplicate_body.");
  graph.def("add_frame", [](GraphBox& b, py::handle name, py::handle body) {
    const std::string_view n = NameArg(name, "add_frame", "name");
    const std::string_view bd = NameArg(body, "add_frame", "body");
    std::lock_guard<std::mutex> lock(b.writer);
    Check(b.Visit([&](auto& g) { return g.AddFrame(n, bd); }));
  }, py::arg("name"), py::arg("body"),
     "Adds a frame fixed to an existing body. RejectedError: invalid_name, frame_without_body, "
     "duplicate_frame, unknown_body.");
  graph.def("add_pose",
      [](GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in, py::handle position,
         py::handle rotation, py::handle quaternion, py::handle rotation_matrix, py::handle rpy,
         py::handle stamp, py::handle repair) -> py::object {
        const PoseNames n = ReadPoseNames("add_pose", of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const Eigen::Vector3d p = Vector3Arg(position, "add_pose", "position");
        const RotationArg rot = RotationArgs(rotation, quaternion, rotation_matrix, rpy, "add_pose");
        const std::optional<core::Stamp> t = OptionalStampArg(stamp, "add_pose", "stamp", false);
        const std::optional<core::RepairPolicy> policy = RepairArg(repair, "add_pose");
        if (t && policy) {
          throw py::value_error("add_pose(): stamp= and repair= cannot be combined (repair applies to timeless "
                                "relations)");
        }
        const core::PoseSpec spec = n.Spec();
        std::lock_guard<std::mutex> lock(b.writer);
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
          if (t) return rot.is_matrix ? g.AddPose(spec, rot.R, p, *t) : g.AddPose(spec, rot.q, p, *t);
          return rot.is_matrix ? g.AddPose(spec, rot.R, p) : g.AddPose(spec, rot.q, p);
        }));
        return py::none();
      },
      py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),
      py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("point") = py::none(), py::arg("orientation") = py::none(),
      py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(),
      py::arg("expressed_in") = py::none(), py::arg("position") = py::none(),
      py::arg("rotation") = py::none(), py::arg("quaternion") = py::none(),
      py::arg("rotation_matrix") = py::none(), py::arg("rpy") = py::none(),
      py::arg("stamp") = py::none(), py::arg("repair") = py::none(),
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
RejectedError (code): invalid_name, invalid_number, invalid_rotation, frame_body_mismatch,
self_edge, representation_constraint, pose_not_convertible, constant_pose_change,
multiple_pose_parents, pose_cycle, duplicate_pose_path, twist_merge_conflict, joint_edge;
with a stamp stamp_mismatch, stamp_too_old, duplicate_stamp, extrapolation (a conversion at a
stamp the other edges have no values for); with repair a refused consistency check keeps its
code and has .discrepancy = (position, angle).
)", (std::string(kPoseNamesDoc) + kRotationDoc).c_str()).c_str());
  graph.def("add_twist",
      [](GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle linear, py::handle angular, py::handle stamp,
         py::handle repair) -> py::object {
        const core::TwistSpec spec = ReadTwistSpec("add_twist", point, body, ref_body, expressed_in);
        const Eigen::Vector3d v = Vector3Arg(linear, "add_twist", "linear");
        const Eigen::Vector3d w = Vector3Arg(angular, "add_twist", "angular");
        const std::optional<core::Stamp> t = OptionalStampArg(stamp, "add_twist", "stamp", false);
        const std::optional<core::RepairPolicy> policy = RepairArg(repair, "add_twist");
        if (t && policy) {
          throw py::value_error("add_twist(): stamp= and repair= cannot be combined (repair applies to timeless "
                                "relations)");
        }
        std::lock_guard<std::mutex> lock(b.writer);
        if (policy) {
          return b.Visit([&](auto& g) -> py::object {
            auto r = g.AddTwist(spec, v, w, *policy);
            if (!r) ThrowRejected(r.error());
            return py::cast(std::move(*r));
          });
        }
        Check(b.Visit([&](auto& g) { return t ? g.AddTwist(spec, v, w, *t) : g.AddTwist(spec, v, w); }));
        return py::none();
      },
      py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none(),
      py::arg("linear") = py::none(), py::arg("angular") = py::none(),
      py::arg("stamp") = py::none(), py::arg("repair") = py::none(),
      R"(Adds the twist of body `body` (default: the body of frame `point`) relative to body
`ref_body`, as the twist edge ref_body -> {point}, or updates it.
linear: velocity of the point of `body` at the origin of `point`; angular: angular velocity;
both expressed in [expressed_in] (converted to [point] once when different); default zero.
stamp: a stamped sample (int nanoseconds or float seconds), as for add_pose.
repair: True or a RepairPolicy: repair a rejection by W1 (the inverse twist on a frame of the
reference body) or duplicate_twist_path (consistency check); returns a RepairReport.
RejectedError: invalid_name, invalid_number, unknown_frame, unknown_body, frame_body_mismatch,
twist_same_body, twist_not_convertible, multiple_twist_parents, duplicate_twist_path,
joint_edge; with a stamp stamp_mismatch, stamp_too_old, duplicate_stamp, extrapolation.)");
  graph.def("remove_pose", [](GraphBox& b, py::handle of, py::handle wrt) {
    const std::string_view o = NameArg(of, "remove_pose", "of");
    const std::string_view w = NameArg(wrt, "remove_pose", "wrt");
    std::lock_guard<std::mutex> lock(b.writer);
    Check(b.Visit([&](auto& g) { return g.RemovePose(o, w); }));
    ++b.topology_generation;
  }, py::kw_only(), py::arg("of"), py::arg("wrt"),
     "Removes the pose edge {wrt} -> {of}. RejectedError: invalid_name, unknown_frame, "
     "no_such_edge. Compiled queries and handles that read it become invalid.");
  graph.def("remove_twist", [](GraphBox& b, py::handle point, py::handle ref_body) {
    const std::string_view p = NameArg(point, "remove_twist", "point");
    const std::string_view r = NameArg(ref_body, "remove_twist", "ref_body");
    std::lock_guard<std::mutex> lock(b.writer);
    Check(b.Visit([&](auto& g) { return g.RemoveTwist(p, r); }));
    ++b.topology_generation;
  }, py::kw_only(), py::arg("point"), py::arg("ref_body"),
     "Removes the twist edge ref_body -> {point}. RejectedError: invalid_name, unknown_frame, "
     "unknown_body, no_such_edge.");

  // ---- queries
#define SEMGRAPH_POSE_ARGS                                                                       \
  py::kw_only(), py::arg("of") = py::none(), py::arg("body") = py::none(),                       \
      py::arg("wrt") = py::none(), py::arg("ref_body") = py::none(),                             \
      py::arg("point") = py::none(), py::arg("orientation") = py::none(),                        \
      py::arg("ref_point") = py::none(), py::arg("ref_orientation") = py::none(),                \
      py::arg("expressed_in") = py::none()
#define SEMGRAPH_TWIST_ARGS                                                                      \
  py::kw_only(), py::arg("point") = py::none(), py::arg("body") = py::none(),                    \
      py::arg("ref_body") = py::none(), py::arg("expressed_in") = py::none()
#define SEMGRAPH_TIME_ARGS                                                                       \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),                          \
      py::arg("not_before") = py::none(), py::arg("ref_at") = py::none(), py::arg("fixed") = py::none()
#define SEMGRAPH_TWIST_TIME_ARGS                                                                 \
  py::arg("at") = py::none(), py::arg("max_extrapolation") = py::none(),                          \
      py::arg("not_before") = py::none(), py::arg("source") = py::none()

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
  const std::string time_doc = std::string(kTimeCommonDoc) + R"(
  ref_at, fixed      time travel: the point side at `at`, the reference side at `ref_at`,
                     through the frame `fixed`, assumed fixed between the two)";
  const std::string twist_time_doc = std::string(kTimeCommonDoc) + R"(
  source             'twists' (default: the twist edges) or 'poses' (the time derivative of the
                     pose history; no twist edge read))";
  const char* kTimeDoc = time_doc.c_str();
  const char* kTwistTimeDoc = twist_time_doc.c_str();

  graph.def("pose",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t = TimeQueryArgs("pose", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("pose", of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          using B = typename std::decay_t<decltype(g)>::Backend;
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetPose(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return MakePoseResult<B>(self, r->semantics, r->value);
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetPose(spec, *t.travel) : g.GetPose(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          PoseResult out = MakePoseResult<B>(self, r->value.semantics, r->value.value);
          out.time = r->time;
          return out;
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The pose of `of` relative to `wrt`, expressed in `expressed_in` (a Pose).\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str()).c_str());
  graph.def("position",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t = TimeQueryArgs("position", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("position", of, body, wrt, ref_body, point, orientation,
                                          ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          if (t.kind == TimeQuery::Kind::kNone) {
            auto r = g.GetPosition(spec);
            if (!r) ThrowPoseQuery(g, r.error(), spec, n);
            return PositionResult{self, r->semantics, r->value};
          }
          auto r = t.kind == TimeQuery::Kind::kTravel ? g.GetPosition(spec, *t.travel) : g.GetPosition(spec, t.policy);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return PositionResult{self, r->value.semantics, r->value.value, r->time};
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The position of the origin of `of` (or `point`) relative to the origin of `wrt` (or "
          "`ref_point`), in `expressed_in` (a Position). Orientation names are ignored.\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str()).c_str());
  graph.def("orientation",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in, py::handle at, py::handle max_extrapolation,
         py::handle not_before, py::handle ref_at, py::handle fixed) {
        const TimeQuery t = TimeQueryArgs("orientation", at, max_extrapolation, not_before, ref_at, fixed, true);
        const PoseNames n = ReadPoseNames("orientation", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          OrientationResult out = MakeOrientationResult<B>(self, r->value.semantics, r->value.value);
          out.time = r->time;
          return out;
        });
      },
      SEMGRAPH_POSE_ARGS, SEMGRAPH_TIME_ARGS,
      Doc("The orientation of [of] (or [orientation]) relative to [wrt] (or [ref_orientation]), "
          "in `expressed_in` (an Orientation). Point names are ignored.\n",
          (std::string(kPoseNamesDoc) + kTimeDoc + kQueryErrors).c_str()).c_str());
  constexpr const char* kTwistNamesDoc = R"(
Names (keyword-only):
  point         a frame: the velocity is that of the point of `body` at this frame's origin
  body          the moving body C (default: the body of `point`'s frame)
  ref_body      the reference body D
  expressed_in  the coordinate frame [r])";
  graph.def("twist",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation, py::handle not_before,
         py::handle source) {
        const core::TwistSpec spec = ReadTwistSpec("twist", point, body, ref_body, expressed_in);
        const TimeQuery t = TimeQueryArgs("twist", at, max_extrapolation, not_before, py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "twist");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          (std::string(kTwistNamesDoc) + kTwistTimeDoc + kQueryErrors).c_str()).c_str());
  graph.def("linear_velocity",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle at, py::handle max_extrapolation, py::handle not_before,
         py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("linear_velocity", point, body, ref_body, expressed_in);
        const TimeQuery t =
            TimeQueryArgs("linear_velocity", at, max_extrapolation, not_before, py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "linear_velocity");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          (std::string(kTwistNamesDoc) + kTwistTimeDoc + kQueryErrors).c_str()).c_str());
  graph.def("angular_velocity",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in, py::handle at,
         py::handle max_extrapolation, py::handle not_before, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("angular_velocity", py::none(), body, ref_body, expressed_in);
        const TimeQuery t =
            TimeQueryArgs("angular_velocity", at, max_extrapolation, not_before, py::none(), py::none(), false);
        const core::TwistSource src = TwistSourceArg(source, "angular_velocity");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          "AngularVelocity). No point is needed.\n", (std::string(kTwistTimeDoc) + kQueryErrors).c_str()).c_str());

  // ---- compiled queries
  graph.def("compile_pose",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_pose", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.CompilePose(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledPoseObject>(CompiledPoseObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS,
      "The pose query of pose(), compiled (a CompiledPose); the same QueryErrors as pose().");
  graph.def("compile_position",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_position", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.CompilePosition(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledPositionObject>(CompiledPositionObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS,
      "The query of position(), compiled (a CompiledPosition).");
  graph.def("compile_orientation",
      [](const GraphBox& b, py::handle of, py::handle body, py::handle wrt, py::handle ref_body,
         py::handle point, py::handle orientation, py::handle ref_point,
         py::handle ref_orientation, py::handle expressed_in) {
        const PoseNames n = ReadPoseNames("compile_orientation", of, body, wrt, ref_body, point,
                                          orientation, ref_point, ref_orientation, expressed_in);
        const core::PoseSpec spec = n.Spec();
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.CompileOrientation(spec);
          if (!r) ThrowPoseQuery(g, r.error(), spec, n);
          return std::make_shared<CompiledOrientationObject>(
              CompiledOrientationObject{self, std::move(*r)});
        });
      },
      SEMGRAPH_POSE_ARGS,
      "The query of orientation(), compiled (a CompiledOrientation).");
  graph.def("compile_twist",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle source) {
        const core::TwistSpec spec = ReadTwistSpec("compile_twist", point, body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_twist");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
        return b.Visit([&](const auto& g) {
          auto r = g.CompileTwist(spec, src);
          if (!r) ThrowTwistQuery(g, r.error(), spec);
          auto c = std::make_shared<CompiledTwistObject>(CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kTwist;
          return c;
        });
      },
      SEMGRAPH_TWIST_ARGS, py::arg("source") = py::none(),
      "The query of twist(), compiled (a CompiledTwist returning Twist). source: 'twists' (default) "
      "or 'poses' (the pose history's time derivative; evaluate under a time policy).");
  graph.def("compile_linear_velocity",
      [](const GraphBox& b, py::handle point, py::handle body, py::handle ref_body,
         py::handle expressed_in, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_linear_velocity", point, body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_linear_velocity");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          auto c = std::make_shared<CompiledTwistObject>(CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kLinear;
          c->linear_semantics = linear;
          return c;
        });
      },
      SEMGRAPH_TWIST_ARGS, py::arg("source") = py::none(),
      "The query of linear_velocity(), compiled (a CompiledTwist returning LinearVelocity); source as "
      "compile_twist.");
  graph.def("compile_angular_velocity",
      [](const GraphBox& b, py::handle body, py::handle ref_body, py::handle expressed_in, py::handle source) {
        const core::TwistSpec spec =
            ReadTwistSpec("compile_angular_velocity", py::none(), body, ref_body, expressed_in);
        const core::TwistSource src = TwistSourceArg(source, "compile_angular_velocity");
        GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
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
          auto c = std::make_shared<CompiledTwistObject>(CompiledTwistObject{self, std::move(*r), CompiledKind::kTwist, {}, {}});
          c->kind = CompiledKind::kAngular;
          c->angular_semantics = angular;
          return c;
        });
      },
      py::kw_only(), py::arg("body") = py::none(), py::arg("ref_body") = py::none(),
      py::arg("expressed_in") = py::none(), py::arg("source") = py::none(),
      "The query of angular_velocity(), compiled (a CompiledTwist returning AngularVelocity); source as "
      "compile_twist.");
#undef SEMGRAPH_POSE_ARGS
#undef SEMGRAPH_TWIST_ARGS
#undef SEMGRAPH_TIME_ARGS
#undef SEMGRAPH_TWIST_TIME_ARGS

  // ---- handles
  graph.def("pose_handle", [](const GraphBox& b, py::handle of, py::handle wrt) {
    const std::string_view o = NameArg(of, "pose_handle", "of");
    const std::string_view w = NameArg(wrt, "pose_handle", "wrt");
    GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
    return b.Visit([&](const auto& g) {
      auto h = g.FindPoseEdge(o, w);
      if (!h) ThrowRejected(h.error().code, h.error().message);
      return std::make_shared<PoseHandleObject>(
          PoseHandleObject{self, *h, std::string(o), std::string(w)});
    });
  }, py::kw_only(), py::arg("of"), py::arg("wrt"),
     "The handle of the existing pose edge {wrt} -> {of} (a PoseHandle). RejectedError: "
     "unknown_frame, no_such_edge, constant_pose_change (a same-body edge cannot be updated).");
  graph.def("twist_handle", [](const GraphBox& b, py::handle point, py::handle ref_body) {
    const std::string_view p = NameArg(point, "twist_handle", "point");
    const std::string_view r = NameArg(ref_body, "twist_handle", "ref_body");
    GraphPtr self = std::const_pointer_cast<GraphBox>(b.shared_from_this());
    return b.Visit([&](const auto& g) {
      auto h = g.FindTwistEdge(p, r);
      if (!h) ThrowRejected(h.error().code, h.error().message);
      return std::make_shared<TwistHandleObject>(
          TwistHandleObject{self, *h, std::string(p), std::string(r)});
    });
  }, py::kw_only(), py::arg("point"), py::arg("ref_body"),
     "The handle of the existing twist edge ref_body -> {point} (a TwistHandle). RejectedError: "
     "unknown_frame, unknown_body, no_such_edge.");
  graph.def("set_pose", &SetPose, py::arg("handle"), py::kw_only(),
            py::arg("position") = py::none(), py::arg("rotation") = py::none(),
            py::arg("quaternion") = py::none(), py::arg("rotation_matrix") = py::none(),
            py::arg("rpy") = py::none(), py::arg("stamp") = py::none(),
            Doc(R"(New value of the edge behind `handle`: the head's origin in the tail (position,
default (0, 0, 0)) and the head's orientation in the tail, both in [tail]. O(1).
stamp: a new sample of a stamped edge (int nanoseconds or float seconds); never allocates.
RejectedError: invalid_number, invalid_rotation, no_such_edge (removed since the handle was
made), stamp_mismatch (a stamp for a timeless edge, or none for a stamped one), stamp_too_old,
duplicate_stamp; the stored value is then unchanged. ValueError: a handle of another SceneGraph.
)", kRotationDoc).c_str());
  graph.def("set_twist", &SetTwist, py::arg("handle"), py::kw_only(),
            py::arg("linear") = py::none(), py::arg("angular") = py::none(), py::arg("stamp") = py::none(),
            R"(New screw twist of the edge behind `handle`: velocity of the head frame's origin
and angular velocity of its body relative to the reference body, both in [head]. O(1).
stamp: a new sample of a stamped edge (int nanoseconds or float seconds).
RejectedError: invalid_number, no_such_edge, stamp_mismatch, stamp_too_old, duplicate_stamp.)");
  graph.def("pose_batch", [](GraphBox& b, py::handle handles) {
    auto list = HandleList<PoseHandleObject>(handles, "pose_batch", "PoseHandle");
    auto batch = std::make_shared<PoseBatchObject>();
    batch->graph = b.shared_from_this();
    for (const auto& h : list) {
      if (h->graph.get() != &b) throw py::value_error("pose_batch(): a handle belongs to another SceneGraph");
      batch->handles.push_back(h->handle);
      batch->of.push_back(h->of);
      batch->wrt.push_back(h->wrt);
    }
    batch->checked_generation = b.topology_generation - 1;  // checked at the first set()
    return batch;
  }, py::arg("handles"),
     "A PoseBatch over these PoseHandles, to update them all from one array (PoseBatch.set).");
  graph.def("twist_batch", [](GraphBox& b, py::handle handles) {
    auto list = HandleList<TwistHandleObject>(handles, "twist_batch", "TwistHandle");
    auto batch = std::make_shared<TwistBatchObject>();
    batch->graph = b.shared_from_this();
    for (const auto& h : list) {
      if (h->graph.get() != &b) throw py::value_error("twist_batch(): a handle belongs to another SceneGraph");
      batch->handles.push_back(h->handle);
      batch->point.push_back(h->point);
      batch->ref_body.push_back(h->ref_body);
    }
    batch->checked_generation = b.topology_generation - 1;
    return batch;
  }, py::arg("handles"),
     "A TwistBatch over these TwistHandles, to update them all from one array (TwistBatch.set).");

  // ---- inspection
  graph.def("dump", [](const GraphBox& b) { return b.Visit([](const auto& g) { return Dump(g); }); },
            "A canonical, complete text dump of the graph (names, topology, values), e.g. to "
            "compare states.");
  graph.def("check_invariants",
            [](const GraphBox& b) { return b.Visit([](const auto& g) { return CheckInvariants(g); }); },
            "Verifies every invariant of the graph from scratch (slow); '' when all hold.");
  graph.def("dot", [](const GraphBox& b) -> std::string {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
    return b.Visit([](const auto& g) { return script::WriteDot(g); });
#else
    (void)b;
    throw std::runtime_error("dot(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
  }, R"(The graph as Graphviz DOT in the style of the paper's Fig. 8: a cluster per body holding its
frames, pose edges solid (tail -> head), twist edges dashed (reference body -> head frame).)");
  graph.def("to_script", [](const GraphBox& b) -> std::string {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
    return b.Visit([](const auto& g) { return script::WriteScene(g); });
#else
    (void)b;
    throw std::runtime_error(
        "to_script(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
  }, R"(The graph as a scene script (YAML, like `semgraph export`) that rebuilds it:
run_script_text(g.to_script()).graph has the same names, ids, edges and values (its dump() is
g.dump()). Save it to a file to load the scene later with run_script.)");

  BindTime(m, graph);
  BindKinematics(m, graph);
}

}  // namespace semgraph::python
