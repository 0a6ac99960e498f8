// File: python/src/accelerations.h
//
// The accelerations of the twist edges in Python (docs/dynamics.md §7, docs/python.md
// "Accelerations"): SceneGraph.add_acceleration / set_acceleration / acceleration /
// linear_acceleration / angular_acceleration / compile_acceleration, the result classes
// Acceleration, LinearAcceleration, AngularAcceleration and CompiledAcceleration. (add_twist's
// linear_acceleration= / angular_acceleration= are read in scene_graph.cc.) Every number comes
// from SceneGraph<B> (AddAcceleration, SetAcceleration, GetAcceleration, CompileAcceleration);
// this layer reads the keywords and raises the core's errors as RejectedError / QueryError.
#pragma once

#include "graph.h"

namespace semgraph::python {

/// The result classes and CompiledAcceleration (before the SceneGraph class, whose methods
/// return them).
void BindAccelerationResults(py::module_& m);
/// The SceneGraph methods.
void BindAccelerations(GraphClass& graph);

}  // namespace semgraph::python
