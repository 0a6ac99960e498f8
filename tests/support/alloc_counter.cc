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

void Count() noexcept {
  if (g_armed.load(std::memory_order_relaxed)) g_count.fetch_add(1, std::memory_order_relaxed);
}

void* AllocateOrNull(std::size_t size) noexcept {
  Count();
  return std::malloc(size == 0 ? 1 : size);
}

void* AllocateAlignedOrNull(std::size_t size, std::align_val_t alignment) noexcept {
  Count();
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
  g_armed.store(true, std::memory_order_seq_cst);
}

void AllocationCounter::Disarm() noexcept { g_armed.store(false, std::memory_order_seq_cst); }

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
