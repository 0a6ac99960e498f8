// The extension module semgraph._semgraph; the package semgraph (python/semgraph/__init__.py)
// re-exports it with the exception classes of semgraph/_errors.py.
#include <pybind11/pybind11.h>

#include "graph.h"

#ifndef SEMGRAPH_VERSION
#define SEMGRAPH_VERSION "0.0.0"
#endif

PYBIND11_MODULE(_semgraph, m) {
  namespace py = pybind11;
  m.doc() = "The C++ kernel of semgraph; import semgraph, not this module.";
  py::module_::import("numpy");  // results are numpy arrays: fail at import, not at first use
  semgraph::python::InitErrors(py::module_::import("semgraph._errors"));
  semgraph::python::BindGraph(m);
  semgraph::python::BindScript(m);
  m.attr("__version__") = SEMGRAPH_VERSION;
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
  m.attr("_has_tools") = true;  // dot() and run_script() work (the tool's library is linked)
#else
  m.attr("_has_tools") = false;
#endif
#ifdef SEMGRAPH_PYTHON_WITH_MODELS
  m.attr("_has_models") = true;  // load_urdf() works (the models layer, urdfdom, is linked)
#else
  m.attr("_has_models") = false;
#endif
}
