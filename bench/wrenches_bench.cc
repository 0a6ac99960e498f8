// semgraph_wrenches_bench: a compiled wrench query (core/wrenches.h) against the hand-written
// Eigen chain it must stay close to (target: at most 1.25x). Scene: the bench chain f0 <- f1 <-
// ... <- fd (bench_scenes.h links, each frame on its own body), a wrench on L<d> by L<d-1>
// stored at fd; the query moves it to f0 in [f0]: the pose chain X_f0fd (d compositions), then
// f' = R f, m' = R m + p x f'. The raw kernel: RawQuatChain (p += q p_i; q = q q_i) and the same
// two lines. main() checks both against each other before timing.
//
//   semgraph_wrenches_bench [google-benchmark flags]      wall time (median and min)
//   semgraph_wrenches_bench icount <kernel> <d> <iters>   one kernel in a loop, for callgrind:
//     valgrind --tool=callgrind --toggle-collect=icount_<kernel> ... ; kernels: compiled_wrench,
//     raw_wrench_chain (docs/performance.md has the numbers and the command).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>

#include "bench_scenes.h"

namespace semgraph_bench {
namespace {

using semgraph::core::CompiledWrench;
using semgraph::core::WrenchSpec;
using QuatB = semgraph::coord::QuaternionBackend;

template <class T>
inline void Use(const T& v) {
  benchmark::DoNotOptimize(v);
}

const Eigen::Vector3d kForce(1.0, -2.0, 3.0), kMoment(0.5, 0.25, -1.0);

struct WrenchScene {
  semgraph::core::SceneGraph<QuatB> graph;
  std::unique_ptr<CompiledWrench<QuatB>> compiled;
};

WrenchScene& SceneOf(int d) {
  static std::map<int, std::unique_ptr<WrenchScene>> scenes;
  auto& s = scenes[d];
  if (s) return *s;
  s = std::make_unique<WrenchScene>();
  for (int i = 1; i <= d; ++i) {
    const Link& l = Poses().links[static_cast<std::size_t>(i - 1)];
    CheckOk(s->graph.AddPose(semgraph::core::PoseSpec::Of(FrameName(i), BodyName(i))
                                 .RelativeTo(FrameName(i - 1), BodyName(i - 1)),
                             l.q, l.p),
            "chain AddPose");
  }
  CheckOk(s->graph.AddWrench(WrenchSpec::On(BodyName(d)).By(BodyName(d - 1)).At(FrameName(d)),
                             kForce, kMoment),
          "AddWrench");
  auto c = s->graph.CompileWrench(WrenchSpec::On(BodyName(d)).By(BodyName(d - 1)).At("f0"));
  if (!c) Fail("CompileWrench");
  s->compiled = std::make_unique<CompiledWrench<QuatB>>(std::move(*c));
  return *s;
}

struct WrenchOut {
  Eigen::Vector3d f, m;
};
inline WrenchOut RawWrenchChain(const Link* links, int d) {
  const QuatPose X = RawQuatChain(links, d);
  const Eigen::Vector3d f = X.q * kForce;
  return {f, X.q * kMoment + X.p.cross(f)};
}

void Verify(int d) {
  WrenchOut c;
  if (SceneOf(d).compiled->Evaluate(c.f, c.m) != semgraph::core::ErrorCode::kOk) {
    Fail("compiled wrench Evaluate");
  }
  const WrenchOut r = RawWrenchChain(Poses().links.data(), d);
  if ((c.f - r.f).norm() > 1e-9 || (c.m - r.m).norm() > 1e-9) Fail("compiled wrench != raw");
}

void BM_CompiledWrench(benchmark::State& state) {
  const CompiledWrench<QuatB>& c = *SceneOf(static_cast<int>(state.range(0))).compiled;
  for (auto _ : state) {
    WrenchOut w;
    if (c.Evaluate(w.f, w.m) != semgraph::core::ErrorCode::kOk) [[unlikely]] {
      state.SkipWithError("Evaluate failed");
      break;
    }
    Use(w);
    benchmark::ClobberMemory();
  }
}

void BM_RawWrenchChain(benchmark::State& state) {
  const int d = static_cast<int>(state.range(0));
  const Link* links = Poses().links.data();
  Use(links);
  for (auto _ : state) {
    const WrenchOut w = RawWrenchChain(links, d);
    Use(w);
    benchmark::ClobberMemory();
  }
}

}  // namespace
}  // namespace semgraph_bench

// The callgrind kernels: one query each, not inlined, so that --toggle-collect counts exactly it.
extern "C" [[gnu::noinline]] void icount_compiled_wrench(
    const semgraph::core::CompiledWrench<semgraph::coord::QuaternionBackend>* c,
    semgraph_bench::WrenchOut* out) {
  if (c->Evaluate(out->f, out->m) != semgraph::core::ErrorCode::kOk) std::abort();
}
extern "C" [[gnu::noinline]] void icount_raw_wrench_chain(const semgraph_bench::Link* links, int d,
                                                          semgraph_bench::WrenchOut* out) {
  *out = semgraph_bench::RawWrenchChain(links, d);
}

int main(int argc, char** argv) {
  using namespace semgraph_bench;
  if (argc == 5 && std::strcmp(argv[1], "icount") == 0) {
    const int d = std::atoi(argv[3]);
    const long iters = std::atol(argv[4]);
    Verify(d);
    WrenchOut out;
    const std::string kernel = argv[2];
    for (long i = 0; i < iters; ++i) {
      if (kernel == "compiled_wrench") {
        icount_compiled_wrench(SceneOf(d).compiled.get(), &out);
      } else if (kernel == "raw_wrench_chain") {
        icount_raw_wrench_chain(Poses().links.data(), d, &out);
      } else {
        std::fprintf(stderr, "unknown kernel %s\n", argv[2]);
        return 2;
      }
      benchmark::DoNotOptimize(out);
    }
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (int d : {1, 8, 64}) Verify(d);
  const auto stats = [](benchmark::internal::Benchmark* b) {
    b->ComputeStatistics(
        "min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); });
    b->Arg(1)->Arg(8)->Arg(64);
  };
  stats(benchmark::RegisterBenchmark("compiled_wrench", BM_CompiledWrench));
  stats(benchmark::RegisterBenchmark("raw_wrench_chain", BM_RawWrenchChain));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
