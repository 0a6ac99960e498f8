// Replacements of every global operator new/delete that count allocations while
// AllocationCounter is armed (see alloc_counter.h). Memory comes from std::malloc /
// std::aligned_alloc and goes back with std::free, so sized and unsized deletes agree.
#include "support/alloc_counter.h"

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace semgraph::testing {
namespace {

std::atomic<bool> g_armed{false};
std::atomic<std::size_t> g_count{0};
std::atomic<std::size_t> g_total{0};
std::atomic<std::size_t> g_fail_at{0};
std::atomic<bool> g_failed{false};

// Counts one allocation; false when it is the one chosen to fail.
bool Count() noexcept {
  g_total.fetch_add(1, std::memory_order_relaxed);
  if (!g_armed.load(std::memory_order_relaxed)) return true;
  const std::size_t n = g_count.fetch_add(1, std::memory_order_relaxed) + 1;
  if (n == g_fail_at.load(std::memory_order_relaxed)) {
    g_failed.store(true, std::memory_order_relaxed);
    return false;
  }
  return true;
}

void* AllocateOrNull(std::size_t size) noexcept {
  if (!Count()) return nullptr;
  return std::malloc(size == 0 ? 1 : size);
}

void* AllocateAlignedOrNull(std::size_t size, std::align_val_t alignment) noexcept {
  if (!Count()) return nullptr;
  std::size_t a = static_cast<std::size_t>(alignment);
  if (a < sizeof(void*)) a = sizeof(void*);
  const std::size_t rounded =
      (size == 0 ? a : (size + a - 1) / a * a);  // aligned_alloc needs a multiple
  return std::aligned_alloc(a, rounded);
}

void* AllocateOrThrow(std::size_t size) {
  if (void* p = AllocateOrNull(size)) return p;
  throw std::bad_alloc();
}

void* AllocateAlignedOrThrow(std::size_t size, std::align_val_t alignment) {
  if (void* p = AllocateAlignedOrNull(size, alignment)) return p;
  throw std::bad_alloc();
}

}  // namespace

void AllocationCounter::Arm() noexcept {
  g_count.store(0, std::memory_order_relaxed);
  g_fail_at.store(0, std::memory_order_relaxed);
  g_failed.store(false, std::memory_order_relaxed);
  g_armed.store(true, std::memory_order_seq_cst);
}

void AllocationCounter::FailAt(std::size_t n) noexcept {
  g_fail_at.store(n, std::memory_order_seq_cst);
}

bool AllocationCounter::failed() noexcept { return g_failed.load(std::memory_order_relaxed); }

std::size_t AllocationCounter::total() noexcept { return g_total.load(std::memory_order_relaxed); }

void AllocationCounter::Disarm() noexcept {
  g_armed.store(false, std::memory_order_seq_cst);
  g_fail_at.store(0, std::memory_order_relaxed);
}

std::size_t AllocationCounter::count() noexcept { return g_count.load(std::memory_order_relaxed); }

}  // namespace semgraph::testing

using semgraph::testing::AllocateAlignedOrNull;
using semgraph::testing::AllocateAlignedOrThrow;
using semgraph::testing::AllocateOrNull;
using semgraph::testing::AllocateOrThrow;

void* operator new(std::size_t size) { return AllocateOrThrow(size); }
void* operator new[](std::size_t size) { return AllocateOrThrow(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return AllocateOrNull(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return AllocateOrNull(size);
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  return AllocateAlignedOrThrow(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return AllocateAlignedOrThrow(size, alignment);
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return AllocateAlignedOrNull(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return AllocateAlignedOrNull(size, alignment);
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
