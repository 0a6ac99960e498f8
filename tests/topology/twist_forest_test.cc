#include "semgraph/topology/twist_forest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <new>
#include <numeric>
#include <queue>
#include <random>
#include <set>
#include <vector>

#include "support/alloc_counter.h"

// Allocations are counted by the suite's one replacement of operator new/delete
// (support/alloc_counter.h: every form, so it links with sanitizer runtimes too).
using semgraph::testing::AllocationCounter;

namespace semgraph::topology {
namespace {

constexpr std::size_t kNoPath = TwistForest::kNoPath;

// Short names for the strong indices the forest takes: body n, edge n.
constexpr BodyIndex B(std::uint32_t n) { return BodyIndex(n); }
constexpr TwistEdgeIndex E(std::uint32_t n) { return TwistEdgeIndex(n); }
PathStep Step(std::uint32_t edge, std::uint32_t from, std::uint32_t to) {
  return PathStep{E(edge), B(from), B(to)};
}

// The naive model: a plain edge list; paths by breadth-first search.
class NaiveForest {
 public:
  std::map<TwistEdgeIndex, TwistEdgeEnds> edges;

  std::set<BodyIndex> Bodies() const {
    std::set<BodyIndex> bodies;
    for (const auto& [edge, ends] : edges) {
      bodies.insert(ends.tail);
      bodies.insert(ends.head);
    }
    return bodies;
  }

  // For every body reachable from `from`: the step that reached it (BFS tree rooted at from).
  std::map<BodyIndex, PathStep> Reach(BodyIndex from) const {
    std::map<BodyIndex, std::vector<PathStep>> adjacent;
    for (const auto& [edge, ends] : edges) {
      adjacent[ends.tail].push_back(PathStep{edge, ends.tail, ends.head});
      adjacent[ends.head].push_back(PathStep{edge, ends.head, ends.tail});
    }
    std::map<BodyIndex, PathStep> reached{{from, PathStep{}}};
    std::queue<BodyIndex> frontier;
    frontier.push(from);
    while (!frontier.empty()) {
      const BodyIndex body = frontier.front();
      frontier.pop();
      for (const PathStep& step : adjacent[body]) {
        if (reached.emplace(step.to, step).second) frontier.push(step.to);
      }
    }
    return reached;
  }

  // Writes the path from the BFS root `from` to `to`; false when `to` was not reached.
  static bool PathTo(const std::map<BodyIndex, PathStep>& reached, BodyIndex from, BodyIndex to,
                     std::vector<PathStep>* path) {
    path->clear();
    if (!reached.contains(to)) return false;
    for (BodyIndex body = to; body != from; body = reached.at(body).from) {
      path->push_back(reached.at(body));
    }
    std::reverse(path->begin(), path->end());
    return true;
  }
};

// Naive W4: the union of two edge lists is a forest (union-find over all endpoints).
bool NaiveUnionIsForest(const NaiveForest& a, const NaiveForest& b) {
  std::map<BodyIndex, BodyIndex> up;
  auto find = [&up](BodyIndex x) {
    if (!up.contains(x)) up[x] = x;
    while (up[x] != x) x = up[x];
    return x;
  };
  for (const NaiveForest* forest : {&a, &b}) {
    for (const auto& [edge, ends] : forest->edges) {
      if (forest == &b && a.edges.contains(edge)) return false;  // shared edge id
      const BodyIndex root_tail = find(ends.tail);
      const BodyIndex root_head = find(ends.head);
      if (root_tail == root_head) return false;
      up[root_tail] = root_head;
    }
  }
  return true;
}

// Checks everything observable against the model, for bodies 0 .. num_bodies-1.
void ExpectMatches(const TwistForest& forest, const NaiveForest& model, std::uint32_t num_bodies) {
  ASSERT_TRUE(forest.CheckInvariants());
  const std::set<BodyIndex> bodies = model.Bodies();
  ASSERT_EQ(forest.num_edges(), model.edges.size());
  ASSERT_EQ(forest.num_bodies(), bodies.size());
  for (const auto& [edge, ends] : model.edges) {
    const TwistEdgeEnds* found = forest.FindEdge(edge);
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(*found, ends);
  }
  std::vector<PathStep> expected;
  std::vector<PathStep> actual(num_bodies);
  for (std::uint32_t i = 0; i < num_bodies; ++i) {
    const BodyIndex u = B(i);
    ASSERT_EQ(forest.Contains(u), bodies.contains(u)) << "body " << i;
    const auto reached = model.Reach(u);
    for (std::uint32_t j = 0; j < num_bodies; ++j) {
      const BodyIndex v = B(j);
      const bool connected = NaiveForest::PathTo(reached, u, v, &expected);
      ASSERT_EQ(forest.Connected(u, v), connected) << i << " - " << j;
      const std::size_t length = forest.Path(u, v, actual);
      if (!connected) {
        ASSERT_EQ(length, kNoPath);
        ASSERT_EQ(forest.PathLength(u, v), kNoPath);
        continue;
      }
      ASSERT_EQ(length, expected.size()) << i << " - " << j;
      ASSERT_EQ(forest.PathLength(u, v), expected.size());
      for (std::size_t i = 0; i < length; ++i) ASSERT_EQ(actual[i], expected[i]);
    }
  }
}

// Links `edge` into both the forest and the model.
void LinkBoth(TwistForest* forest, NaiveForest* model, std::uint32_t edge, std::uint32_t tail,
              std::uint32_t head) {
  forest->Link(E(edge), B(tail), B(head));
  model->edges[E(edge)] = TwistEdgeEnds{B(tail), B(head)};
}

TEST(TwistForest, EmptyForestConnectsEachBodyOnlyToItself) {
  const TwistForest forest;
  EXPECT_TRUE(forest.Connected(B(4), B(4)));
  EXPECT_FALSE(forest.Connected(B(4), B(5)));
  EXPECT_EQ(forest.PathLength(B(4), B(4)), 0u);
  EXPECT_EQ(forest.Path(B(4), B(5), {}), kNoPath);
  EXPECT_EQ(forest.FindRoot(B(4)), B(4));
  EXPECT_FALSE(forest.parent(B(4)).is_valid());
  EXPECT_TRUE(forest.CheckInvariants());
}

// Bodies 1 .. 4, edges (id: tail -> head):
//
//   10: 1 -> 2    11: 3 -> 2    12: 3 -> 4
//
//   1 -- 2 -- 3 -- 4
TEST(TwistForest, PathListsStepsFromUToVAcrossEdgeDirections) {
  TwistForest forest;
  forest.Link(E(10), B(1), B(2));
  forest.Link(E(11), B(3), B(2));
  forest.Link(E(12), B(3), B(4));
  ASSERT_TRUE(forest.CheckInvariants());
  std::vector<PathStep> out(3);
  ASSERT_EQ(forest.Path(B(1), B(4), out), 3u);
  EXPECT_EQ(out[0], Step(10, 1, 2));
  EXPECT_EQ(out[1], Step(11, 2, 3));
  EXPECT_EQ(out[2], Step(12, 3, 4));
  ASSERT_EQ(forest.Path(B(4), B(1), out), 3u);
  EXPECT_EQ(out[0], Step(12, 4, 3));
  EXPECT_EQ(out[2], Step(10, 2, 1));
  EXPECT_EQ(forest.FindEdge(E(11))->tail,
            B(3));  // step 2 -> 3 crosses edge 11 against its direction
}

TEST(TwistForest, PathIntoATooShortSpanReportsTooLongAndWritesNothing) {
  TwistForest forest;
  forest.Link(E(10), B(1), B(2));
  forest.Link(E(11), B(2), B(3));
  std::vector<PathStep> out(3, Step(7, 7, 7));
  EXPECT_EQ(forest.Path(B(1), B(3), std::span(out).first(1)), TwistForest::kPathTooLong);
  EXPECT_EQ(forest.Path(B(1), B(9), std::span(out).first(1)), kNoPath);
  for (const PathStep& step : out) EXPECT_EQ(step, Step(7, 7, 7));
  EXPECT_EQ(forest.Path(B(1), B(3), std::span(out).first(2)), 2u);
  EXPECT_EQ(out[2], Step(7, 7, 7));  // nothing past the path
  EXPECT_NE(TwistForest::kPathTooLong, kNoPath);
}

// Tree A (5 bodies) and tree B (2 bodies), before the link 3 -- 10:
//
//   A:  0 - 1 - 2 - 3 - 4        B:  10 - 11
//
// Linking them hangs B (the smaller) under A's endpoint 3: B is rerooted at 10, A is unchanged.
TEST(TwistForest, LinkRerootsTheSmallerTreeUnderTheLargerOne) {
  for (const bool a_is_tail : {true, false}) {
    TwistForest forest;
    forest.Link(E(100), B(0), B(1));
    forest.Link(E(101), B(1), B(2));
    forest.Link(E(102), B(2), B(3));
    forest.Link(E(103), B(3), B(4));
    forest.Link(E(110), B(11), B(10));
    const BodyIndex root_a = forest.FindRoot(B(0));
    std::vector<BodyIndex> parents_a;
    for (std::uint32_t body = 0; body <= 4; ++body) parents_a.push_back(forest.parent(B(body)));

    if (a_is_tail) {
      forest.Link(E(120), B(3), B(10));
    } else {
      forest.Link(E(120), B(10), B(3));
    }
    ASSERT_TRUE(forest.CheckInvariants());
    for (std::uint32_t body = 0; body <= 4; ++body) {
      EXPECT_EQ(forest.parent(B(body)), parents_a[body]) << "A was rerooted at " << body;
    }
    EXPECT_EQ(forest.FindRoot(B(11)), root_a);
    EXPECT_EQ(forest.parent(B(10)), B(3));
    EXPECT_EQ(forest.parent_edge(B(10)), E(120));
    EXPECT_EQ(forest.parent(B(11)), B(10));
    EXPECT_EQ(forest.depth(B(10)), forest.depth(B(3)) + 1);
    EXPECT_EQ(forest.depth(B(11)), forest.depth(B(3)) + 2);
  }
}

// 1 - 2 - 3 - 4 ; removing 2 - 3 splits it; removing 1 - 2 then leaves 1 and 2 isolated.
TEST(TwistForest, UnlinkSplitsTheTreeAndDropsBodiesLeftWithoutEdges) {
  TwistForest forest;
  forest.Link(E(10), B(1), B(2));
  forest.Link(E(11), B(2), B(3));
  forest.Link(E(12), B(3), B(4));
  forest.Unlink(E(11));
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_FALSE(forest.Connected(B(1), B(4)));
  EXPECT_TRUE(forest.Connected(B(1), B(2)));
  EXPECT_TRUE(forest.Connected(B(3), B(4)));
  EXPECT_EQ(forest.num_bodies(), 4u);
  forest.Unlink(E(10));
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_FALSE(forest.Contains(B(1)));
  EXPECT_FALSE(forest.Contains(B(2)));
  EXPECT_EQ(forest.num_bodies(), 2u);
  EXPECT_FALSE(forest.ContainsEdge(E(10)));
  forest.Unlink(E(12));
  EXPECT_EQ(forest.num_bodies(), 0u);
  EXPECT_TRUE(forest.CheckInvariants());
}

TEST(TwistForest, LinkOfConnectedBodiesAborts) {
  TwistForest forest;
  forest.Link(E(10), B(1), B(2));
  forest.Link(E(11), B(2), B(3));
  EXPECT_DEATH(forest.Link(E(12), B(3), B(1)), "tail_root != head_root");
  EXPECT_DEATH(forest.Link(E(12), B(1), B(1)), "tail != head");
  EXPECT_DEATH(forest.Link(E(10), B(5), B(6)), "edges_.Contains");
  EXPECT_DEATH(forest.Unlink(E(99)), "ends != nullptr");
}

// This: 1 - 2   3 - 4.   A second 2 - 1 is parallel; 2 - 3 plus 4 - 1 closes a cycle;
// 2 - 3 alone is fine; an edge id already used is rejected.
TEST(TwistForest, CanMergeRejectsCyclesParallelEdgesAndSharedIds) {
  TwistForest forest;
  forest.Link(E(10), B(1), B(2));
  forest.Link(E(11), B(3), B(4));
  TwistForest parallel;
  parallel.Link(E(20), B(2), B(1));
  EXPECT_FALSE(forest.CanMerge(parallel));
  EXPECT_FALSE(parallel.CanMerge(forest));
  TwistForest cycle;
  cycle.Link(E(20), B(2), B(3));
  cycle.Link(E(21), B(4), B(1));
  EXPECT_FALSE(forest.CanMerge(cycle));
  EXPECT_FALSE(cycle.CanMerge(forest));
  TwistForest shared_id;
  shared_id.Link(E(10), B(7), B(8));
  EXPECT_FALSE(forest.CanMerge(shared_id));
  TwistForest bridge;
  bridge.Link(E(20), B(2), B(3));
  bridge.Link(E(21), B(4), B(5));
  EXPECT_TRUE(forest.CanMerge(bridge));
  EXPECT_TRUE(bridge.CanMerge(forest));
  EXPECT_TRUE(forest.CanMerge(TwistForest{}));
  EXPECT_FALSE(forest.CanMerge(forest));
  forest.Merge(std::move(bridge));
  EXPECT_TRUE(bridge.empty());  // NOLINT(bugprone-use-after-move): documented state
  ASSERT_TRUE(forest.CheckInvariants());
  EXPECT_EQ(forest.PathLength(B(1), B(5)), 4u);
}

TEST(TwistForest, QueriesDoNotAllocate) {
  TwistForest forest;
  std::mt19937 rng(7);
  for (std::uint32_t body = 1; body < 200; ++body) {
    forest.Link(E(1000 + body), B(body), B(static_cast<std::uint32_t>(rng() % body)));
  }
  std::vector<PathStep> out(200);
  const std::size_t before = AllocationCounter::total();
  std::size_t total = 0;
  for (std::uint32_t u = 0; u < 210; u += 3) {
    for (std::uint32_t v = 0; v < 210; ++v) {
      total += forest.Connected(B(u), B(v)) ? 1 : 0;
      total += forest.PathLength(B(u), B(v)) != kNoPath ? 1 : 0;
      total += forest.Path(B(u), B(v), out) != kNoPath ? 1 : 0;
      total += forest.FindRoot(B(v)).value() + forest.depth(B(v)) + forest.parent(B(v)).value();
    }
  }
  EXPECT_EQ(AllocationCounter::total(), before);
  EXPECT_GT(total, 0u);
}

TEST(TwistForest, ForEachEdgeListsEveryEdgeOnceAndClearEmptiesButKeepsMemory) {
  TwistForest forest;
  forest.Link(E(7), B(1), B(2));
  forest.Link(E(3), B(3), B(2));
  forest.Link(E(9), B(4), B(5));
  std::map<TwistEdgeIndex, TwistEdgeEnds> seen;
  forest.ForEachEdge([&](TwistEdgeIndex e, BodyIndex tail, BodyIndex head) {
    EXPECT_TRUE(seen.emplace(e, TwistEdgeEnds{tail, head}).second) << "edge listed twice";
  });
  const std::map<TwistEdgeIndex, TwistEdgeEnds> expected{
      {E(7), {B(1), B(2)}}, {E(3), {B(3), B(2)}}, {E(9), {B(4), B(5)}}};
  EXPECT_EQ(seen, expected);
  // Unlinked edges are gone from the listing and from FindEdge; their lone bodies too.
  forest.Unlink(E(9));
  EXPECT_EQ(forest.FindEdge(E(9)), nullptr);
  EXPECT_FALSE(forest.Contains(B(4)));
  std::size_t count = 0;
  forest.ForEachEdge([&](TwistEdgeIndex, BodyIndex, BodyIndex) { ++count; });
  EXPECT_EQ(count, 2u);
  const std::size_t bytes = forest.ApproximateBytes();
  EXPECT_GT(bytes, sizeof(TwistForest));
  forest.Clear();
  EXPECT_TRUE(forest.empty());
  EXPECT_EQ(forest.num_bodies(), 0u);
  EXPECT_FALSE(forest.Contains(B(2)));
  EXPECT_FALSE(forest.Connected(B(1), B(3)));
  EXPECT_EQ(forest.ApproximateBytes(), bytes);  // the memory is kept
  EXPECT_TRUE(forest.CheckInvariants());
  // And the forest works again after the clear.
  forest.Link(E(7), B(2), B(1));
  EXPECT_TRUE(forest.Connected(B(1), B(2)));
  const BodyIndex child = forest.parent(B(1)).is_valid() ? B(1) : B(2);
  EXPECT_EQ(forest.parent_edge(child), E(7));
}

TEST(TwistForest, ReservationsMakeTheNextLinksAndMergesAllocationFree) {
  // ReserveLink: one more Link, into a forest whose maps are full enough to grow otherwise.
  TwistForest forest;
  for (std::uint32_t i = 1; i < 64; ++i) forest.Link(E(i), B(i), B(0));
  for (std::uint32_t i = 64; i < 128; ++i) {
    forest.ReserveLink();
    const std::size_t before = AllocationCounter::total();
    forest.Link(E(i), B(i), B(i - 1));
    ASSERT_EQ(AllocationCounter::total(), before) << "Link after ReserveLink allocated at " << i;
  }
  // ReserveMore(bodies, edges): that many Links.
  forest.ReserveMore(40, 40);
  {
    const std::size_t before = AllocationCounter::total();
    for (std::uint32_t i = 0; i < 40; ++i) forest.Link(E(1000 + i), B(1000 + i), B(i));
    EXPECT_EQ(AllocationCounter::total(), before);
  }
  // ReserveMerge: a whole merge, whichever side keeps its storage.
  for (const std::uint32_t other_size : {5u, 300u}) {
    TwistForest a = forest, b;
    for (std::uint32_t i = 0; i < other_size; ++i) {
      b.Link(E(5000 + i), B(5000 + i), B(5000 + i + 1));
    }
    ASSERT_TRUE(a.CanMerge(b));
    a.ReserveMerge(b);
    const std::size_t before = AllocationCounter::total();
    a.Merge(std::move(b));
    EXPECT_EQ(AllocationCounter::total(), before) << other_size;
    EXPECT_EQ(a.num_edges(), forest.num_edges() + other_size);
    EXPECT_TRUE(a.CheckInvariants());
  }
  EXPECT_TRUE(forest.CheckInvariants());
}

TEST(TwistForest, MatchesNaiveModelUnderRandomLinkUnlinkAndMerge) {
  constexpr std::uint32_t kBodies = 30;
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    std::mt19937 rng(seed);
    auto body = [&rng] { return static_cast<std::uint32_t>(rng() % kBodies); };
    // Sparse, non-dense edge ids; a fresh one per edge.
    std::uint32_t next_edge = 5;
    auto fresh_edge = [&next_edge] { return next_edge += 7919; };
    TwistForest forest;
    NaiveForest model;
    int merges = 0;
    int rejected_merges = 0;
    for (int op = 0; op < 700; ++op) {
      SCOPED_TRACE(::testing::Message() << "op " << op);
      const std::uint32_t roll = rng() % 100;
      if (roll < 45) {
        const std::uint32_t tail = body();
        const std::uint32_t head = body();
        if (tail != head && !model.Reach(B(tail)).contains(B(head))) {
          LinkBoth(&forest, &model, fresh_edge(), tail, head);
        }
      } else if (roll < 75) {
        if (!model.edges.empty()) {
          auto it = model.edges.begin();
          std::advance(it, rng() % model.edges.size());
          forest.Unlink(it->first);
          model.edges.erase(it);
        }
      } else if (roll < 99) {
        // A second forest of 1..4 edges, sometimes reusing an edge id of this one.
        TwistForest other;
        NaiveForest other_model;
        const std::uint32_t count = 1 + rng() % 4;
        for (std::uint32_t i = 0; i < count; ++i) {
          const std::uint32_t tail = body();
          const std::uint32_t head = body();
          if (tail == head || other_model.Reach(B(tail)).contains(B(head))) continue;
          std::uint32_t edge = fresh_edge();
          if (rng() % 20 == 0 && !model.edges.empty() &&
              !other_model.edges.contains(model.edges.begin()->first)) {
            edge = model.edges.begin()->first.value();
          }
          LinkBoth(&other, &other_model, edge, tail, head);
        }
        ASSERT_TRUE(other.CheckInvariants());
        const bool expected = NaiveUnionIsForest(model, other_model);
        ASSERT_EQ(forest.CanMerge(other), expected);
        ASSERT_EQ(other.CanMerge(forest), expected);
        if (expected) {
          ++merges;
          if (rng() % 2 == 0) {
            forest.Merge(std::move(other));
          } else {
            other.Merge(std::move(forest));
            forest = std::move(other);
          }
          model.edges.insert(other_model.edges.begin(), other_model.edges.end());
        } else {
          ++rejected_merges;
        }
      } else {
        forest.Clear();
        model.edges.clear();
      }
      ExpectMatches(forest, model, kBodies);
      if (::testing::Test::HasFatalFailure()) return;
    }
    EXPECT_GT(merges, 10);
    EXPECT_GT(rejected_merges, 10);
  }
}

TEST(TwistForest, StaysCorrectForThousandsOfBodies) {
  constexpr std::uint32_t kBodies = 3000;
  std::mt19937 rng(11);
  // A long chain (depth ~kBodies) first: the worst case for the parent walks.
  TwistForest chain;
  for (std::uint32_t body = 1; body < kBodies; ++body) chain.Link(E(body), B(body - 1), B(body));
  ASSERT_TRUE(chain.CheckInvariants());
  EXPECT_EQ(chain.PathLength(B(0), B(kBodies - 1)), kBodies - 1);
  std::vector<PathStep> out(kBodies);
  ASSERT_EQ(chain.Path(B(kBodies - 1), B(0), out), kBodies - 1);
  EXPECT_EQ(out.front(), Step(kBodies - 1, kBodies - 1, kBodies - 2));
  EXPECT_EQ(out[kBodies - 2], Step(1, 1, 0));

  // A random tree linked in random edge order, so trees of all sizes get joined.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> tree_edges;
  for (std::uint32_t body = 1; body < kBodies; ++body) {
    tree_edges.emplace_back(body, static_cast<std::uint32_t>(rng() % body));
  }
  std::shuffle(tree_edges.begin(), tree_edges.end(), rng);
  TwistForest forest;
  NaiveForest model;
  std::uint32_t edge = 0;
  for (const auto& [tail, head] : tree_edges) LinkBoth(&forest, &model, ++edge, tail, head);
  ASSERT_TRUE(forest.CheckInvariants());
  // Remove a third of the edges, then relink random unconnected pairs.
  for (int i = 0; i < 1000; ++i) {
    auto it = model.edges.begin();
    std::advance(it, rng() % model.edges.size());
    forest.Unlink(it->first);
    model.edges.erase(it);
  }
  ASSERT_TRUE(forest.CheckInvariants());
  for (int i = 0; i < 500; ++i) {
    const auto tail = static_cast<std::uint32_t>(rng() % kBodies);
    const auto head = static_cast<std::uint32_t>(rng() % kBodies);
    if (tail != head && !forest.Connected(B(tail), B(head))) {
      LinkBoth(&forest, &model, ++edge + kBodies, tail, head);
    }
  }
  ASSERT_TRUE(forest.CheckInvariants());
  ASSERT_EQ(forest.num_edges(), model.edges.size());
  std::vector<PathStep> expected;
  for (int i = 0; i < 30; ++i) {
    const auto u = static_cast<std::uint32_t>(rng() % kBodies);
    const auto reached = model.Reach(B(u));
    for (std::uint32_t v = 0; v < kBodies; v += 7) {
      const bool connected = NaiveForest::PathTo(reached, B(u), B(v), &expected);
      const std::size_t length = forest.Path(B(u), B(v), out);
      ASSERT_EQ(length, connected ? expected.size() : kNoPath) << u << " - " << v;
      if (connected) {
        ASSERT_TRUE(std::equal(expected.begin(), expected.end(), out.begin()));
      }
    }
  }
}

}  // namespace
}  // namespace semgraph::topology
