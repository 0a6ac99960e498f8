// The extension module semgraph._semgraph; the package semgraph (python/semgraph/__init__.py)
// re-exports it with the exception classes of semgraph/_errors.py. Each class is bound in a file
// of its own (graph.h lists them); this file calls them in order.
#include <pybind11/pybind11.h>

#include "accelerations.h"
#include "common.h"
#include "compiled_covariance.h"
#include "graph.h"
#include "uncertainty.h"
#include "wrenches.h"
#ifdef SEMGRAPH_PYTHON_WITH_ROS
#include "ros.h"
#endif

#ifndef SEMGRAPH_VERSION
#define SEMGRAPH_VERSION "0.0.0"
#endif

PYBIND11_MODULE(_semgraph, m) {
  namespace py = pybind11;
  m.doc() = "The C++ kernel of semgraph; import semgraph, not this module.";
  py::module_::import("numpy");  // results are numpy arrays: fail at import, not at first use
  semgraph::python::InitErrors(py::module_::import("semgraph._errors"));
  {
    using namespace semgraph::python;
    BindResults(m);
    BindCompiled(m);
    BindCompiledCovariance(m);
    BindHandles(m);
    BindBatches(m);
    BindRepair(m);
    BindWrenchResult(m);
    BindAccelerationResults(m);
    GraphClass graph = BindSceneGraph(m);
    BindBuild(graph);
    BindQueries(graph);
    BindUncertainty(graph);
    BindCompiledCovarianceMethods(graph);
    BindWrenches(graph);
    BindAccelerations(graph);
    BindHandleMethods(graph);
    BindBatchMethods(graph);
    BindInspection(graph);
    BindTime(m, graph);
    BindKinematics(m, graph);
    BindScript(m);
#ifdef SEMGRAPH_PYTHON_WITH_ROS
    py::module_ ros = m.def_submodule("_ros", "semgraph.ros's kernel; import semgraph.ros.");
    BindRosBags(ros);
    BindRosRecords(ros);
#ifdef SEMGRAPH_PYTHON_WITH_ROS_DDS
    BindRosLive(ros);
#endif
#endif
  }
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
#ifdef SEMGRAPH_PYTHON_WITH_ROS
  m.attr("_has_ros") = true;  // semgraph.ros: bags (the ROS layer is linked)
#else
  m.attr("_has_ros") = false;
#endif
#ifdef SEMGRAPH_PYTHON_WITH_ROS_DDS
  m.attr("_has_ros_dds") = true;  // semgraph.ros.Listener, Broadcaster (Cyclone DDS)
#else
  m.attr("_has_ros_dds") = false;
#endif
}
