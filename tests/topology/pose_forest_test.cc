#include "semgraph/topology/pose_forest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "support/alloc_counter.h"

// Allocations are counted by the suite's one replacement of operator new/delete
// (support/alloc_counter.h: every form, so it links with sanitizer runtimes too).
using semgraph::testing::AllocationCounter;

namespace semgraph::topology {
namespace {

constexpr std::uint32_t kNone = FrameIndex::kInvalid;

FrameIndex F(std::uint32_t v) { return FrameIndex(v); }

// The oracle: a plain parent array, answered by walking parent links one step at a time.
struct NaiveForest {
  std::vector<std::uint32_t> parent;

  std::uint32_t Depth(std::uint32_t v) const {
    std::uint32_t d = 0;
    for (; parent[v] != kNone; v = parent[v]) ++d;
    return d;
  }
  std::uint32_t Root(std::uint32_t v) const {
    while (parent[v] != kNone) v = parent[v];
    return v;
  }
  bool IsAncestor(std::uint32_t a, std::uint32_t d) const {
    for (std::uint32_t v = d; v != kNone; v = parent[v]) {
      if (v == a) return true;
    }
    return false;
  }
  std::uint32_t AncestorAtDepth(std::uint32_t v, std::uint32_t d) const {
    std::uint32_t k = Depth(v);
    if (d > k) return kNone;
    for (; k > d; --k) v = parent[v];
    return v;
  }
  std::uint32_t CommonAncestor(std::uint32_t a, std::uint32_t b) const {
    std::uint32_t da = Depth(a);
    std::uint32_t db = Depth(b);
    for (; da > db; --da) a = parent[a];
    for (; db > da; --db) b = parent[b];
    while (a != b) {
      if (parent[a] == kNone) return kNone;
      a = parent[a];
      b = parent[b];
    }
    return a;
  }
};

// Compares every query on the pair (a, b) (and the per-node ones on a) with the oracle.
::testing::AssertionResult AgreesWithNaive(const PoseForest& forest, const NaiveForest& naive,
                                           std::uint32_t a, std::uint32_t b) {
  auto fail = [&](const char* what) {
    return ::testing::AssertionFailure() << what << " differs for a=" << a << " b=" << b;
  };
  if (forest.parent(F(a)).value() != naive.parent[a]) return fail("parent");
  if (forest.is_root(F(a)) != (naive.parent[a] == kNone)) return fail("is_root");
  if (forest.depth(F(a)) != naive.Depth(a)) return fail("depth");
  if (forest.Root(F(a)).value() != naive.Root(a)) return fail("Root");
  if (forest.IsAncestor(F(a), F(b)) != naive.IsAncestor(a, b)) return fail("IsAncestor");
  if (forest.CommonAncestor(F(a), F(b)).value() != naive.CommonAncestor(a, b)) {
    return fail("CommonAncestor");
  }
  if (forest.SameTree(F(a), F(b)) != (naive.Root(a) == naive.Root(b))) return fail("SameTree");
  const std::uint32_t d = naive.Depth(b);  // any depth, sometimes above depth(a)
  if (forest.AncestorAtDepth(F(a), d).value() != naive.AncestorAtDepth(a, d)) {
    return fail("AncestorAtDepth");
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult AllPairsAgree(const PoseForest& forest, const NaiveForest& naive) {
  if (!forest.CheckInvariants()) return ::testing::AssertionFailure() << "CheckInvariants";
  const auto n = static_cast<std::uint32_t>(naive.parent.size());
  for (std::uint32_t a = 0; a < n; ++a) {
    for (std::uint32_t b = 0; b < n; ++b) {
      if (auto r = AgreesWithNaive(forest, naive, a, b); !r) return r;
    }
  }
  return ::testing::AssertionSuccess();
}

PoseForest WithNodes(std::uint32_t n) {
  PoseForest forest;
  for (std::uint32_t i = 0; i < n; ++i) forest.AddNode();
  return forest;
}

TEST(PoseForest, NewNodesAreIsolatedRoots) {
  PoseForest forest = WithNodes(3);
  ASSERT_EQ(forest.size(), 3u);
  for (std::uint32_t v = 0; v < 3; ++v) {
    EXPECT_TRUE(forest.is_root(F(v)));
    EXPECT_FALSE(forest.parent(F(v)).is_valid());
    EXPECT_EQ(forest.depth(F(v)), 0u);
    EXPECT_EQ(forest.Root(F(v)), F(v));
    EXPECT_FALSE(forest.first_child(F(v)).is_valid());
  }
  EXPECT_FALSE(forest.SameTree(F(0), F(1)));
  EXPECT_TRUE(forest.CheckInvariants());
}

// Fixture:
//   0
//   +-- 1
//   |   +-- 3
//   |   +-- 4
//   +-- 2
//       +-- 5
TEST(PoseForest, CommonAncestorOfCousinsIsGrandparent) {
  PoseForest forest = WithNodes(6);
  forest.Link(F(0), F(1));
  forest.Link(F(0), F(2));
  forest.Link(F(1), F(3));
  forest.Link(F(1), F(4));
  forest.Link(F(2), F(5));
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_EQ(forest.CommonAncestor(F(3), F(5)), F(0));
  EXPECT_EQ(forest.CommonAncestor(F(3), F(4)), F(1));
  EXPECT_EQ(forest.CommonAncestor(F(3), F(1)), F(1));
  EXPECT_EQ(forest.CommonAncestor(F(5), F(5)), F(5));
  EXPECT_TRUE(forest.IsAncestor(F(0), F(4)));
  EXPECT_TRUE(forest.IsAncestor(F(4), F(4)));
  EXPECT_FALSE(forest.IsAncestor(F(2), F(4)));
  EXPECT_EQ(forest.AncestorAtDepth(F(4), 1), F(1));
  EXPECT_FALSE(forest.AncestorAtDepth(F(1), 2).is_valid());
  EXPECT_EQ(forest.depth(F(5)), 2u);
}

TEST(PoseForest, NodesInDifferentTreesHaveNoCommonAncestor) {
  // Fixture:  0     2
  //           |     |
  //           1     3
  PoseForest forest = WithNodes(4);
  forest.Link(F(0), F(1));
  forest.Link(F(2), F(3));
  EXPECT_FALSE(forest.CommonAncestor(F(1), F(3)).is_valid());
  EXPECT_FALSE(forest.CommonAncestor(F(0), F(3)).is_valid());
  EXPECT_FALSE(forest.SameTree(F(1), F(2)));
  EXPECT_FALSE(forest.IsAncestor(F(0), F(3)));
}

TEST(PoseForest, CutMakesTheChildARootAndUnlinksItFromItsSiblings) {
  // Fixture: 0 with children 1, 2, 3 (linked in that order); 3 has child 4.
  PoseForest forest = WithNodes(5);
  forest.Link(F(0), F(1));
  forest.Link(F(0), F(2));
  forest.Link(F(0), F(3));
  forest.Link(F(3), F(4));
  forest.Cut(F(2));  // a middle sibling
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_TRUE(forest.is_root(F(2)));
  EXPECT_FALSE(forest.SameTree(F(0), F(2)));
  forest.Cut(F(3));  // the first sibling (most recently linked), with a subtree
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_EQ(forest.depth(F(4)), 1u);
  EXPECT_EQ(forest.Root(F(4)), F(3));
  EXPECT_EQ(forest.first_child(F(0)), F(1));
  EXPECT_FALSE(forest.next_sibling(F(1)).is_valid());
}

// Every forest on n <= 7 nodes: node i's parent is "none" or one of 0 .. i-1 (all n! arrays),
// relabelled at random so that parents are not always smaller, linked in a random order, then
// cut edge by edge in another random order. Every query on every pair is compared with the
// oracle after every operation.
TEST(PoseForest, AgreesWithNaiveWalkOnEveryForestUpToSevenNodes) {
  std::mt19937 rng(20240601);
  std::size_t forests = 0;
  for (std::uint32_t n = 1; n <= 7; ++n) {
    std::uint64_t count = 1;
    for (std::uint32_t i = 2; i <= n; ++i) count *= i;
    for (std::uint64_t code = 0; code < count; ++code) {
      // Decode `code` in mixed radix: digit i in 0..i, 0 meaning root.
      std::vector<std::uint32_t> shape(n);
      std::uint64_t rest = code;
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint64_t digit = rest % (i + 1);
        rest /= i + 1;
        shape[i] = digit == 0 ? kNone : static_cast<std::uint32_t>(digit - 1);
      }
      std::vector<std::uint32_t> label(n);
      std::iota(label.begin(), label.end(), 0u);
      std::shuffle(label.begin(), label.end(), rng);
      NaiveForest target{std::vector<std::uint32_t>(n, kNone)};
      std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // (parent, child)
      for (std::uint32_t i = 0; i < n; ++i) {
        if (shape[i] == kNone) continue;
        target.parent[label[i]] = label[shape[i]];
        edges.emplace_back(label[shape[i]], label[i]);
      }
      // Any order of the target's edges is a valid Link sequence: each child is still a root
      // until its own edge, and no edge can close a cycle in a sub-forest of a forest.
      std::shuffle(edges.begin(), edges.end(), rng);
      PoseForest forest = WithNodes(n);
      NaiveForest naive{std::vector<std::uint32_t>(n, kNone)};
      for (const auto& [p, c] : edges) {
        forest.Link(F(p), F(c));
        naive.parent[c] = p;
        ASSERT_TRUE(AllPairsAgree(forest, naive)) << "n=" << n << " code=" << code;
      }
      ASSERT_EQ(naive.parent, target.parent);
      std::shuffle(edges.begin(), edges.end(), rng);
      for (const auto& [p, c] : edges) {
        forest.Cut(F(c));
        naive.parent[c] = kNone;
        ASSERT_TRUE(AllPairsAgree(forest, naive)) << "n=" << n << " code=" << code;
      }
      ++forests;
    }
  }
  EXPECT_EQ(forests, 1u + 2 + 6 + 24 + 120 + 720 + 5040);
}

// Random valid Link/Cut sequences on 2000 nodes; invariants after every operation and the
// oracle on a sample of pairs (always including the nodes the operation touched).
TEST(PoseForest, RandomLinksAndCutsKeepInvariantsAndAnswers) {
  constexpr std::uint32_t kNodes = 2000;
  constexpr int kOperations = 3000;
  constexpr int kPairsPerOperation = 32;
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> node(0, kNodes - 1);
  PoseForest forest;
  forest.Reserve(kNodes);
  for (std::uint32_t i = 0; i < kNodes; ++i) forest.AddNode();
  NaiveForest naive{std::vector<std::uint32_t>(kNodes, kNone)};
  std::size_t links = 0;
  std::size_t cuts = 0;
  for (int op = 0; op < kOperations; ++op) {
    std::uint32_t touched_a = node(rng);
    std::uint32_t touched_b = node(rng);
    // Link about 60% of the time, so trees grow large and cuts split big subtrees.
    if (std::uniform_int_distribution<int>(0, 9)(rng) < 6) {
      const std::uint32_t root = naive.Root(touched_a);
      const std::uint32_t parent = touched_b;
      if (naive.Root(parent) == root) continue;  // would close a cycle: not a valid Link
      forest.Link(F(parent), F(root));
      naive.parent[root] = parent;
      touched_a = root;
      ++links;
    } else {
      if (naive.parent[touched_a] == kNone) continue;  // a root has no edge to cut
      forest.Cut(F(touched_a));
      naive.parent[touched_a] = kNone;
      ++cuts;
    }
    ASSERT_TRUE(forest.CheckInvariants()) << "after operation " << op;
    ASSERT_TRUE(AgreesWithNaive(forest, naive, touched_a, touched_b)) << "operation " << op;
    ASSERT_TRUE(AgreesWithNaive(forest, naive, touched_b, touched_a)) << "operation " << op;
    for (int k = 0; k < kPairsPerOperation; ++k) {
      ASSERT_TRUE(AgreesWithNaive(forest, naive, node(rng), node(rng))) << "operation " << op;
    }
  }
  // The sequence really exercised both operations.
  EXPECT_GT(links, 500u);
  EXPECT_GT(cuts, 300u);
}

TEST(PoseForest, LinkingABigTreeRecomputesEveryDepth) {
  // A: chain 0 - 1 - ... - 499. B: random recursive tree on 500 .. 1499 rooted at 500.
  constexpr std::uint32_t kChain = 500;
  constexpr std::uint32_t kTree = 1000;
  std::mt19937 rng(11);
  PoseForest forest = WithNodes(kChain + kTree);
  for (std::uint32_t v = 1; v < kChain; ++v) forest.Link(F(v - 1), F(v));
  for (std::uint32_t i = 1; i < kTree; ++i) {
    const std::uint32_t p = std::uniform_int_distribution<std::uint32_t>(0, i - 1)(rng);
    forest.Link(F(kChain + p), F(kChain + i));
  }
  std::vector<std::uint32_t> depth_before(kTree);
  for (std::uint32_t i = 0; i < kTree; ++i) depth_before[i] = forest.depth(F(kChain + i));

  const FrameIndex leaf_a = F(kChain - 1);
  const FrameIndex root_b = F(kChain);
  forest.Link(leaf_a, root_b);
  ASSERT_TRUE(forest.CheckInvariants());
  for (std::uint32_t i = 0; i < kTree; ++i) {
    const FrameIndex v = F(kChain + i);
    ASSERT_EQ(forest.depth(v), depth_before[i] + kChain) << "node " << v.value();
    ASSERT_EQ(forest.Root(v), F(0));
    ASSERT_TRUE(forest.IsAncestor(leaf_a, v));
    ASSERT_EQ(forest.CommonAncestor(v, F(kChain / 2)), F(kChain / 2));
  }

  forest.Cut(root_b);
  ASSERT_TRUE(forest.CheckInvariants());
  for (std::uint32_t i = 0; i < kTree; ++i) {
    ASSERT_EQ(forest.depth(F(kChain + i)), depth_before[i]);
    ASSERT_EQ(forest.Root(F(kChain + i)), root_b);
  }
}

TEST(PoseForest, ForEachInSubtreeVisitsParentsBeforeChildren) {
  // Fixture:
  //   0                 6 (another tree)
  //   +-- 1
  //   |   +-- 3
  //   |   +-- 4
  //   +-- 2
  //       +-- 5
  PoseForest forest = WithNodes(7);
  forest.Link(F(0), F(1));
  forest.Link(F(0), F(2));
  forest.Link(F(1), F(3));
  forest.Link(F(1), F(4));
  forest.Link(F(2), F(5));
  for (std::uint32_t top : {0u, 1u, 5u, 6u}) {
    std::vector<std::uint32_t> position(7, kNone);
    std::uint32_t visited = 0;
    forest.ForEachInSubtree(F(top), [&](FrameIndex f) { position[f.value()] = visited++; });
    for (std::uint32_t v = 0; v < 7; ++v) {
      const bool in_subtree = forest.IsAncestor(F(top), F(v));
      EXPECT_EQ(position[v] != kNone, in_subtree) << "top " << top << " node " << v;
      if (in_subtree && v != top) {
        EXPECT_LT(position[forest.parent(F(v)).value()], position[v]);
      }
    }
  }
}

// A 10^6-deep chain (the depth at which any recursive walk would overflow the stack): built
// leaf by leaf, queried, walked and split in the middle.
TEST(PoseForest, MillionDeepChainAnswersWithoutRecursion) {
  constexpr std::uint32_t kDepth = 1'000'000;
  PoseForest forest;
  forest.Reserve(kDepth);
  forest.AddNode();
  for (std::uint32_t v = 1; v < kDepth; ++v) forest.Link(F(v - 1), forest.AddNode());
  ASSERT_TRUE(forest.CheckInvariants());
  const FrameIndex leaf = F(kDepth - 1);
  const FrameIndex middle = F(kDepth / 2);
  EXPECT_EQ(forest.depth(leaf), kDepth - 1);
  EXPECT_EQ(forest.Root(leaf), F(0));
  EXPECT_EQ(forest.CommonAncestor(leaf, middle), middle);
  EXPECT_EQ(forest.CommonAncestor(leaf, F(kDepth - 2)), F(kDepth - 2));
  EXPECT_EQ(forest.AncestorAtDepth(leaf, 12345), F(12345));
  EXPECT_TRUE(forest.IsAncestor(F(1), leaf));
  EXPECT_FALSE(forest.IsAncestor(leaf, F(1)));
  std::uint32_t visited = 0;
  forest.ForEachInSubtree(F(0), [&](FrameIndex) { ++visited; });
  EXPECT_EQ(visited, kDepth);

  forest.Cut(middle);  // recomputes 500000 depths and jumps, iteratively
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_EQ(forest.Root(leaf), middle);
  EXPECT_EQ(forest.depth(leaf), kDepth - 1 - kDepth / 2);
  EXPECT_FALSE(forest.CommonAncestor(leaf, F(0)).is_valid());
  EXPECT_FALSE(forest.SameTree(leaf, F(kDepth / 2 - 1)));
}

// Random Link / Cut / Reroot sequences on few nodes (so trees get big relative to n and every
// case of the representation occurs: semantic root = rep root or not, either end of a cut edge
// holding the rep root); invariants after every step and the oracle on every pair.
TEST(PoseForest, RandomLinksCutsAndRerootsAgreeWithNaiveOnEveryPair) {
  constexpr std::uint32_t kNodes = 40;
  constexpr int kOperations = 4000;
  std::mt19937 rng(20261202);
  std::uniform_int_distribution<std::uint32_t> node(0, kNodes - 1);
  PoseForest forest = WithNodes(kNodes);
  NaiveForest naive{std::vector<std::uint32_t>(kNodes, kNone)};
  std::size_t links = 0, cuts = 0, reroots = 0, off_rep_root = 0;
  for (int op = 0; op < kOperations; ++op) {
    const std::uint32_t a = node(rng);
    const std::uint32_t b = node(rng);
    const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
    if (kind < 5) {  // link the tree of a under b
      const std::uint32_t root = naive.Root(a);
      if (naive.Root(b) == root) continue;
      forest.Link(F(b), F(root));
      naive.parent[root] = b;
      ++links;
    } else if (kind < 8) {
      if (naive.parent[a] == kNone) continue;
      forest.Cut(F(a));
      naive.parent[a] = kNone;
      ++cuts;
    } else {  // reroot at a: reverse the naive path a .. root
      forest.Reroot(F(a));
      std::uint32_t child = a, parent = naive.parent[a];
      naive.parent[a] = kNone;
      while (parent != kNone) {
        const std::uint32_t next = naive.parent[parent];
        naive.parent[parent] = child;
        child = parent;
        parent = next;
      }
      ++reroots;
    }
    ASSERT_TRUE(AllPairsAgree(forest, naive)) << "after operation " << op;
    // Count the states where some tree's semantic root is not its rep root (the slow path).
    for (std::uint32_t v = 0; v < kNodes; ++v) {
      if (naive.parent[v] == kNone && forest.TreeKey(F(v)) != F(v)) {
        ++off_rep_root;
        break;
      }
    }
  }
  EXPECT_GT(links, 1000u);
  EXPECT_GT(cuts, 500u);
  EXPECT_GT(reroots, 500u);
  EXPECT_GT(off_rep_root, 1000u);
}

// One random tree of 300 nodes built in the three orders of its edges the scene graph sees:
// parents first (every link adds a leaf), children first (every link hangs the tree built so
// far under a new root) and random (links of subtrees). After each link: invariants and the
// oracle on every pair; TreeSize against the naive count.
TEST(PoseForest, EveryBuildOrderAgreesWithNaive) {
  constexpr std::uint32_t kNodes = 300;
  std::mt19937 rng(5);
  std::vector<std::uint32_t> target(kNodes, kNone);
  for (std::uint32_t i = 1; i < kNodes; ++i) {
    target[i] = std::uniform_int_distribution<std::uint32_t>(0, i - 1)(rng);
  }
  for (int order = 0; order < 3; ++order) {
    std::vector<std::uint32_t> sequence(kNodes - 1);
    std::iota(sequence.begin(), sequence.end(), 1u);
    if (order == 1) std::reverse(sequence.begin(), sequence.end());
    if (order == 2) std::shuffle(sequence.begin(), sequence.end(), rng);
    PoseForest forest = WithNodes(kNodes);
    NaiveForest naive{std::vector<std::uint32_t>(kNodes, kNone)};
    std::size_t step = 0;
    for (const std::uint32_t child : sequence) {
      forest.Link(F(target[child]), F(child));
      naive.parent[child] = target[child];
      // Every pair after the first links and every 16th one later (all pairs is O(n^2 log n)).
      if (step++ % 16 == 0 || step < 20) {
        ASSERT_TRUE(AllPairsAgree(forest, naive)) << "order " << order << " link " << step;
      } else {
        ASSERT_TRUE(forest.CheckInvariants()) << "order " << order << " link " << step;
      }
      std::uint32_t same = 0;
      for (std::uint32_t v = 0; v < kNodes; ++v) same += naive.Root(v) == naive.Root(child);
      ASSERT_EQ(forest.TreeSize(F(child)), same);
    }
    ASSERT_TRUE(AllPairsAgree(forest, naive)) << "order " << order;
    EXPECT_EQ(forest.Root(F(kNodes - 1)), F(0));
  }
}

// The cost of linking, counted rather than timed: building a 10^4-frame chain or random tree
// in any order re-represents O(n log n) nodes in total. Before small-to-large linking, every
// link of the leaf-up chain recomputed the whole tree that moved: n^2/2 = 5 * 10^7 here.
TEST(PoseForest, EveryBuildOrderRerepresentsAtMostNLogNNodes) {
  constexpr std::uint32_t kNodes = 10'000;
  const double bound = kNodes * std::log2(double{kNodes});  // ~1.3 * 10^5
  std::mt19937 rng(17);
  for (const bool chain : {true, false}) {
    std::vector<std::uint32_t> target(kNodes, kNone);
    for (std::uint32_t i = 1; i < kNodes; ++i) {
      target[i] = chain ? i - 1 : std::uniform_int_distribution<std::uint32_t>(0, i - 1)(rng);
    }
    for (int order = 0; order < 3; ++order) {
      std::vector<std::uint32_t> sequence(kNodes - 1);
      std::iota(sequence.begin(), sequence.end(), 1u);
      if (order == 1) std::reverse(sequence.begin(), sequence.end());
      if (order == 2) std::shuffle(sequence.begin(), sequence.end(), rng);
      PoseForest forest = WithNodes(kNodes);
      for (const std::uint32_t child : sequence) forest.Link(F(target[child]), F(child));
      ASSERT_TRUE(forest.CheckInvariants());
      EXPECT_LE(static_cast<double>(forest.rerepresented_nodes()), bound)
          << (chain ? "chain" : "random tree") << " order " << order;
      // Parents first moves one node per link (a new leaf), and so does children first on the
      // chain (a new root above the chain).
      if (order == 0 || (chain && order == 1)) {
        EXPECT_EQ(forest.rerepresented_nodes(), kNodes - 1u);
      }
      const FrameIndex last = F(kNodes - 1);
      EXPECT_EQ(forest.Root(last), F(0));
      if (chain) {
        EXPECT_EQ(forest.depth(last), kNodes - 1);
        EXPECT_EQ(forest.AncestorAtDepth(last, 1234), F(1234));
        EXPECT_EQ(forest.CommonAncestor(last, F(4321)), F(4321));
        EXPECT_TRUE(forest.IsAncestor(F(1), last));
        EXPECT_FALSE(forest.IsAncestor(last, F(1)));
      }
    }
  }
}

// Reroot turns the semantic edges round and keeps the representation: nothing re-represented,
// and the answers follow the new root.
TEST(PoseForest, RerootReversesThePathOnly) {
  constexpr std::uint32_t kDepth = 1000;
  PoseForest forest = WithNodes(kDepth);
  for (std::uint32_t v = 1; v < kDepth; ++v) forest.Link(F(v - 1), F(v));
  const std::uint64_t before = forest.rerepresented_nodes();
  forest.Reroot(F(kDepth - 1));
  EXPECT_EQ(forest.rerepresented_nodes(), before);
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_EQ(forest.Root(F(0)), F(kDepth - 1));
  EXPECT_EQ(forest.depth(F(0)), kDepth - 1);
  EXPECT_EQ(forest.parent(F(0)), F(1));
  EXPECT_EQ(forest.AncestorAtDepth(F(0), 10), F(kDepth - 11));
  EXPECT_EQ(forest.CommonAncestor(F(3), F(700)), F(700));
  EXPECT_TRUE(forest.IsAncestor(F(700), F(3)));
  EXPECT_FALSE(forest.IsAncestor(F(3), F(700)));
}

TEST(PoseForest, QueriesDoNotAllocate) {
  PoseForest forest = WithNodes(64);
  for (std::uint32_t v = 1; v < 64; ++v) forest.Link(F((v - 1) / 2), F(v));  // a heap shape
  std::uint32_t sink = 0;
  const std::size_t before = AllocationCounter::total();
  for (std::uint32_t a = 0; a < 64; ++a) {
    for (std::uint32_t b = 0; b < 64; ++b) {
      sink += forest.CommonAncestor(F(a), F(b)).value() + forest.Root(F(a)).value() +
              forest.AncestorAtDepth(F(a), 1).value();
      sink += forest.IsAncestor(F(a), F(b)) + forest.SameTree(F(a), F(b));
    }
  }
  forest.ForEachInSubtree(F(0), [&](FrameIndex f) { sink += f.value(); });
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_NE(sink, 0u);
}

// The same on a tree built children first, whose semantic root is not its rep root (each
// query is then up to three rep queries, still without allocation).
TEST(PoseForest, QueriesOffTheRepRootDoNotAllocate) {
  PoseForest forest = WithNodes(64);
  for (std::uint32_t v = 63; v > 0; --v) forest.Link(F((v - 1) / 2), F(v));  // heap, bottom up
  ASSERT_NE(forest.TreeKey(F(0)), F(0));  // really the off-root case
  std::uint32_t sink = 0;
  const std::size_t before = AllocationCounter::total();
  for (std::uint32_t a = 0; a < 64; ++a) {
    for (std::uint32_t b = 0; b < 64; ++b) {
      sink += forest.CommonAncestor(F(a), F(b)).value() + forest.Root(F(a)).value() +
              forest.AncestorAtDepth(F(a), 1).value() + forest.depth(F(b));
      sink += forest.IsAncestor(F(a), F(b)) + forest.SameTree(F(a), F(b));
    }
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_EQ(forest.CommonAncestor(F(62), F(61)), F(30));  // siblings under 30 = (61 - 1) / 2
  EXPECT_EQ(forest.depth(F(63)), 6u);                     // 63, 31, 15, 7, 3, 1, 0
  EXPECT_NE(sink, 0u);
}

// Eight words: four semantic, four of the representation (rep_root replaces SceneTopology's
// union-find, which took two).
TEST(PoseForest, UsesThirtyTwoBytesPerNode) {
  PoseForest forest;
  forest.Reserve(1000);
  EXPECT_GE(forest.ApproximateBytes(), 32u * 1000);
  EXPECT_LE(forest.ApproximateBytes(), 32u * 1024);  // reserve() may round up a little
}

TEST(PoseForest, TreeKeyAndTreeSizeFollowLinksCutsAndReroots) {
  // 0 -> 1 -> 2 (three nodes) and 3 -> 4 (two): linking the smaller under the larger keeps the
  // larger tree's key for all five; a reroot keeps it; a cut gives the parts their sizes and
  // keeps the key for one of them.
  PoseForest forest = WithNodes(5);
  forest.Link(F(0), F(1));
  forest.Link(F(1), F(2));
  forest.Link(F(3), F(4));
  const FrameIndex big = forest.TreeKey(F(2));
  EXPECT_EQ(forest.TreeKey(F(0)), big);
  EXPECT_NE(forest.TreeKey(F(3)), big);
  EXPECT_EQ(forest.TreeSize(F(1)), 3u);
  EXPECT_EQ(forest.TreeSize(F(4)), 2u);
  forest.Link(F(2), F(3));
  for (std::uint32_t v = 0; v < 5; ++v) {
    EXPECT_EQ(forest.TreeKey(F(v)), big) << v;
    EXPECT_EQ(forest.TreeSize(F(v)), 5u) << v;
  }
  forest.Reroot(F(4));
  EXPECT_EQ(forest.Root(F(0)), F(4));
  EXPECT_EQ(forest.TreeKey(F(0)), big);
  ASSERT_TRUE(forest.CheckInvariants());
  // After the reroot 1 is the parent of 0: cutting 0 leaves {0} and {1, 2, 3, 4}.
  ASSERT_EQ(forest.parent(F(0)), F(1));
  forest.Cut(F(0));
  EXPECT_EQ(forest.TreeSize(F(0)), 1u);
  EXPECT_EQ(forest.TreeSize(F(3)), 4u);
  EXPECT_NE(forest.TreeKey(F(0)), forest.TreeKey(F(3)));
  EXPECT_TRUE(forest.TreeKey(F(0)) == big || forest.TreeKey(F(3)) == big);
  EXPECT_EQ(forest.Root(F(2)), F(4));
  ASSERT_TRUE(forest.CheckInvariants());
}

TEST(PoseForestDeathTest, LinkThatWouldCloseACycleAborts) {
  PoseForest forest = WithNodes(3);
  forest.Link(F(0), F(1));
  forest.Link(F(1), F(2));
  EXPECT_DEATH(forest.Link(F(2), F(0)), "internal check failed");
  EXPECT_DEATH(forest.Link(F(0), F(0)), "internal check failed");
}

TEST(PoseForestDeathTest, LinkOfANonRootAborts) {
  PoseForest forest = WithNodes(3);
  forest.Link(F(0), F(1));
  EXPECT_DEATH(forest.Link(F(2), F(1)), "internal check failed");
}

TEST(PoseForestDeathTest, CutOfARootAborts) {
  PoseForest forest = WithNodes(1);
  EXPECT_DEATH(forest.Cut(F(0)), "internal check failed");
}

}  // namespace
}  // namespace semgraph::topology
