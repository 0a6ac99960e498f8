// The live ROS 2 subcommands of the `semgraph` tool (docs/ros.md, "Live ROS 2"):
//   semgraph echo --ros pose OF WRT [--in FRAME] ...   a semantic tf2_echo
//   semgraph check --ros ...                          a semantic tf2_monitor (findings)
//   semgraph serve --ros FILE ...                     a scene script's graph published as tf
// Built when semgraph::ros_dds is (SEMGRAPH_WITH_ROS_DDS).
#pragma once

namespace semgraph::script {

/// True when argv is `echo`, `check` or `serve` with the flag --ros.
[[nodiscard]] bool IsRosLiveCommand(int argc, char** argv);
/// Runs it; the exit status (echo: 0 when an answer was printed, 1 none; check: 0 clean, 1
/// findings; serve: the script's status; 2 bad usage, script or domain).
[[nodiscard]] int RunRosLiveCommand(int argc, char** argv);

}  // namespace semgraph::script
