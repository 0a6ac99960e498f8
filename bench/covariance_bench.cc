// semgraph_covariance_bench: a compiled pose query with covariance (compiled_covariance.h) on a
// chain of d uncertain edges, against (1) a hand-written Eigen chain propagating the same
// covariances (X_acc = X_acc X_i, S = J1 S J1^T + J2 S_i J2^T with dense 6x6 Jacobians, the
// coordinates convention: J1 = [[I, -[R_acc p_i]x], [0, I]], J2 = diag(R_acc, R_acc)) and (2)
// the same compiled query without covariance (CompiledPose). Both answers are checked against
// the compiled one before timing.
//   semgraph_covariance_bench [google benchmark flags]      wall time, d = 8 and 64
//   semgraph_covariance_bench icount KERNEL D ITERS          one kernel ITERS times, for
//     valgrind --tool=callgrind --toggle-collect=icount_KERNEL (bench/covariance_icount.sh)
// KERNEL: compiled_cov, raw_eigen_cov, compiled_plain.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph.h"

using namespace semgraph::core;
using QuatB = semgraph::coord::QuaternionBackend;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

namespace {

// The chain f0 <- f1 <- ... <- fd (one body each), random values and covariances; the same
// numbers as plain arrays for the hand-written chain.
struct ChainScene {
  SceneGraph<QuatB> graph;
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> p;
  std::vector<Covariance6> S;
  PoseSpec spec;
  std::string tip, base;
};

void MakeChain(ChainScene& s, int d) {
  std::mt19937 rng(42);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 1; k <= d; ++k) {
    const Eigen::Vector3d w(n(rng), n(rng), n(rng));
    const Eigen::Matrix3d R(Eigen::AngleAxisd(w.norm(), w.normalized()));
    const Eigen::Vector3d p(n(rng), n(rng), n(rng));
    Matrix6 L;
    for (int i = 0; i < 36; ++i) L(i / 6, i % 6) = n(rng);
    const Covariance6 S = 1e-6 * L * L.transpose();
    const std::string f = "f" + std::to_string(k), parent = "f" + std::to_string(k - 1);
    const auto ok = s.graph.AddPose(PoseSpec::Of(f, "B" + std::to_string(k))
                                        .RelativeTo(parent, "B" + std::to_string(k - 1)),
                                    R, p, CovarianceInput{&S});
    if (!ok) std::abort();
    // The stored (normalized quaternion) value, so the hand-written chain reads the same numbers.
    const auto X = s.graph.pose_value(s.graph.FindFrame(f));
    s.R.push_back(QuatB::ToMatrix(QuatB::RotationOf(X)));
    s.p.push_back(QuatB::TranslationOf(X));
    s.S.push_back(s.graph.pose_covariance(s.graph.FindFrame(f)));
  }
  s.tip = "f" + std::to_string(d);
  s.base = "f0";
  s.spec = PoseSpec::Of(s.tip).RelativeTo(s.base);
}

Eigen::Matrix3d Hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace

extern "C" {
__attribute__((noinline)) int icount_compiled_cov(CompiledPoseWithCovariance<QuatB>* q,
                                                  QuatB::PoseCoords* X, Covariance6* S) {
  return static_cast<int>(q->Evaluate(*X, *S));
}
__attribute__((noinline)) int icount_compiled_plain(const CompiledPose<QuatB>* q,
                                                    QuatB::PoseCoords* X) {
  return static_cast<int>(q->Evaluate(*X));
}
// X_0d = X_01 X_12 ... and its covariance, the textbook way.
__attribute__((noinline)) int icount_raw_eigen_cov(const ChainScene* s, Eigen::Matrix3d* R_out,
                                                   Eigen::Vector3d* p_out, Covariance6* S_out) {
  Eigen::Matrix3d R = s->R[0];
  Eigen::Vector3d p = s->p[0];
  Covariance6 S = s->S[0];
  for (std::size_t i = 1; i < s->R.size(); ++i) {
    Matrix6 J1 = Matrix6::Identity(), J2 = Matrix6::Zero();
    J1.topRightCorner<3, 3>() = -Hat(R * s->p[i]);
    J2.topLeftCorner<3, 3>() = R;
    J2.bottomRightCorner<3, 3>() = R;
    S = J1 * S * J1.transpose() + J2 * s->S[i] * J2.transpose();
    p += R * s->p[i];
    R = R * s->R[i];
  }
  *R_out = R;
  *p_out = p;
  *S_out = S;
  return 0;
}
}

namespace {

struct Kernels {
  ChainScene scene;
  CompiledPoseWithCovariance<QuatB> cov;
  CompiledPose<QuatB> plain;
  explicit Kernels(int d) {
    MakeChain(scene, d);
    cov = *scene.graph.CompilePoseWithCovariance(scene.spec);
    plain = *scene.graph.CompilePose(scene.spec);
    // The three agree (else the comparison means nothing).
    QuatB::PoseCoords X, X_plain;
    Covariance6 S, S_raw;
    Eigen::Matrix3d R;
    Eigen::Vector3d p;
    if (icount_compiled_cov(&cov, &X, &S) != 0 || icount_compiled_plain(&plain, &X_plain) != 0)
      std::abort();
    icount_raw_eigen_cov(&scene, &R, &p, &S_raw);
    if ((S - S_raw).norm() > 1e-9 * S.norm() || (QuatB::TranslationOf(X) - p).norm() > 1e-9 * (1 + p.norm()) ||
        (QuatB::TranslationOf(X_plain) - p).norm() > 1e-9 * (1 + p.norm())) {
      std::fprintf(stderr, "covariance_bench: the kernels disagree\n");
      std::abort();
    }
  }
};

void BM_CompiledPoseWithCovariance(benchmark::State& st) {
  Kernels k(static_cast<int>(st.range(0)));
  QuatB::PoseCoords X;
  Covariance6 S;
  for (auto _ : st) {
    benchmark::DoNotOptimize(icount_compiled_cov(&k.cov, &X, &S));
    benchmark::DoNotOptimize(S);
  }
}
void BM_RawEigenChainWithCovariance(benchmark::State& st) {
  Kernels k(static_cast<int>(st.range(0)));
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  Covariance6 S;
  for (auto _ : st) {
    benchmark::DoNotOptimize(icount_raw_eigen_cov(&k.scene, &R, &p, &S));
    benchmark::DoNotOptimize(S);
  }
}
void BM_CompiledPoseWithoutCovariance(benchmark::State& st) {
  Kernels k(static_cast<int>(st.range(0)));
  QuatB::PoseCoords X;
  for (auto _ : st) {
    benchmark::DoNotOptimize(icount_compiled_plain(&k.plain, &X));
    benchmark::DoNotOptimize(X);
  }
}
BENCHMARK(BM_CompiledPoseWithCovariance)->Arg(8)->Arg(64);
BENCHMARK(BM_RawEigenChainWithCovariance)->Arg(8)->Arg(64);
BENCHMARK(BM_CompiledPoseWithoutCovariance)->Arg(8)->Arg(64);

int RunIcount(const char* kernel, int d, long iters) {
  Kernels k(d);
  QuatB::PoseCoords X;
  Covariance6 S;
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  int sum = 0;
  for (long i = 0; i < iters; ++i) {
    if (std::strcmp(kernel, "compiled_cov") == 0) {
      sum += icount_compiled_cov(&k.cov, &X, &S);
    } else if (std::strcmp(kernel, "raw_eigen_cov") == 0) {
      sum += icount_raw_eigen_cov(&k.scene, &R, &p, &S);
    } else if (std::strcmp(kernel, "compiled_plain") == 0) {
      sum += icount_compiled_plain(&k.plain, &X);
    } else {
      std::fprintf(stderr, "unknown kernel %s\n", kernel);
      return 2;
    }
  }
  benchmark::DoNotOptimize(S);
  benchmark::DoNotOptimize(X);
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::strcmp(argv[1], "icount") == 0) {
    return RunIcount(argv[2], std::atoi(argv[3]), std::atol(argv[4]));
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
