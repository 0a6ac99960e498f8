// `semgraph bag info FILE` and `semgraph bag check FILE ...` (docs/ros.md, "The tool"): part of
// the semgraph executable when semgraph::ros is built (SEMGRAPH_WITH_ROS).
#pragma once

#include <string>

#include "semgraph/ros/body_plan.h"

namespace semgraph::script {

/// Reads a bodies map file, YAML {BODY: [frame, ...]}, into `out` (also used by `check --ros`);
/// false with `error` naming the file (and line) when it cannot be read or is not such a map.
[[nodiscard]] bool ReadBodiesMap(const std::string& file, ros::BodiesMap* out, std::string* error);

/// True for `bag ...` command lines.
[[nodiscard]] bool IsBagCommand(int argc, char** argv);
/// Runs one; the exit status (info: 0, or 2 when the file cannot be read; check: 0 clean, 1
/// with findings, 2 when the file cannot be read or is corrupt or the usage is wrong).
[[nodiscard]] int RunBagCommand(int argc, char** argv);

}  // namespace semgraph::script
