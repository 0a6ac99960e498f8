// The scaffolding the live commands share (dds_commands.cc: serve, echo, monitor, dot --live;
// ros_live_commands.cc: echo/check/serve --ros): the --help check, the stop flag that SIGINT
// and SIGTERM set, and the time limit of --seconds. Process-wide state: one live command runs
// per process.
#pragma once

#include <chrono>
#include <string_view>

namespace semgraph::script::live {

/// Whether argv[2..] holds `flag` (e.g. "--ros", "--live").
[[nodiscard]] bool HasFlag(int argc, char** argv, std::string_view flag);
/// Whether argv[2..] holds --help or -h; prints `usage` to stdout then.
[[nodiscard]] bool PrintedHelp(int argc, char** argv, std::string_view usage);
/// Installs the SIGINT and SIGTERM handlers that set StopRequested().
void StopOnSignals();
[[nodiscard]] bool StopRequested() noexcept;
/// StopRequested(), or `seconds` (when >= 0) passed since `start`.
[[nodiscard]] bool TimeUp(std::chrono::steady_clock::time_point start, double seconds);

}  // namespace semgraph::script::live
