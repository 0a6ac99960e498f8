// `semgraph bag info FILE` and `semgraph bag check FILE ...` (docs/ros.md, "The tool"): part of
// the semgraph executable when semgraph::ros is built (SEMGRAPH_WITH_ROS).
#pragma once

namespace semgraph::script {

/// True for `bag ...` command lines.
[[nodiscard]] bool IsBagCommand(int argc, char** argv);
/// Runs one; the exit status (info: 0, or 2 when the file cannot be read; check: 0 clean, 1
/// with findings, 2 when the file cannot be read or is corrupt or the usage is wrong).
[[nodiscard]] int RunBagCommand(int argc, char** argv);

}  // namespace semgraph::script
