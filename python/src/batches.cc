// PoseBatch and TwistBatch, and SceneGraph.pose_batch / twist_batch: N edges updated from one
// array without the GIL, every row checked before any is stored.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common.h"
#include "semgraph/coord/validate.h"

namespace semgraph::python {

namespace {

// Why a batch update was refused (filled without the GIL, raised with it).
struct BatchFailure {
  bool failed = false;
  std::size_t row = 0;
  bool removed = false;
  coord::Error error;
};

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

// Row i of a pose batch: the position, then the bottom row of a matrix, then the rotation.
std::optional<coord::Error> CheckPoseRow(const double* data, bool matrices, std::size_t i) {
  const PoseRow row = ReadPoseRow(data, matrices, i);
  auto vp = coord::ValidateVector(row.p, coord::ValueRole::kPosition);
  if (!vp) return vp.error();
  if (matrices) {
    const double* T = data + 16 * i;
    if (T[12] != 0.0 || T[13] != 0.0 || T[14] != 0.0 || T[15] != 1.0) {
      coord::Error e;
      e.code = ErrorCode::kInvalidRotation;
      e.value.problem = coord::ValueProblem::kNotRigidTransform;
      e.value.role = coord::ValueRole::kHomogeneousMatrix;
      return e;
    }
    auto v = coord::ValidateRotationMatrix(row.R);
    if (!v) return v.error();
  } else {
    auto v = coord::ValidateQuaternion(row.q);
    if (!v) return v.error();
  }
  return std::nullopt;
}

// Row i of a twist batch: the linear, then the angular velocity.
std::optional<coord::Error> CheckTwistRow(const double* data, std::size_t i) {
  const double* x = data + 6 * i;
  auto vv =
      coord::ValidateVector(Eigen::Vector3d(x[0], x[1], x[2]), coord::ValueRole::kLinearVelocity);
  if (!vv) return vv.error();
  auto vw =
      coord::ValidateVector(Eigen::Vector3d(x[3], x[4], x[5]), coord::ValueRole::kAngularVelocity);
  if (!vw) return vw.error();
  return std::nullopt;
}

// The one update of both batches: the row count; then, without the GIL and under the writer
// lock, the handles re-checked once per topology generation (find(g, i): the edge's handle
// now), every row checked (check(i)) before any is stored (store(g, i)), so a refused batch
// changes nothing. The failure names its row; the caller raises it with the GIL.
template <class Batch, class Find, class Check, class Store>
BatchFailure RunBatch(Batch& batch, const char* fn, py::ssize_t rows, const Find& find,
                      const Check& check, const Store& store) {
  const auto n = static_cast<py::ssize_t>(batch.handles.size());
  if (rows != n) {
    throw py::value_error(std::string(fn) + "(): values has " + std::to_string(rows) +
                          " rows, the batch has " + std::to_string(n) + " edges");
  }
  GraphBox& box = *batch.graph;
  BatchFailure failure;
  py::gil_scoped_release release;
  std::lock_guard<WriterMutex> lock(box.writer);
  box.Visit([&](auto& g) {
    const std::size_t count = batch.handles.size();
    if (batch.checked_generation != box.topology_generation) {
      for (std::size_t i = 0; i < count; ++i) {
        auto current = find(g, i);
        if (!current || !SameHandle(*current, batch.handles[i])) {
          failure = {true, i, true, {}};
          return;
        }
      }
      batch.checked_generation = box.topology_generation;
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (std::optional<coord::Error> e = check(i)) {
        failure = {true, i, false, *e};
        return;
      }
    }
    for (std::size_t i = 0; i < count; ++i) {
      const ErrorCode code = store(g, i);
      if (code != ErrorCode::kOk) {  // not expected: every row and edge was checked above
        coord::Error e;
        e.code = code;
        failure = {true, i, code == ErrorCode::kNoSuchEdge, e};
        return;
      }
    }
  });
  return failure;
}

void SetPoseBatch(PoseBatchObject& batch, py::handle values) {
  auto array = FloatArrayArg(values, "PoseBatch.set", "values");
  const bool rows7 = array.ndim() == 2 && array.shape(1) == 7;
  const bool mats = array.ndim() == 3 && array.shape(1) == 4 && array.shape(2) == 4;
  if (!rows7 && !mats) {
    throw py::value_error(
        "PoseBatch.set(): values must have shape (N, 7) [x, y, z, qw, qx, qy, "
        "qz] or (N, 4, 4), got " +
        ShapeText(array));
  }
  const double* data = array.data();
  const BatchFailure failure = RunBatch(
      batch, "PoseBatch.set", array.shape(0),
      [&](auto& g, std::size_t i) { return g.FindPoseEdge(batch.of[i], batch.wrt[i]); },
      [&](std::size_t i) { return CheckPoseRow(data, mats, i); },
      [&](auto& g, std::size_t i) {
        const PoseRow row = ReadPoseRow(data, mats, i);
        return mats ? g.SetPose(batch.handles[i], row.R, row.p)
                    : g.SetPose(batch.handles[i], row.q, row.p);
      });
  GraphBox& box = *batch.graph;
  if (!failure.failed) return;
  const std::string context = "row " + std::to_string(failure.row) + " " +
                              EdgeText(batch.wrt[failure.row], batch.of[failure.row]);
  if (failure.removed) ThrowRemoved("PoseBatch.set", context);
  ThrowValue("PoseBatch.set", context, failure.error, box.names());
}

void SetTwistBatch(TwistBatchObject& batch, py::handle values) {
  auto array = FloatArrayArg(values, "TwistBatch.set", "values");
  if (array.ndim() != 2 || array.shape(1) != 6) {
    throw py::value_error(
        "TwistBatch.set(): values must have shape (N, 6) [vx, vy, vz, wx, wy, "
        "wz], got " +
        ShapeText(array));
  }
  const double* data = array.data();
  const BatchFailure failure = RunBatch(
      batch, "TwistBatch.set", array.shape(0),
      [&](auto& g, std::size_t i) { return g.FindTwistEdge(batch.point[i], batch.ref_body[i]); },
      [&](std::size_t i) { return CheckTwistRow(data, i); },
      [&](auto& g, std::size_t i) {
        const double* x = data + 6 * i;
        return g.SetTwist(batch.handles[i], Eigen::Vector3d(x[0], x[1], x[2]),
                          Eigen::Vector3d(x[3], x[4], x[5]));
      });
  GraphBox& box = *batch.graph;
  if (!failure.failed) return;
  const std::string context = "row " + std::to_string(failure.row) + " " +
                              TwistEdgeText(batch.ref_body[failure.row], batch.point[failure.row]);
  if (failure.removed) ThrowRemoved("TwistBatch.set", context);
  ThrowValue("TwistBatch.set", context, failure.error, box.names());
}

template <class T>
std::vector<std::shared_ptr<T>> HandleList(py::handle handles, const char* fn, const char* type) {
  if (PyUnicode_Check(handles.ptr()) || !PySequence_Check(handles.ptr())) {
    throw py::type_error(std::string(fn) + "(): handles must be a sequence of " + type + ", not " +
                         TypeName(handles));
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

}  // namespace

void BindBatches(py::module_& m) {
  py::class_<PoseBatchObject, std::shared_ptr<PoseBatchObject>>(
      m, "PoseBatch", R"(N pose edges updated together from one array (SceneGraph.pose_batch).)")
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
  py::class_<TwistBatchObject, std::shared_ptr<TwistBatchObject>>(
      m, "TwistBatch", R"(N twist edges updated together from one array (SceneGraph.twist_batch).)")
      .def("set", &SetTwistBatch, py::arg("values"),
           R"(Sets the N screw twists from `values` of shape (N, 6), rows [vx, vy, vz, wx, wy, wz]:
velocity of the head frame's origin and angular velocity of its body relative to the reference
body, both in [head]. Checked first, atomic, without the GIL, as PoseBatch.set.)")
      .def("__len__", [](const TwistBatchObject& b) { return b.handles.size(); })
      .def("__repr__", [](const TwistBatchObject& b) {
        return "TwistBatch(" + std::to_string(b.handles.size()) + " edges)";
      });
}

void BindBatchMethods(GraphClass& graph) {
  graph.def(
      "pose_batch",
      [](GraphBox& b, py::handle handles) {
        auto list = HandleList<PoseHandleObject>(handles, "pose_batch", "PoseHandle");
        auto batch = std::make_shared<PoseBatchObject>();
        batch->graph = b.shared_from_this();
        for (const auto& h : list) {
          if (h->graph.get() != &b)
            throw py::value_error("pose_batch(): a handle belongs to another SceneGraph");
          batch->handles.push_back(h->handle);
          batch->of.push_back(h->of);
          batch->wrt.push_back(h->wrt);
        }
        batch->checked_generation = b.topology_generation - 1;  // checked at the first set()
        return batch;
      },
      py::arg("handles"),
      "A PoseBatch over these PoseHandles, to update them all from one array (PoseBatch.set).");
  graph.def(
      "twist_batch",
      [](GraphBox& b, py::handle handles) {
        auto list = HandleList<TwistHandleObject>(handles, "twist_batch", "TwistHandle");
        auto batch = std::make_shared<TwistBatchObject>();
        batch->graph = b.shared_from_this();
        for (const auto& h : list) {
          if (h->graph.get() != &b)
            throw py::value_error("twist_batch(): a handle belongs to another SceneGraph");
          batch->handles.push_back(h->handle);
          batch->point.push_back(h->point);
          batch->ref_body.push_back(h->ref_body);
        }
        batch->checked_generation = b.topology_generation - 1;
        return batch;
      },
      py::arg("handles"),
      "A TwistBatch over these TwistHandles, to update them all from one array (TwistBatch.set).");
}

}  // namespace semgraph::python
