// semgraph_time_icount KERNEL D ITERS: the time benchmarks (docs/time.md), counted with
// callgrind like icount.cc (bench/time_icount.sh runs them all). A chain f0 <- f1 <- ... <- fD
// of stamped edges, 100 samples per edge at 10 ms (0 .. 0.99 s), queried at 0.5055 s (between
// samples). Kernels (each an extern "C" noinline function doing one operation):
//   compiled_at_linear / compiled_at_screw   CompiledPose::Evaluate(X, At{t}, report)
//   oneshot_at_linear                        GetPose(spec, At{t})
//   tf2_at                                   tf2 BufferCore::lookupTransform(f0, fD, t), same data
//   raw_interp_chain                         the hand-written chain: per edge a binary search,
//                                            lerp + Eigen slerp, one quaternion composition
//   raw_chain                                the hand-written chain of already-interpolated links
//   stamped_insert                           SetPose(handle, q, p, stamp), in order, full history
//   tf2_insert                               tf2 setTransform (dynamic), in order
// Before counting, the answers are checked against each other (semgraph vs tf2 vs raw).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"
#if defined(SEMGRAPH_HAVE_TF2)
#include "../tests/core/tf2_time_peer.h"
#endif

using namespace semgraph::core;
using QuatB = semgraph::coord::QuaternionBackend;

namespace {
constexpr int kSamples = 100;
constexpr std::int64_t kStep = 10000000;  // 10 ms
constexpr std::int64_t kT = 505500000;    // 0.5055 s

struct Sample {
  std::int64_t t;
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
};
struct Scene {
  int d;
  std::vector<std::vector<Sample>> edges;  // edges[i]: f(i+1) in f(i)
  SceneGraph<QuatB> linear = *SceneGraph<QuatB>::Create(
      TimeOptions{Duration::Seconds(10), Interpolation::kLinear, DuplicatePolicy::kReplace, 1024});
  SceneGraph<QuatB> screw = *SceneGraph<QuatB>::Create(TimeOptions{});
#if defined(SEMGRAPH_HAVE_TF2)
  semgraph_test::tf2time::Buffer tf;
#endif
};

Scene* MakeScene(int d) {
  auto* s = new Scene;
  s->d = d;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  s->edges.resize(d);
  for (int i = 0; i < d; ++i) {
    for (int k = 0; k < kSamples; ++k) {
      s->edges[i].push_back({k * kStep,
                             Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized(),
                             {u(rng), u(rng), u(rng)}});
    }
  }
  for (int i = 0; i < d; ++i) {
    const std::string parent = "f" + std::to_string(i), child = "f" + std::to_string(i + 1);
    for (const Sample& x : s->edges[i]) {
      for (SceneGraph<QuatB>* g : {&s->linear, &s->screw}) {
        if (!g->AddPose(PoseSpec::Of(child, "B" + std::to_string(i + 1))
                            .RelativeTo(parent, "B" + std::to_string(i)),
                        x.q, x.p, Stamp::Nanoseconds(x.t))) {
          std::abort();
        }
      }
#if defined(SEMGRAPH_HAVE_TF2)
      s->tf.Set(parent, child, {x.q.w(), x.q.x(), x.q.y(), x.q.z(), x.p.x(), x.p.y(), x.p.z()},
                x.t + 1000000000, false);
#endif
    }
  }
  return s;
}

// The hand-written baseline: per edge, the bracket by binary search, lerp + slerp, compose.
struct RawPose {
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
};
RawPose RawInterpChain(const Scene& s, std::int64_t t) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < s.d; ++i) {
    const std::vector<Sample>& e = s.edges[i];
    std::size_t lo = 0, hi = e.size() - 1;
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      (e[mid].t <= t ? lo : hi) = mid;
    }
    const double lambda = static_cast<double>(t - e[lo].t) / static_cast<double>(e[hi].t - e[lo].t);
    const Eigen::Quaterniond qi = e[lo].q.slerp(lambda, e[hi].q);
    const Eigen::Vector3d pi = e[lo].p + lambda * (e[hi].p - e[lo].p);
    p = p + q * pi;
    q = q * qi;
  }
  return {q, p};
}

}  // namespace

#if defined(__clang__)
#define SEMGRAPH_KERNEL __attribute__((noinline))
#else
#define SEMGRAPH_KERNEL \
  __attribute__((noipa))  // no clone, no dead-call removal: callgrind toggles by name
#endif

extern "C" {
SEMGRAPH_KERNEL int icount_compiled_at(const CompiledPose<QuatB>* c, QuatB::PoseCoords* X) {
  TimeReport r;
  return static_cast<int>(c->Evaluate(*X, At{Stamp::Nanoseconds(kT)}, r));
}
SEMGRAPH_KERNEL int icount_oneshot_at(const SceneGraph<QuatB>* g, const std::string* of,
                                      const std::string* wrt, QuatB::PoseCoords* X) {
  auto r = g->GetPose(PoseSpec::Of(*of).RelativeTo(*wrt), At{Stamp::Nanoseconds(kT)});
  if (r) *X = r->value.value;
  return r ? 0 : 1;
}
SEMGRAPH_KERNEL void icount_raw_interp_chain(const Scene* s, RawPose* out) {
  *out = RawInterpChain(*s, kT);
}
SEMGRAPH_KERNEL void icount_raw_chain(const RawPose* links, int d, RawPose* out) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < d; ++i) {
    p = p + q * links[i].p;
    q = q * links[i].q;
  }
  *out = {q, p};
}
SEMGRAPH_KERNEL int icount_stamped_insert(SceneGraph<QuatB>* g, PoseHandle h, std::int64_t t,
                                          const Eigen::Quaterniond* q, const Eigen::Vector3d* p) {
  return static_cast<int>(g->SetPose(h, *q, *p, Stamp::Nanoseconds(t)));
}
#if defined(SEMGRAPH_HAVE_TF2)
SEMGRAPH_KERNEL int icount_tf2_at(const semgraph_test::tf2time::Buffer* tf,
                                  const std::string* target, const std::string* source,
                                  semgraph_test::tf2time::Pose7* out) {
  return tf->Lookup(*target, *source, kT + 1000000000, *out) ? 0 : 1;
}
SEMGRAPH_KERNEL int icount_tf2_insert(semgraph_test::tf2time::Buffer* tf, const std::string* parent,
                                      const std::string* child, std::int64_t t,
                                      const semgraph_test::tf2time::Pose7* x) {
  return tf->Set(*parent, *child, *x, t, false) ? 0 : 1;
}
#endif
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s KERNEL D ITERS\n", argv[0]);
    return 2;
  }
  const std::string kernel = argv[1];
  const int d = std::atoi(argv[2]);
  const long iters = std::atol(argv[3]);
  Scene* s = MakeScene(d);
  const std::string f0 = "f0", fd = "f" + std::to_string(d);
  // Cross-checks: semgraph linear == raw == tf2.
  const RawPose raw = RawInterpChain(*s, kT);
  auto lin = s->linear.GetPose(PoseSpec::Of(fd).RelativeTo(f0), At{Stamp::Nanoseconds(kT)});
  if (!lin || (lin->value.value.translation - raw.p).norm() > 1e-9) {
    std::fprintf(stderr, "semgraph linear differs from the raw chain\n");
    return 1;
  }
#if defined(SEMGRAPH_HAVE_TF2)
  semgraph_test::tf2time::Pose7 y;
  if (!s->tf.Lookup(f0, fd, kT + 1000000000, y) ||
      (Eigen::Vector3d(y.x, y.y, y.z) - raw.p).norm() > 1e-9) {
    std::fprintf(stderr, "tf2 differs from the raw chain\n");
    return 1;
  }
#endif
  QuatB::PoseCoords X;
  if (kernel == "compiled_at_linear" || kernel == "compiled_at_screw") {
    auto c = (kernel == "compiled_at_linear" ? s->linear : s->screw)
                 .CompilePose(PoseSpec::Of(fd).RelativeTo(f0));
    for (long i = 0; i < iters; ++i) icount_compiled_at(&*c, &X);
  } else if (kernel == "oneshot_at_linear") {
    for (long i = 0; i < iters; ++i) icount_oneshot_at(&s->linear, &fd, &f0, &X);
  } else if (kernel == "raw_interp_chain") {
    RawPose out;
    for (long i = 0; i < iters; ++i) icount_raw_interp_chain(s, &out);
  } else if (kernel == "raw_chain") {
    std::vector<RawPose> links(d, RawPose{s->edges[0][50].q, s->edges[0][50].p});
    RawPose out;
    for (long i = 0; i < iters; ++i) icount_raw_chain(links.data(), d, &out);
  } else if (kernel == "stamped_insert") {
    auto h = s->linear.FindPoseEdge("f1", "f0");
    const Eigen::Quaterniond q = s->edges[0][3].q;
    const Eigen::Vector3d p = s->edges[0][3].p;
    // The capacity (1024) fills first: the counted inserts each also drop the oldest sample.
    for (long i = 0; i < 1024; ++i)
      icount_stamped_insert(&s->linear, *h, kSamples * kStep + i * 1000000, &q, &p);
    for (long i = 0; i < iters; ++i)
      icount_stamped_insert(&s->linear, *h, 2000000000 + i * 1000000, &q, &p);
#if defined(SEMGRAPH_HAVE_TF2)
  } else if (kernel == "tf2_at") {
    semgraph_test::tf2time::Pose7 out;
    for (long i = 0; i < iters; ++i) icount_tf2_at(&s->tf, &f0, &fd, &out);
  } else if (kernel == "tf2_insert") {
    const semgraph_test::tf2time::Pose7 x{1, 0, 0, 0, 0.1, 0.2, 0.3};
    const std::string parent = "f0", child = "f1";
    for (long i = 0; i < 1024; ++i)
      icount_tf2_insert(&s->tf, &parent, &child, 2000000000 + i * 1000000, &x);
    for (long i = 0; i < iters; ++i)
      icount_tf2_insert(&s->tf, &parent, &child, 3100000000 + i * 1000000, &x);
#endif
  } else {
    std::fprintf(stderr, "unknown kernel %s\n", kernel.c_str());
    return 2;
  }
  std::printf("%s d=%d ok\n", kernel.c_str(), d);
  return 0;
}
