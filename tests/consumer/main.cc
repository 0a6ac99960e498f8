// Uses the installed semgraph: interns two names and composes two pose semantics.
// Returns 0 on success.
#include <cstdio>

#include "semgraph/semantics/describe.h"
#include "semgraph/semantics/names.h"
#include "semgraph/semantics/operations.h"
#include "semgraph/semantics/relations.h"

int main() {
  namespace sem = semgraph::semantics;
  sem::NameTable names;
  auto base = names.Intern("base");
  auto tool = names.Intern("tool");
  if (!base || !tool) return 1;

  // Each body carries a frame of the same name: {base}|base and {tool}|tool.
  const sem::Frame b(*base), t(*tool);
  const sem::Body B(*base), T(*tool);
  const auto tool_wrt_base = sem::PoseSemantics::OfFrame(t, T, b, B, b.axes());
  const auto base_wrt_tool = sem::PoseSemantics::OfFrame(b, B, t, T, t.axes());

  auto composed = sem::Compose(tool_wrt_base, base_wrt_tool);
  if (!composed) {
    std::printf("unexpected: %s\n", sem::Describe(composed.error(), names).c_str());
    return 1;
  }
  if (!(composed->result == sem::PoseSemantics::OfFrame(t, T, t, T, t.axes()))) return 1;
  if (sem::Compose(tool_wrt_base, tool_wrt_base)) return 1;  // must be rejected

  std::printf("semgraph consumer: %s\n", sem::Describe(composed->result, names).c_str());
  return 0;
}
