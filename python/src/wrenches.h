// File: python/src/wrenches.h
//
// The wrenches of the graph in Python (docs/dynamics.md §7, docs/python.md "Wrenches"):
// SceneGraph.add_wrench / remove_wrench / wrench / force / moment / num_wrenches and the Wrench
// result class. Every number comes from SceneGraph<B> (AddWrench, RemoveWrench, GetWrench); this
// layer reads the keywords and raises the core's errors as RejectedError / QueryError.
#pragma once

#include "graph.h"

namespace semgraph::python {

/// The Wrench result class (before the SceneGraph class, whose methods return it).
void BindWrenchResult(py::module_& m);
/// The SceneGraph methods.
void BindWrenches(GraphClass& graph);

}  // namespace semgraph::python
