// File: tests/support/alloc_counter.h
//
// AllocationCounter: the one replacement of the global operator new/delete of the test suite,
// in every replaceable form (plain, array, nothrow, aligned, aligned nothrow, and every delete:
// sized, aligned, nothrow). Replacing every form matters: a sanitizer runtime linked
// statically (clang's ThreadSanitizer) defines them all in one object file, and a program that
// replaces only some of them pulls that object in for the others and fails to link with
// duplicate definitions of the ones it does replace.
//
// It counts calls of operator new while armed, and counts every call in total(). A test arms
// it, runs the code under test, and compares count() with what it expects (usually 0, to prove
// a "no allocation" claim: aesthetics R10). For allocation-failure injection, FailAt(n) makes
// the n-th allocation after Arm() fail: the throwing forms throw std::bad_alloc, the nothrow
// forms return nullptr; every other allocation succeeds.
//
// The replacements are in alloc_counter.cc, a translation unit of its own (GCC 12 at -O3 reports
// -Wmismatched-new-delete when replacements that call malloc/free are inlined into the code
// that uses them). Only the test binaries that use the counter compile it in (tests/CMakeLists.txt
// adds it per target), since a program may replace operator new only once; a test that needs a
// replacement uses this one.
//
// Not counted: std::malloc called directly (Eigen's dynamic-size storage does that; fixed-size
// Eigen values, which is all semgraph uses, never allocate).
// Thread safety: the counts are atomic and count every thread; arming is process-wide, so run
// one counting test at a time (GoogleTest runs tests sequentially).
// Cost: two relaxed atomic operations per allocation when disarmed, a few more when armed.
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
  /// Every allocation of the process so far, armed or not.
  [[nodiscard]] static std::size_t total() noexcept;
  /// While armed, the n-th allocation counted after Arm() fails (n >= 1); 0 (also the state
  /// after Arm()) fails none. Set it after Arm().
  static void FailAt(std::size_t n) noexcept;
  /// True when the allocation chosen by FailAt has been failed since Arm().
  [[nodiscard]] static bool failed() noexcept;
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
