// semgraph_accelerations_bench: a compiled acceleration query (compiled_acceleration.h) on the
// bench twist chain (bench_scenes.h: f0 <- f1 <- ... <- fd, frame fi on body Li, twist edges
// L(i) -> {f(i+1)} at f(i+1) in [f(i+1)], here each with an acceleration (a_i, alpha_i)). The
// query: Ld relative to L0 at the origin of fd, in [f0]. Kernels:
//   compiled_acceleration      CompiledAcceleration::Evaluate.
//   raw_acceleration_chain     the limit: a hand-written Eigen chain computing the same
//                              composition outward from L0 in one pass (O(d)): the motion of
//                              L(i) rel L0 at fi's origin in [f0] moved to f(i+1)'s origin
//                              (v += w x r, a += alpha x r + w x (w x r)), then edge i rotated
//                              into [f0] and composed (w += w_e, alpha += alpha_e + w x w_e,
//                              v += v_e, a += a_e + 2 w x v_e).
//   raw_acceleration_per_edge  the same numbers in the evaluator's structure, by hand: each edge
//                              moved to fd through its own pose chain X_(i+1)d and rotated
//                              through X_0(i+1) (both RawQuatChain), composed from Ld down to
//                              L0 (O(d^2) pose compositions, as the compiled query).
//   compiled_twist             CompiledTwist::Evaluate on the same path (same graph).
// main() checks every kernel against the others (relative 1e-9) before timing.
//
//   semgraph_accelerations_bench [google-benchmark flags]      wall time, d = 8 and 64
//   semgraph_accelerations_bench icount <kernel> <d> <iters>   one kernel in a loop, for
//     valgrind --tool=callgrind --toggle-collect=icount_<kernel> (bench/accelerations_icount.sh).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "semgraph/core/compiled_acceleration.h"

namespace semgraph_bench {

/// One twist edge's motion: twist and acceleration of L(i+1) rel L(i) at f(i+1)'s origin, in
/// [f(i+1)] (the edge form, as given).
struct EdgeMotion {
  Eigen::Vector3d v, w, a, alpha;
};
/// A motion answer at fd's origin in [f0].
struct MotionOut {
  Eigen::Vector3d v, w, a, alpha;
};

/// Edge accelerations of the 64 twist edges (own seed; the twists are Poses()'s).
inline const std::vector<EdgeMotion>& EdgeMotions() {
  static const std::vector<EdgeMotion> motions = [] {
    std::vector<EdgeMotion> m;
    std::mt19937_64 rng(20261205);
    for (std::size_t i = 0; i < static_cast<std::size_t>(kMaxDepth); ++i) {
      const Eigen::Vector3d a = RandomTranslation(rng), alpha = RandomTranslation(rng);
      m.push_back({Poses().twist_v[i], Poses().twist_w[i], a, alpha});
    }
    return m;
  }();
  return motions;
}

/// The limit: one outward pass (see the file comment). Allocation-free.
inline MotionOut RawAccelerationChain(const Link* links, const EdgeMotion* e, int d) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = v, a = v, alpha = v;  // L(i) rel L0 at fi
  for (int i = 0; i < d; ++i) {
    const Eigen::Vector3d r = q * links[i].p;  // fi's origin -> f(i+1)'s origin, in [f0]
    q = q * links[i].q;
    const Eigen::Vector3d wr = w.cross(r);
    a += alpha.cross(r) + w.cross(wr);
    v += wr;
    const Eigen::Matrix3d R = q.toRotationMatrix();  // [f(i+1)] -> [f0]
    const Eigen::Vector3d v_e = R * e[i].v, w_e = R * e[i].w;
    alpha += R * e[i].alpha + w.cross(w_e);
    a += R * e[i].a + 2.0 * w.cross(v_e);
    v += v_e;
    w += w_e;
  }
  return {v, w, a, alpha};
}

/// The evaluator's structure by hand: edge i moved to fd (a += alpha x p + w x (w x p) with
/// p = p_(i+1)d, v += w x p) and rotated by R_0(i+1), then prepended to the motion of Ld rel
/// L(i+1): alpha = alpha_e + alpha_c + w_e x w_c, a = a_e + a_c + 2 w_e x v_c.
inline MotionOut RawAccelerationPerEdge(const Link* links, const EdgeMotion* e, int d) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = v, a = v, alpha = v;  // Ld rel L(i+1)
  for (int i = d - 1; i >= 0; --i) {
    const Eigen::Vector3d p = RawQuatChain(links + i + 1, d - i - 1).p;  // fd in f(i+1)
    const Eigen::Matrix3d R = RawQuatChain(links, i + 1).q.toRotationMatrix();
    const Eigen::Vector3d wp = e[i].w.cross(p);
    const Eigen::Vector3d v_e = R * (e[i].v + wp), w_e = R * e[i].w;
    const Eigen::Vector3d a_e = R * (e[i].a + e[i].alpha.cross(p) + e[i].w.cross(wp));
    alpha = R * e[i].alpha + alpha + w_e.cross(w);
    a = a_e + a + 2.0 * w_e.cross(v);
    v += v_e;
    w += w_e;
  }
  return {v, w, a, alpha};
}

namespace {

using semgraph::core::AccelerationInput;
using semgraph::core::CompiledAcceleration;

template <class T>
inline void Use(const T& v) {
  benchmark::DoNotOptimize(v);
}

struct AccelerationScene {
  std::unique_ptr<ChainScene<QuatB>> chain;
  std::unique_ptr<CompiledAcceleration<QuatB>> acceleration;
  std::unique_ptr<CompiledTwist<QuatB>> twist;
};

AccelerationScene& SceneOf(int d) {
  static std::map<int, std::unique_ptr<AccelerationScene>> scenes;
  auto& s = scenes[d];
  if (s) return *s;
  s = std::make_unique<AccelerationScene>();
  s->chain = std::make_unique<ChainScene<QuatB>>(d, /*extras=*/false, /*twist_edges=*/0);
  ChainScene<QuatB>& c = *s->chain;
  for (int i = 0; i < d; ++i) {
    const EdgeMotion& m = EdgeMotions()[static_cast<std::size_t>(i)];
    const std::string& h = c.frames[static_cast<std::size_t>(i + 1)];
    CheckOk(c.graph.AddTwist(
                TwistSpec::Of(h).RelativeTo(c.bodies[static_cast<std::size_t>(i)]).ExpressedIn(h),
                m.v, m.w, AccelerationInput{m.a, m.alpha}),
            "chain AddTwist with acceleration");
  }
  auto a = c.graph.CompileAcceleration(c.TwistQuerySpec());
  if (!a) Fail("CompileAcceleration: " + c.graph.Describe(a.error(), c.TwistQuerySpec()));
  s->acceleration = std::make_unique<CompiledAcceleration<QuatB>>(std::move(*a));
  auto t = c.graph.CompileTwist(c.TwistQuerySpec());
  if (!t) Fail("CompileTwist: " + c.graph.Describe(t.error(), c.TwistQuerySpec()));
  s->twist = std::make_unique<CompiledTwist<QuatB>>(std::move(*t));
  return *s;
}

void CheckClose(const char* what, int d, const Eigen::Vector3d& x, const Eigen::Vector3d& ref) {
  const double err = (x - ref).norm(), tol = kTolerance * std::max(1.0, ref.norm());
  if (!(err <= tol)) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%s at d=%d: |diff| = %g (|ref| = %g)", what, d, err,
                  ref.norm());
    Fail(buf);
  }
}

/// Every kernel against the one-pass chain, and the twists against VerifyTwist's reference.
void Verify(int d) {
  AccelerationScene& s = SceneOf(d);
  VerifyTwist(*s.chain);
  const MotionOut ref = RawAccelerationChain(Poses().links.data(), EdgeMotions().data(), d);
  const MotionOut per = RawAccelerationPerEdge(Poses().links.data(), EdgeMotions().data(), d);
  MotionOut c;
  if (s.acceleration->Evaluate(c.a, c.alpha) != ErrorCode::kOk) Fail("acceleration Evaluate");
  if (s.twist->Evaluate(c.v, c.w) != ErrorCode::kOk) Fail("twist Evaluate");
  CheckClose("compiled_twist v vs raw chain", d, c.v, ref.v);
  CheckClose("compiled_twist w vs raw chain", d, c.w, ref.w);
  CheckClose("compiled_acceleration a vs raw chain", d, c.a, ref.a);
  CheckClose("compiled_acceleration alpha vs raw chain", d, c.alpha, ref.alpha);
  CheckClose("per-edge chain v", d, per.v, ref.v);
  CheckClose("per-edge chain w", d, per.w, ref.w);
  CheckClose("per-edge chain a", d, per.a, ref.a);
  CheckClose("per-edge chain alpha", d, per.alpha, ref.alpha);
  auto one = s.chain->graph.GetAcceleration(s.chain->TwistQuerySpec());
  if (!one) Fail("GetAcceleration");
  CheckClose("GetAcceleration a", d, one->linear, ref.a);
  CheckClose("GetAcceleration alpha", d, one->angular, ref.alpha);
}

void BM_CompiledAcceleration(benchmark::State& state) {
  CompiledAcceleration<QuatB>& c = *SceneOf(static_cast<int>(state.range(0))).acceleration;
  for (auto _ : state) {
    Eigen::Vector3d a, alpha;
    if (c.Evaluate(a, alpha) != ErrorCode::kOk) [[unlikely]] {
      state.SkipWithError("Evaluate failed");
      break;
    }
    Use(a);
    Use(alpha);
    benchmark::ClobberMemory();
  }
}

void BM_CompiledTwist(benchmark::State& state) {
  const CompiledTwist<QuatB>& c = *SceneOf(static_cast<int>(state.range(0))).twist;
  for (auto _ : state) {
    Eigen::Vector3d v, w;
    if (c.Evaluate(v, w) != ErrorCode::kOk) [[unlikely]] {
      state.SkipWithError("Evaluate failed");
      break;
    }
    Use(v);
    Use(w);
    benchmark::ClobberMemory();
  }
}

template <MotionOut (*Kernel)(const Link*, const EdgeMotion*, int)>
void BM_Raw(benchmark::State& state) {
  const int d = static_cast<int>(state.range(0));
  const Link* links = Poses().links.data();
  const EdgeMotion* e = EdgeMotions().data();
  Use(links);
  Use(e);
  for (auto _ : state) {
    const MotionOut m = Kernel(links, e, d);
    Use(m);
    benchmark::ClobberMemory();
  }
}

}  // namespace
}  // namespace semgraph_bench

// The callgrind kernels: one query each, not inlined, so that --toggle-collect counts exactly it.
extern "C" [[gnu::noinline]] void icount_compiled_acceleration(
    semgraph::core::CompiledAcceleration<semgraph::coord::QuaternionBackend>* c,
    semgraph_bench::MotionOut* out) {
  if (c->Evaluate(out->a, out->alpha) != semgraph::core::ErrorCode::kOk) std::abort();
}
extern "C" [[gnu::noinline]] void icount_compiled_twist(
    const semgraph::core::CompiledTwist<semgraph::coord::QuaternionBackend>* c,
    semgraph_bench::MotionOut* out) {
  if (c->Evaluate(out->v, out->w) != semgraph::core::ErrorCode::kOk) std::abort();
}
extern "C" [[gnu::noinline]] void icount_raw_acceleration_chain(const semgraph_bench::Link* links,
                                                                const semgraph_bench::EdgeMotion* e,
                                                                int d,
                                                                semgraph_bench::MotionOut* out) {
  *out = semgraph_bench::RawAccelerationChain(links, e, d);
}
extern "C" [[gnu::noinline]] void icount_raw_acceleration_per_edge(
    const semgraph_bench::Link* links, const semgraph_bench::EdgeMotion* e, int d,
    semgraph_bench::MotionOut* out) {
  *out = semgraph_bench::RawAccelerationPerEdge(links, e, d);
}

int main(int argc, char** argv) {
  using namespace semgraph_bench;
  if (argc == 5 && std::strcmp(argv[1], "icount") == 0) {
    const int d = std::atoi(argv[3]);
    const long iters = std::atol(argv[4]);
    Verify(d);
    AccelerationScene& s = SceneOf(d);
    const Link* links = Poses().links.data();
    const EdgeMotion* e = EdgeMotions().data();
    MotionOut out;
    const std::string kernel = argv[2];
    for (long i = 0; i < iters; ++i) {
      if (kernel == "compiled_acceleration") {
        icount_compiled_acceleration(s.acceleration.get(), &out);
      } else if (kernel == "compiled_twist") {
        icount_compiled_twist(s.twist.get(), &out);
      } else if (kernel == "raw_acceleration_chain") {
        icount_raw_acceleration_chain(links, e, d, &out);
      } else if (kernel == "raw_acceleration_per_edge") {
        icount_raw_acceleration_per_edge(links, e, d, &out);
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
    b->Arg(8)->Arg(64);
  };
  stats(benchmark::RegisterBenchmark("compiled_acceleration", BM_CompiledAcceleration));
  stats(benchmark::RegisterBenchmark("raw_acceleration_chain", BM_Raw<RawAccelerationChain>));
  stats(benchmark::RegisterBenchmark("raw_acceleration_per_edge", BM_Raw<RawAccelerationPerEdge>));
  stats(benchmark::RegisterBenchmark("compiled_twist", BM_CompiledTwist));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
