// File: python/src/compiled_covariance.h
//
// The compiled queries with covariance in Python (docs/uncertainty.md, "In Python"; the C++
// compiled_covariance.h and compiled_twist_covariance.h): SceneGraph.compile_pose_with_covariance
// ... compile_angular_velocity_with_covariance and the classes CompiledPoseWithCovariance,
// CompiledPositionWithCovariance, CompiledOrientationWithCovariance and
// CompiledTwistWithCovariance. evaluate() returns (result, covariance) as the one-shot
// *_with_covariance queries (uncertainty.cc), with or without a time policy (the keywords of the
// plain compiled queries' evaluate, compiled.cc), and raises as they do (CheckCompiled). Every
// number comes from SceneGraph<B>::Compile*WithCovariance; this layer reads the keywords, keeps
// the graph alive and turns codes into QueryError.
// Invariants: an object holds its GraphPtr (the graph outlives it and never moves, graph.h) and
// the core object made from that graph; covariance_order is fixed at compile time; the velocity
// kinds keep the semantics of the twist the core object computes (the core wrappers keep none).
// Costs: compile_* = the core's Compile*WithCovariance (build time, allocates; the angular
// velocity compiles its twist a second time, for those semantics); evaluate() = the core's
// Evaluate (noexcept, allocation-free) plus the Python result and a numpy copy of the
// covariance, and the time keywords' parsing when given.
// Thread safety: the core objects evaluate into their own scratch (one evaluating thread per
// object); every evaluate() runs with the GIL held, so calls on one Python object never overlap.
#pragma once

#include "graph.h"

namespace semgraph::python {

/// The four classes (before the SceneGraph class, whose methods return them).
void BindCompiledCovariance(py::module_& m);
/// SceneGraph.compile_*_with_covariance.
void BindCompiledCovarianceMethods(GraphClass& graph);

}  // namespace semgraph::python
