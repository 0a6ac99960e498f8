// Uses the installed semgraph::script: loads a scene script into a graph of the caller's
// (LoadSceneFile) and prints each op's JSON line, which scripts/check_install.sh compares with
// what the installed `semgraph run` prints for the same script. Then queries the loaded graph.
//
//   semgraph_script_consumer SCRIPT
// Exit status: the run's (0 all ops succeeded, 1 an op failed, 2 malformed), 3 on a bad graph.
#include <cstdio>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/script/scene_script.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: semgraph_script_consumer SCRIPT\n");
    return 2;
  }
  semgraph::core::SceneGraph<> graph;
  const auto run = semgraph::script::LoadSceneFile(argv[1], graph);
  if (run.status == semgraph::script::kExitMalformed) {
    std::fprintf(stderr, "%s\n", run.error.c_str());
    return run.status;
  }
  for (const auto& op : run.ops) std::printf("%s\n", op.json.c_str());
  // The graph stays loaded: it holds the script's frames and answers queries itself.
  if (graph.num_frames() == 0 || !CheckInvariants(graph).empty()) return 3;
  return run.status;
}
