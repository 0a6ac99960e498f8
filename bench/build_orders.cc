// semgraph_build_orders: the cost of building one pose tree of N frames by AddPose, in three
// orders of the same edges (Google Benchmark; manual time covers the N adds only, names and
// specs are made before):
//   root_down  a chain t0 <- t1 <- ... <- tN, parents first: every add is a new leaf;
//   leaf_up    the same chain, children first: every add links the chain built so far under a
//              new root (the order that made linking cost O(|T|) per add: quadratic in all);
//   random     a random tree (parent of t_i uniform in t_0 .. t_{i-1}), edges in random order:
//              adds of leaves, of new roots and links of subtrees, mixed.
// Each result is checked before it counts: the pose of the deepest frame wrt the root equals the
// sum of the edges' translations (every edge is a pure translation, so the sum is exact).
//
//   build-bench/bench/semgraph_build_orders [--benchmark_filter=...]
// Sizes 10^4, 10^5, 10^6. Counters: ns_per_add (wall), cpu_ns_per_add (the thread's CPU time,
// which a busy shared machine disturbs less), rerepresented_per_add (PoseForest's count of node
// representations computed by its links: 1 for root-down and leaf-up, <= log2 N in any order).
// Results: docs/performance.md ("Building a tree in any order").
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace {

using semgraph::core::PoseSpec;
using Graph = semgraph::core::SceneGraph<>;

struct Edge {
  std::string of, of_body, wrt, wrt_body;
  Eigen::Vector3d p;
};

// The edges of a chain (parent of t_i is t_{i-1}) or of a random tree, each t_i -> its parent,
// translation (1, i mod 7, 0) so that the sum along a path is an exact integer vector.
struct Tree {
  std::vector<Edge> edges;  // edge i - 1 is the edge into t_i
  std::vector<int> parent;  // parent[i] of t_i; -1 for t_0
  int deepest = 0;          // a frame of greatest depth
};

const Tree& TreeOf(int n, bool chain) {
  static std::vector<std::pair<std::pair<int, bool>, std::unique_ptr<Tree>>> cache;
  for (const auto& [key, tree] : cache) {
    if (key == std::pair{n, chain}) return *tree;
  }
  auto t = std::make_unique<Tree>();
  std::mt19937_64 rng(20240613u + static_cast<unsigned>(n));
  t->parent.assign(n + 1, -1);
  std::vector<int> depth(n + 1, 0);
  for (int i = 1; i <= n; ++i) {
    const int p = chain ? i - 1 : static_cast<int>(rng() % static_cast<std::uint64_t>(i));
    t->parent[i] = p;
    depth[i] = depth[p] + 1;
    if (depth[i] > depth[t->deepest]) t->deepest = i;
    t->edges.push_back(Edge{"t" + std::to_string(i), "T" + std::to_string(i),
                            "t" + std::to_string(p), "T" + std::to_string(p),
                            Eigen::Vector3d(1, i % 7, 0)});
  }
  cache.emplace_back(std::pair{n, chain}, std::move(t));
  return *cache.back().second;
}

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "semgraph_build_orders: %s\n", what);
  std::abort();
}

// The pose of the deepest frame wrt t0 must be the sum of the translations on its path.
void Check(const Graph& g, const Tree& t) {
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  for (int f = t.deepest; f != 0; f = t.parent[f]) expected += t.edges[f - 1].p;
  auto X = g.GetPosition(PoseSpec::Of("t" + std::to_string(t.deepest)).RelativeTo("t0"));
  if (!X || X->value != expected) Fail("wrong pose after the build");
  if (g.num_pose_edges() != t.edges.size() || !CheckInvariants(g).empty())
    Fail("wrong graph after the build");
}

enum class Order { kRootDown, kLeafUp, kRandom };

void BM_Build(benchmark::State& state, Order order) {
  const int n = static_cast<int>(state.range(0));
  const Tree& t = TreeOf(n, order != Order::kRandom);
  std::vector<int> sequence(t.edges.size());
  std::iota(sequence.begin(), sequence.end(), 0);
  if (order == Order::kLeafUp) std::reverse(sequence.begin(), sequence.end());
  if (order == Order::kRandom) std::shuffle(sequence.begin(), sequence.end(), std::mt19937_64(7));
  std::vector<PoseSpec> specs;
  specs.reserve(sequence.size());
  for (const int i : sequence) {
    const Edge& e = t.edges[i];
    specs.push_back(PoseSpec::Of(e.of, e.of_body).RelativeTo(e.wrt, e.wrt_body));
  }
  double seconds = 0, cpu_seconds = 0, rerepresented = 0;
  for (auto _ : state) {
    auto g = std::make_unique<Graph>();
    const double c0 = ThreadCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < specs.size(); ++k) {
      if (!g->AddPose(specs[k], Eigen::Quaterniond::Identity(), t.edges[sequence[k]].p))
        Fail("an add was refused");
    }
    const auto t1 = std::chrono::steady_clock::now();
    cpu_seconds += ThreadCpuSeconds() - c0;
    const double s = std::chrono::duration<double>(t1 - t0).count();
    state.SetIterationTime(s);
    seconds += s;
    rerepresented += static_cast<double>(g->topology().forest().rerepresented_nodes());
    state.PauseTiming();
    Check(*g, t);
    g.reset();
    state.ResumeTiming();
  }
  const double iters = static_cast<double>(state.iterations());
  state.counters["ns_per_add"] = seconds * 1e9 / iters / n;
  state.counters["cpu_ns_per_add"] = cpu_seconds * 1e9 / iters / n;
  state.counters["rerepresented_per_add"] = rerepresented / iters / n;
  if (rerepresented / iters > n * std::log2(static_cast<double>(n)))
    Fail("linking re-represented more than N log2 N nodes");
}

void Register() {
  const std::pair<const char*, Order> orders[] = {{"build_root_down", Order::kRootDown},
                                                  {"build_leaf_up", Order::kLeafUp},
                                                  {"build_random_order", Order::kRandom}};
  for (const auto& [name, order] : orders) {
    for (const int n : {10'000, 100'000, 1'000'000}) {
      benchmark::RegisterBenchmark(name,
                                   [order = order](benchmark::State& s) { BM_Build(s, order); })
          ->Arg(n)
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  Register();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
