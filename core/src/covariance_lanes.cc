// The pose edges' J S J^T with the edges in SIMD lanes: one kernel written once over a vector
// type, built for SSE2 pairs and for AVX2 + FMA quads. Contract: covariance_lanes.h.
#include "semgraph/core/covariance_lanes.h"

#include <cstring>

namespace semgraph::core::internal {

namespace {

using Lanes2 = double __attribute__((vector_size(16)));
using Lanes4 = double __attribute__((vector_size(32)));
using Sums = PoseCovarianceSums;

// Upper-triangle index of a symmetric 3x3's entry (i, j), and the entries in that order.
constexpr int kSym[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
constexpr int kUpperRow[6] = {0, 0, 0, 1, 1, 2};
constexpr int kUpperCol[6] = {0, 1, 2, 1, 2, 2};

// Helpers take and give vectors by reference only: a 32-byte vector by value would change the
// ABI between the SSE2 and AVX2 functions (GCC's -Wpsabi).
template <class V>
[[gnu::always_inline]] inline void Load(const double* x, int row, int j0, V& v) noexcept {
  std::memcpy(&v, x + LaneIndex(row, j0), sizeof v);
}

// out = (l x t)_i.
template <class V>
[[gnu::always_inline]] inline void CrossRow(const V (&l)[3], const V& t0, const V& t1, const V& t2,
                                            int i, V& out) noexcept {
  if (i == 0) {
    out = l[1] * t2 - l[2] * t1;
  } else if (i == 1) {
    out = l[2] * t0 - l[0] * t2;
  } else {  // i == 2 (every branch assigns: GCC's TSan build warned of a path that did not)
    out = l[0] * t1 - l[1] * t0;
  }
}

// RX = R X with X symmetric (upper triangle).
template <class V>
[[gnu::always_inline]] inline void SymmetricTimes(const V (&R)[3][3], const V (&X)[6],
                                                  V (&RX)[3][3]) noexcept {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      RX[i][j] = R[i][0] * X[kSym[0][j]] + R[i][1] * X[kSym[1][j]] + R[i][2] * X[kSym[2][j]];
    }
  }
}

// T = R X R^T's upper triangle, X symmetric (upper triangle).
template <class V>
[[gnu::always_inline]] inline void SymmetricCongruence(const V (&R)[3][3], const V (&X)[6],
                                                       V (&T)[6]) noexcept {
  V RX[3][3];
  SymmetricTimes(R, X, RX);
  for (int u = 0; u < 6; ++u) {
    const int i = kUpperRow[u], j = kUpperCol[u];
    T[u] = RX[i][0] * R[j][0] + RX[i][1] * R[j][1] + RX[i][2] * R[j][2];
  }
}

// T = R X R^T, X general.
template <class V>
[[gnu::always_inline]] inline void Congruence(const V (&R)[3][3], const V (&X)[3][3],
                                              V (&T)[3][3]) noexcept {
  V RX[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      RX[i][j] = R[i][0] * X[0][j] + R[i][1] * X[1][j] + R[i][2] * X[2][j];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      T[i][j] = RX[i][0] * R[j][0] + RX[i][1] * R[j][1] + RX[i][2] * R[j][2];
    }
  }
}

// Adds `v` to the running sum `entry` of the lanes j0 .. j0 + W - 1.
template <class V>
[[gnu::always_inline]] inline void Accumulate(Sums& sums, int entry, int j0, const V& v) noexcept {
  V acc;
  double* at = &sums.lane[entry][j0 % 4];
  std::memcpy(&acc, at, sizeof acc);
  acc += v;
  std::memcpy(at, &acc, sizeof acc);
}

// The kernel, W = sizeof(V) / 8 edges at a time (the formula of covariance_lanes.h). kWithO:
// K = c I + d O per lane (else K = c I, and every lane's d must be 0).
template <class V, bool kWithO>
[[gnu::always_inline]] inline void SumLanes(const double* in, int n, const Eigen::Vector3d& e_Z,
                                            const Eigen::Vector3d& f_Z, const Eigen::Matrix3d& O_Z,
                                            Sums& sums) noexcept {
  constexpr int W = static_cast<int>(sizeof(V) / sizeof(double));
  V e[3], f[3], O[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int w = 0; w < W; ++w) {
      e[i][w] = e_Z[i];
      f[i][w] = f_Z[i];
      for (int j = 0; j < 3; ++j) O[i][j][w] = kWithO ? O_Z(i, j) : 0.0;
    }
  }
  for (int j0 = 0; j0 < n; j0 += W) {
    V R[3][3], l[3], S11[6], S22[6], S12[3][3], alpha, beta, s, c;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        Load(in, LaneRow::kR + 3 * i + j, j0, R[i][j]);
        Load(in, LaneRow::kS12 + 3 * i + j, j0, S12[i][j]);
      }
      Load(in, LaneRow::kLeverBase + i, j0, l[i]);
    }
    for (int u = 0; u < 6; ++u) {
      Load(in, LaneRow::kS11 + u, j0, S11[u]);
      Load(in, LaneRow::kS22 + u, j0, S22[u]);
    }
    Load(in, LaneRow::kAlpha, j0, alpha);
    Load(in, LaneRow::kBeta, j0, beta);
    Load(in, LaneRow::kS, j0, s);
    Load(in, LaneRow::kC, j0, c);
    for (int i = 0; i < 3; ++i) l[i] += alpha * e[i] + beta * f[i];
    V T1[6], T3[6], T2[3][3];
    SymmetricCongruence(R, S11, T1);
    SymmetricCongruence(R, S22, T3);
    Congruence(R, S12, T2);
    V Y[3][3], N[3][3];  // Y(:, j) = l x T2(j, :); N(:, j) = l x T3(:, j)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        CrossRow(l, T2[j][0], T2[j][1], T2[j][2], i, Y[i][j]);
        CrossRow(l, T3[kSym[0][j]], T3[kSym[1][j]], T3[kSym[2][j]], i, N[i][j]);
      }
    }
    const V s2 = s * s;
    for (int u = 0; u < 6; ++u) {
      const int i = kUpperRow[u], j = kUpperCol[u];
      V LNt;  // (L N^T)(i, j) = (l x N(j, :))_i
      CrossRow(l, N[j][0], N[j][1], N[j][2], i, LNt);
      const V tl = s2 * T1[u] + s * (Y[i][j] + Y[j][i]) + LNt;
      Accumulate(sums, Sums::kTL + u, j0, tl);
    }
    V M[3][3];  // s T2 + N
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) M[i][j] = s * T2[i][j] + N[i][j];
    }
    if constexpr (kWithO) {  // TR = M K^T, BR = K T3 K^T: K formed first, as the dense form does
      V d, K[3][3], KT[3][3];
      Load(in, LaneRow::kD, j0, d);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) K[i][j] = i == j ? c + d * O[i][j] : d * O[i][j];
      }
      SymmetricTimes(K, T3, KT);
      for (int u = 0; u < 6; ++u) {
        const int i = kUpperRow[u], j = kUpperCol[u];
        const V br = KT[i][0] * K[j][0] + KT[i][1] * K[j][1] + KT[i][2] * K[j][2];
        Accumulate(sums, Sums::kBR + u, j0, br);
      }
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const V tr = M[i][0] * K[j][0] + M[i][1] * K[j][1] + M[i][2] * K[j][2];
          Accumulate(sums, Sums::kTR + 3 * i + j, j0, tr);
        }
      }
    } else {
      const V c2 = c * c;
      for (int u = 0; u < 6; ++u) {
        const V br = c2 * T3[u];
        Accumulate(sums, Sums::kBR + u, j0, br);
      }
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const V tr = c * M[i][j];
          Accumulate(sums, Sums::kTR + 3 * i + j, j0, tr);
        }
      }
    }
  }
}

template <class V>
[[gnu::always_inline]] inline void SumLanesOf(const double* in, int n, const Eigen::Vector3d& e,
                                              const Eigen::Vector3d& f, const Eigen::Matrix3d* O,
                                              Sums& sums) noexcept {
  if (O != nullptr) return SumLanes<V, true>(in, n, e, f, *O, sums);
  SumLanes<V, false>(in, n, e, f, Eigen::Matrix3d::Zero(), sums);
}

// SEMGRAPH_LANES_SSE2_ONLY (a build knob for measurements: bench/covariance_icount.sh): no
// AVX2 kernel, what a CPU without it runs.
#if defined(__x86_64__) && !(defined(__AVX2__) && defined(__FMA__)) && \
    !defined(SEMGRAPH_LANES_SSE2_ONLY)
#define SEMGRAPH_LANES_DISPATCH 1
// The same kernel built for AVX2 + FMA (the build targets less; the CPU is checked first).
__attribute__((target("avx2,fma"))) void SumLanesAvx2(const double* in, int n,
                                                      const Eigen::Vector3d& e,
                                                      const Eigen::Vector3d& f,
                                                      const Eigen::Matrix3d* O,
                                                      Sums& sums) noexcept {
  SumLanesOf<Lanes4>(in, n, e, f, O, sums);
}
#endif

}  // namespace

bool PoseEdgeLanesUseAvx2() noexcept {
#if defined(SEMGRAPH_LANES_SSE2_ONLY)
  return false;
#elif defined(SEMGRAPH_LANES_DISPATCH)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#elif defined(__AVX2__) && defined(__FMA__)
  return true;
#else
  return false;
#endif
}

void SumPoseEdgeLanes(const double* in, int n, const Eigen::Vector3d& e, const Eigen::Vector3d& f,
                      const Eigen::Matrix3d* O, PoseCovarianceSums& sums) noexcept {
#if defined(SEMGRAPH_LANES_DISPATCH)
  if (PoseEdgeLanesUseAvx2()) return SumLanesAvx2(in, n, e, f, O, sums);
  SumLanesOf<Lanes2>(in, n, e, f, O, sums);
#elif defined(__AVX2__) && defined(__FMA__) && !defined(SEMGRAPH_LANES_SSE2_ONLY)
  SumLanesOf<Lanes4>(in, n, e, f, O, sums);
#else
  SumLanesOf<Lanes2>(in, n, e, f, O, sums);
#endif
}

void SumPoseEdgeLanesSse2(const double* in, int n, const Eigen::Vector3d& e,
                          const Eigen::Vector3d& f, const Eigen::Matrix3d* O,
                          PoseCovarianceSums& sums) noexcept {
  SumLanesOf<Lanes2>(in, n, e, f, O, sums);
}

void PoseCovarianceSums::AddTo(coord::Covariance6& S_Z) const noexcept {
  double t[kEntries];
  for (int k = 0; k < kEntries; ++k) t[k] = (lane[k][0] + lane[k][1]) + (lane[k][2] + lane[k][3]);
  for (int u = 0; u < 6; ++u) {
    const int i = kUpperRow[u], j = kUpperCol[u];
    S_Z(i, j) += t[kTL + u];
    S_Z(i + 3, j + 3) += t[kBR + u];
    if (i != j) {
      S_Z(j, i) += t[kTL + u];
      S_Z(j + 3, i + 3) += t[kBR + u];
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      S_Z(i, j + 3) += t[kTR + 3 * i + j];
      S_Z(j + 3, i) += t[kTR + 3 * i + j];
    }
  }
}

void PoseCovarianceLanes::Flush() noexcept {
  PadLanes(x_, n_);
  SumPoseEdgeLanes(x_, n_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                   with_o_ ? &O_ : nullptr, sums_);
  n_ = 0;
}

void PoseCovarianceLanes::AddTo(coord::Covariance6& S_Z) noexcept {
  if (n_ > 0) Flush();
  sums_.AddTo(S_Z);
}

}  // namespace semgraph::core::internal
