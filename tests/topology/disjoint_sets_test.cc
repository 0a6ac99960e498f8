#include "semgraph/topology/disjoint_sets.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "support/alloc_counter.h"

// Allocations are counted by the suite's one replacement of operator new/delete
// (support/alloc_counter.h: every form, so it links with sanitizer runtimes too).
using semgraph::testing::AllocationCounter;

namespace semgraph::topology {
namespace {

DisjointSets WithElements(std::uint32_t n) {
  DisjointSets sets;
  for (std::uint32_t i = 0; i < n; ++i) EXPECT_EQ(sets.AddElement(), i);
  return sets;
}

std::vector<std::uint32_t> Links(const DisjointSets& sets) {
  std::vector<std::uint32_t> links(sets.size());
  for (std::uint32_t x = 0; x < sets.size(); ++x) links[x] = sets.link(x);
  return links;
}

// The oracle: one label per element; a union relabels every element of one side.
struct NaiveSets {
  std::vector<std::uint32_t> label;

  void Union(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t from = label[b];
    const std::uint32_t to = label[a];
    for (auto& l : label) {
      if (l == from) l = to;
    }
  }
  std::uint32_t SizeOf(std::uint32_t x) const {
    std::uint32_t n = 0;
    for (auto l : label) n += l == label[x];
    return n;
  }
};

TEST(DisjointSets, NewElementsAreSingletons) {
  DisjointSets sets = WithElements(4);
  for (std::uint32_t x = 0; x < 4; ++x) {
    EXPECT_EQ(sets.FindConst(x), x);
    EXPECT_EQ(sets.Find(x), x);
    EXPECT_EQ(sets.SizeOf(x), 1u);
  }
  EXPECT_FALSE(sets.SameSet(0, 1));
  EXPECT_TRUE(sets.CheckInvariants());
}

TEST(DisjointSets, UnionReturnsTheRepresentativeOfTheLargerSet) {
  DisjointSets sets = WithElements(5);
  const std::uint32_t r01 = sets.Union(0, 1);
  const std::uint32_t r012 = sets.Union(2, 0);  // {2} joins the larger {0, 1}
  EXPECT_EQ(r012, r01);
  EXPECT_EQ(sets.Union(1, 2), r012);  // already one set: no-op
  EXPECT_EQ(sets.SizeOf(r012), 3u);
  EXPECT_EQ(sets.SizeOf(2), 3u);
  EXPECT_EQ(sets.FindConst(4), 4u);
  EXPECT_TRUE(sets.CheckInvariants());
}

TEST(DisjointSets, RandomUnionsAgreeWithNaiveLabels) {
  constexpr std::uint32_t kElements = 1000;
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::uint32_t> element(0, kElements - 1);
  DisjointSets sets = WithElements(kElements);
  NaiveSets naive{std::vector<std::uint32_t>(kElements)};
  for (std::uint32_t x = 0; x < kElements; ++x) naive.label[x] = x;
  for (int op = 0; op < 1500; ++op) {
    const std::uint32_t a = element(rng);
    const std::uint32_t b = element(rng);
    const std::uint32_t rep = sets.Union(a, b);
    naive.Union(a, b);
    ASSERT_EQ(sets.FindConst(a), rep);
    ASSERT_EQ(sets.FindConst(b), rep);
    ASSERT_EQ(sets.SizeOf(rep), naive.SizeOf(a));
    if (op % 50 == 0) {
      ASSERT_TRUE(sets.CheckInvariants()) << "operation " << op;
    }
    for (int k = 0; k < 20; ++k) {
      const std::uint32_t x = element(rng);
      const std::uint32_t y = element(rng);
      ASSERT_EQ(sets.SameSet(x, y), naive.label[x] == naive.label[y]);
      // Find (halving paths) and FindConst agree, whichever runs first.
      ASSERT_EQ(sets.FindConst(x), sets.Find(x));
    }
  }
  EXPECT_TRUE(sets.CheckInvariants());
}

TEST(DisjointSets, FindConstWritesNothingWhileFindHalvesPaths) {
  // Two equal unions then one more give 3 -> 2 -> 0: a path of length two.
  DisjointSets sets = WithElements(4);
  sets.Union(0, 1);
  sets.Union(2, 3);
  sets.Union(0, 2);
  ASSERT_EQ(sets.link(3), 2u);
  ASSERT_EQ(sets.link(2), 0u);
  const std::vector<std::uint32_t> before = Links(sets);
  for (std::uint32_t x = 0; x < 4; ++x) EXPECT_EQ(sets.FindConst(x), 0u);
  EXPECT_EQ(Links(sets), before);
  EXPECT_EQ(sets.Find(3), 0u);
  EXPECT_EQ(sets.link(3), 0u);  // relinked to its grandparent
  EXPECT_TRUE(sets.CheckInvariants());
}

TEST(DisjointSets, ReadOnlyQueriesDoNotAllocate) {
  DisjointSets sets = WithElements(64);
  for (std::uint32_t x = 1; x < 64; ++x) sets.Union(x - 1, x);
  std::uint32_t sink = 0;
  const std::size_t before = AllocationCounter::total();
  for (std::uint32_t x = 0; x < 64; ++x) {
    sink += sets.FindConst(x) + sets.SizeOf(x) + sets.SameSet(x, 63 - x) + sets.Find(x);
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_NE(sink, 0u);
}

// The split step of the scene graph: a pose tree {0..9} loses an edge and becomes {0..4} and
// {5..9}; the caller resets the whole old set and re-unions each new tree.
TEST(DisjointSets, ResetAndReunionSplitsASet) {
  DisjointSets sets = WithElements(12);
  for (std::uint32_t x = 1; x < 10; ++x) sets.Union(x - 1, x);
  sets.Union(10, 11);  // an unrelated set that must survive the split untouched
  ASSERT_EQ(sets.SizeOf(0), 10u);
  for (std::uint32_t x = 0; x < 10; ++x) sets.Reset(x);
  for (std::uint32_t x = 0; x < 10; ++x) EXPECT_EQ(sets.FindConst(x), x);
  for (std::uint32_t x = 1; x < 5; ++x) sets.Union(x - 1, x);
  for (std::uint32_t x = 6; x < 10; ++x) sets.Union(x - 1, x);
  ASSERT_TRUE(sets.CheckInvariants());
  EXPECT_EQ(sets.SizeOf(0), 5u);
  EXPECT_EQ(sets.SizeOf(9), 5u);
  EXPECT_TRUE(sets.SameSet(0, 4));
  EXPECT_TRUE(sets.SameSet(5, 9));
  EXPECT_FALSE(sets.SameSet(4, 5));
  EXPECT_TRUE(sets.SameSet(10, 11));
  EXPECT_EQ(sets.SizeOf(10), 2u);
}

TEST(DisjointSets, RandomSplitsAgreeWithNaiveLabels) {
  // Repeatedly split a random set by resetting it and re-unioning a random two-way partition.
  constexpr std::uint32_t kElements = 300;
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::uint32_t> element(0, kElements - 1);
  DisjointSets sets = WithElements(kElements);
  NaiveSets naive{std::vector<std::uint32_t>(kElements)};
  for (std::uint32_t x = 0; x < kElements; ++x) naive.label[x] = x;
  for (int round = 0; round < 200; ++round) {
    for (int k = 0; k < 5; ++k) {
      const std::uint32_t a = element(rng);
      const std::uint32_t b = element(rng);
      sets.Union(a, b);
      naive.Union(a, b);
    }
    const std::uint32_t victim = element(rng);
    std::vector<std::uint32_t> part[2];
    for (std::uint32_t x = 0; x < kElements; ++x) {
      if (naive.label[x] == naive.label[victim]) part[rng() % 2].push_back(x);
    }
    for (const auto& p : part) {
      for (auto x : p) sets.Reset(x);
    }
    for (const auto& p : part) {
      for (auto x : p) naive.label[x] = p.front();
      for (std::size_t i = 1; i < p.size(); ++i) sets.Union(p[i - 1], p[i]);
    }
    ASSERT_TRUE(sets.CheckInvariants()) << "round " << round;
    for (std::uint32_t x = 0; x < kElements; ++x) {
      ASSERT_EQ(sets.SizeOf(x), naive.SizeOf(x)) << "round " << round;
      ASSERT_EQ(sets.SameSet(x, victim), naive.label[x] == naive.label[victim]);
    }
  }
}

}  // namespace
}  // namespace semgraph::topology
