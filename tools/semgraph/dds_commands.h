// The DDS subcommands of the `semgraph` tool (docs/distributed.md): serve, echo, monitor and
// dot --live. Built when semgraph::dds is (SEMGRAPH_WITH_DDS).
#pragma once

namespace semgraph::script {

/// True when argv names a DDS subcommand (`serve`, `echo`, `monitor`, `dot --live`).
[[nodiscard]] bool IsDdsCommand(int argc, char** argv);
/// Runs it; the tool's exit statuses (0 ok, 1 failed query / no data, 2 bad usage or script).
[[nodiscard]] int RunDdsCommand(int argc, char** argv);

}  // namespace semgraph::script
