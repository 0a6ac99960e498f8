#include "semgraph/topology/flat_map.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <random>
#include <thread>
#include <unordered_map>
#include <vector>

#include "semgraph/base/published.h"
#include "support/alloc_counter.h"

// Allocations are counted by the suite's one replacement of operator new/delete
// (support/alloc_counter.h: every form, so it links with sanitizer runtimes too).
using semgraph::testing::AllocationCounter;

namespace semgraph::topology {
namespace {

struct Payload {
  std::uint32_t a = 0;
  std::uint64_t b = 0;
  friend bool operator==(const Payload&, const Payload&) = default;
};

// Compares every entry both ways (sizes equal and each map entry found with the same value).
void ExpectSameContents(const FlatMap<Payload>& map,
                        const std::unordered_map<std::uint32_t, Payload>& model) {
  ASSERT_EQ(map.size(), model.size());
  ASSERT_EQ(map.empty(), model.empty());
  std::size_t visited = 0;
  map.ForEach([&](std::uint32_t key, const Payload& value) {
    ++visited;
    auto it = model.find(key);
    ASSERT_NE(it, model.end()) << "stray key " << key;
    EXPECT_EQ(it->second, value);
  });
  EXPECT_EQ(visited, model.size());
  for (const auto& [key, value] : model) {
    const Payload* found = map.Find(key);
    ASSERT_NE(found, nullptr) << "lost key " << key;
    EXPECT_EQ(*found, value);
  }
}

TEST(FlatMap, DefaultConstructedMapOwnsNoMemoryUntilFirstInsert) {
  const std::size_t before = AllocationCounter::total();
  FlatMap<Payload> map;
  EXPECT_EQ(map.Find(7), nullptr);
  EXPECT_FALSE(map.Erase(7));
  map.Clear();
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_EQ(map.capacity(), 0u);
  EXPECT_TRUE(map.empty());
  map.Insert(7, Payload{1, 2});
  EXPECT_EQ(AllocationCounter::total(), before + 1);
  EXPECT_EQ(map.capacity(), 8u);
}

TEST(FlatMap, InsertFindEraseRoundTrip) {
  FlatMap<Payload> map;
  map.Insert(3, Payload{3, 30});
  map.Insert(0, Payload{0, 0});
  map.Insert(0xFFFFFFFEu, Payload{9, 90});
  ASSERT_NE(map.Find(3), nullptr);
  EXPECT_EQ(map.Find(3)->b, 30u);
  EXPECT_EQ(map.Find(4), nullptr);
  EXPECT_EQ(map.Find(FlatMap<Payload>::kEmptyKey), nullptr);
  EXPECT_TRUE(map.Contains(0xFFFFFFFEu));
  map.Find(3)->b = 31;
  EXPECT_EQ(map.Find(3)->b, 31u);
  EXPECT_EQ(map.FindOrInsert(3, Payload{}).b, 31u);
  EXPECT_EQ(map.FindOrInsert(5, Payload{5, 50}).b, 50u);
  EXPECT_EQ(map.size(), 4u);
  EXPECT_TRUE(map.Erase(3));
  EXPECT_FALSE(map.Erase(3));
  EXPECT_EQ(map.Find(3), nullptr);
  EXPECT_EQ(map.size(), 3u);
}

TEST(FlatMap, LoadFactorStaysAtMostOneHalf) {
  FlatMap<std::uint32_t> map;
  for (std::uint32_t key = 0; key < 1000; ++key) {
    map.Insert(key * 4096, key);  // keys sharing all low bits: the hash must spread them
    EXPECT_LE(2 * map.size(), map.capacity());
  }
  for (std::uint32_t key = 0; key < 1000; ++key) ASSERT_EQ(*map.Find(key * 4096), key);
}

TEST(FlatMap, InsertingAPresentKeyAborts) {
  FlatMap<int> map;
  map.Insert(1, 1);
  EXPECT_DEATH(map.Insert(1, 2), "inserted");
}

TEST(FlatMap, MatchesUnorderedMapUnderRandomOperations) {
  // Phases: insert-heavy, mixed, erase-heavy (backward shift on long runs), refill.
  std::mt19937 rng(20240601);
  FlatMap<Payload> map;
  std::unordered_map<std::uint32_t, Payload> model;
  struct Phase {
    int ops;
    int insert_percent;
    int erase_percent;
    std::uint32_t key_range;
  };
  const Phase phases[] = {{25000, 70, 10, 4096},
                          {25000, 40, 40, 4096},
                          {25000, 10, 75, 4096},
                          {25000, 45, 45, 1u << 20}};
  int op = 0;
  for (const Phase& phase : phases) {
    std::uniform_int_distribution<std::uint32_t> key_of(0, phase.key_range - 1);
    std::uniform_int_distribution<int> percent(0, 99);
    for (int i = 0; i < phase.ops; ++i, ++op) {
      // Half of the keys are multiples of 1024, to stress clustering of shared low bits.
      std::uint32_t key = key_of(rng);
      if (rng() & 1) key = (key % 4096) * 1024;
      const int roll = percent(rng);
      if (roll < phase.insert_percent) {
        const Payload value{key, rng()};
        const bool absent = model.find(key) == model.end();
        if (absent) {
          EXPECT_EQ(map.Insert(key, value), value);
          model[key] = value;
        } else {
          EXPECT_EQ(map.FindOrInsert(key, value), model[key]);
        }
      } else if (roll < phase.insert_percent + phase.erase_percent) {
        EXPECT_EQ(map.Erase(key), model.erase(key) == 1) << "op " << op;
      } else {
        const Payload* found = map.Find(key);
        auto it = model.find(key);
        ASSERT_EQ(found != nullptr, it != model.end()) << "op " << op << " key " << key;
        if (found != nullptr) {
          EXPECT_EQ(*found, it->second);
        }
      }
      ASSERT_EQ(map.size(), model.size()) << "op " << op;
      if (op % 5000 == 0) ExpectSameContents(map, model);
    }
    ExpectSameContents(map, model);
  }
  // Erase everything, in model order, then check nothing is left behind.
  for (const auto& entry : model) ASSERT_TRUE(map.Erase(entry.first));
  model.clear();
  ExpectSameContents(map, model);
}

TEST(FlatMap, FindAndEraseDoNotAllocate) {
  FlatMap<Payload> map;
  for (std::uint32_t key = 0; key < 5000; ++key) map.Insert(key * 7, Payload{key, key});
  const FlatMap<Payload>& view = map;
  const std::size_t before = AllocationCounter::total();
  std::uint64_t sum = 0;
  for (std::uint32_t key = 0; key < 50000; ++key) {
    if (const Payload* found = view.Find(key)) sum += found->b;
  }
  for (std::uint32_t key = 0; key < 5000; key += 2) map.Erase(key * 7);
  view.ForEach([&sum](std::uint32_t, const Payload& value) { sum += value.a; });
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_GT(sum, 0u);
}

TEST(FlatMap, ReserveAndClearAvoidLaterAllocations) {
  FlatMap<std::uint32_t> map;
  map.Reserve(1000);
  const std::size_t before = AllocationCounter::total();
  for (std::uint32_t key = 0; key < 1000; ++key) map.Insert(key, key);
  map.Clear();
  EXPECT_TRUE(map.empty());
  EXPECT_EQ(map.Find(5), nullptr);
  for (std::uint32_t key = 0; key < 1000; ++key) map.Insert(key + 1, key);
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_EQ(map.size(), 1000u);
  EXPECT_GE(map.ApproximateBytes(), map.capacity() * sizeof(std::uint32_t));
}

TEST(FlatMap, MovingLeavesTheSourceEmptyAndCopyingIsDeep) {
  FlatMap<int> map;
  for (int i = 0; i < 20; ++i) map.Insert(static_cast<std::uint32_t>(i), i);
  FlatMap<int> copy = map;
  copy.Erase(3);
  EXPECT_TRUE(map.Contains(3));
  FlatMap<int> moved = std::move(map);
  EXPECT_EQ(moved.size(), 20u);
  EXPECT_TRUE(map.empty());  // NOLINT(bugprone-use-after-move): the documented state
  EXPECT_EQ(map.capacity(), 0u);
  EXPECT_EQ(map.Find(3), nullptr);
  map.Insert(3, 33);  // a moved-from map is usable
  EXPECT_EQ(*map.Find(3), 33);
  copy = std::move(moved);
  EXPECT_EQ(copy.size(), 20u);
  EXPECT_TRUE(moved.empty());  // NOLINT(bugprone-use-after-move)
}

// One writer inserts (growing the map several times), erases and moves maps while readers
// look keys up. Readers validate with a change counter, as the scene topology's one-shot
// queries do: a validated lookup must find every permanent key with its value, and any key it
// finds with that key's value. Unvalidated reads may be stale, but never touch freed memory
// (run under ThreadSanitizer / AddressSanitizer to check that).
struct Shared {
  base::Published<std::uint32_t> key_copy;
  base::Published<std::uint32_t> square;
};
std::uint32_t ValueOf(std::uint32_t key) { return key * key + 7; }

TEST(FlatMap, ReadersValidatedAgainstAWriterFindExactValues) {
  constexpr std::uint32_t kPermanent = 64;
  FlatMap<Shared> map;
  for (std::uint32_t key = 0; key < kPermanent; ++key) map.Insert(key, {key, ValueOf(key)});
  std::atomic<std::uint64_t> changes{0};
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> validated{0};
  std::atomic<bool> wrong{false};
  auto reader = [&](std::uint32_t seed) {
    std::uint32_t key = seed;
    while (!stop.load(std::memory_order_acquire)) {
      key = (key * 1103515245u + 12345u) % 4096u;
      const std::uint64_t before = changes.load(std::memory_order_acquire);
      const Shared* found = map.Find(key);
      const bool present = found != nullptr;
      const std::uint32_t copy = present ? found->key_copy.load() : 0;
      const std::uint32_t square = present ? found->square.load() : 0;
      if ((before & 1) != 0 || changes.load(std::memory_order_acquire) != before) continue;
      validated.fetch_add(1, std::memory_order_relaxed);
      if ((key < kPermanent && !present) || (present && (copy != key || square != ValueOf(key))))
        wrong.store(true);
    }
  };
  std::thread r1(reader, 1u), r2(reader, 2u);
  auto change = [&](auto&& f) {
    changes.fetch_add(1, std::memory_order_acq_rel);
    f();
    changes.fetch_add(1, std::memory_order_acq_rel);
  };
  // About half a second of changes, longer if the readers have not validated enough yet.
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::steady_clock::now() - start; };
  while (elapsed() < std::chrono::milliseconds(500) ||
         (validated.load() < 1000 && elapsed() < std::chrono::seconds(10))) {
    for (std::uint32_t key = kPermanent; key < 4096; key += 3) {
      change([&] { map.Insert(key, {key, ValueOf(key)}); });
    }
    for (std::uint32_t key = kPermanent; key < 4096; key += 3) {
      change([&] { map.Erase(key); });
    }
    change([&] {
      FlatMap<Shared> moved = std::move(map);
      map = std::move(moved);  // the arrays come back (retired ones too)
    });
  }
  stop.store(true, std::memory_order_release);
  r1.join();
  r2.join();
  EXPECT_FALSE(wrong.load());
  EXPECT_GE(validated.load(), 1000u);
  EXPECT_EQ(map.size(), kPermanent);
}

// Assigning maps of one size again and again (a scene topology's tree records when trees are
// cut over and over) copies into the array already there: no allocation, no memory growth.
TEST(FlatMap, AssignOrAdoptReusesTheArrayWhenItHasRoom) {
  FlatMap<int> slot;
  {
    FlatMap<int> first;
    for (int i = 0; i < 40; ++i) first.Insert(static_cast<std::uint32_t>(i), i);
    slot.AssignOrAdopt(std::move(first));  // empty slot: adopts first's array
  }
  EXPECT_EQ(slot.size(), 40u);
  const std::size_t bytes = slot.ApproximateBytes();
  for (int round = 0; round < 100; ++round) {
    FlatMap<int> next;
    for (int i = 0; i < 30; ++i) next.Insert(static_cast<std::uint32_t>(i + round), -i);
    const std::size_t before = AllocationCounter::total();
    slot.AssignOrAdopt(std::move(next));
    EXPECT_EQ(AllocationCounter::total(), before);
    ASSERT_EQ(slot.size(), 30u);
    EXPECT_EQ(*slot.Find(static_cast<std::uint32_t>(round + 7)), -7);
    EXPECT_EQ(slot.Find(static_cast<std::uint32_t>(round + 30)), nullptr);
  }
  EXPECT_EQ(slot.ApproximateBytes(), bytes);
  FlatMap<int> larger;  // no room: adopted, and ours retired
  for (int i = 0; i < 100; ++i) larger.Insert(static_cast<std::uint32_t>(i), i);
  slot.AssignOrAdopt(std::move(larger));
  EXPECT_EQ(slot.size(), 100u);
  EXPECT_EQ(*slot.Find(99), 99);
  EXPECT_TRUE(larger.empty());  // NOLINT(bugprone-use-after-move): adopted
}

}  // namespace
}  // namespace semgraph::topology
