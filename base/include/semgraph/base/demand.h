// File: semgraph/base/demand.h
//
// SEMGRAPH_DEMAND(condition): the always-on check for programming errors (a broken invariant,
// the wrong alternative of an Expected accessed, a precondition a caller had to establish).
// It aborts with the condition, file and line; it never throws, so it may sit on the real-time
// path. User errors never reach it: they are rejected earlier with an ErrorCode.
// Cost: one predictable branch when the condition holds.
#pragma once

#include "semgraph/base/export.h"

namespace semgraph::base {

/// Prints "semgraph: internal check failed: <condition> at <file>:<line>" and aborts.
[[noreturn]] SEMGRAPH_BASE_EXPORT void DemandFailed(const char* condition, const char* file,
                                                    int line) noexcept;

}  // namespace semgraph::base

#define SEMGRAPH_DEMAND(condition)                                    \
  do {                                                                \
    if (!(condition)) [[unlikely]]                                    \
      ::semgraph::base::DemandFailed(#condition, __FILE__, __LINE__); \
  } while (false)
