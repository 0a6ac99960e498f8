// semgraph_icount KERNEL D ITERS: sets up the scene of one kernel of semgraph_bench (same code:
// bench_scenes.h), checks it against the reference, then calls the kernel ITERS times. Every
// kernel is an extern "C" noinline function icount_<KERNEL> doing one query, so
//   valgrind --tool=callgrind --toggle-collect=icount_<KERNEL> semgraph_icount KERNEL D ITERS
// counts exactly the instructions of ITERS queries (plus a call/return each); icount.sh divides
// the total Ir by ITERS. D is the chain depth, the number of twist edges (compiled_twist) or the
// tree size N (reject_*, build_*: for build_*, one iteration is one whole build of N frames).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "bench_scenes.h"

using namespace semgraph_bench;

namespace {
template <class T>
inline void Use(const T& v) {
  benchmark::DoNotOptimize(v);
}
}  // namespace

extern "C" {

__attribute__((noinline)) int icount_compiled_pose_f2f(const CompiledPose<QuatB>* q,
                                                       QuatB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X));
}
__attribute__((noinline)) int icount_compiled_pose_f2f_homogeneous(const CompiledPose<HomB>* q,
                                                                   HomB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X));
}
__attribute__((noinline)) int icount_compiled_pose_changes(const CompiledPose<QuatB>* q,
                                                           QuatB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X));
}
// The memoized evaluation (PoseCache): Ir inside the evaluation only; the SetPose calls that
// change edges between evaluations are outside the counted function.
__attribute__((noinline)) int icount_compiled_pose_cached_one(const CompiledPose<QuatB>* q,
                                                              PoseCache<QuatB>* c,
                                                              QuatB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X, *c));
}
__attribute__((noinline)) int icount_compiled_pose_cached_all(const CompiledPose<QuatB>* q,
                                                              PoseCache<QuatB>* c,
                                                              QuatB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X, *c));
}
__attribute__((noinline)) int icount_compiled_twist(const CompiledTwist<QuatB>* q,
                                                    Eigen::Vector3d* v, Eigen::Vector3d* w) {
  return static_cast<int>(q->Evaluate(*v, *w));
}
__attribute__((noinline)) int icount_oneshot_by_names(const SceneGraph<QuatB>* g,
                                                      const std::string* of,
                                                      const std::string* wrt) {
  auto r = g->GetPose(PoseSpec::Of(*of).RelativeTo(*wrt));
  Use(r);
  return r ? 0 : 1;
}
__attribute__((noinline)) void icount_raw_eigen_quat_chain(const Link* links, int d,
                                                           QuatPose* out) {
  *out = RawQuatChain(links, d);
}
__attribute__((noinline)) void icount_raw_eigen_iso_chain(const Eigen::Isometry3d* T, int d,
                                                          Eigen::Isometry3d* out) {
  *out = RawIsoChain(T, d);
}
__attribute__((noinline)) int icount_reject_P1(RejectScene* s) {
  auto r = s->RejectP1();
  return !r && r.error().code == ErrorCode::kMultiplePoseParents ? 0 : 1;
}
__attribute__((noinline)) int icount_reject_P3(RejectScene* s) {
  auto r = s->RejectP3();
  return !r && r.error().code == ErrorCode::kDuplicatePosePath ? 0 : 1;
}
__attribute__((noinline)) int icount_reject_W3(RejectScene* s) {
  auto r = s->RejectW3();
  return !r && r.error().code == ErrorCode::kDuplicateTwistPath ? 0 : 1;
}
__attribute__((noinline)) void icount_build_random_tree(SceneGraph<QuatB>* g, const RandomTree* t) {
  AddTree(*g, *t);
}
#ifdef SEMGRAPH_HAVE_TF2
__attribute__((noinline)) void icount_tf2_lookup_static(const Tf2Chain* c) { c->LookupOnce(); }
__attribute__((noinline)) void icount_tf2_lookup_dynamic(const Tf2Chain* c) { c->LookupOnce(); }
__attribute__((noinline)) int icount_tf2_build_tree_static(tf2peer::Buffer* buffer,
                                                           const tf2peer::TreeMessages* msgs) {
  return buffer->InsertAllStatic(*msgs) ? 0 : 1;
}
#endif

}  // extern "C"

namespace {

int Usage() {
  std::fprintf(stderr,
               "usage: semgraph_icount KERNEL D ITERS\n"
               "kernels: compiled_pose_f2f compiled_pose_f2f_homogeneous compiled_pose_changes\n"
               "         compiled_pose_cached_one compiled_pose_cached_all\n"
               "         compiled_twist oneshot_by_names raw_eigen_quat_chain raw_eigen_iso_chain\n"
               "         reject_P1 reject_P3 reject_W3 build_random_tree%s\n",
#ifdef SEMGRAPH_HAVE_TF2
               "\n         tf2_lookup_static tf2_lookup_dynamic tf2_build_tree_static"
#else
               ""
#endif
  );
  return 2;
}

void Check(int code, const char* kernel) {
  if (code != 0) Fail(std::string(kernel) + ": the kernel reported an error");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) return Usage();
  const std::string kernel = argv[1];
  const int d = std::atoi(argv[2]);
  const long iters = std::atol(argv[3]);
  if (d < 1 || iters < 1) return Usage();
  const bool chain_kernel =
      kernel.rfind("reject_", 0) != 0 && kernel.find("build_") == std::string::npos;
  if (chain_kernel && d > kMaxDepth) return Usage();

  if (kernel == "compiled_pose_f2f" || kernel == "oneshot_by_names") {
    ChainScene<QuatB> s(d, false, 0);
    VerifyF2F(s);
    if (kernel == "compiled_pose_f2f") {
      const auto q = s.CompileOrDie(s.F2FSpec());
      QuatB::PoseCoords X;
      for (long i = 0; i < iters; ++i) Check(icount_compiled_pose_f2f(&q, &X), "compiled_pose_f2f");
      Use(X);
    } else {
      const std::string of = s.frames.back(), wrt = s.frames.front();
      for (long i = 0; i < iters; ++i)
        Check(icount_oneshot_by_names(&s.graph, &of, &wrt), "oneshot_by_names");
    }
  } else if (kernel == "compiled_pose_cached_one" || kernel == "compiled_pose_cached_all") {
    // One edge (cycling along the chain) or every edge changed before each evaluation.
    ChainScene<QuatB> s(d, false, 0);
    VerifyF2F(s);
    const auto q = s.CompileOrDie(s.F2FSpec());
    auto cache = q.MakeCache();
    std::vector<PoseHandle> handles;
    for (int i = 1; i <= d; ++i) {
      auto h = s.graph.FindPoseEdge(s.frames[static_cast<std::size_t>(i)],
                                    s.frames[static_cast<std::size_t>(i - 1)]);
      if (!h) Fail("FindPoseEdge");
      handles.push_back(*h);
    }
    const bool all = kernel == "compiled_pose_cached_all";
    const Link* links = Poses().links.data();
    QuatB::PoseCoords X;
    Check(static_cast<int>(q.Evaluate(X, cache)), "cached warm-up");
    for (long i = 0; i < iters; ++i) {
      for (int k = 0; k < (all ? d : 1); ++k) {
        const int e = all ? k : static_cast<int>(i % d);
        const Link& l = links[e];
        Check(static_cast<int>(s.graph.SetPose(handles[static_cast<std::size_t>(e)],
                                               (i & 1) ? l.q : l.q.conjugate(), l.p)),
              "SetPose");
      }
      Check(all ? icount_compiled_pose_cached_all(&q, &cache, &X)
                : icount_compiled_pose_cached_one(&q, &cache, &X),
            kernel.c_str());
    }
    Use(X);
  } else if (kernel == "compiled_pose_f2f_homogeneous") {
    ChainScene<HomB> s(d, false, 0);
    VerifyF2F(s);
    const auto q = s.CompileOrDie(s.F2FSpec());
    HomB::PoseCoords X;
    for (long i = 0; i < iters; ++i)
      Check(icount_compiled_pose_f2f_homogeneous(&q, &X), "homogeneous");
    Use(X);
  } else if (kernel == "compiled_pose_changes") {
    ChainScene<QuatB> s(d, true, 0);
    VerifyChanges(s);
    const auto q = s.CompileOrDie(s.ChangesSpec());
    QuatB::PoseCoords X;
    for (long i = 0; i < iters; ++i)
      Check(icount_compiled_pose_changes(&q, &X), "compiled_pose_changes");
    Use(X);
  } else if (kernel == "compiled_twist") {
    ChainScene<QuatB> s(d, false, d);
    VerifyTwist(s);
    auto c = s.graph.CompileTwist(s.TwistQuerySpec());
    if (!c) Fail("CompileTwist");
    Eigen::Vector3d v, w;
    for (long i = 0; i < iters; ++i) Check(icount_compiled_twist(&*c, &v, &w), "compiled_twist");
    Use(v);
    Use(w);
  } else if (kernel == "raw_eigen_quat_chain") {
    const Link* links = Poses().links.data();
    QuatPose out;
    for (long i = 0; i < iters; ++i) icount_raw_eigen_quat_chain(links, d, &out);
    Use(out);
  } else if (kernel == "raw_eigen_iso_chain") {
    const auto T = IsoLinks();
    Eigen::Isometry3d out;
    for (long i = 0; i < iters; ++i) icount_raw_eigen_iso_chain(T.data(), d, &out);
    Use(out);
  } else if (kernel == "reject_P1" || kernel == "reject_P3" || kernel == "reject_W3") {
    RejectScene s(TreeOf(static_cast<std::uint32_t>(d)));
    int (*f)(RejectScene*) = kernel == "reject_P1"   ? icount_reject_P1
                             : kernel == "reject_P3" ? icount_reject_P3
                                                     : icount_reject_W3;
    for (long i = 0; i < iters; ++i) Check(f(&s), kernel.c_str());
  } else if (kernel == "build_random_tree") {
    const RandomTree& t = TreeOf(static_cast<std::uint32_t>(d));
    for (long i = 0; i < iters; ++i) {
      SceneGraph<QuatB> g;
      icount_build_random_tree(&g, &t);
      if (g.num_frames() != t.n + 1u) Fail("build_random_tree: wrong frame count");
    }
#ifdef SEMGRAPH_HAVE_TF2
  } else if (kernel == "tf2_lookup_static" || kernel == "tf2_lookup_dynamic") {
    const bool dynamic = kernel == "tf2_lookup_dynamic";
    Tf2Chain c(d, dynamic);  // checks against the reference
    for (long i = 0; i < iters; ++i) {
      if (dynamic)
        icount_tf2_lookup_dynamic(&c);
      else
        icount_tf2_lookup_static(&c);
    }
  } else if (kernel == "tf2_build_tree_static") {
    const auto msgs = Tf2TreeMessages(TreeOf(static_cast<std::uint32_t>(d)));
    for (long i = 0; i < iters; ++i) {
      tf2peer::Buffer buffer;
      Check(icount_tf2_build_tree_static(&buffer, msgs.get()), "tf2_build_tree_static");
    }
#endif
  } else {
    return Usage();
  }
  std::printf("%s %d %ld done\n", kernel.c_str(), d, iters);
  return 0;
}
