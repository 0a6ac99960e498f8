// File: python/src/graph.h
//
// The C++ objects behind the Python classes, and the functions that register the classes (one
// binding file per class or family of classes, after Pinocchio's expose-*.cpp). Nothing here
// computes geometry: every number comes from semgraph::core (SceneGraph, CompiledX,
// SetPose/SetTwist); this layer converts arguments, shares ownership and turns error values into
// Python exceptions (common.h).
//
// Ownership (why nothing can dangle): a GraphBox is held by std::shared_ptr. The Python
// SceneGraph, every result (for the names in its repr), compiled query, handle and batch hold
// one, so a compiled query made from a graph keeps that graph alive after the Python SceneGraph
// is gone; the SceneGraph<B> inside a box never moves (core's requirement for compiled queries).
//
// Concurrency: every Python call runs with the GIL held, except batch updates and script runs,
// which release it. GraphBox::writer serializes every write (add, remove, set, batch set), so the
// core's "one writer" and "topology changes need exclusive access" rules hold even when a batch
// runs without the GIL; queries and compiled evaluations are readers (sequence locks) and take no
// lock, as in C++.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "semgraph/core/compiled_query.h"
#include "semgraph/core/scene_graph.h"

namespace semgraph::python {

namespace py = pybind11;

using QuaternionGraph = core::SceneGraph<coord::QuaternionBackend>;
using HomogeneousGraph = core::SceneGraph<coord::HomogeneousBackend>;

/// GraphBox::writer: a mutex that refuses to be taken while another component is the graph's one
/// writer (a ROS listener's receive thread, ros_live.cc): lock() then throws GraphReadOnly, which
/// the module raises as RejectedError("read_only") (common.cc), so that a Python write cannot
/// race the listener's.
struct GraphReadOnly {};
class WriterMutex {
 public:
  void lock() {
    if (read_only.load(std::memory_order_acquire)) throw GraphReadOnly{};
    mutex_.lock();
  }
  void unlock() { mutex_.unlock(); }
  std::atomic<bool> read_only{false};

 private:
  std::mutex mutex_;
};

struct GraphBox : std::enable_shared_from_this<GraphBox> {
  explicit GraphBox(bool homogeneous);
  /// A graph made by SceneGraph<B>::Create(options) (the caller checked that it succeeds).
  GraphBox(bool homogeneous, core::SceneGraph<coord::QuaternionBackend>&& made);
  GraphBox(bool homogeneous, core::SceneGraph<coord::HomogeneousBackend>&& made);
  GraphBox(const GraphBox&) = delete;
  GraphBox& operator=(const GraphBox&) = delete;

  template <class F>
  decltype(auto) Visit(F&& f) {
    return std::visit(std::forward<F>(f), graph);
  }
  template <class F>
  decltype(auto) Visit(F&& f) const {
    return std::visit(std::forward<F>(f), graph);
  }
  [[nodiscard]] const char* representation() const noexcept;
  [[nodiscard]] const semantics::NameTable& names() const noexcept;

  std::variant<QuaternionGraph, HomogeneousGraph> graph;
  WriterMutex writer;                     // held by every write (see the file comment)
  std::uint64_t topology_generation = 0;  // bumped by every accepted removal (under writer)
};
using GraphPtr = std::shared_ptr<GraphBox>;
/// The owning pointer of a graph a binding received by reference (results and compiled objects
/// keep their graph alive).
inline GraphPtr Self(const GraphBox& b) {
  return std::const_pointer_cast<GraphBox>(b.shared_from_this());
}

// ---------------------------------------------------------------- results
// Numbers are kept as C++ values and turned into numpy arrays when a property is read, so a
// query costs one small object. `time` is set when the query was asked under a time policy
// (what the core's Timed<T> reported), empty otherwise. Quaternions are stored with w >= 0 (when w
// == 0, the first nonzero component > 0), the rule of the semgraph tool's output, so that q is
// deterministic.

struct PoseResult {
  GraphPtr graph;
  semantics::PoseSemantics semantics;
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
  std::optional<core::TimeReport> time = std::nullopt;
};
struct PositionResult {
  GraphPtr graph;
  semantics::PositionSemantics semantics;
  Eigen::Vector3d p;
  std::optional<core::TimeReport> time = std::nullopt;
};
struct OrientationResult {
  GraphPtr graph;
  semantics::OrientationSemantics semantics;
  Eigen::Quaterniond q;
  std::optional<core::TimeReport> time = std::nullopt;
};
struct TwistResult {
  GraphPtr graph;
  semantics::TwistSemantics semantics;
  Eigen::Vector3d v, w;
  std::optional<core::TimeReport> time = std::nullopt;
};
struct LinearVelocityResult {
  GraphPtr graph;
  semantics::LinearVelocitySemantics semantics;
  Eigen::Vector3d v;
  std::optional<core::TimeReport> time = std::nullopt;
};
struct AngularVelocityResult {
  GraphPtr graph;
  semantics::AngularVelocitySemantics semantics;
  Eigen::Vector3d w;
  std::optional<core::TimeReport> time = std::nullopt;
};

/// q with the sign rule above.
Eigen::Quaterniond CanonicalQuaternion(Eigen::Quaterniond q) noexcept;

// ---------------------------------------------------------------- compiled queries

template <template <class> class C>
using PerBackend = std::variant<C<coord::QuaternionBackend>, C<coord::HomogeneousBackend>>;

enum class CompiledKind : std::uint8_t {
  kPose,
  kPosition,
  kOrientation,
  kTwist,
  kLinear,
  kAngular
};

struct CompiledPoseObject {
  GraphPtr graph;
  PerBackend<core::CompiledPose> query;
};
struct CompiledPositionObject {
  GraphPtr graph;
  PerBackend<core::CompiledPosition> query;
};
struct CompiledOrientationObject {
  GraphPtr graph;
  PerBackend<core::CompiledOrientation> query;
};
/// Twist, linear velocity and angular velocity: one CompiledTwist (core has no separate kinds),
/// results cut to the asked part with the semantics the one-shot query reported.
struct CompiledTwistObject {
  GraphPtr graph;
  PerBackend<core::CompiledTwist> query;
  CompiledKind kind = CompiledKind::kTwist;
  semantics::LinearVelocitySemantics linear_semantics;
  semantics::AngularVelocitySemantics angular_semantics;
};

/// A compiled query's code (`what`: its relation, for the message): returns on kOk; otherwise
/// raises QueryError with the code (kQueryInvalidated: an edge removed; the time codes, which a
/// twist from poses also gives untimed, since it then reads under Latest) (compiled.cc).
void CheckCompiled(core::ErrorCode code, const std::string& what);

// ---------------------------------------------------------------- handles and batches

struct PoseHandleObject {
  GraphPtr graph;
  core::PoseHandle handle;
  std::string of, wrt;
};
struct TwistHandleObject {
  GraphPtr graph;
  core::TwistHandle handle;
  std::string point, ref_body;
};
struct PoseBatchObject {
  GraphPtr graph;
  std::vector<core::PoseHandle> handles;
  std::vector<std::string> of, wrt;
  std::uint64_t checked_generation = 0;  // handles known valid at this topology generation
};
struct TwistBatchObject {
  GraphPtr graph;
  std::vector<core::TwistHandle> handles;
  std::vector<std::string> point, ref_body;
  std::uint64_t checked_generation = 0;
};

// ---------------------------------------------------------------- registration
// One binding file per Python class (or family of classes); module.cc calls them in this order
// (a class is registered before the methods that return it, so signatures name it).

/// Pose, Position, Orientation, Twist, LinearVelocity, AngularVelocity (results.cc).
void BindResults(py::module_& m);
/// CompiledPose, CompiledPosition, CompiledOrientation, CompiledTwist (compiled.cc).
void BindCompiled(py::module_& m);
/// PoseHandle, TwistHandle (handles.cc).
void BindHandles(py::module_& m);
/// PoseBatch, TwistBatch (batches.cc).
void BindBatches(py::module_& m);
/// Registers run_script support (_run_script_text, script.cc).
void BindScript(py::module_& m);

using GraphClass = py::class_<GraphBox, std::shared_ptr<GraphBox>>;
/// The SceneGraph class: constructor, time options, counts, names (scene_graph.cc).
GraphClass BindSceneGraph(py::module_& m);
/// SceneGraph.add_body, add_frame, add_pose, add_twist, remove_pose, remove_twist.
void BindBuild(GraphClass& graph);
/// SceneGraph.pose ... angular_velocity and compile_* (queries.cc).
void BindQueries(GraphClass& graph);
/// SceneGraph.pose_handle, twist_handle, set_pose, set_twist (handles.cc).
void BindHandleMethods(GraphClass& graph);
/// SceneGraph.pose_batch, twist_batch (batches.cc).
void BindBatchMethods(GraphClass& graph);
/// SceneGraph.dump, check_invariants, dot, to_script (scene_graph.cc).
void BindInspection(GraphClass& graph);
/// Registers TimeReport and EdgeUse, and SceneGraph.explain_pose / explain_twist (timed.cc).
void BindTime(py::module_& m, GraphClass& graph);
/// Registers RepairPolicy and RepairReport (repair.cc).
void BindRepair(py::module_& m);
/// repair=: None / False -> no repair, True -> RepairPolicy(), a RepairPolicy -> it (TypeError
/// otherwise).
std::optional<core::RepairPolicy> RepairArg(py::handle repair, const char* function);
/// Registers joints, Jacobians and URDF loading: JointGroup, Jacobian, CompiledJacobian, Robot
/// and their SceneGraph methods (kinematics.cc).
void BindKinematics(py::module_& m, GraphClass& graph);

}  // namespace semgraph::python
