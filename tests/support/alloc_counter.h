// File: tests/support/alloc_counter.h
//
// AllocationCounter: counts calls of the global operator new, in every replaceable form
// (plain, array, nothrow, aligned, aligned nothrow), while armed. It only counts, never fails
// anything itself: a test arms it, runs the code under test, and compares count() with what it
// expects (usually 0, to prove a "no allocation" claim: aesthetics R10).
//
// The replacements of operator new/delete are in alloc_counter.cc, a translation unit of its
// own (GCC 12 at -O3 reports -Wmismatched-new-delete when replacements that call malloc/free are
// inlined into the code that uses them). Only the test binaries that use the counter compile it
// in (tests/CMakeLists.txt adds it per target): several tests/core binaries define their own
// replacements, and a program may replace operator new only once.
//
// Not counted: std::malloc called directly (Eigen's dynamic-size storage does that; fixed-size
// Eigen values, which is all semgraph uses, never allocate).
// Thread safety: the count is atomic and counts every thread; arming is process-wide, so run
// one counting test at a time (GoogleTest runs tests sequentially).
// Cost: one relaxed atomic load per allocation when disarmed, plus an increment when armed.
#pragma once

#include <cstddef>

namespace semgraph::testing {

class AllocationCounter {
 public:
  /// Resets the count to 0 and starts counting.
  static void Arm() noexcept;
  /// Stops counting; count() keeps its value.
  static void Disarm() noexcept;
  /// Allocations since the last Arm() (while armed).
  [[nodiscard]] static std::size_t count() noexcept;
};

/// Arms the counter for its lifetime:
///   { CountAllocations counting; RunQueries(); EXPECT_EQ(counting.count(), 0u); }
class CountAllocations {
 public:
  CountAllocations() noexcept { AllocationCounter::Arm(); }
  ~CountAllocations() { AllocationCounter::Disarm(); }
  CountAllocations(const CountAllocations&) = delete;
  CountAllocations& operator=(const CountAllocations&) = delete;
  [[nodiscard]] std::size_t count() const noexcept { return AllocationCounter::count(); }
};

}  // namespace semgraph::testing
