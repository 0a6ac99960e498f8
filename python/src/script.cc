// semgraph.run_script support: the scene-script reader and runner of the semgraph tool
// (tools/semgraph), applied to a fresh GraphBox without the GIL, so the results are the tool's,
// line for line.
#include <optional>
#include <string>
#include <vector>

#include "graph.h"

#include <pybind11/stl.h>

#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
#include "semgraph/script_reader.h"
#include "semgraph/script_runner.h"
#endif

namespace semgraph::python {

void BindScript(py::module_& m) {
  m.def("_run_script_text", [](py::bytes text, const std::string& file_name, const std::string& base_dir) -> py::tuple {
#ifdef SEMGRAPH_PYTHON_WITH_SCRIPT
    const std::string data = text;
    std::optional<script::ScriptError> error;
    std::string formatted;
    GraphPtr graph;
    std::vector<std::string> lines;
    bool all_ok = true;
    {
      py::gil_scoped_release release;  // the graph is not shared with Python yet
      auto script = script::ReadScript(data);
      if (!script) {
        error = script.error();
        formatted = script::FormatScriptError(file_name, *error);
      } else {
        // A fresh graph with the script's representation and time options, as the tool makes.
        const core::TimeOptions time = script::TimeOptionsOf(script->time);
        if (script->representation == script::Representation::kHomogeneous) {
          graph = std::make_shared<GraphBox>(true, *core::SceneGraph<coord::HomogeneousBackend>::Create(time));
        } else {
          graph = std::make_shared<GraphBox>(false, *core::SceneGraph<coord::QuaternionBackend>::Create(time));
        }
        graph->Visit([&](auto& g) {
          lines.reserve(script->ops.size());
          for (std::size_t i = 0; i < script->ops.size(); ++i) {
            script::OpOutcome outcome = script::ApplyOp(g, script->ops[i], i, base_dir);
            all_ok = all_ok && outcome.ok;
            lines.push_back(std::move(outcome.json));
          }
        });
      }
    }
    if (error) {
      return py::make_tuple(false, error->location.line, error->location.column, error->message,
                            formatted);
    }
    return py::make_tuple(true, graph, lines, all_ok);
#else
    (void)text;
    (void)file_name;
    (void)base_dir;
    throw std::runtime_error(
        "run_script(): semgraph was built without the tool library (SEMGRAPH_BUILD_TOOLS=OFF)");
#endif
  }, py::arg("text"), py::arg("file_name"), py::arg("base_dir") = std::string());
}

}  // namespace semgraph::python
