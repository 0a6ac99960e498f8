// Optimistic reads of the topology (private to core/src): the one driver of every one-shot
// query and Compile* on a reader thread while the writer changes the topology
// (docs/realtime.md, "Topology changes while readers run").
//
// An attempt runs between two reads of the topology's change counter: even and unchanged means
// the planner and the evaluator read one consistent topology (its fields are atomics written
// with release and read with acquire, so a reader that saw any store of a change sees the odd
// counter after it), and the edge values it read were those of edges that existed throughout
// (each value untorn through its own sequence lock). Otherwise the attempt is thrown away and
// the query runs again: readers never block the writer, and the writer never waits for them.
//
// Bound: at most kReadAttempts attempts; while a change is in progress (odd counter) a reader
// first spins up to kSpinsPerAttempt pause instructions for it to end. A query that never sees
// a quiet topology returns kQueryInvalidated (a writer changing the topology without pause).
// Costs: two acquire loads of the counter per attempt (plain moves on x86-64); no allocation,
// no lock, no system call.
#pragma once

#include <cstdint>

#include "semgraph/base/expected.h"
#include "semgraph/core/evaluate.h"
#include "semgraph/core/specs.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core::internal {

inline constexpr int kReadAttempts = 32;
inline constexpr int kSpinsPerAttempt = 4096;

inline void SpinPause() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

/// The error of a query that found the topology changing on every attempt.
inline QueryError TopologyBusy() noexcept {
  QueryError e;
  e.code = ErrorCode::kQueryInvalidated;
  return e;
}

/// The counter once even (or odd after kSpinsPerAttempt pauses: the attempt then fails).
inline std::uint64_t QuietCount(const topology::SceneTopology& t) noexcept {
  std::uint64_t count = t.change_count();
  for (int spin = 0; (count & 1) != 0 && spin < kSpinsPerAttempt; ++spin) {
    SpinPause();
    count = t.change_count();
  }
  return count;
}

/// attempt() (planning and evaluation, returning an Expected<T, QueryError>) on a validated
/// snapshot of t: its result when no change overlapped it, else kQueryInvalidated after
/// kReadAttempts attempts. Every return returns `result`, so the first attempt's answer is
/// built in the caller's return slot (no copy on the common path).
template <class Attempt>
auto ReadValidated(const topology::SceneTopology& t, Attempt&& attempt) noexcept
    -> decltype(attempt()) {
#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
  // The checked replay (evaluate.h) trusts a plan only on the topology it was made on.
  struct PlanCountScope {
    std::uint64_t saved = ReplayPlanCount();
    ~PlanCountScope() { ReplayPlanCount() = saved; }
  } scope;
  const auto run = [&](std::uint64_t count) {
    ReplayPlanCount() = count;
    return attempt();
  };
#else
  const auto run = [&](std::uint64_t) { return attempt(); };
#endif
  std::uint64_t before = QuietCount(t);
  decltype(attempt()) result = run(before);
  for (int i = 1;; ++i) {
    if ((before & 1) == 0 && t.change_count() == before) return result;
    if (i == kReadAttempts) break;
    before = QuietCount(t);
    result = run(before);
  }
  result = base::Unexpected{TopologyBusy()};
  return result;
}

}  // namespace semgraph::core::internal
