// Live commands' scaffolding (live_command.h).
#include "live_command.h"

#include <atomic>
#include <csignal>
#include <cstdio>

namespace semgraph::script::live {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

}  // namespace

bool HasFlag(int argc, char** argv, std::string_view flag) {
  for (int i = 2; i < argc; ++i) {
    if (std::string_view(argv[i]) == flag) return true;
  }
  return false;
}

bool PrintedHelp(int argc, char** argv, std::string_view usage) {
  if (!HasFlag(argc, argv, "--help") && !HasFlag(argc, argv, "-h")) return false;
  std::fwrite(usage.data(), 1, usage.size(), stdout);
  return true;
}

void StopOnSignals() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

bool StopRequested() noexcept { return g_stop.load(); }

bool TimeUp(std::chrono::steady_clock::time_point start, double seconds) {
  return g_stop.load() ||
         (seconds >= 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
              seconds);
}

}  // namespace semgraph::script::live
