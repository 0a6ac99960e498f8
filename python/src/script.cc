// semgraph.run_script support: BuildScene of the tool's public library (semgraph::script,
// semgraph/script/scene_script.h) without the GIL, so that the results are the tool's, line for
// line, and the graph it built becomes the run's SceneGraph.
#include <pybind11/stl.h>

#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "graph.h"

#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
#include "semgraph/script/scene_script.h"
#endif

namespace semgraph::python {

namespace {

#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
// The built graph in a box of its own (the graph is not shared with Python yet, and moving it
// is allowed: nothing was compiled against it).
GraphPtr BoxOf(script::AnySceneGraph&& graph) {
  return std::visit(
      [](auto&& g) -> GraphPtr {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, std::monostate>) {
          return nullptr;
        } else {
          return std::make_shared<GraphBox>(std::is_same_v<G, HomogeneousGraph>, std::move(g));
        }
      },
      std::move(graph));
}
#endif

// (True, graph, lines, all_ok), or (False, line, column, message, "FILE:LINE:COLUMN: message")
// for a malformed script; MemoryError when memory runs out.
py::tuple RunScriptText(py::bytes text, const std::string& file_name, const std::string& base_dir) {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
  const std::string data = text;
  script::RunOptions options;
  options.display_name = file_name;
  options.base_dir = base_dir;
  script::SceneRun run;
  GraphPtr graph;
  {
    py::gil_scoped_release release;
    script::BuiltScene built = script::BuildScene(data, options);
    run = std::move(built.run);
    if (!run.out_of_memory) graph = BoxOf(std::move(built.graph));
  }
  if (run.out_of_memory) {  // MemoryError, saying how far the run got
    PyErr_SetString(PyExc_MemoryError, run.error.c_str());
    throw py::error_already_set();
  }
  if (run.status == script::kExitMalformed) {
    return py::make_tuple(false, run.error_line, run.error_column, run.error_message, run.error);
  }
  std::vector<std::string> lines;
  lines.reserve(run.ops.size());
  for (script::OpResult& op : run.ops) lines.push_back(std::move(op.json));
  return py::make_tuple(true, graph, lines, run.status == script::kExitOk);
#else
  (void)text;
  (void)file_name;
  (void)base_dir;
  throw std::runtime_error(
      "run_script(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
}

}  // namespace

void BindScript(py::module_& m) {
  m.def("_run_script_text", &RunScriptText, py::arg("text"), py::arg("file_name"),
        py::arg("base_dir") = std::string());
}

}  // namespace semgraph::python
